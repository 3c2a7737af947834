#pragma once
// The swirl solver's finite-volume discretisation on the axisymmetric (r, z) grid: the unknown
// numbering (Layout), μ on cells and faces (ViscosityField) and the assembly of the linearised
// momentum and continuity system with its residual (Discretisation). Private to swirl.cpp.
#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <vector>

#include "rheosim/fluid/swirl.hpp"
#include "rheosim/numerics/quadrature.hpp"

namespace rheosim::fluid::swirl_detail {

// 3-point Gauss–Legendre on [-1, 1]: exact for polynomials of degree 5, so ∫ μ r³ dr over a
// face is exact for Newtonian fluids and very accurate for smooth μ(r).
constexpr auto gauss_nodes = numerics::GaussLegendre<3>::nodes;
constexpr auto gauss_weights = numerics::GaussLegendre<3>::weights;

using Triplets = std::vector<Eigen::Triplet<double>>;

// Geometry and unknown numbering of the (r, z) grid.
struct Layout {
  std::size_t nr, nz, nc;
  std::vector<double> rf, rc, zf, zc;
  bool inertia;

  Layout(const CylindricalGrid& g, bool with_inertia)
      : nr(g.radial_cells()),
        nz(g.axial_cells()),
        nc(nr * nz),
        rf(g.radial_faces().begin(), g.radial_faces().end()),
        rc(g.radial_centres().begin(), g.radial_centres().end()),
        zf(g.axial_faces().begin(), g.axial_faces().end()),
        zc(g.axial_centres().begin(), g.axial_centres().end()),
        inertia(with_inertia) {
    if (nz >= 2) {
      bottom_plate = one_sided_plate_stencil(false);
      top_plate = one_sided_plate_stencil(true);
    }
  }

  std::size_t cell(std::size_t i, std::size_t k) const { return i * nz + k; }
  // Unknowns: ω, then (with inertia) p, interior u_r faces, interior u_z faces.
  std::size_t omega(std::size_t i, std::size_t k) const { return cell(i, k); }
  std::size_t pressure(std::size_t i, std::size_t k) const { return nc + cell(i, k); }
  std::size_t radial(std::size_t i, std::size_t k) const { return 2 * nc + (i - 1) * nz + k; }  // i in [1, nr-1]
  std::size_t axial(std::size_t i, std::size_t k) const {                                       // k in [1, nz-1]
    return 2 * nc + (nr - 1) * nz + i * (nz - 1) + (k - 1);
  }
  std::size_t unknowns() const { return inertia ? 2 * nc + (nr - 1) * nz + nr * (nz - 1) : nc; }

  double dr(std::size_t i) const { return rf[i + 1] - rf[i]; }
  double dz(std::size_t k) const { return zf[k + 1] - zf[k]; }
  // Distance between the centres either side of radial face i / axial face k (walls: half cell).
  double dr_centres(std::size_t i) const { return rc[i] - rc[i - 1]; }
  double dz_centres(std::size_t k) const {
    if (k == 0) return zc[0] - zf[0];
    if (k == nz) return zf[nz] - zc[nz - 1];
    return zc[k] - zc[k - 1];
  }
  double axial_area(std::size_t i) const { return 0.5 * (rf[i + 1] * rf[i + 1] - rf[i] * rf[i]); }  // per radian
  double r4_moment(std::size_t i) const { return 0.25 * (std::pow(rf[i + 1], 4) - std::pow(rf[i], 4)); }
  std::size_t ur_index(std::size_t i, std::size_t k) const { return i * nz + k; }        // faces i = 0..nr
  std::size_t uz_index(std::size_t i, std::size_t k) const { return i * (nz + 1) + k; }  // faces k = 0..nz

  // Second-order one-sided ∂φ/∂z at a plate: the quadratic through the wall value and the two
  // nearest cell centres, ∂φ/∂z ≈ wall·φ_w + near·φ_near + far·φ_far, for any cell widths (a
  // stretched axial grid). Uniform cells of height h give (8φ_w − 9φ₀ + φ₁)/(3h) (sign by side).
  struct PlateStencil {
    std::size_t near_cell = 0, far_cell = 0;  // k of the wall cell and of its neighbour
    double wall = 0, near = 0, far = 0;       // [1/m]
    double gradient(double at_wall, double at_near, double at_far) const {
      return wall * at_wall + near * at_near + far * at_far;
    }
  };
  PlateStencil bottom_plate, top_plate;  // set when nz >= 2
  const PlateStencil& plate(std::size_t k) const { return k == 0 ? bottom_plate : top_plate; }

