#pragma once
// Structured staggered grid over the gap of a parallel-plate rheometer, in cylindrical
// coordinates (r, θ, z): 0 <= r <= R, 0 <= θ < 2π, 0 <= z <= H. The plates
// z = 0 and z = H and the rim r = R are coordinate surfaces.
//
// Layout (MAC staggering): pressure and scalars at cell centres, u_r on radial faces (r = const),
// u_θ on azimuthal faces (θ = const), u_z on axial faces (z = const).
//
// Cell (i, j, k) spans [r_i, r_{i+1}] × [θ_j, θ_{j+1}] × [z_k, z_{k+1}], with Δθ = 2π/N_θ and
// Δz_k = z_{k+1} − z_k (uniform H/N_z unless stretched, below). Exact finite-volume geometry of that annular sector:
//   volume                 V_ik = (Δθ/2)(r_{i+1}² − r_i²) Δz_k
//   axial face (z = const) A_z,i = (Δθ/2)(r_{i+1}² − r_i²)          (so V = A_z Δz exactly)
//   radial face (r = r_i)  A_r,ik = r_i Δθ Δz_k                      (a cylinder patch)
//   azimuthal face         A_θ,ik = (r_{i+1} − r_i) Δz_k             (a flat rectangle)
// The axis r_0 = 0 is a degenerate radial face of zero area: no flux crosses it, which is
// the r·u_r = 0 condition a solver imposes there. Centres are face midpoints, e.g.
// r_c,i = (r_i + r_{i+1})/2 (not the area centroid), as usual on staggered grids.
//
// Radial grading (as blockMesh's simpleGrading, so the OpenFOAM export can reproduce it):
// g = Δr_last/Δr_first; the widths form a geometric series with ratio q = g^(1/(N_r−1)),
//   r_i = R (q^i − 1)/(q^N_r − 1),   i = 0..N_r   (r_i = i R/N_r for g = 1).
// g < 1 refines towards the rim, where the torque ∫ r τ_θz dA collects most of its weight.
//
// Axial stretching towards both plates, symmetric about mid-gap: with β >= 0,
//   z_k = (H/2) [1 + tanh(β(2k/N_z − 1)) / tanh β],   k = 0..N_z   (z_k = k H/N_z for β = 0).
// The faces are a smooth map of k/N_z, so neighbouring widths differ by O(N_z⁻²) (centred
// differences stay second order) and the grid with N_z/2 cells has every other face of this
// one (grid sequencing and Richardson pairs refine by exactly 2). Δz_mid/Δz_plate → cosh²β as
// N_z grows (β = 1: 2.4, β = 1.5: 5.5). It resolves the thin plate layers of shear-thinning
// fluids with inertia (docs/performance.md). Only the steady swirl solver supports β > 0.
//
// Parameters (SI):
//   radius           R    [m]  > 0
//   gap              H    [m]  > 0
//   radial_cells     N_r  [-]  >= 1
//   azimuthal_cells  N_θ  [-]  >= 1; 1 = axisymmetric (one sector of Δθ = 2π)
//   axial_cells      N_z  [-]  >= 1
//   radial_grading   g    [-]  > 0, default 1 (uniform)
//   axial_stretching β    [-]  >= 0, default 0 (uniform)
#include <cstddef>
#include <span>
#include <vector>

namespace rheosim::fluid {

class CylindricalGrid {
 public:
  struct Params {
    double radius = 0.0;            // R [m], > 0
    double gap = 0.0;               // H [m], > 0
    int radial_cells = 1;           // N_r, >= 1
    int azimuthal_cells = 1;        // N_θ, >= 1; 1 = axisymmetric
    int axial_cells = 1;            // N_z, >= 1
    double radial_grading = 1.0;    // Δr_last/Δr_first, > 0; 1 = uniform
    double axial_stretching = 0.0;  // β of the tanh clustering towards both plates, >= 0; 0 = uniform
  };

  // Throws std::invalid_argument naming the parameter and its valid range.
  explicit CylindricalGrid(Params params);

  [[nodiscard]] const Params& params() const { return params_; }
  [[nodiscard]] std::size_t radial_cells() const { return radial_centres_.size(); }
  [[nodiscard]] std::size_t azimuthal_cells() const { return azimuthal_centres_.size(); }
  [[nodiscard]] std::size_t axial_cells() const { return axial_centres_.size(); }
  [[nodiscard]] std::size_t cell_count() const { return radial_cells() * azimuthal_cells() * axial_cells(); }
  [[nodiscard]] bool is_axisymmetric() const { return azimuthal_cells() == 1; }

  // Face coordinates (N+1 values, first 0, last R, 2π or H) and centre coordinates (N values).
  [[nodiscard]] std::span<const double> radial_faces() const { return radial_faces_; }        // r_i [m]
  [[nodiscard]] std::span<const double> radial_centres() const { return radial_centres_; }    // [m]
  [[nodiscard]] std::span<const double> azimuthal_faces() const { return azimuthal_faces_; }  // θ_j [rad]
  [[nodiscard]] std::span<const double> azimuthal_centres() const { return azimuthal_centres_; }
  [[nodiscard]] std::span<const double> axial_faces() const { return axial_faces_; }  // z_k [m]
  [[nodiscard]] std::span<const double> axial_centres() const { return axial_centres_; }

  [[nodiscard]] double radial_width(std::size_t i) const { return radial_faces_[i + 1] - radial_faces_[i]; }
  [[nodiscard]] double azimuthal_width() const { return dtheta_; }  // Δθ [rad]
  [[nodiscard]] double axial_width(std::size_t k) const { return axial_faces_[k + 1] - axial_faces_[k]; }

  // Geometry of cell (i, ·, k); nothing depends on the azimuthal index j.
  [[nodiscard]] double cell_volume(std::size_t i, std::size_t k) const;  // [m³]
  // Area of the radial face at r = r_i, i in [0, N_r]; 0 on the axis (i = 0).
  [[nodiscard]] double radial_face_area(std::size_t i, std::size_t k) const;  // [m²]
  // Area of a θ = const face of cell (i, ·, k).
  [[nodiscard]] double azimuthal_face_area(std::size_t i, std::size_t k) const;  // [m²]
  // Area of a z = const face over radial cell i (the same at every z).
  [[nodiscard]] double axial_face_area(std::size_t i) const;  // [m²]
  // The radial face i = 0 is the axis, a degenerate face of zero area.
  [[nodiscard]] static bool is_axis_face(std::size_t i) { return i == 0; }
  [[nodiscard]] bool is_axially_uniform() const { return params_.axial_stretching == 0.0; }

 private:
  Params params_;
  double dtheta_ = 0.0;
  std::vector<double> radial_faces_, radial_centres_;
  std::vector<double> azimuthal_faces_, azimuthal_centres_;
  std::vector<double> axial_faces_, axial_centres_;
};

}  // namespace rheosim::fluid
