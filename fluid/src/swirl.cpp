#include "rheosim/fluid/swirl.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "rheosim/numerics/anderson.hpp"
#include "rheosim/numerics/gmres.hpp"
#include "swirl_discretisation.hpp"

namespace rheosim::fluid {

namespace {

using namespace swirl_detail;

bool all_finite(const Eigen::VectorXd& x) { return x.allFinite(); }

// Bilinear interpolation of v (index i * ys.size() + j, at (xs[i], ys[j])) at (x, y); constant
// beyond the ends. For the coarse-grid start of grid sequencing.
double bilinear(const std::vector<double>& xs, const std::vector<double>& ys, const std::vector<double>& v, double x,
                double y) {
  const auto locate = [](const std::vector<double>& a, double t) {
    if (a.size() < 2 || t <= a.front()) return std::pair<std::size_t, double>{0, 0.0};
    if (t >= a.back()) return std::pair<std::size_t, double>{a.size() - 2, 1.0};
    const auto it = std::upper_bound(a.begin(), a.end(), t);
    const auto i = static_cast<std::size_t>(it - a.begin()) - 1;
    return std::pair<std::size_t, double>{i, (t - a[i]) / (a[i + 1] - a[i])};
  };
  const auto [i, wx] = locate(xs, x);
  const auto [j, wy] = locate(ys, y);
  const std::size_t ny = ys.size();
  const auto at = [&](std::size_t a, std::size_t b) {
    return v[std::min(a, xs.size() - 1) * ny + std::min(b, ny - 1)];
  };
  return (1 - wx) * ((1 - wy) * at(i, j) + wy * at(i, j + 1)) + wx * ((1 - wy) * at(i + 1, j) + wy * at(i + 1, j + 1));
}

// A coarse solution carried to a finer grid of the same gap: ω, p, u_r, u_z interpolated
// bilinearly, with the plate values (ω = 0 and Ω, u = 0) as the end points in z.
SwirlState interpolate_state(const CylindricalGrid& from, const SwirlState& s, const CylindricalGrid& to,
                             double top_angular_velocity) {
  const std::size_t nr = from.radial_cells(), nz = from.axial_cells();
  const auto vec = [](std::span<const double> a) { return std::vector<double>(a.begin(), a.end()); };
  const std::vector<double> rc = vec(from.radial_centres()), rf = vec(from.radial_faces()),
                            zf = vec(from.axial_faces());
  std::vector<double> zc_walls = {zf.front()};
  for (double z : from.axial_centres()) zc_walls.push_back(z);
  zc_walls.push_back(zf.back());
  // Cell-centred fields padded with their plate values.
  const auto pad = [&](const std::vector<double>& field, std::size_t columns, double bottom, double top,
                       bool zero_walls) {
    std::vector<double> out(columns * (nz + 2));
    for (std::size_t i = 0; i < columns; ++i) {
      out[i * (nz + 2)] = zero_walls ? 0.0 : bottom;
      for (std::size_t k = 0; k < nz; ++k) out[i * (nz + 2) + k + 1] = field[i * nz + k];
      out[i * (nz + 2) + nz + 1] = zero_walls ? 0.0 : top;
    }
    return out;
  };
  const std::vector<double> omega = pad(s.angular_velocity, nr, 0.0, top_angular_velocity, false);
  std::vector<double> pressure = pad(s.pressure, nr, 0.0, 0.0, false);
  for (std::size_t i = 0; i < nr; ++i) {  // no plate value for p: repeat the wall cells
    pressure[i * (nz + 2)] = pressure[i * (nz + 2) + 1];
    pressure[i * (nz + 2) + nz + 1] = pressure[i * (nz + 2) + nz];
  }
  const std::vector<double> radial = pad(s.radial_velocity, nr + 1, 0.0, 0.0, true);

  const std::size_t mr = to.radial_cells(), mz = to.axial_cells();
  SwirlState out;
  out.angular_velocity.resize(mr * mz);
  out.pressure.resize(mr * mz);
  out.radial_velocity.assign((mr + 1) * mz, 0.0);
  out.axial_velocity.assign(mr * (mz + 1), 0.0);
  for (std::size_t i = 0; i < mr; ++i)
    for (std::size_t k = 0; k < mz; ++k) {
      const double r = to.radial_centres()[i], z = to.axial_centres()[k];
      out.angular_velocity[i * mz + k] = bilinear(rc, zc_walls, omega, r, z);
      out.pressure[i * mz + k] = bilinear(rc, zc_walls, pressure, r, z);
    }
  for (std::size_t i = 1; i < mr; ++i)
    for (std::size_t k = 0; k < mz; ++k)
      out.radial_velocity[i * mz + k] = bilinear(rf, zc_walls, radial, to.radial_faces()[i], to.axial_centres()[k]);
  for (std::size_t i = 0; i < mr; ++i)
    for (std::size_t k = 1; k < mz; ++k)
      out.axial_velocity[i * (mz + 1) + k] =
          bilinear(rc, zf, s.axial_velocity, to.radial_centres()[i], to.axial_faces()[k]);
  return out;
}

}  // namespace

SwirlSolver::SwirlSolver(SwirlParams params) : params_(std::move(params)), grid_(params_.grid) {
  if (grid_.azimuthal_cells() != 1)
    throw std::invalid_argument("SwirlSolver: grid.azimuthal_cells must be 1 (axisymmetric)");
  if (!(params_.density > 0)) throw std::invalid_argument("SwirlSolver: density must be > 0 kg/m³");
  if (!params_.rheology) throw std::invalid_argument("SwirlSolver: rheology must be set");
  if (!(params_.tolerance > 0)) throw std::invalid_argument("SwirlSolver: tolerance must be > 0");
  if (params_.max_iterations < 1) throw std::invalid_argument("SwirlSolver: max_iterations must be >= 1");
  if (!(params_.viscosity_relaxation > 0 && params_.viscosity_relaxation <= 1))
    throw std::invalid_argument("SwirlSolver: viscosity_relaxation must be in (0, 1]");
  if (!(params_.velocity_relaxation > 0 && params_.velocity_relaxation <= 1))
    throw std::invalid_argument("SwirlSolver: velocity_relaxation must be in (0, 1]");
  if (params_.inertia && (grid_.radial_cells() < 2 || grid_.axial_cells() < 2))
    throw std::invalid_argument("SwirlSolver: with inertia the grid needs >= 2 cells in r and in z");
}

SwirlState SwirlSolver::rest_state() const {
  const Layout layout(grid_, params_.inertia);
  SwirlState s;
  s.angular_velocity.assign(layout.nc, 0.0);
  s.pressure.assign(layout.nc, 0.0);
  s.radial_velocity.assign((layout.nr + 1) * layout.nz, 0.0);
  s.axial_velocity.assign(layout.nr * (layout.nz + 1), 0.0);
  return s;
}

SwirlResult SwirlSolver::attempt(double angular_velocity, const SwirlState* initial, const SwirlCoupling& coupling,
                                 double beta_start, int max_iterations) const {
  const auto start = std::chrono::steady_clock::now();
  const Layout L(grid_, params_.inertia);
  if (!coupling.void_fraction.empty() && coupling.void_fraction.size() != L.nc)
    throw std::invalid_argument("SwirlSolver: void_fraction needs one value per cell");
  if (!coupling.torque_density.empty() && coupling.torque_density.size() != L.nc)
    throw std::invalid_argument("SwirlSolver: torque_density needs one value per cell");
  const Discretisation disc(L, params_, angular_velocity, coupling.void_fraction);

  SwirlState state = rest_state();
  if (initial) {
    if (initial->angular_velocity.size() != L.nc)
      throw std::invalid_argument("SwirlSolver: initial state of another grid");
    state = *initial;
  } else {
    for (std::size_t i = 0; i < L.nr; ++i)
      for (std::size_t k = 0; k < L.nz; ++k)
        state.angular_velocity[L.cell(i, k)] = angular_velocity * L.zc[k] / L.zf[L.nz];
  }
  if (!L.inertia) {
    std::fill(state.radial_velocity.begin(), state.radial_velocity.end(), 0.0);
    std::fill(state.axial_velocity.begin(), state.axial_velocity.end(), 0.0);
  }

  SwirlResult result;
  ViscosityField mu = disc.viscosity(state);
  Triplets triplets;
  Eigen::VectorXd rhs;
  Eigen::SparseMatrix<double> matrix(static_cast<Eigen::Index>(L.unknowns()), static_cast<Eigen::Index>(L.unknowns()));
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
  bool pattern_known = false;
  double torque = disc.wall_torque(state, mu, true);
  const double velocity_scale = std::abs(angular_velocity) * L.rf[L.nr] + 1e-300;
  const double omega_scale = std::abs(angular_velocity) + 1e-300;

  double beta = beta_start;
  int rising = 0;  // consecutive iterations whose change grew
  // Newton–Krylov (inertia only): the Picard linearisation leaves out how μ depends on the
  // secondary flow and on the cross gradients, which strong shear thinning makes large; GMRES
  // with the exact Jacobian supplies it, and the Picard LU is its preconditioner.
  const bool krylov = L.inertia && params_.newton_krylov;
  numerics::AndersonMixer mixer(krylov ? 0 : params_.anderson_depth);
  // System vector (ω, p, interior u_r, u_z) ↔ state; pressure pinned to 0 at cell (0, 0) as in
  // the assembled continuity rows.
  const auto to_system = [&](const SwirlState& st) {
    Eigen::VectorXd z(static_cast<Eigen::Index>(L.unknowns()));
    for (std::size_t c = 0; c < L.nc; ++c) {
      z[static_cast<Eigen::Index>(L.omega(c / L.nz, c % L.nz))] = st.angular_velocity[c];
      z[static_cast<Eigen::Index>(L.pressure(c / L.nz, c % L.nz))] = st.pressure[c] - st.pressure[0];
    }
    for (std::size_t i = 1; i < L.nr; ++i)
      for (std::size_t k = 0; k < L.nz; ++k)
        z[static_cast<Eigen::Index>(L.radial(i, k))] = st.radial_velocity[L.ur_index(i, k)];
    for (std::size_t i = 0; i < L.nr; ++i)
      for (std::size_t k = 1; k < L.nz; ++k)
        z[static_cast<Eigen::Index>(L.axial(i, k))] = st.axial_velocity[L.uz_index(i, k)];
    return z;
  };
  const auto from_system = [&](const Eigen::VectorXd& z, SwirlState& st) {
    for (std::size_t c = 0; c < L.nc; ++c) {
      st.angular_velocity[c] = z[static_cast<Eigen::Index>(L.omega(c / L.nz, c % L.nz))];
      st.pressure[c] = z[static_cast<Eigen::Index>(L.pressure(c / L.nz, c % L.nz))];
    }
    for (std::size_t i = 1; i < L.nr; ++i)
      for (std::size_t k = 0; k < L.nz; ++k)
        st.radial_velocity[L.ur_index(i, k)] = z[static_cast<Eigen::Index>(L.radial(i, k))];
    for (std::size_t i = 0; i < L.nr; ++i)
      for (std::size_t k = 1; k < L.nz; ++k)
        st.axial_velocity[L.uz_index(i, k)] = z[static_cast<Eigen::Index>(L.axial(i, k))];
  };
  // Steady residual A(z) z − b(z) of the discrete equations (the Newton terms of the
  // linearisation cancel at its own expansion point, so this is the nonlinear residual).
  SwirlState scratch = rest_state();
  Triplets residual_triplets;
  Eigen::VectorXd residual_rhs;
  const auto steady_residual = [&](const Eigen::VectorXd& z) {
    from_system(z, scratch);
    const ViscosityField m = disc.viscosity(scratch);
    disc.assemble(scratch, m, coupling.torque_density, std::numeric_limits<double>::infinity(), residual_triplets,
                  residual_rhs);
    Eigen::VectorXd f = -residual_rhs;
    for (const auto& e : residual_triplets) f[e.row()] += e.value() * z[e.col()];
    return f;
  };
  // One inexact Newton step from `state`: solves (J + D) δ = −F by GMRES, left-preconditioned
  // with the Picard LU (whose solution x_picard gives the first Krylov vector), in variables
  // scaled by Ω, ΩR and the pressure's magnitude; J·v by a forward difference of F. D is the
  // pseudo-time term, so with it each step is one implicit pseudo-time step.
  int floor_count = 0;          // consecutive Newton changes below floor_limit that gain nothing
  double newton_step_size = 0;  // ‖δ‖∞ of the last full Newton step (scaled), for the stopping test
  const auto newton_krylov_step = [&](const Eigen::VectorXd& x_picard, double dtau, const auto& factor) {
    const Eigen::VectorXd y0 = to_system(state);
    const Eigen::VectorXd f0 = steady_residual(y0);
    double p_scale = 0;
    for (std::size_t c = 0; c < L.nc; ++c)
      p_scale = std::max(p_scale, std::abs(x_picard[static_cast<Eigen::Index>(L.nc + c)]));
    Eigen::VectorXd scale = Eigen::VectorXd::Constant(y0.size(), velocity_scale);
    scale.head(static_cast<Eigen::Index>(L.nc)).setConstant(omega_scale);
    scale.segment(static_cast<Eigen::Index>(L.nc), static_cast<Eigen::Index>(L.nc))
        .setConstant(p_scale > 0 ? p_scale : 1.0);
    Eigen::VectorXd pseudo = Eigen::VectorXd::Zero(y0.size());
    if (std::isfinite(dtau)) {
      Triplets tp;
      Eigen::VectorXd unused = Eigen::VectorXd::Zero(y0.size());
      disc.add_pseudo_time(state, dtau, tp, unused);
      for (const auto& e : tp) pseudo[e.row()] += e.value();
    }
    const Eigen::VectorXd b = (x_picard - y0).cwiseQuotient(scale);
    constexpr double h = 1e-7;  // forward-difference step in the scaled variables (O(1))
    const auto apply = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
      const Eigen::VectorXd w = v.cwiseProduct(scale);
      const Eigen::VectorXd jw = (steady_residual(y0 + h * w) - f0) / h + pseudo.cwiseProduct(w);
      return Eigen::VectorXd(factor.solve(jw)).cwiseQuotient(scale);
    };
    // Inexact Newton: the linear tolerance follows the size of the step (superlinear near the end).
    const double eta = std::clamp(b.lpNorm<Eigen::Infinity>(), 1e-6, 1e-2);
    const Eigen::VectorXd delta = numerics::gmres(apply, b, eta, 30);
    newton_step_size = delta.lpNorm<Eigen::Infinity>();
    // Backtracking on the row-scaled residual (rows scaled by Σ|a_rj| of the linearised
    // system): far from the solution the full step can overshoot, as plain Newton does.
    Eigen::VectorXd row_scale = Eigen::VectorXd::Constant(y0.size(), 1e-300);
    for (const auto& e : triplets) row_scale[e.row()] += std::abs(e.value());
    const double merit = f0.cwiseQuotient(row_scale).norm();
    const Eigen::VectorXd step = delta.cwiseProduct(scale);
    double lambda = 1;
    for (int trial = 0; trial < 6; ++trial, lambda *= 0.5) {
      const Eigen::VectorXd f = steady_residual(y0 + lambda * step);
      if (f.allFinite() && f.cwiseQuotient(row_scale).norm() < (1 - 1e-4 * lambda) * merit) break;
    }
    return Eigen::VectorXd(y0 + lambda * step);
  };
  // Pseudo-time step: starts at a fraction of a revolution, only used with inertia.
  const double pseudo_start = params_.pseudo_time_step > 0
                                  ? params_.pseudo_time_step / (std::abs(angular_velocity) + 1e-300)
                                  : std::numeric_limits<double>::infinity();
  double pseudo_dt = params_.inertia ? pseudo_start : std::numeric_limits<double>::infinity();
  double best_residual = std::numeric_limits<double>::infinity();
  double previous_residual = std::numeric_limits<double>::infinity();
  // The fixed-point variable: ω/Ω and (with inertia) interior u_r, u_z over ΩR, so that one
  // tolerance fits all components. Pressure follows from each linear solve.
  const auto pack = [&](const SwirlState& st) {
    Eigen::VectorXd v(static_cast<Eigen::Index>(L.inertia ? L.nc + (L.nr - 1) * L.nz + L.nr * (L.nz - 1) : L.nc));
    Eigen::Index j = 0;
    for (double w : st.angular_velocity) v[j++] = w / omega_scale;
    if (L.inertia) {
      for (std::size_t i = 1; i < L.nr; ++i)
        for (std::size_t k = 0; k < L.nz; ++k) v[j++] = st.radial_velocity[L.ur_index(i, k)] / velocity_scale;
      for (std::size_t i = 0; i < L.nr; ++i)
        for (std::size_t k = 1; k < L.nz; ++k) v[j++] = st.axial_velocity[L.uz_index(i, k)] / velocity_scale;
    }
    return v;
  };
  const auto unpack = [&](const Eigen::VectorXd& v, SwirlState& st) {
    Eigen::Index j = 0;
    for (double& w : st.angular_velocity) w = v[j++] * omega_scale;
    if (L.inertia) {
      for (std::size_t i = 1; i < L.nr; ++i)
        for (std::size_t k = 0; k < L.nz; ++k) st.radial_velocity[L.ur_index(i, k)] = v[j++] * velocity_scale;
      for (std::size_t i = 0; i < L.nr; ++i)
        for (std::size_t k = 1; k < L.nz; ++k) st.axial_velocity[L.uz_index(i, k)] = v[j++] * velocity_scale;
    }
  };
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    disc.assemble(state, mu, coupling.torque_density, pseudo_dt, triplets, rhs);
    matrix.setFromTriplets(triplets.begin(), triplets.end());
    if (!pattern_known) {
      lu.analyzePattern(matrix);
      pattern_known = true;
    }
    lu.factorize(matrix);
    if (lu.info() != Eigen::Success) {
      result.failure = "sparse LU factorisation failed at iteration " + std::to_string(iteration);
      break;
    }
    Eigen::VectorXd x = lu.solve(rhs);
    if (krylov && all_finite(x)) x = newton_krylov_step(x, pseudo_dt, lu);
    if (!all_finite(x)) {
      result.failure = "non-finite values (NaN/inf) at iteration " + std::to_string(iteration);
      break;
    }