 private:
  PlateStencil one_sided_plate_stencil(bool top) const {
    // d1, d2: distances of the two centres from the plate; φ(d) = φ_w + a d + b d² through both.
    const double d1 = top ? zf[nz] - zc[nz - 1] : zc[0] - zf[0];
    const double d2 = top ? zf[nz] - zc[nz - 2] : zc[1] - zf[0];
    const double near = d2 / (d1 * (d2 - d1)), far = -d1 / (d2 * (d2 - d1));
    const double along_z = top ? -1.0 : 1.0;  // d runs against z from the top plate
    return {top ? nz - 1 : 0, top ? nz - 2 : 1, -along_z * (near + far), along_z * near, along_z * far};
  }
};

// Velocity gradients and the viscosity they imply, for one iterate.
struct ViscosityField {
  std::vector<double> centre;      // μ at cell centres
  std::vector<double> axial_flux;  // W = ∫ μ r³ dr over each axial face (i * (nz+1) + k)
  std::vector<double> radial;      // μ at radial faces (i * nz + k), i = 0..nr
  std::vector<double> shear_rate;  // γ̇ at cell centres
  // Newton terms: dW/dg on axial faces and d(r³μ)/dg on radial faces, g the face-normal
  // gradient of ω (the dependence on the other gradients is left to the outer iteration).
  std::vector<double> axial_flux_slope;
  std::vector<double> radial_slope;
  // μ at the plate corners (radial face i, bottom: [i], top: [nr + 1 + i]) from the wall shear
  // rate, for τ_rz at the plates.
  std::vector<double> wall_corner;
};

class Discretisation {
 public:
  Discretisation(const Layout& layout, const SwirlParams& params, double top_angular_velocity,
                 std::span<const double> void_fraction_field)
      : L(layout), p(params), omega_top(top_angular_velocity), eps(void_fraction_field) {}

  double void_fraction(std::size_t c) const { return eps.empty() ? 1.0 : eps[c]; }

  // ∂ω/∂z on axial face (i, k) and ∂ω/∂r on radial face (i, k) from cell values.
  double domega_dz(const SwirlState& s, std::size_t i, std::size_t k) const {
    const double below = k == 0 ? 0.0 : s.angular_velocity[L.cell(i, k - 1)];
    const double above = k == L.nz ? omega_top : s.angular_velocity[L.cell(i, k)];
    return (above - below) / L.dz_centres(k);
  }
  double domega_dr(const SwirlState& s, std::size_t i, std::size_t k) const {
    if (i == 0 || i == L.nr) return 0.0;  // axis symmetry; shear-free rim
    return (s.angular_velocity[L.cell(i, k)] - s.angular_velocity[L.cell(i - 1, k)]) / L.dr_centres(i);
  }
  // The same, second-order at the plates (quadratic through the wall value and two cells),
  // for evaluating μ: the half-cell difference is first-order there, which is harmless in
  // the conservative flux but would make μ at the wall, and so the torque, first-order.
  // Creeping runs keep the half-cell form: it is exact for their linear profile and keeps the
  // Newton linearisation consistent, which the hardest yield-stress cases need.
  double domega_dz_for_viscosity(const SwirlState& s, std::size_t i, std::size_t k) const {
    if ((k != 0 && k != L.nz) || L.nz < 2 || !L.inertia) return domega_dz(s, i, k);
    const auto& plate = L.plate(k);
    return plate.gradient(k == 0 ? 0.0 : omega_top, s.angular_velocity[L.cell(i, plate.near_cell)],
                          s.angular_velocity[L.cell(i, plate.far_cell)]);
  }
  double corner_shear_for_viscosity(const SwirlState& s, std::size_t i, std::size_t k) const {
    if ((k != 0 && k != L.nz) || L.nz < 2 || i == 0 || i == L.nr) return corner_shear(s, i, k);
    const auto& plate = L.plate(k);  // u_r = 0 on both plates
    return plate.gradient(0.0, s.radial_velocity[L.ur_index(i, plate.near_cell)],
                          s.radial_velocity[L.ur_index(i, plate.far_cell)]);
  }

  // Engineering shear strain rate ∂u_r/∂z + ∂u_z/∂r at corner (radial face i, axial face k).
  double corner_shear(const SwirlState& s, std::size_t i, std::size_t k) const {
    if (i == 0 || i == L.nr) return 0.0;  // u_r = 0 on axis and rim; shear-free rim
    double dur_dz = 0;
    if (k == 0)
      dur_dz = s.radial_velocity[L.ur_index(i, 0)] / L.dz_centres(0);
    else if (k == L.nz)
      dur_dz = -s.radial_velocity[L.ur_index(i, L.nz - 1)] / L.dz_centres(L.nz);
    else
      dur_dz = (s.radial_velocity[L.ur_index(i, k)] - s.radial_velocity[L.ur_index(i, k - 1)]) / L.dz_centres(k);
    double duz_dr = 0;
    if (k != 0 && k != L.nz)
      duz_dr = (s.axial_velocity[L.uz_index(i, k)] - s.axial_velocity[L.uz_index(i - 1, k)]) / L.dr_centres(i);
    return dur_dz + duz_dr;
  }

