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

// ------------------------------------------------------------------------------ solver

FreeSurfaceSolver::FreeSurfaceSolver(SolverParams params, std::vector<std::shared_ptr<const Boundary>> boundaries,
                                     NodeCloud cloud)
    : Solver(std::move(params)), boundaries_(std::move(boundaries)) {
  const auto dim = static_cast<std::size_t>(dimension());
  const std::size_t n = cloud.size();
  if (cloud.dimension != dimension() || cloud.positions.size() != dim * n || cloud.normals.size() != dim * n ||
      cloud.boundary.size() != n)
    throw std::invalid_argument("LDD free-surface solver: node cloud arrays have inconsistent sizes");
  for (int b : cloud.boundary)
    if (b >= static_cast<int>(boundaries_.size()))
      throw std::invalid_argument("LDD free-surface solver: a wall node names a boundary that does not exist");
  positions_ = std::move(cloud.positions);
  normals_ = std::move(cloud.normals);
  corner_.resize(n);
  for (std::size_t i = 0; i < n; ++i) corner_[i] = cloud.kinds[i] == NodeKind::corner ? 1 : 0;
  boundary_of_ = std::move(cloud.boundary);
  kinds_.resize(n);
  for (std::size_t i = 0; i < n; ++i) kinds_[i] = cloud.is_wall(i) ? NodeKind::wall : NodeKind::interior;
  search_radius_ = support_radius_ + params_.neighbour_skin * params_.spacing;
  velocity_.assign(dim * n, 0.0);
  std::vector<double> v(dim);
  for (std::size_t i = 0; i < n; ++i)
    if (boundary_of_[i] >= 0) {
      boundaries_[static_cast<std::size_t>(boundary_of_[i])]->surface_velocity(0.0, v);
      for (std::size_t d = 0; d < dim; ++d) velocity_[dim * i + d] = v[d];
    }
  previous_velocity_ = velocity_;
  pressure_.assign(n, 0.0);
  shear_rate_.assign(n, 0.0);
  viscosity_.assign(n, params_.rheology->viscosity(0.0));
  // Probe directions of the empty-cone test: every 10° in 2D, a 64-point Fibonacci sphere in 3D.
  if (dimension() == 2) {
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
        if (is_continuum(i)) top = std::max(top, height(i));
      for (std::size_t i = 0; i < n; ++i)
        if (kinds_[i] == NodeKind::interior || kinds_[i] == NodeKind::wall || kinds_[i] == NodeKind::corner)
          pressure_[i] = params_.density * g * std::max(0.0, top - height(i));
    }
  }
}

SolverState FreeSurfaceSolver::state() const { return common_state(); }

void FreeSurfaceSolver::restore(SolverState state) {
  restore_common_state(state, "LDD free-surface");
  candidates_ = numerics::NeighbourList{};  // searched afresh at the next step (the same list either way)
  candidate_positions_.clear();
  steps_since_search_ = 0;
}

void FreeSurfaceSolver::rebuild_neighbours() {
  const double skin = params_.neighbour_reuse_skin * params_.spacing;
  const auto dim = static_cast<std::size_t>(dimension());
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
      numerics::neighbours_within(candidates_, positions_, dimension(), search_radius_, neighbours_);
      return;
    }
  }
  // A Verlet list costs ~1.5 plain searches: worth it only if the nodes, moving as fast as since
  // the last search, would keep it for two steps or more (not for splashing nodes at δt = 1e-3).
  const bool known_speed = searched_before && steps_since_search_ > 0;
  const double per_step = known_speed ? moved / static_cast<double>(steps_since_search_) : 0.0;
  if (skin > 0 && (!known_speed || 0.9 * skin >= 2.0 * 2.0 * per_step)) {
    candidates_ = numerics::find_neighbours(positions_, dimension(), search_radius_ + skin);
    numerics::neighbours_within(candidates_, positions_, dimension(), search_radius_, neighbours_);
  } else {
    candidates_ = numerics::NeighbourList{};
    neighbours_ = numerics::find_neighbours(positions_, dimension(), search_radius_);
  }
  candidate_positions_ = positions_;
  steps_since_search_ = 1;
  ++candidate_searches_;
}