    // The Picard map's output G(y); its mix with earlier iterates (Anderson) is the next y.
    SwirlState picard = state;
    for (std::size_t c = 0; c < L.nc; ++c) picard.angular_velocity[c] = x[static_cast<Eigen::Index>(c)];
    if (L.inertia) {
      double mean_p = 0;
      for (std::size_t c = 0; c < L.nc; ++c) mean_p += x[static_cast<Eigen::Index>(L.nc + c)];
      mean_p /= static_cast<double>(L.nc);
      for (std::size_t c = 0; c < L.nc; ++c) picard.pressure[c] = x[static_cast<Eigen::Index>(L.nc + c)] - mean_p;
      for (std::size_t i = 1; i < L.nr; ++i)
        for (std::size_t k = 0; k < L.nz; ++k)
          picard.radial_velocity[L.ur_index(i, k)] = x[static_cast<Eigen::Index>(L.radial(i, k))];
      for (std::size_t i = 0; i < L.nr; ++i)
        for (std::size_t k = 1; k < L.nz; ++k)
          picard.axial_velocity[L.uz_index(i, k)] = x[static_cast<Eigen::Index>(L.axial(i, k))];
    }
    const Eigen::VectorXd y = pack(state), g = pack(picard);
    const double residual =
        krylov ? std::max(newton_step_size, (g - y).lpNorm<Eigen::Infinity>()) : (g - y).lpNorm<Eigen::Infinity>();
    if (residual > 10 * best_residual) mixer.reset();  // a bad extrapolation: restart the history
    if (std::isfinite(pseudo_dt)) {
      // Switched evolution relaxation: Δτ follows the residual's fall, and is dropped (steady
      // Picard/Newton) once it exceeds 10⁴ revolutions.
      if (residual < previous_residual)
        pseudo_dt *= std::min(4.0, 1.5 * previous_residual / residual);
      else
        pseudo_dt *= 0.5;
      if (pseudo_dt * std::abs(angular_velocity) > 1e4) pseudo_dt = std::numeric_limits<double>::infinity();
    }
    previous_residual = residual;
    best_residual = std::min(best_residual, residual);
    const Eigen::VectorXd y_next = mixer.next(y, g, krylov ? 1.0 : beta);  // Newton: damped by its line search
    if (!y_next.allFinite() || y_next.lpNorm<Eigen::Infinity>() > 1e3) {
      result.failure = fmt::format("diverged at iteration {}: velocities above 1000 times the plate speed", iteration);
      break;
    }
    SwirlState next = picard;
    unpack(y_next, next);