  // γ̇² = r²|∇ω|² + S, S from the secondary flow (u_r, u_z); LDD eq. 5 in cylindrical form.
  ViscosityField viscosity(const SwirlState& s) const {
    const std::size_t nr = L.nr, nz = L.nz;
    std::vector<double> omega_grad2(L.nc), secondary(L.nc);
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t k = 0; k < nz; ++k) {
        const double gz_lo = domega_dz_for_viscosity(s, i, k), gz_hi = domega_dz_for_viscosity(s, i, k + 1);
        const double gr_lo = domega_dr(s, i, k), gr_hi = domega_dr(s, i + 1, k);
        omega_grad2[L.cell(i, k)] = 0.5 * (gz_lo * gz_lo + gz_hi * gz_hi + gr_lo * gr_lo + gr_hi * gr_hi);
        double sec = 0;
        if (L.inertia) {
          const double ur_w = s.radial_velocity[L.ur_index(i, k)], ur_e = s.radial_velocity[L.ur_index(i + 1, k)];
          const double uz_b = s.axial_velocity[L.uz_index(i, k)], uz_t = s.axial_velocity[L.uz_index(i, k + 1)];
          const double drr = (ur_e - ur_w) / L.dr(i), hoop = 0.5 * (ur_e + ur_w) / L.rc[i],
                       dzz = (uz_t - uz_b) / L.dz(k);
          double shear2 = 0;
          for (std::size_t a : {i, i + 1})
            for (std::size_t b : {k, k + 1}) {
              const double g = corner_shear_for_viscosity(s, a, b);
              shear2 += 0.25 * g * g;
            }
          sec = 2.0 * (drr * drr + hoop * hoop + dzz * dzz) + shear2;
        }
        secondary[L.cell(i, k)] = sec;
      }

    // All shear rates into one array: one virtual viscosity call for the whole field.
    const std::size_t n_axial = nr * (nz + 1);
    const std::size_t n_radial = (nr + 1) * nz;
    std::vector<double> rates(L.nc + 3 * n_axial + n_radial);
    for (std::size_t c = 0; c < L.nc; ++c) {
      const std::size_t i = c / nz;
      rates[c] = std::sqrt(L.rc[i] * L.rc[i] * omega_grad2[c] + secondary[c]);
    }
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t k = 0; k <= nz; ++k) {
        const double gz = domega_dz_for_viscosity(s, i, k);
        // Radial gradient and secondary part: mean of the adjacent cells; at a plate the
        // secondary part is the wall shear alone (u = 0 and, by continuity, ∂_z u_z = 0 there).
        double gr2 = 0, sec = 0, n = 0;
        for (std::size_t kk : {k - 1, k}) {
          if (kk >= nz) continue;  // k - 1 wraps at k = 0
          const double a = domega_dr(s, i, kk), b = domega_dr(s, i + 1, kk);
          gr2 += 0.5 * (a * a + b * b);
          sec += secondary[L.cell(i, kk)];
          n += 1;
        }
        gr2 /= n;
        sec /= n;
        if (L.inertia && (k == 0 || k == nz)) {
          const double a = corner_shear_for_viscosity(s, i, k), b = corner_shear_for_viscosity(s, i + 1, k);
          sec = 0.5 * (a * a + b * b);
        }
        const double mid = 0.5 * (L.rf[i] + L.rf[i + 1]), half = 0.5 * L.dr(i);
        for (std::size_t q = 0; q < 3; ++q) {
          const double r = mid + half * gauss_nodes[q];
          rates[L.nc + 3 * (i * (nz + 1) + k) + q] = std::sqrt(r * r * (gz * gz + gr2) + sec);
        }
      }
    const std::size_t radial_offset = L.nc + 3 * n_axial;
    for (std::size_t i = 0; i <= nr; ++i)
      for (std::size_t k = 0; k < nz; ++k) {
        const double gr = domega_dr(s, i, k);
        double gz2 = 0, sec = 0, n = 0;
        for (std::size_t ii : {i - 1, i}) {
          if (ii >= nr) continue;
          const double a = domega_dz_for_viscosity(s, ii, k), b = domega_dz_for_viscosity(s, ii, k + 1);
          gz2 += 0.5 * (a * a + b * b);
          sec += secondary[L.cell(ii, k)];
          n += 1;
        }
        const double r = L.rf[i];
        rates[radial_offset + i * nz + k] = std::sqrt(r * r * (gr * gr + gz2 / n) + sec / n);
      }

    std::vector<double> mu(rates.size()), dmu(rates.size());
    p.rheology->viscosity(rates, mu);
    p.rheology->viscosity_derivative(rates, dmu);

