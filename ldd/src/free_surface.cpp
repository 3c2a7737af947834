#include "rheosim/ldd/free_surface.hpp"
#include "free_surface_internal.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace rheosim::ldd {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

const char* kind_name(FreeNode k) {
  switch (k) {
    case FreeNode::interior:
      return "interior";
    case FreeNode::surface:
      return "free-surface";
    case FreeNode::splash:
      return "splash";
    case FreeNode::wall:
      return "wall";
    case FreeNode::corner:
      return "corner";
    default:
      return "idle wall";
  }
}

}  // namespace

// ------------------------------------------------------------------------------ solver

FreeSurfaceSolver::FreeSurfaceSolver(FreeSurfaceParams params, std::vector<std::shared_ptr<const Boundary>> boundaries,
                                     FreeSurfaceCloud cloud)
    : params_(std::move(params)), dim_(params_.dimension), boundaries_(std::move(boundaries)) {
  params_.check();
  pressure_amg_ = numerics::AmgPreconditioner(params_.pressure_amg);
  velocity_amg_ = numerics::AmgPreconditioner(params_.velocity_amg);
  const auto dim = static_cast<std::size_t>(dim_);
  const std::size_t n = cloud.size();
  if (cloud.dimension != dim_ || cloud.positions.size() != dim * n || cloud.normals.size() != dim * n ||
      cloud.is_corner.size() != n || cloud.boundary.size() != n)
    throw std::invalid_argument("LDD free-surface solver: node cloud arrays have inconsistent sizes");
  for (int b : cloud.boundary)
    if (b >= static_cast<int>(boundaries_.size()))
      throw std::invalid_argument("LDD free-surface solver: a wall node names a boundary that does not exist");
  positions_ = std::move(cloud.positions);
  normals_ = std::move(cloud.normals);
  corner_ = std::move(cloud.is_corner);
  boundary_of_ = std::move(cloud.boundary);
  kinds_.resize(n);
  for (std::size_t i = 0; i < n; ++i) kinds_[i] = cloud.is_wall[i] ? FreeNode::wall : FreeNode::interior;
  support_radius_ = params_.smoothing_ratio * params_.spacing;
  search_radius_ = support_radius_ + params_.neighbour_skin * params_.spacing;
  velocity_.assign(dim * n, 0.0);
  std::vector<double> v(dim);
  for (std::size_t i = 0; i < n; ++i)
    if (boundary_of_[i] >= 0) {
      boundaries_[static_cast<std::size_t>(boundary_of_[i])]->velocity(0.0, v);
      for (std::size_t d = 0; d < dim; ++d) velocity_[dim * i + d] = v[d];
    }
  previous_velocity_ = velocity_;
  pressure_.assign(n, 0.0);
  shear_rate_.assign(n, 0.0);
  viscosity_.assign(n, params_.rheology->viscosity(0.0));
  // Probe directions of the empty-cone test: every 10° in 2D, a 64-point Fibonacci sphere in 3D.
  if (dim_ == 2) {
    for (int q = 0; q < 36; ++q) {
      const double angle = 2 * std::numbers::pi * q / 36;
      probe_directions_.insert(probe_directions_.end(), {std::cos(angle), std::sin(angle)});
    }
  } else {
    const int count = 64;
    for (int q = 0; q < count; ++q) {
      const double z = 1 - (2.0 * q + 1) / count, radius = std::sqrt(1 - z * z);
      const double angle = q * std::numbers::pi * (3 - std::sqrt(5.0));
      probe_directions_.insert(probe_directions_.end(), {radius * std::cos(angle), radius * std::sin(angle), z});
    }
    // Visited as a nearest-neighbour tour, so that a probe is mostly covered by the direction
    // that covered the one before it (classify starts its scan there; the test's outcome does
    // not depend on the order).
    std::vector<double> tour(probe_directions_.begin(), probe_directions_.begin() + 3);
    std::vector<bool> visited(count, false);
    visited[0] = true;
    for (int step = 1, current = 0; step < count; ++step) {
      int next = -1;
      double best = -2;
      for (int q = 0; q < count; ++q) {
        if (visited[static_cast<std::size_t>(q)]) continue;
        double dot = 0;
        for (std::size_t d = 0; d < 3; ++d)
          dot += probe_directions_[3 * static_cast<std::size_t>(q) + d] *
                 probe_directions_[3 * static_cast<std::size_t>(current) + d];
        if (dot > best) {
          best = dot;
          next = q;
        }
      }
      visited[static_cast<std::size_t>(next)] = true;
      tour.insert(tour.end(), probe_directions_.begin() + 3 * next, probe_directions_.begin() + 3 * next + 3);
      current = next;
    }
    probe_directions_ = std::move(tour);
  }
  rebuild_neighbours();

  // Rest values from the initial cloud: n₀ and ρ₀ are the medians over fluid nodes that are
  // not near the cloud's own surface (a lattice interior is the large majority).
  std::vector<double> counts, densities;
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_fluid(i)) continue;
    counts.push_back(static_cast<double>(neighbours_.offsets[i + 1] - neighbours_.offsets[i]));
    densities.push_back(kernel_density(i));
  }
  if (counts.empty()) throw std::invalid_argument("LDD free-surface solver: the cloud has no fluid nodes");
  const auto median = [](std::vector<double>& values) {
    const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), middle, values.end());
    return *middle;
  };
  rest_count_ = median(counts);
  rest_density_ = median(densities);
  classify();

  if (params_.hydrostatic_start) {
    // p = ρ|g| × depth below the highest fluid node along −g (a flat-topped initial column).
    const double g =
        std::sqrt(std::inner_product(params_.gravity.begin(), params_.gravity.end(), params_.gravity.begin(), 0.0));
    if (g > 0) {
      double top = -std::numeric_limits<double>::infinity();
      const auto height = [&](std::size_t i) {
        double s = 0;
        for (std::size_t d = 0; d < dim; ++d) s -= params_.gravity[d] / g * positions_[dim * i + d];
        return s;
      };
      for (std::size_t i = 0; i < n; ++i)
        if (kinds_[i] == FreeNode::interior || kinds_[i] == FreeNode::surface) top = std::max(top, height(i));
      for (std::size_t i = 0; i < n; ++i)
        if (kinds_[i] == FreeNode::interior || kinds_[i] == FreeNode::wall || kinds_[i] == FreeNode::corner)
          pressure_[i] = params_.density * g * std::max(0.0, top - height(i));
    }
  }
}