    ViscosityField next_mu = disc.viscosity(next);
    const double alpha = params_.viscosity_relaxation;
    if (alpha < 1) {
      const auto relax = [alpha](std::vector<double>& now, const std::vector<double>& old) {
        for (std::size_t j = 0; j < now.size(); ++j) now[j] = old[j] + alpha * (now[j] - old[j]);
      };
      relax(next_mu.centre, mu.centre);
      relax(next_mu.axial_flux, mu.axial_flux);
      relax(next_mu.radial, mu.radial);
    }
    const double next_torque = disc.wall_torque(next, next_mu, true);
    const double change = std::max(residual, std::abs(next_torque - torque) / (std::abs(next_torque) + 1e-300));
    // A change that keeps growing means the Picard map overshoots: damp it (down to β = 0.05).
    if (!result.residual_history.empty() && change > result.residual_history.back()) {
      if (++rising >= 3 && beta > 0.05) {
        beta = std::max(0.05, 0.5 * beta);
        rising = 0;
      }
    } else {
      rising = 0;
    }
    result.residual_history.push_back(change);
    result.iterations = iteration;
    if (!std::isfinite(next_torque)) {
      result.failure = "non-finite torque at iteration " + std::to_string(iteration);
      break;
    }
    state = std::move(next);
    mu = std::move(next_mu);
    torque = next_torque;
    if (change < params_.tolerance) {
      result.converged = true;
      break;
    }
    // Newton reaches a floor that may sit above a tight tolerance: the rounding of the
    // residual's cancelling terms at large Re (~1e-9 of their size), or the stiff regularised
    // viscosity of a yield-stress liquid at low Bingham numbers (~1e-7). Five changes in a row
    // below floor_limit that gain less than a decade together, where a working Newton step
    // would have gained orders, count as converged at that floor, which is reported.
    constexpr double floor_limit = 1e-5;
    floor_count = krylov && change < floor_limit ? floor_count + 1 : 0;
    if (floor_count >= 5) {
      const auto window = result.residual_history.end() - 5;
      const double largest = *std::max_element(window, result.residual_history.end());
      const double smallest = *std::min_element(window, result.residual_history.end());
      if (largest < 10.0 * smallest || largest < 1e-8) {
        result.converged = true;
        result.accepted_change = largest;
        break;
      }
    }
  }
  if (!result.converged && result.failure.empty())
    result.failure = "no convergence to " + fmt::format("{:g}", params_.tolerance) + " in " +
                     std::to_string(max_iterations) + " iterations (last change " +
                     std::to_string(result.residual_history.empty() ? 0.0 : result.residual_history.back()) + ")";

  state.viscosity = mu.centre;
  state.shear_rate = mu.shear_rate;
  result.torque = torque;
  result.bottom_torque = disc.wall_torque(state, mu, false);
  result.state = std::move(state);
  result.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