    ViscosityField out;
    out.centre.assign(mu.begin(), mu.begin() + static_cast<std::ptrdiff_t>(L.nc));
    out.shear_rate.assign(rates.begin(), rates.begin() + static_cast<std::ptrdiff_t>(L.nc));
    out.axial_flux.resize(n_axial);
    out.axial_flux_slope.resize(n_axial);
    for (std::size_t i = 0; i < nr; ++i) {
      const double mid = 0.5 * (L.rf[i] + L.rf[i + 1]), half = 0.5 * L.dr(i);
      for (std::size_t k = 0; k <= nz; ++k) {
        const double g = domega_dz_for_viscosity(s, i, k);
        double w = 0, slope = 0;
        for (std::size_t q = 0; q < 3; ++q) {
          const double r = mid + half * gauss_nodes[q];
          const std::size_t j = L.nc + 3 * (i * (nz + 1) + k) + q;
          w += gauss_weights[q] * mu[j] * r * r * r;
          // dγ̇/dg = r² g / γ̇ (γ̇² = r²(g² + …) + S)
          if (rates[j] > 0) slope += gauss_weights[q] * dmu[j] * r * r * g / rates[j] * r * r * r;
        }
        out.axial_flux[i * (nz + 1) + k] = w * half;
        out.axial_flux_slope[i * (nz + 1) + k] = slope * half;
      }
    }
    out.wall_corner.assign(2 * (nr + 1), 0.0);
    if (L.inertia) {
      std::vector<double> wall_rates(2 * (nr + 1));
      for (std::size_t side = 0; side < 2; ++side) {
        const std::size_t k = side == 0 ? 0 : nz;
        for (std::size_t i = 0; i <= nr; ++i) {
          double g = 0, n = 0;
          for (std::size_t ii : {i - 1, i})
            if (ii < nr) {
              g += domega_dz_for_viscosity(s, ii, k);
              n += 1;
            }
          g /= n;
          const double shear = corner_shear_for_viscosity(s, i, k);
          wall_rates[side * (nr + 1) + i] = std::sqrt(L.rf[i] * L.rf[i] * g * g + shear * shear);
        }
      }
      p.rheology->viscosity(wall_rates, out.wall_corner);
    }
    out.radial.assign(mu.begin() + static_cast<std::ptrdiff_t>(radial_offset), mu.end());
    out.radial_slope.assign(out.radial.size(), 0.0);
    for (std::size_t i = 1; i < nr; ++i)
      for (std::size_t k = 0; k < nz; ++k) {
        const std::size_t j = radial_offset + i * nz + k;
        const double r = L.rf[i], g = domega_dr(s, i, k);
        if (rates[j] > 0) out.radial_slope[i * nz + k] = dmu[j] * r * r * g / rates[j];
      }
    return out;
  }

  // Assembles the Picard-linearised system around iterate `s` with viscosity `mu`.
  void assemble(const SwirlState& s, const ViscosityField& mu, std::span<const double> torque_density,
                double pseudo_time_step, Triplets& t, Eigen::VectorXd& rhs) const {
    t.clear();
    rhs.setZero(static_cast<Eigen::Index>(L.unknowns()));
    assemble_angular(s, mu, torque_density, t, rhs);
    if (L.inertia) {
      assemble_radial(s, mu, t, rhs);
      assemble_axial(s, mu, t, rhs);
      assemble_continuity(t);
      if (std::isfinite(pseudo_time_step)) add_pseudo_time(s, pseudo_time_step, t, rhs);
    }
  }

  // Pseudo-transient continuation: ρ V (x − x*)/Δτ in every momentum row makes each Picard
  // step an implicit Euler step in pseudo-time, which damps the large-Re iterations; Δτ grows
  // as the residual falls and the term is dropped near convergence, so the steady solution
  // is unchanged.
  void add_pseudo_time(const SwirlState& s, double dtau, Triplets& t, Eigen::VectorXd& rhs) const {
    const double rho = p.density;
    const auto add = [&](std::size_t row, double mass, double old_value) {
      const double c = rho * mass / dtau;
      t.emplace_back(row, row, -c);
      rhs[static_cast<Eigen::Index>(row)] -= c * old_value;
    };
    for (std::size_t i = 0; i < L.nr; ++i)
      for (std::size_t k = 0; k < L.nz; ++k)
        add(L.omega(i, k), L.r4_moment(i) * L.dz(k), s.angular_velocity[L.cell(i, k)]);
    for (std::size_t i = 1; i < L.nr; ++i)
      for (std::size_t k = 0; k < L.nz; ++k)
        add(L.radial(i, k), L.rf[i] * L.dr_centres(i) * L.dz(k), s.radial_velocity[L.ur_index(i, k)]);
    for (std::size_t i = 0; i < L.nr; ++i)
      for (std::size_t k = 1; k < L.nz; ++k)
        add(L.axial(i, k), L.rc[i] * L.dr(i) * L.dz_centres(k), s.axial_velocity[L.uz_index(i, k)]);
  }

  // Whether the plate gradients of ω and u_r are the second-order one-sided ones (with
  // inertia) rather than half-cell differences (creeping: exact for the linear profile).
  bool wall_gradient_is_one_sided() const { return L.inertia && L.nz >= 2 && p.one_sided_plate_gradients; }

  // Torque transmitted through the top (or bottom) plate, 2π Σ ∫ r² τ_θz dr [N·m]: the
  // plate fluxes exactly as assembled, so top and bottom balance at convergence.
  double wall_torque(const SwirlState& s, const ViscosityField& mu, bool top) const {
    const std::size_t k = top ? L.nz : 0;
    double per_radian = 0;
    for (std::size_t i = 0; i < L.nr; ++i)
      per_radian += mu.axial_flux[i * (L.nz + 1) + k] *
                    (wall_gradient_is_one_sided() ? domega_dz_for_viscosity(s, i, k) : domega_dz(s, i, k));
    return 2.0 * std::acos(-1.0) * per_radian;
  }

 private:
  const Layout& L;
  const SwirlParams& p;
  double omega_top;
  double newton = 1.0;  // 1: Newton terms of the viscous flux on; 0: plain Picard
  std::span<const double> eps;

  double face_eps_r(std::size_t i, std::size_t k) const {
    return 0.5 * (void_fraction(L.cell(i - 1, k)) + void_fraction(L.cell(i, k)));
  }
  double face_eps_z(std::size_t i, std::size_t k) const {
    return 0.5 * (void_fraction(L.cell(i, k - 1)) + void_fraction(L.cell(i, k)));
  }
  // Newton part of a convective flux −ρ ṁ φ_f: the Picard terms hold ṁ* φ_f; this adds
  // ṁ(u) φ_f* − ṁ* φ_f*, so the quadratic term is linearised exactly (quadratic convergence
  // near the solution instead of the lagged-flux iteration's slow linear one at high Re).
  using Sensitivities = std::vector<std::pair<std::size_t, double>>;  // (unknown, ∂ṁ/∂unknown)
  void newton_flux(Triplets& t, Eigen::VectorXd& rhs, std::size_t row, double mdot, double phi_face,
                   const Sensitivities& dmdot) const {
    const double rho = p.density;
    for (const auto& [unknown, d] : dmdot) t.emplace_back(row, unknown, -rho * d * phi_face);
    rhs[static_cast<Eigen::Index>(row)] -= rho * mdot * phi_face;
  }
  double ur(const SwirlState& s, std::size_t i, std::size_t k) const { return s.radial_velocity[L.ur_index(i, k)]; }
  double uz(const SwirlState& s, std::size_t i, std::size_t k) const { return s.axial_velocity[L.uz_index(i, k)]; }

  // Angular momentum: ε r[∇·τ]_θ − ρ∇·(ε u L) + r f_θ = 0, L = r²ω (CD eq. 27, θ part).
  void assemble_angular(const SwirlState& s, const ViscosityField& mu, std::span<const double> torque_density,
                        Triplets& t, Eigen::VectorXd& rhs) const {
    const std::size_t nr = L.nr, nz = L.nz;
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t k = 0; k < nz; ++k) {
        const std::size_t row = L.omega(i, k);
        const double e = void_fraction(L.cell(i, k));
        double diag = 0;
        // Radial faces: angular-momentum flux r³ μ ∂_rω Δz (none through axis and rim).
        // Newton-linearised face flux: F(g) ≈ J g − g*² dW/dg with J = W + g* dW/dg.
        double constant = 0;  // of the row, moved to the right-hand side
        for (std::size_t f : {i, i + 1}) {
          if (f == 0 || f == nr) continue;
          const double geometry = e * std::pow(L.rf[f], 3) * L.dz(k);
          const double g_star = domega_dr(s, f, k), slope = mu.radial_slope[f * nz + k];
          const double coef = geometry * (mu.radial[f * nz + k] + newton * g_star * slope) / L.dr_centres(f);
          const std::size_t other = f == i ? i - 1 : i + 1;
          t.emplace_back(row, L.omega(other, k), coef);
          diag -= coef;
          const double outward = f == i + 1 ? 1.0 : -1.0;
          constant -= outward * newton * geometry * g_star * g_star * slope;
        }
        // Axial faces: ∫ μ r³ dr ∂_zω; plates give Dirichlet values 0 (bottom) and Ω (top).
        // With inertia the plate fluxes use the second-order one-sided gradient that μ is
        // evaluated with: the half-cell difference there is first-order, and since μ(γ̇) then
        // sees the O(h²) shift of the wall cell's ω as an O(h) error of the wall gradient, the
        // torque of a shear-thinning fluid converged only at first order in N_z.
        for (std::size_t f : {k, k + 1}) {
          const std::size_t face = i * (nz + 1) + f;
          const bool one_sided = (f == 0 || f == nz) && wall_gradient_is_one_sided();
          const double g_star = one_sided ? domega_dz_for_viscosity(s, i, f) : domega_dz(s, i, f);
          const double slope = mu.axial_flux_slope[face];
          const double jacobian = e * (mu.axial_flux[face] + newton * g_star * slope);
          const double outward = f == k + 1 ? 1.0 : -1.0;
          constant -= outward * newton * e * g_star * g_star * slope;
          if (one_sided) {
            // the row gets outward·F with F = J (wall ω_w + near ω_near + far ω_far); this
            // cell is the plate's near cell
            const auto& plate = L.plate(f);
            diag += outward * jacobian * plate.near;
            t.emplace_back(row, L.omega(i, plate.far_cell), outward * jacobian * plate.far);
            if (f == nz) rhs[static_cast<Eigen::Index>(row)] -= outward * jacobian * plate.wall * omega_top;
            continue;
          }
          const double coef = jacobian / L.dz_centres(f);
          diag -= coef;
          if (f == 0) continue;  // ω = 0 on the bottom plate
          if (f == nz) {
            rhs[static_cast<Eigen::Index>(row)] -= coef * omega_top;
            continue;
          }
          t.emplace_back(row, L.omega(i, f == k ? k - 1 : k + 1), coef);
        }
        if (L.inertia) {
          // −ρ Σ_out ṁ L_face, central interpolation of ω, lagged mass fluxes.
          const double rho = p.density;
          for (std::size_t f : {i, i + 1}) {
            if (f == 0 || f == nr) continue;
            const double sign = f == i + 1 ? 1.0 : -1.0;                       // outward
            const double dmdot = sign * face_eps_r(f, k) * L.rf[f] * L.dz(k);  // ∂ṁ/∂u_r
            const double mdot = dmdot * ur(s, f, k);
            const double l = L.rf[f] * L.rf[f];
            const std::size_t other = f == i ? i - 1 : i + 1;
            const double w_other = (L.rc[i] - L.rf[f]) / (L.rc[i] - L.rc[other]);
            t.emplace_back(row, L.omega(i, k), -rho * mdot * l * (1 - w_other));
            t.emplace_back(row, L.omega(other, k), -rho * mdot * l * w_other);
            const double omega_face =
                (1 - w_other) * s.angular_velocity[L.cell(i, k)] + w_other * s.angular_velocity[L.cell(other, k)];
            newton_flux(t, rhs, row, mdot, l * omega_face, {{L.radial(f, k), dmdot}});
          }
          for (std::size_t f : {k, k + 1}) {
            if (f == 0 || f == nz) continue;  // no flow through the plates
            const double sign = f == k + 1 ? 1.0 : -1.0;
            const double dmdot = sign * face_eps_z(i, f) * L.axial_area(i);  // ∂ṁ/∂u_z
            const double mdot = dmdot * uz(s, i, f);
            const double l = 0.5 * (L.rf[i] * L.rf[i] + L.rf[i + 1] * L.rf[i + 1]);
            const std::size_t other = f == k ? k - 1 : k + 1;
            const double w_other = (L.zc[k] - L.zf[f]) / (L.zc[k] - L.zc[other]);
            t.emplace_back(row, L.omega(i, k), -rho * mdot * l * (1 - w_other));
            t.emplace_back(row, L.omega(i, other), -rho * mdot * l * w_other);
            const double omega_face =
                (1 - w_other) * s.angular_velocity[L.cell(i, k)] + w_other * s.angular_velocity[L.cell(i, other)];
            newton_flux(t, rhs, row, mdot, l * omega_face, {{L.axial(i, f), dmdot}});
          }
        }
        t.emplace_back(row, row, diag);
        rhs[static_cast<Eigen::Index>(row)] -= constant;
        if (!torque_density.empty())
          rhs[static_cast<Eigen::Index>(row)] -= torque_density[L.cell(i, k)] * L.axial_area(i) * L.dz(k);
      }
  }

  // r-momentum on the u_r control volume of interior radial face (i, k), weighted by r.
  void assemble_radial(const SwirlState& s, const ViscosityField& mu, Triplets& t, Eigen::VectorXd& rhs) const {
    const std::size_t nr = L.nr, nz = L.nz;
    const double rho = p.density;
    for (std::size_t i = 1; i < nr; ++i)
      for (std::size_t k = 0; k < nz; ++k) {
        const std::size_t row = L.radial(i, k);
        const double e = face_eps_r(i, k);
        const double drc = L.dr_centres(i), dzk = L.dz(k), r = L.rf[i];
        const auto add_ur = [&](std::size_t fi, std::size_t fk, double coef) {
          if (fi == 0 || fi == nr) return;  // u_r = 0 on axis and rim
          t.emplace_back(row, L.radial(fi, fk), coef);
        };
        const auto add_uz = [&](std::size_t fi, std::size_t fk, double coef) {
          if (fk == 0 || fk == nz) return;  // u_z = 0 on the plates
          t.emplace_back(row, L.axial(fi, fk), coef);
        };
        // Pressure: −ε r Δz (p_i − p_{i−1}).
        t.emplace_back(row, L.pressure(i, k), -e * r * dzk);
        t.emplace_back(row, L.pressure(i - 1, k), e * r * dzk);
        // Normal stress: Δz [r τ_rr] between the two cell centres, τ_rr = 2μ ∂_r u_r.
        for (std::size_t c : {i - 1, i}) {
          const double sign = c == i ? 1.0 : -1.0;
          const double coef = e * sign * dzk * L.rc[c] * 2.0 * mu.centre[L.cell(c, k)] / L.dr(c);
          add_ur(c + 1, k, coef);
          add_ur(c, k, -coef);
        }
        // Shear stress: r Δr_c [τ_rz] between the corners below and above.
        for (std::size_t f : {k, k + 1}) {
          const double sign = f == k + 1 ? 1.0 : -1.0;
          const double mu_corner = corner_viscosity(mu, i, f);
          const double coef = e * sign * r * drc * mu_corner;
          // ∂u_r/∂z at the corner; at a plate second-order one-sided (as μ there), for the
          // reason given in assemble_angular
          if ((f == 0 || f == nz) && wall_gradient_is_one_sided()) {
            const auto& plate = L.plate(f);  // u_r = 0 on the plate
            add_ur(i, plate.near_cell, coef * plate.near);
            add_ur(i, plate.far_cell, coef * plate.far);
          } else if (f == 0)
            add_ur(i, 0, coef / L.dz_centres(0));
          else if (f == nz)
            add_ur(i, nz - 1, -coef / L.dz_centres(nz));
          else {
            add_ur(i, f, coef / L.dz_centres(f));
            add_ur(i, f - 1, -coef / L.dz_centres(f));
          }
          // ∂u_z/∂r at the corner
          add_uz(i, f, coef / drc);
          add_uz(i - 1, f, -coef / drc);
        }
        // Hoop stress: −τ_θθ Δr_c Δz, τ_θθ = 2μ u_r / r.
        const double mu_face = 0.5 * (mu.centre[L.cell(i - 1, k)] + mu.centre[L.cell(i, k)]);
        add_ur(i, k, -e * 2.0 * mu_face / r * drc * dzk);
        // Centrifugal force ρ ε ω² r · r Δr_c Δz, Newton-linearised: ω² ≈ 2ω*ω − ω*².
        const double w_star = 0.5 * (s.angular_velocity[L.cell(i - 1, k)] + s.angular_velocity[L.cell(i, k)]);
        const double cf = rho * e * r * r * drc * dzk;
        t.emplace_back(row, L.omega(i - 1, k), cf * w_star);
        t.emplace_back(row, L.omega(i, k), cf * w_star);
        rhs[static_cast<Eigen::Index>(row)] += cf * w_star * w_star;
        // Convection −ρ[Δz (r ε u_r u_r) + r Δr_c (ε u_z u_r)], central, lagged mass fluxes.
        for (std::size_t c : {i - 1, i}) {
          const double sign = c == i ? 1.0 : -1.0;
          const double dmdot = sign * void_fraction(L.cell(c, k)) * L.rc[c] * dzk * 0.5;  // per u_r face
          const double ur_centre = 0.5 * (ur(s, c, k) + ur(s, c + 1, k));
          const double mdot = 2 * dmdot * ur_centre;
          add_ur(c, k, -rho * mdot * 0.5);
          add_ur(c + 1, k, -rho * mdot * 0.5);
          Sensitivities d;
          if (c != 0) d.push_back({L.radial(c, k), dmdot});
          if (c + 1 != nr) d.push_back({L.radial(c + 1, k), dmdot});
          newton_flux(t, rhs, row, mdot, ur_centre, d);
        }
        for (std::size_t f : {k, k + 1}) {
          if (f == 0 || f == nz) continue;
          const double sign = f == k + 1 ? 1.0 : -1.0;
          const double wr = (r - L.rc[i - 1]) / drc;
          const double uz_corner = (1 - wr) * uz(s, i - 1, f) + wr * uz(s, i, f);
          const double dmdot = sign * face_eps_z_corner(i, f) * r * drc;  // per unit corner u_z
          const double mdot = dmdot * uz_corner;
          const double wz = (L.zf[f] - L.zc[f - 1]) / L.dz_centres(f);  // 1/2 unless z is stretched
          add_ur(i, f - 1, -rho * mdot * (1 - wz));
          add_ur(i, f, -rho * mdot * wz);
          const double ur_corner = (1 - wz) * ur(s, i, f - 1) + wz * ur(s, i, f);
          newton_flux(t, rhs, row, mdot, ur_corner,
                      {{L.axial(i - 1, f), dmdot * (1 - wr)}, {L.axial(i, f), dmdot * wr}});
        }
      }
  }

  // z-momentum on the u_z control volume of interior axial face (i, k), weighted by r.
  void assemble_axial(const SwirlState& s, const ViscosityField& mu, Triplets& t, Eigen::VectorXd& rhs) const {
    const std::size_t nr = L.nr, nz = L.nz;
    const double rho = p.density;
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t k = 1; k < nz; ++k) {
        const std::size_t row = L.axial(i, k);
        const double e = face_eps_z(i, k);
        const double dzc = L.dz_centres(k), dri = L.dr(i), r = L.rc[i];
        const auto add_ur = [&](std::size_t fi, std::size_t fk, double coef) {
          if (fi == 0 || fi == nr) return;
          t.emplace_back(row, L.radial(fi, fk), coef);
        };
        const auto add_uz = [&](std::size_t fi, std::size_t fk, double coef) {
          if (fk == 0 || fk == nz) return;
          t.emplace_back(row, L.axial(fi, fk), coef);
        };
        t.emplace_back(row, L.pressure(i, k), -e * r * dri);
        t.emplace_back(row, L.pressure(i, k - 1), e * r * dri);
        // Normal stress: r Δr [τ_zz], τ_zz = 2μ ∂_z u_z at cell centres.
        for (std::size_t c : {k - 1, k}) {
          const double sign = c == k ? 1.0 : -1.0;
          const double coef = e * sign * r * dri * 2.0 * mu.centre[L.cell(i, c)] / L.dz(c);
          add_uz(i, c + 1, coef);
          add_uz(i, c, -coef);
        }
        // Shear stress: Δz_c [r τ_rz] between radial faces i and i+1 (zero on axis and rim).
        for (std::size_t f : {i, i + 1}) {
          if (f == 0 || f == nr) continue;
          const double sign = f == i + 1 ? 1.0 : -1.0;
          const double coef = e * sign * dzc * L.rf[f] * corner_viscosity(mu, f, k);
          add_ur(f, k, coef / L.dz_centres(k));
          add_ur(f, k - 1, -coef / L.dz_centres(k));
          add_uz(f, k, coef / L.dr_centres(f));
          add_uz(f - 1, k, -coef / L.dr_centres(f));
        }
        // Convection −ρ[Δz_c (r ε u_r u_z) + r Δr (ε u_z u_z)].
        for (std::size_t f : {i, i + 1}) {
          if (f == 0 || f == nr) continue;
          const double sign = f == i + 1 ? 1.0 : -1.0;
          const double wz = (L.zf[k] - L.zc[k - 1]) / dzc;
          const double ur_corner = (1 - wz) * ur(s, f, k - 1) + wz * ur(s, f, k);
          const double dmdot = sign * face_eps_r_corner(f, k) * L.rf[f] * dzc;  // per unit corner u_r
          const double mdot = dmdot * ur_corner;
          add_uz(f - 1, k, -rho * mdot * 0.5);
          add_uz(f, k, -rho * mdot * 0.5);
          const double uz_corner = 0.5 * (uz(s, f - 1, k) + uz(s, f, k));
          newton_flux(t, rhs, row, mdot, uz_corner,
                      {{L.radial(f, k - 1), dmdot * (1 - wz)}, {L.radial(f, k), dmdot * wz}});
        }
        for (std::size_t c : {k - 1, k}) {
          const double sign = c == k ? 1.0 : -1.0;
          const double dmdot = sign * void_fraction(L.cell(i, c)) * r * dri * 0.5;  // per u_z face
          const double uz_centre = 0.5 * (uz(s, i, c) + uz(s, i, c + 1));
          const double mdot = 2 * dmdot * uz_centre;
          add_uz(i, c, -rho * mdot * 0.5);
          add_uz(i, c + 1, -rho * mdot * 0.5);
          Sensitivities d;
          if (c != 0) d.push_back({L.axial(i, c), dmdot});
          if (c + 1 != nz) d.push_back({L.axial(i, c + 1), dmdot});
          newton_flux(t, rhs, row, mdot, uz_centre, d);
        }
      }
  }

  // ∇·(εu) = 0 per cell (CD eq. 26, steady); one equation is replaced by p = 0 at cell (0, 0),
  // since the closed gap makes the continuity equations sum to zero.
  void assemble_continuity(Triplets& t) const {
    const std::size_t nr = L.nr, nz = L.nz;
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t k = 0; k < nz; ++k) {
        const std::size_t row = L.pressure(i, k);
        if (i == 0 && k == 0) {
          t.emplace_back(row, row, 1.0);
          continue;
        }
        if (i + 1 < nr) t.emplace_back(row, L.radial(i + 1, k), face_eps_r(i + 1, k) * L.rf[i + 1] * L.dz(k));
        if (i > 0) t.emplace_back(row, L.radial(i, k), -face_eps_r(i, k) * L.rf[i] * L.dz(k));
        if (k + 1 < nz) t.emplace_back(row, L.axial(i, k + 1), face_eps_z(i, k + 1) * L.axial_area(i));
        if (k > 0) t.emplace_back(row, L.axial(i, k), -face_eps_z(i, k) * L.axial_area(i));
      }
  }

  // μ at corner (radial face i, axial face k): from the wall shear rate on the plates, else
  // the mean of the adjacent cells.
  double corner_viscosity(const ViscosityField& mu, std::size_t i, std::size_t k) const {
    if (k == 0) return mu.wall_corner[i];
    if (k == L.nz) return mu.wall_corner[L.nr + 1 + i];
    double sum = 0, n = 0;
    for (std::size_t ii : {i - 1, i})
      for (std::size_t kk : {k - 1, k})
        if (ii < L.nr && kk < L.nz) {
          sum += mu.centre[L.cell(ii, kk)];
          n += 1;
        }
    return sum / n;
  }
  double face_eps_z_corner(std::size_t i, std::size_t k) const {
    return 0.25 * (void_fraction(L.cell(i - 1, k - 1)) + void_fraction(L.cell(i, k - 1)) +
                   void_fraction(L.cell(i - 1, k)) + void_fraction(L.cell(i, k)));
  }
  double face_eps_r_corner(std::size_t i, std::size_t k) const { return face_eps_z_corner(i, k); }
};

}  // namespace rheosim::fluid::swirl_detail