std::size_t FreeSurfaceSolver::fluid_node_count() const {
  std::size_t count = 0;
  for (std::size_t i = 0; i < kinds_.size(); ++i) count += is_fluid(i) ? 1 : 0;
  return count;
}

FreeSurfaceState FreeSurfaceSolver::state() const {
  return FreeSurfaceState{
      time_,       steps_,     first_step_, positions_,  velocity_, previous_velocity_,    pressure_,
      shear_rate_, viscosity_, kinds_,      neighbours_, times_,    pressure_amg_.state(), velocity_amg_.state()};
}

void FreeSurfaceSolver::restore(FreeSurfaceState state) {
  const std::size_t n = kinds_.size(), nd = static_cast<std::size_t>(dim_) * n;
  const auto fits = [](const std::vector<double>& v, std::size_t size) { return v.size() == size; };
  if (state.kinds.size() != n || !fits(state.positions, nd) || !fits(state.velocity, nd) ||
      !fits(state.previous_velocity, nd) || !fits(state.pressure, n) || !fits(state.shear_rate, n) ||
      !fits(state.viscosity, n))
    throw std::invalid_argument(
        fmt::format("LDD free-surface state: its arrays do not fit this cloud of {} nodes in {}D", n, dim_));
  for (std::size_t i = 0; i < n; ++i)
    if ((state.kinds[i] <= FreeNode::splash) != is_fluid(i) || state.kinds[i] > FreeNode::idle_wall)
      throw std::invalid_argument(fmt::format("LDD free-surface state: node {} is a {} node in the state but {} here",
                                              i, kind_name(state.kinds[i]), is_fluid(i) ? "fluid" : "a wall"));
  const numerics::NeighbourList& nb = state.neighbours;
  bool list_fits = nb.offsets.size() == n + 1 && nb.offsets.front() == 0 && nb.offsets.back() == nb.indices.size() &&
                   nb.distances.size() == nb.indices.size();
  for (std::size_t i = 0; list_fits && i < n; ++i) list_fits = nb.offsets[i] <= nb.offsets[i + 1];
  for (std::size_t k = 0; list_fits && k < nb.indices.size(); ++k) list_fits = nb.indices[k] < n;
  if (!list_fits) throw std::invalid_argument("LDD free-surface state: its neighbour list does not fit the cloud");
  for (const numerics::AmgState* amg : {&state.pressure_amg, &state.velocity_amg})
    if (!amg->empty() && (amg->diagonal.size() != n || amg->offsets.size() != n + 1))
      throw std::invalid_argument("LDD free-surface state: a kept AMG set-up matrix does not fit the cloud");
  pressure_amg_.restore(state.pressure_amg);
  velocity_amg_.restore(state.velocity_amg);
  time_ = state.time;
  steps_ = state.steps;
  first_step_ = state.first_step;
  positions_ = std::move(state.positions);
  velocity_ = std::move(state.velocity);
  previous_velocity_ = std::move(state.previous_velocity);
  pressure_ = std::move(state.pressure);
  shear_rate_ = std::move(state.shear_rate);
  viscosity_ = std::move(state.viscosity);
  kinds_ = std::move(state.kinds);
  neighbours_ = std::move(state.neighbours);
  candidates_ = numerics::NeighbourList{};  // searched afresh at the next step (the same list either way)
  candidate_positions_.clear();
  steps_since_search_ = 0;
  times_ = state.times;
}