SwirlResult SwirlSolver::solve(double angular_velocity, const SwirlState* initial,
                               const SwirlCoupling& coupling) const {
  // Grid sequencing (inertia, single phase, no start given): solve on the grid with half the
  // cells in r and z first (recursively), start here from its interpolated solution, and
  // report the pair's Richardson extrapolation.
  const bool single_phase = coupling.void_fraction.empty() && coupling.torque_density.empty();
  const int nr = params_.grid.radial_cells, nz = params_.grid.axial_cells;
  if (params_.inertia && params_.grid_sequencing && !initial && single_phase && nr >= 8 && nz >= 8 && nr % 2 == 0 &&
      nz % 2 == 0) {
    const auto start = std::chrono::steady_clock::now();
    SwirlParams half = params_;
    half.grid.radial_cells = nr / 2;
    half.grid.axial_cells = nz / 2;
    const SwirlSolver coarse_solver(half);
    const SwirlResult coarse = coarse_solver.solve(angular_velocity);
    if (coarse.converged) {
      const SwirlState guess = interpolate_state(coarse_solver.grid(), coarse.state, grid_, angular_velocity);
      SwirlResult fine = solve_from(angular_velocity, &guess, coupling);
      fine.iterations += coarse.iterations;
      fine.coarse_torque = coarse.torque;
      // Second order in h (docs/performance.md, grid convergence): T + (T − T_2h)/3.
      fine.extrapolated_torque = fine.torque + (fine.torque - coarse.torque) / 3;
      fine.extrapolation_error = std::abs(fine.torque - coarse.torque) / 3 / std::abs(fine.extrapolated_torque);
      fine.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return fine;
    }
  }
  return solve_from(angular_velocity, initial, coupling);
}

