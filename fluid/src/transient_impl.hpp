#pragma once
// TransientSolver::Impl: the state and the step of the transient solver. Its member functions
// live in transient.cpp (set-up, diagnostics, sampling), transient_viscosity.cpp (μ of a
// velocity field), transient_explicit.cpp (convection and viscous cross terms) and
// transient_step.cpp (the projection step). Private to fluid/src/.
#include <chrono>
#include <span>
#include <tuple>

#include "rheosim/fluid/transient.hpp"
#include "transient_grid.hpp"
#include "transient_linear_systems.hpp"

namespace rheosim::fluid {

using namespace transient_detail;  // the private grid types, in this module's transient files only

struct TransientSolver::Impl {
  TransientParams params;
  CylindricalGrid grid;
  Geometry g;
  PressureSolver pressure_solver;
  PredictorSystem system_r, system_w, system_z;

  Velocity u, u_old;      // u^n, u^(n−1)
  std::vector<double> p;  // p^n
  std::vector<double> eps_next, eps_now, eps_old;
  std::vector<double> source_r, source_t, source_z, drag;  // empty = none
  double time = 0, dt_old = 0;
  long steps = 0;
  bool have_old = false;  // u^(n−1) valid: the next step is BDF2

  ViscosityField mu_now;         // of the current state
  int predictor_iterations = 0;  // largest CG iteration count of the last predictor (0: direct)
  double torque_top = 0, torque_bottom = 0;

  explicit Impl(TransientParams prm) : params(std::move(prm)), grid(params.grid), g(grid), pressure_solver(g) {
    u.ur.assign(g.n_ur(), 0.0);
    u.ut.assign(g.nc, 0.0);
    u.uz.assign(g.n_uz(), 0.0);
    u_old = u;
    p.assign(g.nc, 0.0);
    eps_next.assign(g.nc, 1.0);
    eps_now = eps_old = eps_next;
    update_diagnostics();
  }

  double omega_top() const { return params.top_angular_velocity; }
  double omega_bottom() const { return params.bottom_angular_velocity; }
  double omega(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    return v.ut[g.cell(i, j, k)] / g.rc[i];
  }

  // ---- strain rates -------------------------------------------------------------------
  double dw_dz(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (k == 0) return (omega(v, i, j, 0) - omega_bottom()) / g.dzc[0];
    if (k == g.nz) return (omega_top() - omega(v, i, j, g.nz - 1)) / g.dzc[g.nz];
    return (omega(v, i, j, k) - omega(v, i, j, k - 1)) / g.dzc[k];
  }
  // The same for evaluating μ: second order at the plates (quadratic through the wall value and
  // the two nearest centres), as SwirlSolver does; the half-cell difference is first order
  // there and would make μ at the wall, and so the torque of a non-Newtonian fluid, first
  // order. Exact, like the half-cell form, for the creeping linear profile.
  double dw_dz_for_viscosity(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (k != 0 && k != g.nz) return dw_dz(v, i, j, k);
    if (k == 0) {
      const double h = g.dz[0], a = omega(v, i, j, 0), b = omega(v, i, j, 1);
      return (9 * a - b - 8 * omega_bottom()) / (3 * h);
    }
    const double h = g.dz[g.nz - 1], a = omega(v, i, j, g.nz - 1), b = omega(v, i, j, g.nz - 2);
    return (8 * omega_top() - 9 * a + b) / (3 * h);
  }
  double duz_dtheta(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (k == 0 || k == g.nz || g.nt == 1) return 0.0;
    return (v.uz[g.uz(i, j, k)] - v.uz[g.uz(i, g.jm(j), k)]) / g.dth;
  }
  double dur_dz(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (k == 0) return v.ur[g.ur(i, j, 0)] / g.dzc[0];
    if (k == g.nz) return -v.ur[g.ur(i, j, g.nz - 1)] / g.dzc[g.nz];
    return (v.ur[g.ur(i, j, k)] - v.ur[g.ur(i, j, k - 1)]) / g.dzc[k];
  }
  double duz_dr(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (k == 0 || k == g.nz) return 0.0;
    return (v.uz[g.uz(i, j, k)] - v.uz[g.uz(i - 1, j, k)]) / g.drc[i];
  }
  // 2E_rz on the rz-edge (r_i, θ_c,j, z_k) for evaluating μ (second order at the plates, where
  // ∂_ru_z = 0); zero on the axis and the shear-free rim.
  double strain_rz_for_viscosity(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (i == 0 || i == g.nr) return 0.0;
    if (k == 0) return (9 * v.ur[g.ur(i, j, 0)] - v.ur[g.ur(i, j, 1)]) / (3 * g.dz[0]);
    if (k == g.nz) return -(9 * v.ur[g.ur(i, j, g.nz - 1)] - v.ur[g.ur(i, j, g.nz - 2)]) / (3 * g.dz[g.nz - 1]);
    return dur_dz(v, i, j, k) + duz_dr(v, i, j, k);
  }
  // ∇·u per cell [1/s] (not ε-weighted): the −(2/3)μ∇·u part of CD eq. 28.
  std::vector<double> velocity_divergence(const Velocity& v) const {
    std::vector<double> div(g.nc);
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          double flux = (g.rf[i + 1] * v.ur[g.ur(i + 1, j, k)] - g.rf[i] * v.ur[g.ur(i, j, k)]) * g.dth * g.dz[k];
          if (g.nt > 1) flux += (v.ut[g.cell(i, g.jp(j), k)] - v.ut[g.cell(i, j, k)]) * g.dr[i] * g.dz[k];
          flux += (v.uz[g.uz(i, j, k + 1)] - v.uz[g.uz(i, j, k)]) * g.a1[i] * g.dth;
          div[g.cell(i, j, k)] = flux / g.volume(i, k);
        }
    return div;
  }

