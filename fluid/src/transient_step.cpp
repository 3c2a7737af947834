// One projection step of the transient solver: the implicit viscous predictor and the pressure
// correction (see transient.hpp).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "transient_impl.hpp"

namespace rheosim::fluid {

StepReport TransientSolver::Impl::advance(double dt) {
  const auto start = std::chrono::steady_clock::now();
  StepReport report;
  report.time_step = dt;
  report.time = time;
  if (!(dt > 0) || !std::isfinite(dt))
    throw std::invalid_argument(fmt::format("TransientSolver::advance: dt = {} s, expected a finite value > 0", dt));
  check_courant(dt, report);
  const Sbdf2 c = sbdf2(dt);
  Candidate next;
  next.u = u;
  const Velocity ue = extrapolated_velocity(c);
  const ViscosityField mu = evaluate_viscosity(ue);
  for (const std::vector<double>* field : {&mu.centre, &mu.rt, &mu.tz_moment, &mu.wall_rz})
    if (!all_finite(*field))
      fail(StepFailure::non_finite,
           fmt::format("the rheology law '{}' returned a non-finite viscosity (NaN or inf) at t = {:.6g} s (step {}); "
                       "the state before the step is kept",
                       params.rheology->name(), time, steps + 1),
           report);
  const Explicit conv = convection(ue, eps_next);
  const Explicit cross = viscous_cross(ue, mu);
  try {
    solve_predictor(dt, c.a0, c.a1, c.a2, mu, conv, cross, next.u);
  } catch (const std::runtime_error& e) {
    fail(StepFailure::linear_solver, e.what(), report);
  }
  if (!all_finite(next.u.ur) || !all_finite(next.u.ut) || !all_finite(next.u.uz))
    fail(StepFailure::non_finite,
         fmt::format("NaN or inf in the predicted velocity at t = {:.6g} s (step {}, dt = {:.4g} s); the state before "
                     "the step is kept",
                     time + dt, steps + 1, dt),
         report);
  project(dt, c, mu, next, report);
  check_candidate(dt, next, report);
  commit(dt, next, report);
  report.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

// The step is refused before anything is computed when the current flow breaks max_courant.
void TransientSolver::Impl::check_courant(double dt, StepReport& report) const {
  const CourantResult before = courant(u, dt);
  report.courant = before.value;
  if (!(before.value <= params.max_courant))
    fail(StepFailure::courant_exceeded,
         fmt::format("Courant number {:.4g} at cell (i={}, j={}, k={}) exceeds max_courant = {:.4g} for dt = {:.4g} s; "
                     "use dt <= {:.4g} s",
                     before.value, before.i, before.j, before.k, params.max_courant, dt,
                     dt * params.max_courant / before.value),
         report);
}

// SBDF2 coefficients (variable step); BDF1 after a reset and when the step grows by more than
// max_step_ratio (variable-step BDF2 is zero-stable only for ratios below 1 + √2).
TransientSolver::Impl::Sbdf2 TransientSolver::Impl::sbdf2(double dt) const {
  Sbdf2 c;
  c.second_order = have_old && dt <= max_step_ratio * dt_old;
  if (c.second_order) {
    c.w = dt / dt_old;
    c.a0 = (1 + 2 * c.w) / (1 + c.w);
    c.a1 = -(1 + c.w);
    c.a2 = c.w * c.w / (1 + c.w);
  }
  return c;
}

// The velocity the explicit terms and μ are evaluated at: (1 + w)uⁿ − w u^(n−1) (second order),
// else uⁿ.
Velocity TransientSolver::Impl::extrapolated_velocity(const Sbdf2& c) const {
  Velocity ue = u;
  if (!c.second_order) return ue;
  const double w = c.w;
  const auto extrapolate = [w](std::vector<double>& out, const std::vector<double>& now,
                               const std::vector<double>& old) {
    for (std::size_t n = 0; n < out.size(); ++n) out[n] = (1 + w) * now[n] - w * old[n];
  };
  extrapolate(ue.ur, u.ur, u_old.ur);
  extrapolate(ue.ut, u.ut, u_old.ut);
  extrapolate(ue.uz, u.uz, u_old.uz);
  impose_boundary_values(g, ue);
  return ue;
}

// Projection of the predicted velocity onto the volume-averaged continuity (CD eq. 26, with the
// BDF2 ∂ε/∂t), the rotational pressure update, and the continuity residual left.
void TransientSolver::Impl::project(double dt, const Sbdf2& c, const ViscosityField& mu, Candidate& next,
                                    StepReport& report) {
  try {
    pressure_solver.set_void_fraction(eps_next);
  } catch (const std::runtime_error& e) {
    fail(StepFailure::linear_solver, e.what(), report);
  }
  const std::vector<double> flux = flux_divergence(next.u, eps_next);
  const std::vector<double> flux_magnitude = flux_divergence(next.u, eps_next, true);
  Eigen::VectorXd b(static_cast<Eigen::Index>(g.nc));
  const double scale = dt / (c.a0 * params.density);
  double flux_scale = 0;
  // BDF2 ∂ε/∂t with a₁ = −a₀ − a₂ substituted: exactly zero where ε does not change.
  const auto eps_rate = [&](std::size_t cell) {
    return (c.a0 * (eps_next[cell] - eps_now[cell]) + c.a2 * (eps_old[cell] - eps_now[cell])) / dt;
  };
  for (std::size_t i = 0; i < g.nr; ++i)
    for (std::size_t j = 0; j < g.nt; ++j)
      for (std::size_t k = 0; k < g.nz; ++k) {
        const std::size_t cell = g.cell(i, j, k);
        const double rate = g.volume(i, k) * eps_rate(cell);
        b[static_cast<Eigen::Index>(cell)] = -(flux[cell] + rate) / scale;
        const double magnitude = (flux_magnitude[cell] + std::abs(rate)) / scale;
        flux_scale += magnitude * magnitude;
      }
  Eigen::VectorXd phi;
  next.pressure =
      pressure_solver.solve(b, phi, params.pressure_tolerance, params.pressure_max_iterations, std::sqrt(flux_scale));
  report.pressure_iterations = next.pressure.iterations;
  report.viscous_iterations = predictor_iterations;
  report.pressure_residual = next.pressure.relative_residual;
  if (!next.pressure.converged)
    fail(StepFailure::linear_solver,
         fmt::format("pressure PCG did not reach the relative residual {:.3g} in {} iterations (last {:.3g})",
                     params.pressure_tolerance, next.pressure.iterations, next.pressure.relative_residual),
         report);
  const std::vector<double> div_star = velocity_divergence(next.u);
  correct(next.u, phi, scale);
  // Rotational pressure update: p += φ − μ∇·(u* − u^(n+1)), the viscous stress of the
  // gradient the projection removed. Without it the pressure update φ ∝ ρ/Δt vanishes at
  // large viscous Courant numbers and the pressure converges like an Uzawa iteration with a
  // tiny step; the term is zero at a steady state.
  const std::vector<double> div_new = velocity_divergence(next.u);
  next.p = p;
  for (std::size_t cell = 0; cell < g.nc; ++cell)
    next.p[cell] += phi[static_cast<Eigen::Index>(cell)] - mu.centre[cell] * (div_star[cell] - div_new[cell]);
  remove_volume_mean(next.p);

  // Continuity residual after the projection.
  const std::vector<double> flux_after = flux_divergence(next.u, eps_next);
  for (std::size_t i = 0; i < g.nr; ++i)
    for (std::size_t j = 0; j < g.nt; ++j)
      for (std::size_t k = 0; k < g.nz; ++k) {
        const std::size_t cell = g.cell(i, j, k);
        next.max_divergence =
            std::max(next.max_divergence, std::abs(flux_after[cell] / g.volume(i, k) + eps_rate(cell)));
      }
  report.max_divergence = next.max_divergence;
}

// Health of the candidate: finite, and no blow-up.
void TransientSolver::Impl::check_candidate(double dt, const Candidate& next, const StepReport& report) const {
  if (!all_finite(next.u.ur) || !all_finite(next.u.ut) || !all_finite(next.u.uz) || !all_finite(next.p))
    fail(StepFailure::non_finite,
         fmt::format("NaN or inf in the velocity or pressure at t = {:.6g} s (step {}, dt = {:.4g} s); "
                     "the state before the step is kept",
                     time + dt, steps + 1, dt),
         report);
  const double speed = std::max({max_abs(next.u.ur), max_abs(next.u.ut), max_abs(next.u.uz)});
  const double reference = reference_speed(dt);
  if (speed > params.blow_up_factor * reference)
    fail(StepFailure::diverged,
         fmt::format(
             "velocity {:.4g} m/s at t = {:.6g} s exceeds blow_up_factor × reference speed ({:.4g} × {:.4g} m/s); "
             "reduce dt (was {:.4g} s) — the state before the step is kept",
             speed, time + dt, params.blow_up_factor, reference, dt),
         report);
}

void TransientSolver::Impl::commit(double dt, Candidate& next, StepReport& report) {
  u_old = std::move(u);
  u = std::move(next.u);
  p = std::move(next.p);
  eps_old = eps_now;
  eps_now = eps_next;
  time += dt;
  dt_old = dt;
  ++steps;
  have_old = true;
  update_diagnostics();
  report.time = time;
  report.courant = courant(u, dt).value;
  report.torque = torque_top;
  report.bottom_torque = torque_bottom;
}

void TransientSolver::Impl::solve_predictor(double dt, double a0, double a1, double a2, const ViscosityField& mu,
                                            const Explicit& conv, const Explicit& cross, Velocity& star) {
  const std::size_t nr = g.nr, nt = g.nt, nz = g.nz;
  const double rho = params.density;
  const auto mu_c = [&](std::size_t i, std::size_t j, std::size_t k) { return mu.centre[g.cell(i, j, k)]; };
  Triplets t;
  predictor_iterations = 0;
  const auto run = [&](PredictorSystem& system, std::string_view name, std::size_t n, const Triplets& triplets,
                       const Eigen::VectorXd& rhs, const Eigen::VectorXd& guess, Eigen::VectorXd& x) {
    const auto outcome = system.solve(n, triplets, rhs, guess, static_cast<std::size_t>(params.direct_solver_limit),
                                      params.viscous_tolerance, params.viscous_max_iterations, x);
    if (!outcome.ok) throw std::runtime_error(fmt::format("{} predictor: {}", name, outcome.failure));
    predictor_iterations = std::max(predictor_iterations, outcome.iterations);
  };

  // ---- u_r --------------------------------------------------------------------------------
  {
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(g.rows_r()));
    t.clear();
    for (std::size_t i = 1; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k) {
          const std::size_t row = g.row_r(i, j, k), face = g.ur(i, j, k);
          const auto add = [&](std::size_t col, double value) {
            t.emplace_back(static_cast<int>(row), static_cast<int>(col), value);
          };
          const double volume = g.rf[i] * g.drc[i] * g.dth * g.dz[k];
          const double en = CellFields::face_r(eps_next, g, i, j, k);
          const double e0 = CellFields::face_r(eps_now, g, i, j, k);
          const double e1 = CellFields::face_r(eps_old, g, i, j, k);
          double diag = rho * a0 * volume / dt;
          double b = -rho * volume / dt * (a1 * e0 * u.ur[face] + a2 * e1 * u_old.ur[face]) / en;
          if (!drag.empty()) diag += 0.5 * (drag[g.cell(i - 1, j, k)] + drag[g.cell(i, j, k)]) * volume / en;
          b -= g.rf[i] * g.dth * g.dz[k] * (p[g.cell(i, j, k)] - p[g.cell(i - 1, j, k)]);
          for (std::size_t c : {i - 1, i}) {  // τ_rr ⊃ μ∂_ru_r at the centres (the other μ∂_ru_r explicit)
            const double k_rr = mu_c(c, j, k) * g.rc[c] * g.dth * g.dz[k] / g.dr[c];
            diag += k_rr;
            const std::size_t other = c == i ? i + 1 : i - 1;
            if (other != 0 && other != nr) add(g.row_r(other, j, k), -k_rr);  // axis: explicit; rim: u_r = 0
          }
          if (nt > 1)
            for (std::size_t b_edge : {j, g.jp(j)}) {  // τ_rθ ⊃ μ(1/r)∂_θu_r
              const double k_rt = mu.rt[g.ur(i, b_edge, k)] * g.drc[i] * g.dz[k] / (g.rf[i] * g.dth);
              diag += k_rt;
              add(g.row_r(i, b_edge == j ? g.jm(j) : g.jp(j), k), -k_rt);
            }
          for (std::size_t f : {k, k + 1}) {  // τ_rz ⊃ μ∂_zu_r (u_r = 0 on the plates)
            const double k_rz = mu_rz(mu, i, j, f) * g.rf[i] * g.drc[i] * g.dth / g.dzc[f];
            diag += k_rz;
            if (f != 0 && f != nz) add(g.row_r(i, j, f == k ? k - 1 : k + 1), -k_rz);
          }
          diag += 0.5 * (mu_c(i - 1, j, k) + mu_c(i, j, k)) * g.drc[i] * g.dth * g.dz[k] / g.rf[i];  // hoop ⊃ μu_r/r²
          const double source =
              0.5 * (source_value(source_r, g.cell(i - 1, j, k)) + source_value(source_r, g.cell(i, j, k))) * volume;
          b += cross.r[row] + (conv.r[row] + source) / en;
          add(row, diag);
          rhs[static_cast<Eigen::Index>(row)] = b;
        }
    Eigen::VectorXd guess(static_cast<Eigen::Index>(g.rows_r())), x;
    for (std::size_t i = 1; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k) guess[static_cast<Eigen::Index>(g.row_r(i, j, k))] = u.ur[g.ur(i, j, k)];
    run(system_r, "u_r", g.rows_r(), t, rhs, guess, x);
    for (std::size_t i = 1; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k) star.ur[g.ur(i, j, k)] = x[static_cast<Eigen::Index>(g.row_r(i, j, k))];
  }

  // ---- ω = u_θ/r_c, angular-momentum form -------------------------------------------------
  {
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(g.nc));
    t.clear();
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k) {
          const std::size_t row = g.cell(i, j, k);
          const auto add = [&](std::size_t col, double value) {
            t.emplace_back(static_cast<int>(row), static_cast<int>(col), value);
          };
          const double inertia_moment = g.dth * g.dz[k] * g.r4[i];  // ∫ r · r dV per unit ω
          const double en = CellFields::face_t(eps_next, g, i, j, k);
          const double e0 = CellFields::face_t(eps_now, g, i, j, k);
          const double e1 = CellFields::face_t(eps_old, g, i, j, k);
          double diag = rho * a0 * inertia_moment / dt;
          double b = -rho * inertia_moment / dt * (a1 * e0 * omega(u, i, j, k) + a2 * e1 * omega(u_old, i, j, k)) / en;
          // Drag torque ∫ r βu_θ dV with the stored u_θ = r_c ω over the control volume, like the
          // source torque below, so that f_θ = βu_θ balances exactly.
          if (!drag.empty())
            diag +=
                0.5 * (drag[g.cell(i, g.jm(j), k)] + drag[g.cell(i, j, k)]) * g.rc[i] * g.dth * g.dz[k] * g.r3[i] / en;
          if (nt > 1) b -= g.dz[k] * g.a1[i] * (p[g.cell(i, j, k)] - p[g.cell(i, g.jm(j), k)]);
          for (std::size_t f : {i, i + 1}) {  // r³μ∂_rω (none through axis and rim)
            if (f == 0 || f == nr) continue;
            const double k_r = g.dth * g.dz[k] * std::pow(g.rf[f], 3) * mu.rt[g.ur(f, j, k)] / g.drc[f];
            diag += k_r;
            add(g.cell(f == i ? i - 1 : i + 1, j, k), -k_r);
          }
          for (std::size_t f : {k, k + 1}) {  // ∫μr³dr ∂_zω; plates give ω_bottom, ω_top
            const double k_z = g.dth * mu.tz_moment[g.uz(i, j, f)] / g.dzc[f];
            diag += k_z;
            if (f == 0)
              b += k_z * omega_bottom();
            else if (f == nz)
              b += k_z * omega_top();
            else
              add(g.cell(i, j, f == k ? k - 1 : k + 1), -k_z);
          }
          if (nt > 1)
            for (std::size_t c :
                 {g.jm(j), j}) {  // r τ_θθ ⊃ μ r ∂_θω through the cell centres (the other half explicit)
              const double k_t = mu_c(i, c, k) * g.dz[k] * g.a1[i] / g.dth;
              diag += k_t;
              add(g.cell(i, c == j ? g.jp(j) : g.jm(j), k), -k_t);
            }
          const double source =
              0.5 * (source_value(source_t, g.cell(i, g.jm(j), k)) + source_value(source_t, g.cell(i, j, k))) * g.dth *
              g.dz[k] * g.r3[i];
          b += cross.w[row] + (conv.w[row] + source) / en;
          add(row, diag);
          rhs[static_cast<Eigen::Index>(row)] = b;
        }
    Eigen::VectorXd guess(static_cast<Eigen::Index>(g.nc)), x;
    for (std::size_t c = 0; c < g.nc; ++c) guess[static_cast<Eigen::Index>(c)] = u.ut[c] / g.rc[c / (nt * nz)];
    run(system_w, "ω", g.nc, t, rhs, guess, x);
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k)
          star.ut[g.cell(i, j, k)] = g.rc[i] * x[static_cast<Eigen::Index>(g.cell(i, j, k))];
  }

  // ---- u_z --------------------------------------------------------------------------------
  {
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(g.rows_z()));
    t.clear();
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 1; k < nz; ++k) {
          const std::size_t row = g.row_z(i, j, k), face = g.uz(i, j, k);
          const auto add = [&](std::size_t col, double value) {
            t.emplace_back(static_cast<int>(row), static_cast<int>(col), value);
          };
          const double volume = g.a1[i] * g.dth * g.dzc[k];
          const double en = CellFields::face_z(eps_next, g, i, j, k);
          const double e0 = CellFields::face_z(eps_now, g, i, j, k);
          const double e1 = CellFields::face_z(eps_old, g, i, j, k);
          double diag = rho * a0 * volume / dt;
          double b = -rho * volume / dt * (a1 * e0 * u.uz[face] + a2 * e1 * u_old.uz[face]) / en;
          if (!drag.empty()) diag += 0.5 * (drag[g.cell(i, j, k - 1)] + drag[g.cell(i, j, k)]) * volume / en;
          b -= g.a1[i] * g.dth * (p[g.cell(i, j, k)] - p[g.cell(i, j, k - 1)]);
          for (std::size_t c : {k - 1, k}) {  // τ_zz ⊃ μ∂_zu_z (the other μ∂_zu_z explicit)
            const double k_zz = mu_c(i, j, c) * g.a1[i] * g.dth / g.dz[c];
            diag += k_zz;
            const std::size_t other = c == k ? k + 1 : k - 1;
            if (other != 0 && other != nz) add(g.row_z(i, j, other), -k_zz);
          }
          for (std::size_t f : {i, i + 1}) {  // τ_rz ⊃ μ∂_ru_z (none through axis and rim)
            if (f == 0 || f == nr) continue;
            const double k_rz = mu_rz(mu, f, j, k) * g.rf[f] * g.dth * g.dzc[k] / g.drc[f];
            diag += k_rz;
            add(g.row_z(f == i ? i - 1 : i + 1, j, k), -k_rz);
          }
          if (nt > 1)
            for (std::size_t b_edge : {j, g.jp(j)}) {  // τ_θz ⊃ μ(1/r)∂_θu_z
              const double k_tz = mu.tz[g.uz(i, b_edge, k)] * g.dr[i] * g.dzc[k] / (g.rc[i] * g.dth);
              diag += k_tz;
              add(g.row_z(i, b_edge == j ? g.jm(j) : g.jp(j), k), -k_tz);
            }
          const double source =
              0.5 * (source_value(source_z, g.cell(i, j, k - 1)) + source_value(source_z, g.cell(i, j, k))) * volume;
          b += cross.z[row] + (conv.z[row] + source) / en + rho * params.axial_gravity * volume;
          add(row, diag);
          rhs[static_cast<Eigen::Index>(row)] = b;
        }
    Eigen::VectorXd guess(static_cast<Eigen::Index>(g.rows_z())), x;
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 1; k < nz; ++k) guess[static_cast<Eigen::Index>(g.row_z(i, j, k))] = u.uz[g.uz(i, j, k)];
    run(system_z, "u_z", g.rows_z(), t, rhs, guess, x);
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 1; k < nz; ++k) star.uz[g.uz(i, j, k)] = x[static_cast<Eigen::Index>(g.row_z(i, j, k))];
  }
  impose_boundary_values(g, star);
}

}  // namespace rheosim::fluid