void FreeSurfaceSolver::rebuild_neighbours() {
  const double skin = params_.neighbour_reuse_skin * params_.spacing;
  const auto dim = static_cast<std::size_t>(dim_);
  // A pair now within the search radius but not a candidate has closed by more than the skin,
  // so one of its nodes has moved more than half of it: search again before that (with a 10 %
  // margin for rounding).
  double moved = 0;  // the largest displacement since the last search
  const bool searched_before = candidate_positions_.size() == positions_.size();
  if (searched_before) {
    const auto count = static_cast<std::ptrdiff_t>(kinds_.size());
    double most = 0;
#pragma omp parallel for schedule(static) reduction(max : most)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      most = std::max(most, detail::squared_distance(&positions_[dim * i], &candidate_positions_[dim * i], dim));
    }
    moved = std::sqrt(most);
    const bool verlet_list = candidates_.node_count() == kinds_.size();  // else the last search was plain
    if (verlet_list && 2.0 * moved < 0.9 * skin) {
      ++steps_since_search_;
      numerics::neighbours_within(candidates_, positions_, dim_, search_radius_, neighbours_);
      return;
    }
  }
  // A Verlet list costs ~1.5 plain searches: worth it only if the nodes, moving as fast as since
  // the last search, would keep it for two steps or more (not for splashing nodes at δt = 1e-3).
  const bool known_speed = searched_before && steps_since_search_ > 0;
  const double per_step = known_speed ? moved / static_cast<double>(steps_since_search_) : 0.0;
  if (skin > 0 && (!known_speed || 0.9 * skin >= 2.0 * 2.0 * per_step)) {
    candidates_ = numerics::find_neighbours(positions_, dim_, search_radius_ + skin);
    numerics::neighbours_within(candidates_, positions_, dim_, search_radius_, neighbours_);
  } else {
    candidates_ = numerics::NeighbourList{};
    neighbours_ = numerics::find_neighbours(positions_, dim_, search_radius_);
  }
  candidate_positions_ = positions_;
  steps_since_search_ = 1;
  ++candidate_searches_;
}

double FreeSurfaceSolver::fluid_volume() const {
  const double cell = std::pow(params_.spacing, dim_);
  double volume = 0;
  for (std::size_t i = 0; i < kinds_.size(); ++i) {
    if (kinds_[i] == FreeNode::interior)
      volume += cell * rest_density_ / kernel_density(i);
    else if (is_fluid(i))
      volume += cell;
  }
  return volume;
}

double FreeSurfaceSolver::kinetic_energy() const {
  const auto dim = static_cast<std::size_t>(dim_);
  double sum = 0;
  for (std::size_t i = 0; i < kinds_.size(); ++i)
    if (is_fluid(i))
      for (std::size_t d = 0; d < dim; ++d) sum += velocity_[dim * i + d] * velocity_[dim * i + d];
  return 0.5 * params_.density * sum * std::pow(params_.spacing, dim_);
}

double FreeSurfaceSolver::potential_energy() const {
  const auto dim = static_cast<std::size_t>(dim_);
  double sum = 0;
  for (std::size_t i = 0; i < kinds_.size(); ++i)
    if (is_fluid(i))
      for (std::size_t d = 0; d < dim; ++d) sum -= params_.gravity[d] * positions_[dim * i + d];
  return params_.density * sum * std::pow(params_.spacing, dim_);
}