bool FreeSurfaceSolver::in_bulk(std::size_t i) const {
  if (kinds_[i] != NodeKind::interior) return false;
  const auto dim = static_cast<std::size_t>(dimension());
  const double h2 = support_radius_ * support_radius_;
  for (std::size_t k = neighbours_.offsets[i]; k < neighbours_.offsets[i + 1]; ++k) {
    const std::size_t j = neighbours_.indices[k];
    if ((kinds_[j] == NodeKind::surface || kinds_[j] == NodeKind::splash) &&
        detail::squared_distance(&positions_[dim * i], &positions_[dim * j], dim) < h2)
      return false;
  }
  return true;
}

double FreeSurfaceSolver::bulk_density_ratio() const {
  return bulk_mean([&](std::size_t i) { return kernel_density(i) / rest_density_; }, 1.0);
}

std::optional<double> FreeSurfaceSolver::bulk_number_density() const {
  const auto dim = static_cast<std::size_t>(dimension());
  const double radius = bulk_ball_radius * params_.spacing, step = bulk_ball_step * params_.spacing;
  // Centres over the interior nodes' bounding box (a counted ball holds only interior nodes, so
  // splash nodes far off do not widen the grid).
  double low[3] = {0, 0, 0}, high[3] = {0, 0, 0};
  bool any = false;
  for (std::size_t i = 0; i < kinds_.size(); ++i) {
    if (kinds_[i] != NodeKind::interior) continue;
    for (std::size_t d = 0; d < dim; ++d) {
      const double x = positions_[dim * i + d];
      low[d] = any ? std::min(low[d], x) : x;
      high[d] = any ? std::max(high[d], x) : x;
    }
    any = true;
  }
  if (!any) return std::nullopt;
  const numerics::NodeLocator locator(positions_, dimension(), radius);
  std::size_t steps[3] = {1, 1, 1};
  for (std::size_t d = 0; d < dim; ++d) steps[d] = static_cast<std::size_t>((high[d] - low[d]) / step) + 1;
  std::vector<std::size_t> inside;
  double total = 0;
  std::size_t balls = 0;
  for (std::size_t a = 0; a < steps[0]; ++a)
    for (std::size_t b = 0; b < steps[1]; ++b)
      for (std::size_t e = 0; e < steps[2]; ++e) {
        const std::size_t along[3] = {a, b, e};
        double centre[3] = {0, 0, 0};
        for (std::size_t d = 0; d < dim; ++d) centre[d] = low[d] + step * static_cast<double>(along[d]);
        locator.nodes_near(std::span<const double>(centre, dim), inside);
        if (inside.empty() ||
            std::ranges::any_of(inside, [&](std::size_t j) { return kinds_[j] != NodeKind::interior; }))
          continue;
        total += static_cast<double>(inside.size());
        ++balls;
      }
  // A few balls sample a small patch, where a lattice's count depends on where the centres fall.
  if (balls < bulk_ball_minimum) return std::nullopt;
  const double ball =
      dim == 3 ? 4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3) : std::numbers::pi * radius * radius;
  return total / static_cast<double>(balls) * std::pow(params_.spacing, dimension()) / ball;
}

double FreeSurfaceSolver::fluid_volume() const {
  const double cell = std::pow(params_.spacing, dimension());
  double volume = 0;
  for (std::size_t i = 0; i < kinds_.size(); ++i) {
    if (kinds_[i] == NodeKind::interior)
      volume += cell * rest_density_ / kernel_density(i);
    else if (is_fluid(i))
      volume += cell;
  }
  return volume;
}

double FreeSurfaceSolver::potential_energy() const {
  const auto dim = static_cast<std::size_t>(dimension());
  double sum = 0;
  for (std::size_t i = 0; i < kinds_.size(); ++i)
    if (is_fluid(i))
      for (std::size_t d = 0; d < dim; ++d) sum -= params_.gravity[d] * positions_[dim * i + d];
  return params_.density * sum * std::pow(params_.spacing, dimension());
}

}  // namespace rheosim::ldd