  // μ and γ̇ = √(2E:E) of a velocity field, with
  //   2E:E = 2(E_rr² + E_θθ² + E_zz²) + (2E_rθ)² + (2E_θz)² + (2E_rz)²,
  //   E_rr = ∂_ru_r, E_θθ = ∂_θω + u_r/r, E_zz = ∂_zu_z,
  //   2E_rθ = r∂_rω + (1/r)∂_θu_r, 2E_θz = r∂_zω + (1/r)∂_θu_z, 2E_rz = ∂_zu_r + ∂_ru_z.
  // Normal parts live at cell centres, shear parts on their edges. A shear part of the form
  // r·g + h (g a gradient of ω, h = (1/r)∂_θu at the edge's own radius) is evaluated at the
  // radius where μ is wanted: a cell keeps the means of g², g·h and h² over its four edges of
  // that kind, giving r²⟨g²⟩ + 2r⟨gh⟩ + ⟨h²⟩ at any r. On an edge, its own shear component is
  // exact and the rest is the mean over the adjacent cells at the edge's radius; on θz-edges
  // μ is taken at the three Gauss radii. For N_θ = 1 this is SwirlSolver's evaluation exactly.
  ViscosityField evaluate_viscosity(const Velocity& v) const;
  // evaluate_viscosity()'s parts (transient_viscosity.cpp).
  struct EdgeGradients;  // ∂_rω, ∂_θu_r/r on rθ-edges; ∂_zω, ∂_θu_z/r on θz-edges; 2E_rz on rz-edges
  struct CellStrain;     // per cell: the normal strains and the edge moments of the shear rates
  struct ShearRates;     // every γ̇ the viscosity is wanted at, in one array
  [[nodiscard]] EdgeGradients edge_gradients(const Velocity& v) const;
  [[nodiscard]] CellStrain cell_strain(const Velocity& v, const EdgeGradients& e) const;
  [[nodiscard]] ShearRates shear_rates(const EdgeGradients& e, const CellStrain& c) const;
  [[nodiscard]] ViscosityField viscosity_field(const ShearRates& rates) const;

  // μ on the rz-edge (r_i, θ_c,j, z_k): from the wall shear rate on the plates, else the mean of
  // the adjacent cells (SwirlSolver's corner value).
  double mu_rz(const ViscosityField& mu, std::size_t i, std::size_t j, std::size_t k) const {
    if (k == 0) return mu.wall_rz[i * g.nt + j];
    if (k == g.nz) return mu.wall_rz[((g.nr + 1) + i) * g.nt + j];
    double sum = 0, n = 0;
    for (std::size_t a : {i - 1, i})
      for (std::size_t f : {k - 1, k})
        if (a < g.nr && f < g.nz) {
          sum += mu.centre[g.cell(a, j, f)];
          n += 1;
        }
    return sum / n;
  }

