#include "rheosim/fluid/swirl.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "rheosim/numerics/anderson.hpp"
#include "swirl_discretisation.hpp"
#include "swirl_iteration.hpp"

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

// μ ← μ_old + α(μ_new − μ_old) on every viscosity field of the iteration; α = 1: unchanged.
void relax_viscosity(ViscosityField& next, const ViscosityField& old, double alpha) {
  if (alpha >= 1) return;
  const auto relax = [alpha](std::vector<double>& now, const std::vector<double>& before) {
    for (std::size_t j = 0; j < now.size(); ++j) now[j] = before[j] + alpha * (now[j] - before[j]);
  };
  relax(next.centre, old.centre);
  relax(next.axial_flux, old.axial_flux);
  relax(next.radial, old.radial);
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

SwirlState SwirlSolver::start_state(double angular_velocity, const SwirlState* initial) const {
  const Layout L(grid_, params_.inertia);
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
  return state;
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
  SwirlSystem system(L, disc, coupling.torque_density, angular_velocity, rest_state());
  SwirlState state = start_state(angular_velocity, initial);

  SwirlResult result;
  ViscosityField mu = disc.viscosity(state);
  Triplets triplets;
  Eigen::VectorXd rhs;
  Eigen::SparseMatrix<double> matrix(static_cast<Eigen::Index>(L.unknowns()), static_cast<Eigen::Index>(L.unknowns()));
  SparseLu lu;
  bool pattern_known = false;
  double torque = disc.wall_torque(state, mu, true);

  double beta = beta_start;
  int rising = 0;       // consecutive iterations whose change grew
  int below_floor = 0;  // consecutive Newton changes below the floor's limit
  // Newton–Krylov (inertia only): the Picard linearisation leaves out how μ depends on the
  // secondary flow and on the cross gradients, which strong shear thinning makes large; GMRES
  // with the exact Jacobian supplies it, and the Picard LU is its preconditioner.
  const bool krylov = L.inertia && params_.newton_krylov;
  numerics::AndersonMixer mixer(krylov ? 0 : params_.anderson_depth);
  // Pseudo-time step: starts at a fraction of a revolution, only used with inertia.
  const double pseudo_start = params_.pseudo_time_step > 0
                                  ? params_.pseudo_time_step / (std::abs(angular_velocity) + 1e-300)
                                  : std::numeric_limits<double>::infinity();
  double pseudo_dt = params_.inertia ? pseudo_start : std::numeric_limits<double>::infinity();
  double best_residual = std::numeric_limits<double>::infinity();
  double previous_residual = std::numeric_limits<double>::infinity();
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
    if (krylov && all_finite(x)) x = system.newton_krylov_step(state, x, pseudo_dt, lu, triplets);
    if (!all_finite(x)) {
      result.failure = "non-finite values (NaN/inf) at iteration " + std::to_string(iteration);
      break;
    }

    // The Picard map's output G(y); its mix with earlier iterates (Anderson) is the next y.
    const SwirlState picard = system.picard_state(x, state);
    const Eigen::VectorXd y = system.pack(state), g = system.pack(picard);
    const double residual = krylov ? std::max(system.newton_step_size(), (g - y).lpNorm<Eigen::Infinity>())
                                   : (g - y).lpNorm<Eigen::Infinity>();
    if (residual > 10 * best_residual) mixer.reset();  // a bad extrapolation: restart the history
    pseudo_dt = next_pseudo_time_step(pseudo_dt, residual, previous_residual, angular_velocity);
    previous_residual = residual;
    best_residual = std::min(best_residual, residual);
    const Eigen::VectorXd y_next = mixer.next(y, g, krylov ? 1.0 : beta);  // Newton: damped by its line search
    if (!y_next.allFinite() || y_next.lpNorm<Eigen::Infinity>() > 1e3) {
      result.failure = fmt::format("diverged at iteration {}: velocities above 1000 times the plate speed", iteration);
      break;
    }
    SwirlState next = picard;
    system.unpack(y_next, next);

    ViscosityField next_mu = disc.viscosity(next);
    relax_viscosity(next_mu, mu, params_.viscosity_relaxation);
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
    if (!krylov) continue;
    if (const std::optional<double> floor = newton_floor(result.residual_history, below_floor)) {
      result.converged = true;  // at the floor, which is reported
      result.accepted_change = *floor;
      break;
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
