#pragma once
// The transient solver's staggered cylindrical grid (index maps, metric integrals), its fields
// and the kinematic boundary values. Private to fluid/src/transient*.cpp.
#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "rheosim/fluid/grid.hpp"
#include "rheosim/numerics/quadrature.hpp"

namespace rheosim::fluid::transient_detail {

constexpr double pi = std::numbers::pi;
constexpr double max_step_ratio = 2.0;  // Δt/Δt_prev above which a step falls back to BDF1

// 3-point Gauss–Legendre on [-1, 1], as in SwirlSolver: ∫ μ r³ dr over an axial face is exact
// for a Newtonian fluid and the torque matches the steady solver's on the same (r, z) grid.
constexpr auto gauss_nodes = numerics::GaussLegendre<3>::nodes;
constexpr auto gauss_weights = numerics::GaussLegendre<3>::weights;

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;
using Factor = Eigen::SimplicialLDLT<SparseMatrix>;

// Geometry of the staggered grid and the index maps of every staggered array.
//   cells and u_θ (faces θ_j at r_c,i):                  (i·N_θ + j)·N_z + k
//   u_r (i = 0..N_r) and rθ-edges (r_i, θ_j, z_c,k):     (i·N_θ + j)·N_z + k
//   u_z (k = 0..N_z) and θz-edges (r_c,i, θ_j, z_k):      (i·N_θ + j)·(N_z + 1) + k
//   rz-edges (r_i, θ_c,j, z_k), i = 0..N_r, k = 0..N_z:   (i·N_θ + j)·(N_z + 1) + k
struct Geometry {
  std::size_t nr, nt, nz, nc;
  double dth;
  std::vector<double> rf, rc, zf, zc, dr, dz;
  std::vector<double> drc;   // [nr+1]: r_c,i − r_c,i−1 for interior radial faces i
  std::vector<double> dzc;   // [nz+1]: z_c,k − z_c,k−1 inside, half cells at the plates
  std::vector<double> a1;    // ∫ r dr over radial cell i (= r_c Δr)
  std::vector<double> r3;    // ∫ r² dr
  std::vector<double> r4;    // ∫ r³ dr
  std::vector<double> reff;  // r_eff = ∫r³dr / (r_c ∫r dr): θ-gradient length of the u_θ correction
  std::vector<double> theta_c, cos_c, sin_c;

  explicit Geometry(const CylindricalGrid& g)
      : nr(g.radial_cells()),
        nt(g.azimuthal_cells()),
        nz(g.axial_cells()),
        nc(g.cell_count()),
        dth(g.azimuthal_width()),
        rf(g.radial_faces().begin(), g.radial_faces().end()),
        rc(g.radial_centres().begin(), g.radial_centres().end()),
        zf(g.axial_faces().begin(), g.axial_faces().end()),
        zc(g.axial_centres().begin(), g.axial_centres().end()) {
    dr.resize(nr);
    a1.resize(nr);
    r3.resize(nr);
    r4.resize(nr);
    reff.resize(nr);
    for (std::size_t i = 0; i < nr; ++i) {
      dr[i] = rf[i + 1] - rf[i];
      a1[i] = rc[i] * dr[i];
      r3[i] = (std::pow(rf[i + 1], 3) - std::pow(rf[i], 3)) / 3.0;
      r4[i] = 0.25 * (std::pow(rf[i + 1], 4) - std::pow(rf[i], 4));
      reff[i] = r4[i] / (rc[i] * a1[i]);
    }
    drc.assign(nr + 1, 0.0);
    for (std::size_t i = 1; i < nr; ++i) drc[i] = rc[i] - rc[i - 1];
    dz.resize(nz);
    for (std::size_t k = 0; k < nz; ++k) dz[k] = zf[k + 1] - zf[k];
    dzc.resize(nz + 1);
    dzc[0] = zc[0] - zf[0];
    dzc[nz] = zf[nz] - zc[nz - 1];
    for (std::size_t k = 1; k < nz; ++k) dzc[k] = zc[k] - zc[k - 1];
    theta_c.assign(g.azimuthal_centres().begin(), g.azimuthal_centres().end());
    for (double t : theta_c) {
      cos_c.push_back(std::cos(t));
      sin_c.push_back(std::sin(t));
    }
  }