FreeSurfaceStats FreeSurfaceSolver::step() {
  const auto dim = static_cast<std::size_t>(dim_);
  const std::size_t n = kinds_.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  const double dt = params_.time_step, rho = params_.density;
  const std::vector<double>& g = params_.gravity;
  const double g_norm = std::sqrt(std::inner_product(g.begin(), g.end(), g.begin(), 0.0));
  const numerics::NeighbourList& nb = neighbours_;
  FreeSurfaceStats stats;

  // 1. Operators (eqs. 13–16) and the free-surface classification.
  auto t0 = Clock::now();
  build_operators(positions_, dim_, nb,
                  OperatorSettings{support_radius_, params_.min_moment_rcond, params_.centred_gradient}, operators_);
  keep_laplacian_positive();
  const Operators& ops = operators_;
  last_kinds_ = kinds_;
  classify();
  regradient_for_boundary_values();
  stats.positivity_guarded = laplacian_guarded_;
  for (std::size_t i = 0; i < n; ++i) {
    stats.surface_nodes += kinds_[i] == FreeNode::surface ? 1 : 0;
    stats.splash_nodes += kinds_[i] == FreeNode::splash ? 1 : 0;
  }
  times_.operators += seconds_since(t0);

  // 2. ∇u (eq. 14), γ̇ = √(2E:E) (eq. 5), μ(γ̇), explicit ∇·(μ(∇u)ᵀ).
  t0 = Clock::now();
  const std::size_t dd = dim * dim;
  velocity_gradient_.assign(dd * n, 0.0);
  const auto velocity_gradient_of = [&](std::span<const double> u, std::span<double> out) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      double grad[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};  // grad[a·dim + b] = ∂u_a/∂x_b
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
        const std::size_t j = nb.indices[k];
        for (std::size_t a = 0; a < dim; ++a) {
          const double du = u[dim * j + a] - u[dim * i + a];
          for (std::size_t b = 0; b < dim; ++b) grad[a * dim + b] += ops.gradient[k * dim + b] * du;
        }
      }
      for (std::size_t c = 0; c < dd; ++c) out[dd * i + c] = grad[c];
    }
  };
  velocity_gradient_of(velocity_, velocity_gradient_);
  for (std::size_t i = 0; i < n; ++i) {
    const double* grad = &velocity_gradient_[dd * i];
    double e2 = 0;  // E:E
    for (std::size_t a = 0; a < dim; ++a)
      for (std::size_t b = 0; b < dim; ++b) {
        const double e = 0.5 * (grad[a * dim + b] + grad[b * dim + a]);
        e2 += e * e;
      }
    shear_rate_[i] = std::sqrt(2.0 * e2);  // eq. 5
  }
  params_.rheology->viscosity(shear_rate_, viscosity_);
  // Optional (SolverParams::transpose_stress): (∇·(μ(∇u)ᵀ))_a = Σ_b ∂_b(μ ∂u_b/∂x_a) explicit, on
  // interior nodes. Off by default: explicit, it is unstable once δt μ_max/(ρΔ²) ≫ 1 (Bingham
  // m = 1000 s: μ_max = 25 025 Pa·s, ratio ~10²–10³) — the dam break blew up within 0.35 s with
  // it (docs/ldd.md). It vanishes for constant μ.
  transpose_stress_.assign(dim * n, 0.0);
  stress_component_.resize(n);
  stress_gradient_.resize(dim * n);
  if (params_.transpose_stress) {
    for (std::size_t b = 0; b < dim; ++b)
      for (std::size_t a = 0; a < dim; ++a) {
        for (std::size_t i = 0; i < n; ++i)
          stress_component_[i] = viscosity_[i] * velocity_gradient_[dd * i + b * dim + a];
        gradient(nb, ops, stress_component_, stress_gradient_);
        for (std::size_t i = 0; i < n; ++i)
          if (kinds_[i] == FreeNode::interior) transpose_stress_[dim * i + a] += stress_gradient_[dim * i + b];
      }
  }
  times_.rheology += seconds_since(t0);

  // 3. Semi-implicit momentum (eq. 19), one solve per component.
  t0 = Clock::now();
  pressure_gradient_.resize(dim * n);
  impose_boundary_pressure();
  gradient(nb, ops, previous_pressure_, pressure_gradient_);
  momentum_matrix_.pattern = &nb;
  momentum_matrix_.diagonal.resize(n);
  momentum_matrix_.off_diagonal.resize(nb.pair_count());
  rhs_.assign(dim * n, 0.0);  // component-major: rhs_[d·n + i]
  const double next_time = time_ + dt;
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const std::size_t begin = nb.offsets[i], end = nb.offsets[i + 1];
    const FreeNode kind = kinds_[i];
    if (kind == FreeNode::interior || kind == FreeNode::surface) {
      double sum = 0;
      for (std::size_t k = begin; k < end; ++k) {
        const double c = dt * 0.5 * (viscosity_[i] + viscosity_[nb.indices[k]]) * ops.laplacian[k];
        momentum_matrix_.off_diagonal[k] = -c;
        sum += c;
      }
      momentum_matrix_.diagonal[i] = rho + sum;
      for (std::size_t d = 0; d < dim; ++d)
        rhs_[d * n + i] = rho * velocity_[dim * i + d] +
                          dt * (-pressure_gradient_[dim * i + d] + rho * g[d] + transpose_stress_[dim * i + d]);
      continue;
    }
    for (std::size_t k = begin; k < end; ++k) momentum_matrix_.off_diagonal[k] = 0.0;
    if (kind == FreeNode::splash) {  // ballistic: too few neighbours for the operators
      momentum_matrix_.diagonal[i] = rho;
      for (std::size_t d = 0; d < dim; ++d) rhs_[d * n + i] = rho * (velocity_[dim * i + d] + dt * g[d]);
    } else {  // wall: no slip at the wall's velocity (Dirichlet)
      momentum_matrix_.diagonal[i] = 1.0;
      double v[3] = {0, 0, 0};
      const Boundary* boundary =
          boundary_of_[i] >= 0 ? boundaries_[static_cast<std::size_t>(boundary_of_[i])].get() : nullptr;
      if (boundary) boundary->velocity(next_time, std::span<double>(v, dim));
      if (boundary && boundary->slip()) {
        // Free slip: the wall's normal velocity plus the tangential part of the fluid's (Shepard
        // average of the fluid neighbours' u_{n−1}, eq. 12); the fluid's own normal velocity
        // where it leaves the wall (below).
        double mean[3] = {0, 0, 0}, wsum = 0;
        for (std::size_t k = begin; k < end; ++k) {
          const std::size_t j = nb.indices[k];
          if (kinds_[j] != FreeNode::interior && kinds_[j] != FreeNode::surface) continue;
          wsum += ops.weights[k];
          for (std::size_t d = 0; d < dim; ++d) mean[d] += ops.weights[k] * velocity_[dim * j + d];
        }
        if (wsum > 0) {
          const double* normal = &normals_[dim * i];
          double relative_normal = 0;
          for (std::size_t d = 0; d < dim; ++d) {
            mean[d] = mean[d] / wsum - v[d];
            relative_normal += mean[d] * normal[d];
          }
          // Unilateral contact: a wall can push the fluid but not pull it. Where the fluid's
          // normal velocity leaves the wall (relative_normal > 0: the rising mould's slanted side
          // receding from resting concrete, or concrete sinking away from its overhang) the wall
          // node takes the fluid's whole velocity. Imposing the recession (0.0164 m/s on the
          // mould) demanded an expansion of 0.4 /s that only suction could supply, and the
          // no-tension clip turned that into p = 0 in the whole cake (docs/ldd.md).
          const double held = relative_normal > 0 ? 0.0 : relative_normal;
          for (std::size_t d = 0; d < dim; ++d) v[d] += mean[d] - held * normal[d];
        }
      }
      for (std::size_t d = 0; d < dim; ++d) rhs_[d * n + i] = v[d];
    }
  }
  new_velocity_.resize(dim * n);
  component_.resize(n);
  const double sqrt_n = std::sqrt(static_cast<double>(n));
  numerics::KrylovSettings velocity_settings{params_.velocity_tolerance,
                                             params_.velocity_tolerance * rho * std::max(g_norm * dt, 1e-12) * sqrt_n,
                                             params_.max_iterations,
                                             {}};
  numerics::SparseLu momentum_lu;
  if (params_.velocity_preconditioner == Preconditioner::sparse_lu && dim_ == 2 &&
      momentum_lu.factorise(momentum_matrix_))
    velocity_settings.preconditioner = momentum_lu.as_preconditioner();
  const bool velocity_amg = params_.velocity_preconditioner == Preconditioner::amg;
  bool velocity_hierarchy_fresh = false;
  if (velocity_amg) {
    velocity_hierarchy_fresh = velocity_amg_.prepare(momentum_matrix_);
    velocity_settings.preconditioner = velocity_amg_.as_preconditioner();
  }
  bool velocity_converged = true;
  int most_velocity_iterations = 0;
  for (std::size_t d = 0; d < dim; ++d) {
    for (std::size_t i = 0; i < n; ++i) component_[i] = velocity_[dim * i + d];
    auto result = numerics::bicgstab(momentum_matrix_, std::span<const double>(&rhs_[d * n], n), component_,
                                     velocity_settings, krylov_);
    if (!result.converged && velocity_amg && !velocity_hierarchy_fresh) {
      // A hierarchy kept from earlier steps no longer fits the matrix: rebuild it, solve again.
      velocity_amg_.setup(momentum_matrix_);
      velocity_hierarchy_fresh = true;
      ++stats.repeated_solves;
      for (std::size_t i = 0; i < n; ++i) component_[i] = velocity_[dim * i + d];
      stats.velocity_iterations += result.iterations;
      result = numerics::bicgstab(momentum_matrix_, std::span<const double>(&rhs_[d * n], n), component_,
                                  velocity_settings, krylov_);
    }
    most_velocity_iterations = std::max(most_velocity_iterations, result.iterations);
    stats.velocity_iterations += result.iterations;
    stats.velocity_residual = std::max(stats.velocity_residual, result.relative_residual);
    velocity_converged = velocity_converged && result.converged;
    for (std::size_t i = 0; i < n; ++i) new_velocity_[dim * i + d] = component_[i];
  }
  if (velocity_amg) velocity_amg_.record_iterations(most_velocity_iterations);
  times_.momentum += seconds_since(t0);

  // 4. PPE (eq. 17) for φ = p_n − p_{n−1}.
  t0 = Clock::now();
  divergence_.resize(n);
  divergence(nb, ops, new_velocity_, divergence_);
  pressure_matrix_.pattern = &nb;
  pressure_matrix_.diagonal.resize(n);
  pressure_matrix_.off_diagonal.resize(nb.pair_count());
  rhs_.resize(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const std::size_t begin = nb.offsets[i], end = nb.offsets[i + 1];
    double sum = 0;
    switch (kinds_[i]) {
      case FreeNode::interior:
        for (std::size_t k = begin; k < end; ++k) {
          pressure_matrix_.off_diagonal[k] = ops.laplacian[k];
          sum += ops.laplacian[k];
        }
        pressure_matrix_.diagonal[i] = -sum;
        rhs_[i] = rho / dt * divergence_[i];
        break;
      case FreeNode::wall:
      case FreeNode::corner: {
        // Wall pressure extrapolated from the fluid (eq. 12 with the hydrostatic offset):
        //   p_w = Σ_j W_wj (p_j + ρ g·(x_w − x_j)) / Σ_j W_wj over fluid neighbours j,
        // which gives n·∇p = ρ n·g at rest (eq. 17's Neumann condition) and, unlike a Neumann
        // row through the wall node's own gradient, has only positive couplings. As a row for φ:
        //   φ_w − Σ w_j φ_j = Σ w_j (p_j + ρ g·(x_w − x_j)) − p_w.
        // A wall node that sees only surface nodes stands above the fluid: p = p_atm there (the
        // hydrostatic extrapolation would give suction that pulls the fluid up the wall).
        double wsum = 0;
        for (std::size_t k = begin; k < end; ++k) {
          const FreeNode kj = kinds_[nb.indices[k]];
          if (kj == FreeNode::interior || kj == FreeNode::surface) wsum += ops.weights[k];
        }
        if (dry_wall_[i]) wsum = 0;
        double source = 0;
        for (std::size_t k = begin; k < end; ++k) {
          const std::size_t j = nb.indices[k];
          const FreeNode kj = kinds_[j];
          const double w =
              (wsum > 0 && (kj == FreeNode::interior || kj == FreeNode::surface)) ? ops.weights[k] / wsum : 0.0;
          pressure_matrix_.off_diagonal[k] = -w;
          if (w == 0) continue;
          double hydrostatic = 0;
          for (std::size_t d = 0; d < dim; ++d)
            hydrostatic += rho * g[d] * (positions_[dim * i + d] - positions_[dim * j + d]);
          source += w * (previous_pressure_[j] + hydrostatic);
        }
        pressure_matrix_.diagonal[i] = 1.0;
        rhs_[i] = source - previous_pressure_[i];
        break;
      }
      default:  // surface, splash, idle wall: p_n = p_atm = 0
        for (std::size_t k = begin; k < end; ++k) pressure_matrix_.off_diagonal[k] = 0.0;
        pressure_matrix_.diagonal[i] = 1.0;
        rhs_[i] = -previous_pressure_[i];
    }
  }
  increment_.assign(n, 0.0);
  numerics::KrylovSettings pressure_settings{
      params_.pressure_tolerance,
      params_.pressure_tolerance * rho * std::max(g_norm, 1e-12) / params_.spacing * sqrt_n,
      params_.max_iterations,
      {}};
  numerics::SparseLu pressure_lu;
  if (params_.pressure_preconditioner == Preconditioner::sparse_lu && dim_ == 2 &&
      pressure_lu.factorise(pressure_matrix_))
    pressure_settings.preconditioner = pressure_lu.as_preconditioner();
  const bool pressure_amg = params_.pressure_preconditioner == Preconditioner::amg;
  bool pressure_hierarchy_fresh = false;
  if (pressure_amg) {
    pressure_hierarchy_fresh = pressure_amg_.prepare(pressure_matrix_);
    pressure_settings.preconditioner = pressure_amg_.as_preconditioner();
  }
  auto pressure_result = numerics::bicgstab(pressure_matrix_, rhs_, increment_, pressure_settings, krylov_);
  const auto repeat_pressure_solve = [&] {
    ++stats.repeated_solves;
    increment_.assign(n, 0.0);
    const int failed_iterations = pressure_result.iterations;
    pressure_result = numerics::bicgstab(pressure_matrix_, rhs_, increment_, pressure_settings, krylov_);
    pressure_result.iterations += failed_iterations;
  };
  if (!pressure_result.converged && pressure_amg && !pressure_hierarchy_fresh) {
    // As for the velocity: the kept hierarchy was built for an older cloud and classification.
    pressure_amg_.setup(pressure_matrix_);
    repeat_pressure_solve();
  }
  numerics::SparseLu pressure_direct;  // outlives pressure_settings' use in the stability probe
  if (!pressure_result.converged && !(pressure_result.relative_residual < 1e3 * params_.pressure_tolerance) &&
      dim_ == 2 && params_.pressure_preconditioner != Preconditioner::sparse_lu &&
      pressure_direct.factorise(pressure_matrix_)) {
    // Last resort in 2D: the exact factors as the preconditioner (seconds at 200 000 nodes).
    pressure_settings.preconditioner = pressure_direct.as_preconditioner();
    ++stats.repeated_with_lu;
    repeat_pressure_solve();
  }
  if (pressure_amg) pressure_amg_.record_iterations(pressure_result.iterations);
  stats.pressure_iterations = pressure_result.iterations;
  stats.pressure_residual = pressure_result.relative_residual;
  if (params_.stability_probe_iterations > 0) probe_step_map(velocity_settings, pressure_settings, stats);
  // No tension: p_n = max(p_{n−1} + φ, p_atm). A free-surface fluid cannot pull on the void, and
  // without the clip the suction at a stretching toe (ρ/δt ∇·u* > 0 on a torn cloud) grew without
  // bound; the velocity is corrected with the increment actually applied.
  std::vector<double> new_pressure(n);
  for (std::size_t i = 0; i < n; ++i) {
    new_pressure[i] = std::max(previous_pressure_[i] + increment_[i], 0.0);
    increment_[i] = new_pressure[i] - previous_pressure_[i];
  }
  increment_gradient_.resize(dim * n);
  gradient(nb, ops, increment_, increment_gradient_);
  bool finite = true;
  double max_speed_squared = 0;
  std::size_t fastest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (kinds_[i] == FreeNode::interior || kinds_[i] == FreeNode::surface)
      for (std::size_t d = 0; d < dim; ++d) new_velocity_[dim * i + d] -= dt / rho * increment_gradient_[dim * i + d];
    double speed2 = 0;
    for (std::size_t d = 0; d < dim; ++d) {
      speed2 += new_velocity_[dim * i + d] * new_velocity_[dim * i + d];
      if (!std::isfinite(new_velocity_[dim * i + d])) finite = false;
    }
    if (!std::isfinite(new_pressure[i])) finite = false;
    // Splash nodes fall ballistically (no operators): they do not limit the Courant number.
    if ((kinds_[i] == FreeNode::interior || kinds_[i] == FreeNode::surface) && speed2 > max_speed_squared) {
      max_speed_squared = speed2;
      fastest = i;
    }
  }
  times_.pressure += seconds_since(t0);

  // 5. Divergence checks; the state is untouched until they pass.
  stats.max_speed = std::sqrt(max_speed_squared);
  stats.courant = stats.max_speed * dt / params_.spacing;
  if (!finite)
    throw DivergenceError(
        fmt::format("NaN or infinite velocity/pressure at t = {:.6g} s (step {})", next_time, steps_ + 1));
  if (stats.courant > params_.max_courant)
    throw DivergenceError(
        fmt::format("Courant number max|u|·δt/Δ = {:.3g} exceeds {:.3g} at t = {:.6g} s (step {}, max |u| = "
                    "{:.4g} m/s at a {} node at ({:.4g}, {:.4g}{}){}): reduce time.step",
                    stats.courant, params_.max_courant, next_time, steps_ + 1, stats.max_speed,
                    kind_name(kinds_[fastest]), positions_[dim * fastest], positions_[dim * fastest + 1],
                    dim == 3 ? fmt::format(", {:.4g}", positions_[dim * fastest + 2]) : std::string(),
                    fmt::format(", {} neighbours", nb.offsets[fastest + 1] - nb.offsets[fastest])));
  if (!pressure_result.converged && !(pressure_result.relative_residual < 1e3 * params_.pressure_tolerance)) {
    const numerics::FloatingGroups floating = numerics::floating_groups(pressure_matrix_);
    const std::size_t at = floating.largest_member;
    throw DivergenceError(fmt::format(
        "pressure solve failed at t = {:.6g} s (step {}): relative residual {:.3g} after {} iterations ({} repeated "
        "solve(s)); {}",
        next_time, steps_ + 1, pressure_result.relative_residual, pressure_result.iterations, stats.repeated_solves,
        floating.groups == 0
            ? std::string("every node reaches a free-surface node through the pressure matrix")
            : fmt::format("{} node group(s), {} nodes, reach no free-surface node (a singular Neumann block); the "
                          "largest, {} nodes, includes a {} node at ({:.4g}, {:.4g}{})",
                          floating.groups, floating.nodes, floating.largest, kind_name(kinds_[at]),
                          positions_[dim * at], positions_[dim * at + 1],
                          dim == 3 ? fmt::format(", {:.4g}", positions_[dim * at + 2]) : std::string())));
  }
  if (!velocity_converged && !(stats.velocity_residual < 1e3 * params_.velocity_tolerance))
    throw DivergenceError(fmt::format("velocity solve failed at t = {:.6g} s (step {}): relative residual {:.3g}",
                                      next_time, steps_ + 1, stats.velocity_residual));
  stats.pressure_accepted_unconverged = !pressure_result.converged;
  stats.velocity_accepted_unconverged = !velocity_converged;

  // 6. Commit, advect (eq. 20), move the walls, keep fluid off the boundaries.
  t0 = Clock::now();
  pressure_.swap(new_pressure);
  velocity_gradient_of(new_velocity_, velocity_gradient_);  // ∇u_n, to carry velocities along PBD shifts
  const double older = first_step_ ? 0.0 : 0.5;
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (is_fluid(i)) {
      for (std::size_t d = 0; d < dim; ++d)
        positions_[dim * i + d] += ((1.0 + older) * new_velocity_[dim * i + d] - older * velocity_[dim * i + d]) * dt;
      keep_off_boundaries(i, next_time, new_velocity_);
    } else if (boundary_of_[i] >= 0) {  // wall nodes move with their boundary (slip or not)
      double v[3] = {0, 0, 0};
      boundaries_[static_cast<std::size_t>(boundary_of_[i])]->velocity(next_time, std::span<double>(v, dim));
      for (std::size_t d = 0; d < dim; ++d) positions_[dim * i + d] += v[d] * dt;
    }
  }
  previous_velocity_.swap(velocity_);
  velocity_.swap(new_velocity_);
  first_step_ = false;
  time_ = next_time;
  ++steps_;
  times_.advection += seconds_since(t0);

  t0 = Clock::now();
  rebuild_neighbours();
  times_.neighbours += seconds_since(t0);

  // 7. PBD reordering that keeps the volume.
  t0 = Clock::now();
  reorder(velocity_gradient_);
  double max_shift = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double s2 = 0;
    for (std::size_t d = 0; d < dim; ++d) s2 += shift_[dim * i + d] * shift_[dim * i + d];
    max_shift = std::max(max_shift, s2);
  }
  stats.max_pbd_shift = std::sqrt(max_shift) / params_.spacing;
  times_.reordering += seconds_since(t0);
  return stats;
}

}  // namespace rheosim::ldd