SwirlResult SwirlSolver::solve_from(double angular_velocity, const SwirlState* initial,
                                    const SwirlCoupling& coupling) const {
  // Newton converges in a handful of steps or not at all: give the direct attempt only a few
  // dozen before the continuation takes over.
  const bool krylov = params_.inertia && params_.newton_krylov;
  // dozen before the continuation takes over (pseudo-time steps: a few hundred, since Δτ only
  // grows as fast as the residual falls).
  const int newton_budget = params_.pseudo_time_step > 0 ? 200 : 30;
  const int direct_iterations = krylov ? std::min(params_.max_iterations, newton_budget) : params_.max_iterations;
  SwirlResult direct = attempt(angular_velocity, initial, coupling, params_.velocity_relaxation, direct_iterations);
  if (direct.converged || !params_.inertia) return direct;

  // Continuation in Ω: climb from a converged lower speed, growing the step after successes
  // and halving it after failures. Each stage starts from the previous converged state.
  const auto start = std::chrono::steady_clock::now();
  SwirlResult last;
  bool have_last = false;
  double reached = 0, step = angular_velocity / 4;
  int total_iterations = direct.iterations;
  std::vector<double> history = direct.residual_history;
  while (reached < angular_velocity) {
    const double target = std::min(angular_velocity, reached + step);
    SwirlResult stage = attempt(target, have_last ? &last.state : nullptr, coupling,
                                std::min(params_.velocity_relaxation, 0.5), direct_iterations);
    total_iterations += stage.iterations;
    history.insert(history.end(), stage.residual_history.begin(), stage.residual_history.end());
    if (stage.converged) {
      reached = target;
      last = std::move(stage);
      have_last = true;
      step *= 1.5;
    } else {
      step *= 0.5;
      if (step < angular_velocity / 256) {
        direct.failure += fmt::format("; continuation in Ω also failed at {:.4g} rad/s ({:.3g} % of the target)",
                                      target, 100 * target / angular_velocity);
        return direct;
      }
    }
  }
  last.iterations = total_iterations;
  last.residual_history = std::move(history);
  last.wall_time = direct.wall_time + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return last;
}

}  // namespace rheosim::fluid