  // Torque transmitted through the top (or bottom) plate: Σ Δθ W ∂_zω [N·m].
  double wall_torque(const Velocity& v, const ViscosityField& mu, bool top) const {
    const std::size_t k = top ? g.nz : 0;
    double sum = 0;
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j) sum += mu.tz_moment[g.uz(i, j, k)] * dw_dz(v, i, j, k);
    return g.dth * sum;
  }

  void update_diagnostics() {
    mu_now = evaluate_viscosity(u);
    torque_top = wall_torque(u, mu_now, true);
    torque_bottom = wall_torque(u, mu_now, false);
  }

  // ---- Courant number ---------------------------------------------------------------------
  struct CourantResult {
    double value = 0;
    std::size_t i = 0, j = 0, k = 0;
  };
  CourantResult courant(const Velocity& v, double dt) const {
    CourantResult out;
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          double rate = std::abs(0.5 * (v.ur[g.ur(i, j, k)] + v.ur[g.ur(i + 1, j, k)])) / g.dr[i] +
                        std::abs(0.5 * (v.uz[g.uz(i, j, k)] + v.uz[g.uz(i, j, k + 1)])) / g.dz[k];
          if (g.nt > 1)
            rate += std::abs(0.5 * (v.ut[g.cell(i, j, k)] + v.ut[g.cell(i, g.jp(j), k)])) / (g.rc[i] * g.dth);
          if (!std::isfinite(rate)) return {std::numeric_limits<double>::infinity(), i, j, k};
          if (rate * dt > out.value) out = {rate * dt, i, j, k};
        }
    return out;
  }

  // ---- explicit terms ----------------------------------------------------------------------
  // Integrated explicit forces (u_r, u_z: N) and torques (ω: N·m) per unknown, before the
  // division by ε^(n+1): convection (with the centrifugal force), then viscous cross terms.
  struct Explicit {
    std::vector<double> r, w, z;
  };

  // −∇·(ρεuu) (+ ρεu_θ²/r for u_r), central and conservative; ε = ε^(n+1).
  Explicit convection(const Velocity& v, const std::vector<double>& e) const;

  // The viscous terms left explicit: the transposed-gradient part ∇·(μ(∇u)ᵀ) — cross-component
  // terms and half of each normal stress (the implicit operator is the Laplacian form) — plus
  // −(2/3)μ∇·u and the axis value of u_r in τ_rr of the first ring (the axis is not an unknown).
  // For constant μ and ∇·u = 0 this part is μ∇(∇·u) = 0 in the continuum.
  Explicit viscous_cross(const Velocity& v, const ViscosityField& mu) const;

  // ---- the step ---------------------------------------------------------------------------
  struct Candidate {
    Velocity u;
    std::vector<double> p;
    numerics::KrylovResult pressure;
    double max_divergence = 0;
  };

  double source_value(const std::vector<double>& s, std::size_t c) const { return s.empty() ? 0.0 : s[c]; }

  // Integrated Σ_faces ε_f u_n A_f per cell with the pressure solver's face ε (or, with
  // `magnitude`, Σ_faces |ε_f u_n A_f|: the scale against which continuity is judged).
  std::vector<double> flux_divergence(const Velocity& v, const std::vector<double>& e, bool magnitude = false) const {
    std::vector<double> d(g.nc);
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          double flux = 0;
          const auto add = [&](double sign, double value) { flux += magnitude ? std::abs(value) : sign * value; };
          if (i + 1 < g.nr)
            add(1, CellFields::face_r(e, g, i + 1, j, k) * g.rf[i + 1] * g.dth * g.dz[k] * v.ur[g.ur(i + 1, j, k)]);
          if (i > 0) add(-1, CellFields::face_r(e, g, i, j, k) * g.rf[i] * g.dth * g.dz[k] * v.ur[g.ur(i, j, k)]);
          if (g.nt > 1) {
            add(1, CellFields::face_t(e, g, i, g.jp(j), k) * g.dr[i] * g.dz[k] * v.ut[g.cell(i, g.jp(j), k)]);
            add(-1, CellFields::face_t(e, g, i, j, k) * g.dr[i] * g.dz[k] * v.ut[g.cell(i, j, k)]);
          }
          if (k + 1 < g.nz) add(1, CellFields::face_z(e, g, i, j, k + 1) * g.a1[i] * g.dth * v.uz[g.uz(i, j, k + 1)]);
          if (k > 0) add(-1, CellFields::face_z(e, g, i, j, k) * g.a1[i] * g.dth * v.uz[g.uz(i, j, k)]);
          d[g.cell(i, j, k)] = flux;
        }
    return d;
  }

  // v ← v − scale ∇φ with the gradients of the Poisson operator.
  void correct(Velocity& v, const Eigen::VectorXd& phi, double scale) const {
    const auto ph = [&](std::size_t i, std::size_t j, std::size_t k) {
      return phi[static_cast<Eigen::Index>(g.cell(i, j, k))];
    };
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          if (i > 0) v.ur[g.ur(i, j, k)] -= scale * (ph(i, j, k) - ph(i - 1, j, k)) / g.drc[i];
          if (g.nt > 1) v.ut[g.cell(i, j, k)] -= scale * (ph(i, j, k) - ph(i, g.jm(j), k)) / (g.reff[i] * g.dth);
          if (k > 0) v.uz[g.uz(i, j, k)] -= scale * (ph(i, j, k) - ph(i, j, k - 1)) / g.dzc[k];
        }
    impose_boundary_values(g, v);
  }

  [[noreturn]] void fail(StepFailure kind, const std::string& message, StepReport report) const {
    throw StepError(kind, "TransientSolver: " + message, report);
  }

  StepReport advance(double dt);
  // advance()'s phases (transient_step.cpp).
  struct Sbdf2 {  // the step's coefficients: a₀u^(n+1) + a₁uⁿ + a₂u^(n−1), extrapolation weight w
    double a0 = 1, a1 = -1, a2 = 0, w = 0;
    bool second_order = false;
  };
  void check_courant(double dt, StepReport& report) const;
  [[nodiscard]] Sbdf2 sbdf2(double dt) const;
  [[nodiscard]] Velocity extrapolated_velocity(const Sbdf2& c) const;
  void project(double dt, const Sbdf2& c, const ViscosityField& mu, Candidate& next, StepReport& report);
  void check_candidate(double dt, const Candidate& next, const StepReport& report) const;
  void commit(double dt, Candidate& next, StepReport& report);

  // Speed scale against which a blow-up is judged: plates, current flow, what the source, the
  // gravity and the change of ε can drive within one step.
  double reference_speed(double dt) const {
    const double radius = g.rf[g.nr], gap = g.zf[g.nz];
    double ref = std::max(std::abs(omega_top()), std::abs(omega_bottom())) * radius;
    ref += std::max({max_abs(u.ur), max_abs(u.ut), max_abs(u.uz)});
    const double eps_min = *std::min_element(eps_next.begin(), eps_next.end());
    const double force = std::max({max_abs(source_r), max_abs(source_t), max_abs(source_z)});
    ref += dt * (force / (params.density * eps_min) + std::abs(params.axial_gravity));
    double deps = 0;
    for (std::size_t c = 0; c < g.nc; ++c) deps = std::max(deps, std::abs(eps_next[c] - eps_now[c]));
    ref += std::max(radius, gap) * deps / (dt * eps_min);
    return std::max(ref, 1e-30);
  }

  void remove_volume_mean(std::vector<double>& field) const {
    double sum = 0, volume = 0;
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          sum += field[g.cell(i, j, k)] * g.volume(i, k);
          volume += g.volume(i, k);
        }
    const double mean = sum / volume;
    for (double& x : field) x -= mean;
  }

  // Assembles and solves the three implicit viscous systems (divided by ε^(n+1) of the control
  // volume, which makes each symmetric positive definite); writes u* into `star`.
  void solve_predictor(double dt, double a0, double a1, double a2, const ViscosityField& mu, const Explicit& conv,
                       const Explicit& cross, Velocity& star);

  // ---- sampling ---------------------------------------------------------------------------
  // Bracket x in sorted nodes: index a and weight t of nodes[a + 1].
  static std::pair<std::size_t, double> bracket(const std::vector<double>& nodes, double x) {
    if (x <= nodes.front()) return {0, 0.0};
    if (x >= nodes.back()) return {nodes.size() - 2, 1.0};
    const auto it = std::upper_bound(nodes.begin(), nodes.end(), x);
    const auto a = static_cast<std::size_t>(it - nodes.begin()) - 1;
    return {a, (x - nodes[a]) / (nodes[a + 1] - nodes[a])};
  }
  // Periodic bracket on θ_j = offset + jΔθ.
  std::tuple<std::size_t, std::size_t, double> bracket_theta(double theta, double offset) const {
    double s = (theta - offset) / g.dth;
    const double fl = std::floor(s);
    const double t = s - fl;
    const auto n = static_cast<long>(g.nt);
    long j0 = static_cast<long>(fl) % n;
    if (j0 < 0) j0 += n;
    return {static_cast<std::size_t>(j0), static_cast<std::size_t>((j0 + 1) % n), t};
  }

  template <class Value>
  double trilinear(const std::vector<double>& rn, double theta_offset, const std::vector<double>& zn,
                   const CylindricalPoint& pt, Value value) const {
    const auto [a, tr] = bracket(rn, pt.r);
    const auto [j0, j1, tt] = bracket_theta(pt.theta, theta_offset);
    const auto [c, tz] = bracket(zn, pt.z);
    double sum = 0;
    for (int da = 0; da < 2; ++da)
      for (int db = 0; db < 2; ++db)
        for (int dc = 0; dc < 2; ++dc) {
          const double weight = (da ? tr : 1 - tr) * (db ? tt : 1 - tt) * (dc ? tz : 1 - tz);
          if (weight == 0.0) continue;
          sum += weight * value(a + static_cast<std::size_t>(da), db ? j1 : j0, c + static_cast<std::size_t>(dc));
        }
    return sum;
  }

  std::vector<CylindricalVelocity> sample(std::span<const CylindricalPoint> points) const {
    const double radius = g.rf[g.nr], gap = g.zf[g.nz];
    std::vector<double> r_ext{0.0}, z_ext{0.0};  // centres extended by the boundaries
    r_ext.insert(r_ext.end(), g.rc.begin(), g.rc.end());
    r_ext.push_back(radius);
    z_ext.insert(z_ext.end(), g.zc.begin(), g.zc.end());
    z_ext.push_back(gap);
    std::vector<std::pair<double, double>> axis(g.nz);
    for (std::size_t k = 0; k < g.nz; ++k) axis[k] = axis_velocity(g, u.ur, k);
    std::vector<CylindricalVelocity> out;
    out.reserve(points.size());
    for (const CylindricalPoint& raw : points) {
      CylindricalPoint pt = raw;
      pt.r = std::clamp(pt.r, 0.0, radius);
      pt.z = std::clamp(pt.z, 0.0, gap);
      CylindricalVelocity vel;
      vel.radial = trilinear(g.rf, 0.5 * g.dth, z_ext, pt, [&](std::size_t a, std::size_t j, std::size_t c) {
        if (c == 0 || c == g.nz + 1) return 0.0;
        return u.ur[g.ur(a, j, c - 1)];
      });
      vel.azimuthal = trilinear(r_ext, 0.0, z_ext, pt, [&](std::size_t a, std::size_t j, std::size_t c) {
        const double r = r_ext[a];
        if (c == 0) return omega_bottom() * r;
        if (c == g.nz + 1) return omega_top() * r;
        if (a == 0) {  // Cartesian axis velocity seen in direction θ_j
          const double th = static_cast<double>(j) * g.dth;
          return -axis[c - 1].first * std::sin(th) + axis[c - 1].second * std::cos(th);
        }
        if (a == g.nr + 1) return omega(u, g.nr - 1, j, c - 1) * radius;  // shear-free rim: ∂_rω = 0
        return u.ut[g.cell(a - 1, j, c - 1)];
      });
      vel.axial = trilinear(r_ext, 0.5 * g.dth, g.zf, pt, [&](std::size_t a, std::size_t j, std::size_t c) {
        if (a == 0) {
          double mean = 0;
          for (std::size_t b = 0; b < g.nt; ++b) mean += u.uz[g.uz(0, b, c)];
          return mean / static_cast<double>(g.nt);
        }
        if (a == g.nr + 1) return u.uz[g.uz(g.nr - 1, j, c)];
        return u.uz[g.uz(a - 1, j, c)];
      });
      out.push_back(vel);
    }
    return out;
  }
};

}  // namespace rheosim::fluid