  std::size_t cell(std::size_t i, std::size_t j, std::size_t k) const { return (i * nt + j) * nz + k; }
  std::size_t ur(std::size_t i, std::size_t j, std::size_t k) const { return (i * nt + j) * nz + k; }
  std::size_t uz(std::size_t i, std::size_t j, std::size_t k) const { return (i * nt + j) * (nz + 1) + k; }
  std::size_t jm(std::size_t j) const { return (j + nt - 1) % nt; }
  std::size_t jp(std::size_t j) const { return (j + 1) % nt; }
  std::size_t n_ur() const { return (nr + 1) * nt * nz; }
  std::size_t n_uz() const { return nr * nt * (nz + 1); }
  std::size_t n_rz() const { return (nr + 1) * nt * (nz + 1); }
  // Unknowns of the predictor systems: interior u_r faces and interior u_z faces.
  std::size_t row_r(std::size_t i, std::size_t j, std::size_t k) const { return ((i - 1) * nt + j) * nz + k; }
  std::size_t row_z(std::size_t i, std::size_t j, std::size_t k) const { return (i * nt + j) * (nz - 1) + k - 1; }
  std::size_t rows_r() const { return (nr - 1) * nt * nz; }
  std::size_t rows_z() const { return nr * nt * (nz - 1); }
  double volume(std::size_t i, std::size_t k) const { return a1[i] * dth * dz[k]; }
};

struct Velocity {
  std::vector<double> ur, ut, uz;  // u_r (with the axis value at i = 0), u_θ, u_z
};

struct ViscosityField {
  std::vector<double> centre, shear_rate;  // cells
  std::vector<double> rt;                  // rθ-edges, ur(i, j, k) index
  std::vector<double> tz_moment;           // W = ∫ μ r³ dr on θz-edges, uz index
  std::vector<double> tz;                  // W / ∫ r³ dr, a representative μ on θz-edges
  std::vector<double> wall_rz;             // μ on the rz-edges of the plates: (side·(N_r+1) + i)·N_θ + j
};

struct CellFields {  // per-cell ε-like scalar helpers
  static double face_r(const std::vector<double>& e, const Geometry& g, std::size_t i, std::size_t j, std::size_t k) {
    return 0.5 * (e[g.cell(i - 1, j, k)] + e[g.cell(i, j, k)]);
  }
  static double face_t(const std::vector<double>& e, const Geometry& g, std::size_t i, std::size_t j, std::size_t k) {
    return 0.5 * (e[g.cell(i, g.jm(j), k)] + e[g.cell(i, j, k)]);
  }
  static double face_z(const std::vector<double>& e, const Geometry& g, std::size_t i, std::size_t j, std::size_t k) {
    return 0.5 * (e[g.cell(i, j, k - 1)] + e[g.cell(i, j, k)]);
  }
};

// Cartesian velocity (U_x, U_y) on the axis at height z_c,k from the first interior ring of u_r:
// its θ-mode 1 for N_θ >= 3, the half-difference of the two opposite faces for N_θ = 2.
inline std::pair<double, double> axis_velocity(const Geometry& g, const std::vector<double>& ur, std::size_t k) {
  if (g.nt == 1) return {0.0, 0.0};
  if (g.nt == 2) return {0.0, 0.5 * (ur[g.ur(1, 0, k)] - ur[g.ur(1, 1, k)])};  // θ_c = π/2, 3π/2
  double ux = 0, uy = 0;
  for (std::size_t j = 0; j < g.nt; ++j) {
    ux += ur[g.ur(1, j, k)] * g.cos_c[j];
    uy += ur[g.ur(1, j, k)] * g.sin_c[j];
  }
  const double scale = 2.0 / static_cast<double>(g.nt);
  return {scale * ux, scale * uy};
}

// Imposes the kinematic boundary values: u_r on the axis (Cartesian extrapolation), u_r = 0 on
// the rim, u_z = 0 on the plates.
inline void impose_boundary_values(const Geometry& g, Velocity& v) {
  for (std::size_t k = 0; k < g.nz; ++k) {
    const auto [ux, uy] = axis_velocity(g, v.ur, k);
    for (std::size_t j = 0; j < g.nt; ++j) {
      v.ur[g.ur(0, j, k)] = ux * g.cos_c[j] + uy * g.sin_c[j];
      v.ur[g.ur(g.nr, j, k)] = 0.0;
    }
  }
  for (std::size_t i = 0; i < g.nr; ++i)
    for (std::size_t j = 0; j < g.nt; ++j) {
      v.uz[g.uz(i, j, 0)] = 0.0;
      v.uz[g.uz(i, j, g.nz)] = 0.0;
    }
}

inline double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

inline bool all_finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

}  // namespace rheosim::fluid::transient_detail
