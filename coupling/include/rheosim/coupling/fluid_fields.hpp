#pragma once
// Cell-centred fluid fields the particle forces need (CD eqs. 30–35), computed from a
// fluid::TransientSolver state once per coupling step: the velocity, the pressure gradient ∇p and
// the stress divergence ∇·τ, in cylindrical components (r, θ, z) at the cell centres, and the
// apparent viscosity μ(γ̇) of the generalized-Newtonian law (the solver's own cell values).
//
// Discretisation (second order inside, first order at the walls):
//   - velocity: the staggered components averaged to the centre;
//   - ∇p: central differences in r, θ and z (non-uniform r), one-sided in the first/last cell of
//     each direction; the θ term is 0 for N_θ <= 2;
//   - ∇·τ = μ ∇²u + 2 E·∇μ, the divergence of τ = 2μE for ∇·u = 0 (CD eq. 28 without the
//     −(2/3)∇·u term, which only ∂ε/∂t makes nonzero). ∇²u is the cylindrical vector Laplacian
//     (∇²u_r − u_r/r² − (2/r²)∂_θu_θ, ∇²u_θ − u_θ/r² + (2/r²)∂_θu_r, ∇²u_z) with a finite-volume
//     scalar Laplacian: no flux through the axis, periodic in θ, the plates' Dirichlet values
//     (u_θ = Ω r, u_r = u_z = 0) at half a cell, and at the shear-free rim u_r = 0,
//     ∂_ru_z = 0 and ∂_r(u_θ/r) = 0. E·∇μ is skipped when μ is uniform (Newtonian).
// Time filter on ∇p (set_pressure_gradient_filter): the projection pressure also answers ∂ε/∂t,
// the grid-scale flow a particle displaces as it crosses a cell face. Fed back explicitly as
// −V_p∇p on the next coupling interval, that answer is an added-mass-like loop whose gain exceeds
// 1 for neutrally buoyant particles in cells not much larger than them: at φ = 0.3 on the 3 mm
// disk the Courant number grew from 1e-4 to 0.5 in 60 steps with ∇p and ran 4 000 steps calm
// without it. An exponential moving average over a time constant τ (a few fluid steps, far
// below the flow's 1/γ̇) keeps the mean-flow gradient (centripetal, hydrostatic, exact at steady
// state) and removes that high-frequency part.
// For the linear Couette profile u_θ = Ωrz/H, ∇·τ vanishes to the truncation error of the θ
// differences (test_fluid_fields).
#include <array>
#include <span>
#include <vector>

#include "rheosim/fluid/grid.hpp"
#include "rheosim/fluid/transient.hpp"

namespace rheosim::coupling {

// A cell-centred vector field in cylindrical components.
struct CellVectorField {
  std::vector<double> radial, azimuthal, axial;
  void resize(std::size_t n) {
    radial.assign(n, 0.0);
    azimuthal.assign(n, 0.0);
    axial.assign(n, 0.0);
  }
};

class FluidCellFields {
 public:
  explicit FluidCellFields(const fluid::CylindricalGrid& grid);

  // Recomputes every field from the solver's current state.
  void update(const fluid::TransientSolver& solver);
  // Time constant τ [s] of the ∇p filter (header comment); 0 (the default) = no filter.
  // Throws std::invalid_argument unless τ is finite and >= 0.
  void set_pressure_gradient_filter(double time_constant);

  [[nodiscard]] const CellVectorField& velocity() const { return velocity_; }                    // [m/s]
  [[nodiscard]] const CellVectorField& pressure_gradient() const { return pressure_gradient_; }  // [Pa/m]
  [[nodiscard]] const CellVectorField& stress_divergence() const { return stress_divergence_; }  // [N/m³]
  [[nodiscard]] std::span<const double> viscosity() const { return viscosity_; }                 // [Pa·s]

  // Building blocks, public for tests: cell-centred gradient (∂_r f, (1/r)∂_θ f, ∂_z f) of a cell
  // scalar, and the cylindrical vector Laplacian of a cell-centred velocity field with plate
  // angular velocities Ω_bottom, Ω_top.
  void gradient(std::span<const double> f, CellVectorField& out) const;
  void vector_laplacian(const CellVectorField& u, double bottom_angular_velocity, double top_angular_velocity,
                        CellVectorField& out) const;

 private:
  [[nodiscard]] std::size_t index(std::size_t i, std::size_t j, std::size_t k) const {
    return (i * n_theta_ + j) * n_z_ + k;
  }
  enum class Rim { zero_gradient, zero_value, rigid_rotation };
  void scalar_laplacian(std::span<const double> f, Rim rim, std::span<const double> bottom_wall,
                        std::span<const double> top_wall, std::vector<double>& out) const;

  const fluid::CylindricalGrid* grid_;
  std::size_t n_r_, n_theta_, n_z_;
  CellVectorField velocity_, pressure_gradient_, stress_divergence_;
  double filter_time_constant_ = 0.0;
  double last_update_time_ = 0.0;
  bool has_pressure_gradient_ = false;
  std::vector<double> viscosity_;
  // Scratch
  CellVectorField laplacian_, grad_a_, grad_b_, grad_c_, grad_mu_;
};

}  // namespace rheosim::coupling
