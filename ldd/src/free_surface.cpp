#include "rheosim/ldd/free_surface.hpp"

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
#include <Eigen/SparseLU>

namespace rheosim::ldd {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

void require(bool ok, const char* field, double value, const char* range) {
  if (!ok)
    throw std::invalid_argument(
        fmt::format("LDD free-surface solver: {} = {} is out of range, expected {}", field, value, range));
}

double squared_distance(const double* a, const double* b, std::size_t dim) {
  double s = 0;
  for (std::size_t d = 0; d < dim; ++d) s += (a[d] - b[d]) * (a[d] - b[d]);
  return s;
}

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

// Sparse LU of a stencil matrix as a BiCGStab preconditioner (the matrices change every step on a
// Lagrangian cloud, so it is refactorised each step; one factorisation serves all velocity
// components). Jacobi needed ~250 iterations per component at Δ = 2 mm (μ δt/(ρΔ²) up to 5·10³).
class LuPreconditioner {
 public:
  bool factorise(const StencilMatrix& a) {
    const NeighbourList& nb = *a.pattern;
    const std::size_t n = a.size();
    entries_.clear();
    entries_.reserve(n + nb.pair_count());
    for (std::size_t i = 0; i < n; ++i) {
      entries_.emplace_back(static_cast<int>(i), static_cast<int>(i), a.diagonal[i]);
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k)
        if (a.off_diagonal[k] != 0.0)
          entries_.emplace_back(static_cast<int>(i), static_cast<int>(nb.indices[k]), a.off_diagonal[k]);
    }
    matrix_.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    matrix_.setFromTriplets(entries_.begin(), entries_.end());
    lu_.compute(matrix_);
    return lu_.info() == Eigen::Success;
  }
  [[nodiscard]] std::function<void(std::span<const double>, std::span<double>)> apply() {
    return [this](std::span<const double> r, std::span<double> z) {
      const Eigen::Map<const Eigen::VectorXd> in(r.data(), static_cast<Eigen::Index>(r.size()));
      Eigen::Map<Eigen::VectorXd>(z.data(), static_cast<Eigen::Index>(z.size())) = lu_.solve(in);
    };
  }

 private:
  std::vector<Eigen::Triplet<double>> entries_;
  Eigen::SparseMatrix<double> matrix_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu_;
};

}  // namespace

// ------------------------------------------------------------------------------ boundaries

PlaneBoundary::PlaneBoundary(std::vector<double> point, std::vector<double> inward_normal)
    : point_(std::move(point)), normal_(std::move(inward_normal)) {
  if (point_.size() != normal_.size() || (point_.size() != 2 && point_.size() != 3))
    throw std::invalid_argument("PlaneBoundary: point and normal need 2 or 3 equal-sized entries");
  double length = 0;
  for (double v : normal_) length += v * v;
  length = std::sqrt(length);
  if (!(length > 0)) throw std::invalid_argument("PlaneBoundary: zero normal");
  for (double& v : normal_) v /= length;
}

bool PlaneBoundary::distance(std::span<const double> x, double /*t*/, double& distance,
                             std::span<double> normal) const {
  distance = 0;
  for (std::size_t d = 0; d < point_.size(); ++d) {
    distance += normal_[d] * (x[d] - point_[d]);
    normal[d] = normal_[d];
  }
  return true;
}

void PlaneBoundary::velocity(double /*t*/, std::span<double> v) const { std::fill(v.begin(), v.end(), 0.0); }

ConeMouldBoundary::ConeMouldBoundary(double bottom_radius, double top_radius, double height, double z0,
                                     double lift_velocity, double lift_height)
    : bottom_radius_(bottom_radius),
      top_radius_(top_radius),
      height_(height),
      z0_(z0),
      lift_velocity_(lift_velocity),
      lift_height_(lift_height) {
  if (!(top_radius > 0 && bottom_radius > top_radius && height > 0 && lift_velocity >= 0))
    throw std::invalid_argument(
        "ConeMouldBoundary: needs 0 < top radius < bottom radius, height > 0, lift velocity >= 0");
}

double ConeMouldBoundary::bottom(double t) const { return z0_ + std::min(lift_velocity_ * t, lift_height_); }

bool ConeMouldBoundary::distance(std::span<const double> x, double t, double& distance,
                                 std::span<double> normal) const {
  const double zb = bottom(t);
  if (x[2] < zb || x[2] > zb + height_) return false;
  const double slope = (bottom_radius_ - top_radius_) / height_;  // dr/dz, radius shrinks upwards
  const double radius = bottom_radius_ - slope * (x[2] - zb);
  const double rho = std::hypot(x[0], x[1]);
  const double cosine = 1.0 / std::sqrt(1.0 + slope * slope);
  distance = (radius - rho) * cosine;  // perpendicular distance to the slanted wall
  // Inward normal: towards the axis and down the slope, −(r̂, slope)/√(1 + slope²).
  const double rx = rho > 0 ? x[0] / rho : 1.0, ry = rho > 0 ? x[1] / rho : 0.0;
  normal[0] = -rx * cosine;
  normal[1] = -ry * cosine;
  normal[2] = -slope * cosine;
  return true;
}

void ConeMouldBoundary::velocity(double t, std::span<double> v) const {
  std::fill(v.begin(), v.end(), 0.0);
  if (lift_velocity_ * t < lift_height_) v[2] = lift_velocity_;
}

void FreeSurfaceCloud::add(std::span<const double> x, bool wall, bool corner, std::span<const double> normal,
                           int boundary_index) {
  positions.insert(positions.end(), x.begin(), x.end());
  normals.insert(normals.end(), normal.begin(), normal.end());
  is_wall.push_back(wall ? 1 : 0);
  is_corner.push_back(corner ? 1 : 0);
  boundary.push_back(boundary_index);
}

// ------------------------------------------------------------------------------ parameters

void FreeSurfaceParams::check() const {
  require(dimension == 2 || dimension == 3, "dimension", dimension, "2 or 3");
  require(density > 0, "density", density, "> 0 kg/m³");
  if (!rheology) throw std::invalid_argument("LDD free-surface solver: no rheology law");
  require(gravity.size() == static_cast<std::size_t>(dimension), "gravity entries", static_cast<double>(gravity.size()),
          "one per dimension");
  require(spacing > 0, "spacing", spacing, "> 0 m");
  require(smoothing_ratio >= 1.2 && smoothing_ratio <= 3.0, "smoothing_ratio", smoothing_ratio, "[1.2, 3]");
  require(time_step > 0, "time_step", time_step, "> 0 s");
  require(pressure_tolerance > 0 && pressure_tolerance < 1, "pressure_tolerance", pressure_tolerance, "(0, 1)");
  require(velocity_tolerance > 0 && velocity_tolerance < 1, "velocity_tolerance", velocity_tolerance, "(0, 1)");
  require(max_iterations >= 1, "max_iterations", max_iterations, ">= 1");
  require(surface_offset > 0 && surface_offset < 1, "surface_offset", surface_offset, "(0, 1)");
  require(surface_count > 0 && surface_count < 1, "surface_count", surface_count, "(0, 1)");
  require(min_moment_rcond > 0 && min_moment_rcond < 1, "min_moment_rcond", min_moment_rcond, "(0, 1)");
  require(surface_moment_rcond > 0 && surface_moment_rcond < 1, "surface_moment_rcond", surface_moment_rcond, "(0, 1)");
  require(surface_fluid_weight >= 0 && surface_fluid_weight < 1, "surface_fluid_weight", surface_fluid_weight,
          "[0, 1)");
  require(surface_cone_angle > 0 && surface_cone_angle < 90, "surface_cone_angle", surface_cone_angle,
          "(0, 90) degrees");
  require(neighbour_skin >= 0 && neighbour_skin <= 1, "neighbour_skin", neighbour_skin, "[0, 1]");
  require(neighbour_reuse_skin >= 0 && neighbour_reuse_skin <= 2, "neighbour_reuse_skin", neighbour_reuse_skin,
          "[0, 2]");
  require(pbd_iterations >= 0, "pbd_iterations", pbd_iterations, ">= 0");
  require(pbd_stiffness > 0 && pbd_stiffness <= 1, "pbd_stiffness", pbd_stiffness, "(0, 1]");
  require(pbd_max_shift > 0 && pbd_max_shift <= 0.5, "pbd_max_shift", pbd_max_shift, "(0, 0.5]");
  require(wall_clearance > 0 && wall_clearance < 1, "wall_clearance", wall_clearance, "(0, 1)");
  require(max_courant > 0, "max_courant", max_courant, "> 0");
  require(stability_probe_iterations >= 0, "stability_probe_iterations", stability_probe_iterations, ">= 0");
}

// ------------------------------------------------------------------------------ solver

FreeSurfaceSolver::FreeSurfaceSolver(FreeSurfaceParams params, std::vector<std::shared_ptr<const Boundary>> boundaries,
                                     FreeSurfaceCloud cloud)
    : params_(std::move(params)), dim_(params_.dimension), boundaries_(std::move(boundaries)) {
  params_.check();
  pressure_amg_ = AmgPreconditioner(params_.pressure_amg);
  velocity_amg_ = AmgPreconditioner(params_.velocity_amg);
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
  const NeighbourList& nb = state.neighbours;
  bool list_fits = nb.offsets.size() == n + 1 && nb.offsets.front() == 0 && nb.offsets.back() == nb.indices.size() &&
                   nb.distances.size() == nb.indices.size();
  for (std::size_t i = 0; list_fits && i < n; ++i) list_fits = nb.offsets[i] <= nb.offsets[i + 1];
  for (std::size_t k = 0; list_fits && k < nb.indices.size(); ++k) list_fits = nb.indices[k] < n;
  if (!list_fits) throw std::invalid_argument("LDD free-surface state: its neighbour list does not fit the cloud");
  for (const AmgState* amg : {&state.pressure_amg, &state.velocity_amg})
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
  candidates_ = NeighbourList{};  // searched afresh at the next step (the same list either way)
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
      most = std::max(most, squared_distance(&positions_[dim * i], &candidate_positions_[dim * i], dim));
    }
    moved = std::sqrt(most);
    const bool verlet_list = candidates_.node_count() == kinds_.size();  // else the last search was plain
    if (verlet_list && 2.0 * moved < 0.9 * skin) {
      ++steps_since_search_;
      neighbours_within(candidates_, positions_, dim_, search_radius_, neighbours_);
      return;
    }
  }
  // A Verlet list costs ~1.5 plain searches: worth it only if the nodes, moving as fast as since
  // the last search, would keep it for two steps or more (not for splashing nodes at δt = 1e-3).
  const bool known_speed = searched_before && steps_since_search_ > 0;
  const double per_step = known_speed ? moved / static_cast<double>(steps_since_search_) : 0.0;
  if (skin > 0 && (!known_speed || 0.9 * skin >= 2.0 * 2.0 * per_step)) {
    candidates_ = find_neighbours(positions_, dim_, search_radius_ + skin);
    neighbours_within(candidates_, positions_, dim_, search_radius_, neighbours_);
  } else {
    candidates_ = NeighbourList{};
    neighbours_ = find_neighbours(positions_, dim_, search_radius_);
  }
  candidate_positions_ = positions_;
  steps_since_search_ = 1;
  ++candidate_searches_;
}

double FreeSurfaceSolver::kernel_density(std::size_t i) const {
  const auto dim = static_cast<std::size_t>(dim_);
  double rho = weight(0.0, support_radius_);
  for (std::size_t k = neighbours_.offsets[i]; k < neighbours_.offsets[i + 1]; ++k) {
    const std::size_t j = neighbours_.indices[k];
    rho += weight(std::sqrt(squared_distance(&positions_[dim * i], &positions_[dim * j], dim)), support_radius_);
  }
  return rho;
}

void FreeSurfaceSolver::classify() {
  const auto dim = static_cast<std::size_t>(dim_);
  const NeighbourList& nb = neighbours_;
  const auto count = static_cast<std::ptrdiff_t>(kinds_.size());
  const double h2 = support_radius_ * support_radius_, r2 = search_radius_ * search_radius_;
  const double offset_limit = params_.surface_offset * params_.spacing;
  const double count_limit = params_.surface_count * rest_count_;
  const double weight_limit = params_.surface_fluid_weight * (rest_density_ - weight(0.0, support_radius_));
  const std::size_t splash_limit = dim + 1;
  // 3D clouds leave wider empty cones near curved walls (64 probes, 26 lattice neighbours), so
  // the 3D half-angle is 15° wider.
  const double cone_angle = params_.surface_cone_angle + (dim_ == 3 ? 15.0 : 0.0);
  const double cone_cosine = std::cos(cone_angle * std::numbers::pi / 180.0);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (!is_fluid(i)) continue;
    constexpr std::size_t max_directions = 96;
    double seen[3 * max_directions];
    std::size_t directions_seen = 0;
    double centroid[3] = {0, 0, 0};
    double wall_normals[3][3] = {};  // distinct normals of the wall nodes nearby (up to 3)
    std::size_t walls_near = 0, within_search = 0, within_support = 0, fluid_within = 0;
    double fluid_weight = 0;  // Σ W_ij over fluid neighbours: what the PPE row actually couples to
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
      const std::size_t j = nb.indices[k];
      const double r = squared_distance(&positions_[dim * i], &positions_[dim * j], dim);
      if (r >= r2) continue;
      ++within_search;
      if (r < h2) ++within_support;
      if (r > 0 && directions_seen < max_directions) {
        const double inverse = 1.0 / std::sqrt(r);
        for (std::size_t d = 0; d < dim; ++d)
          seen[directions_seen * 3 + d] = (positions_[dim * j + d] - positions_[dim * i + d]) * inverse;
        ++directions_seen;
      }
      if (is_fluid(j)) {
        ++fluid_within;
        fluid_weight += weight(std::sqrt(r), support_radius_);
        for (std::size_t d = 0; d < dim; ++d) centroid[d] += positions_[dim * j + d] - positions_[dim * i + d];
        continue;
      }
      const double* normal = &normals_[dim * j];
      bool known = corner_[j] != 0;  // corners have no normal of their own
      for (std::size_t w = 0; w < walls_near && !known; ++w) {
        double dot = 0;
        for (std::size_t d = 0; d < dim; ++d) dot += wall_normals[w][d] * normal[d];
        known = dot > 0.9;
      }
      if (!known && walls_near < 3) {
        for (std::size_t d = 0; d < dim; ++d) wall_normals[walls_near][d] = normal[d];
        ++walls_near;
      }
    }
    if (within_support < splash_limit) {
      kinds_[i] = FreeNode::splash;
      continue;
    }
    // The fluid neighbours' centroid offset; next to a wall the wall-normal part of it is the
    // wall's doing, not a free surface's, so it is projected out (Gram–Schmidt on the normals).
    double basis[3][3] = {};
    std::size_t rank = 0;
    for (std::size_t w = 0; w < walls_near; ++w) {
      double v[3] = {wall_normals[w][0], wall_normals[w][1], wall_normals[w][2]};
      for (std::size_t b = 0; b < rank; ++b) {
        double dot = 0;
        for (std::size_t d = 0; d < dim; ++d) dot += v[d] * basis[b][d];
        for (std::size_t d = 0; d < dim; ++d) v[d] -= dot * basis[b][d];
      }
      double length = 0;
      for (std::size_t d = 0; d < dim; ++d) length += v[d] * v[d];
      length = std::sqrt(length);
      if (length < 0.3) continue;
      for (std::size_t d = 0; d < dim; ++d) basis[rank][d] = v[d] / length;
      ++rank;
    }
    for (std::size_t b = 0; b < rank; ++b) {
      double dot = 0;
      for (std::size_t d = 0; d < dim; ++d) dot += centroid[d] * basis[b][d];
      for (std::size_t d = 0; d < dim; ++d) centroid[d] -= dot * basis[b][d];
    }
    double offset = 0;
    for (std::size_t d = 0; d < dim; ++d) offset += centroid[d] * centroid[d];
    // Normalised by all neighbours, walls included: the wall nodes stand in for missing fluid.
    offset = std::sqrt(offset) / static_cast<double>(within_search);
    // Empty-cone test: some probe direction with no neighbour (fluid or wall) within the cone
    // half-angle of it means a void beside the node — a surface, also under an overhang where the
    // centroid stays balanced (the dam-break toe).
    bool empty_cone = false;
    std::size_t last_cover = 0;  // neighbouring probes are mostly covered by the same direction
    for (std::size_t q = 0; q + dim <= probe_directions_.size() && !empty_cone; q += dim) {
      bool covered = false;
      // Directions into a nearby wall are covered by the wall itself (its nodes may sit up to
      // ~1.5 Δ away on a sloped or curved boundary such as the Abrams mould).
      for (std::size_t w = 0; w < walls_near && !covered; ++w) {
        double dot = 0;
        for (std::size_t d = 0; d < dim; ++d) dot -= probe_directions_[q + d] * wall_normals[w][d];
        covered = dot > 0.3;
      }
      for (std::size_t tried = 0; tried < directions_seen && !covered; ++tried) {
        const std::size_t m = (last_cover + tried) % directions_seen;
        double dot = 0;
        for (std::size_t d = 0; d < dim; ++d) dot += probe_directions_[q + d] * seen[3 * m + d];
        covered = dot > cone_cosine;
        if (covered) last_cover = m;
      }
      empty_cone = !covered;
    }
    // Fluid support: wall pressures are extrapolated from the fluid (the PPE's wall rows), so a
    // node whose kernel sees mostly wall nodes has no pressure level of its own — as interior it
    // formed a floating block with its walls (the slump cake's edge reached 9·10⁶ Pa, docs/ldd.md).
    // Degenerate stencil: the neighbours (eq. 13's moment matrix) do not span all directions —
    // the node is at an edge of the fluid. A bound of its own, lower than the pseudo-inverse's: a
    // flattened interior stencil needs its weak direction dropped, not p = p_atm, which next to
    // hydrostatic neighbours kicks it by δt·g·h/Δ (the δt = 1e-2 slump, docs/ldd.md).
    const bool degenerate =
        operators_.conditioning.size() == kinds_.size() && operators_.conditioning[i] < params_.surface_moment_rcond;
    const bool thin_support = fluid_weight < weight_limit || degenerate;
    const bool surface =
        empty_cone || thin_support || offset > offset_limit || static_cast<double>(within_search) < count_limit;
    kinds_[i] = surface ? FreeNode::surface : FreeNode::interior;
  }
  // Wall nodes: active (Neumann/Dirichlet rows) when a fluid node is within h, else idle.
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (is_fluid(i)) continue;
    bool active = false;
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1] && !active; ++k) {
      const std::size_t j = nb.indices[k];
      active = kinds_[j] <= FreeNode::splash && squared_distance(&positions_[dim * i], &positions_[dim * j], dim) < h2;
    }
    kinds_[i] = !active ? FreeNode::idle_wall : (corner_[i] ? FreeNode::corner : FreeNode::wall);
  }
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

// Positivity guard: on one-sided neighbourhoods (free surface, a flow's toe) the offset factor
// 1 − x_ij·B_i o_i of eq. 15 turns some coefficients negative, the PPE and momentum rows lose
// diagonal dominance and a lone node's pressure runs away (seen at the dam-break toe). Such nodes
// use eq. 15 without the offset correction (o_i = 0): first order there, all coefficients ≥ 0.
void FreeSurfaceSolver::keep_laplacian_positive() {
  const auto dim = static_cast<std::size_t>(dim_);
  const NeighbourList& nb = neighbours_;
  const auto count = static_cast<std::ptrdiff_t>(kinds_.size());
  std::size_t guarded = 0;
#pragma omp parallel for schedule(static) reduction(+ : guarded)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const std::size_t begin = nb.offsets[i], end = nb.offsets[i + 1];
    bool negative = false;
    for (std::size_t k = begin; k < end && !negative; ++k) negative = operators_.laplacian[k] < 0;
    if (!negative) continue;
    ++guarded;
    double denominator = 0;
    for (std::size_t k = begin; k < end; ++k)
      denominator +=
          operators_.weights[k] * squared_distance(&positions_[dim * i], &positions_[dim * nb.indices[k]], dim);
    const double scale = denominator > 0 ? 2.0 * static_cast<double>(dim) / denominator : 0.0;
    for (std::size_t k = begin; k < end; ++k) operators_.laplacian[k] = scale * operators_.weights[k];
  }
  laplacian_guarded_ = guarded;
}

// previous_pressure_: p_{n−1} evaluated on the current cloud and classification before the
// momentum predictor (pressure_ itself is kept until the step passes its divergence checks).
// Where the classification or the geometry changed, last step's value is not a pressure the
// node can have now:
//   * surface, splash and idle wall nodes: p = p_atm = 0. Left at its old value, a node that had
//     just turned surface kept its hydrostatic pressure until the PPE set φ = −p_{n−1}, and the
//     projection kicked it by δt/ρ · p/Δ — inviscid, unseen by the implicit viscous solve (the
//     viscous time ρΔ²/μ is far below δt in the slump and the dam break);
//   * nodes that have just turned interior: Shepard over their neighbours of known pressure
//     (interior before and now, or surface) with the hydrostatic offset, as a wall node's —
//     instead of the 0 they had as surface nodes. Only the first item made the opposite jump
//     (0 → ρgh, inviscid) the one left, so nodes flickering between the two kinds pushed their
//     neighbours outwards every cycle: the Δ = 10 mm dam break's front ran 24–31 % ahead;
//   * wall nodes: re-extrapolated from the fluid as in the PPE's wall rows (φ = 0 there at rest).
//     A moved wall node (the rising mould, δz = v δt) otherwise kept a pressure off by ρ g δz —
//     a Neumann source over the whole mould that the PPE can drain only through the small top
//     surface: φ ≈ −10 kPa in the 50 000-node slump at δt = 1e-2, clipped to p = 0 everywhere.
// Gradients that must see the boundary values as they are: free-surface nodes their own p = 0
// (anchored_surface_gradient), and fluid nodes beside a dry wall node (one without an interior
// fluid node within h, p = p_atm) not that wall node (exclude_dry_walls). A dry wall node stands
// above the surface: its p = 0 is not the hydrostatic field's extension there, and a contact-line
// node that counts it loses part of the support that balances gravity.
void FreeSurfaceSolver::regradient_for_boundary_values() {
  const std::size_t n = kinds_.size();
  const NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  dry_wall_.assign(params_.exclude_dry_walls ? n : 0, 0);
  if (params_.exclude_dry_walls)
    for (std::size_t i = 0; i < n; ++i) {
      if (kinds_[i] != FreeNode::wall && kinds_[i] != FreeNode::corner) continue;
      bool wet = false;
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1] && !wet; ++k)
        wet = kinds_[nb.indices[k]] == FreeNode::interior && ops.weights[k] > 0;
      dry_wall_[i] = wet ? 0 : 1;
    }
  const auto beside_dry_wall = [&](std::size_t i) {
    if (dry_wall_.empty()) return false;
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k)
      if (dry_wall_[nb.indices[k]] && ops.weights[k] > 0) return true;
    return false;
  };
  std::vector<std::size_t> centred, anchored;
  for (std::size_t i = 0; i < n; ++i) {
    if (kinds_[i] == FreeNode::surface && params_.anchored_surface_gradient)
      anchored.push_back(i);
    else if ((kinds_[i] == FreeNode::interior || kinds_[i] == FreeNode::surface) && beside_dry_wall(i))
      centred.push_back(i);
  }
  rebuild_gradients(positions_, nb, OperatorSettings{support_radius_, params_.min_moment_rcond, params_.centred_gradient},
                    centred, dry_wall_, operators_);
  rebuild_gradients(positions_, nb, OperatorSettings{support_radius_, params_.min_moment_rcond, false}, anchored,
                    dry_wall_, operators_);
}

void FreeSurfaceSolver::impose_boundary_pressure() {
  const auto dim = static_cast<std::size_t>(dim_);
  const NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  const auto count = static_cast<std::ptrdiff_t>(kinds_.size());
  const double rho = params_.density;
  const std::vector<double>& g = params_.gravity;
  std::vector<double>& p = previous_pressure_;
  p = pressure_;
  for (std::size_t i = 0; i < kinds_.size(); ++i)
    if (kinds_[i] == FreeNode::surface || kinds_[i] == FreeNode::splash || kinds_[i] == FreeNode::idle_wall) p[i] = 0.0;
  const bool history = last_kinds_.size() == kinds_.size();
  // Shepard average of p_j + ρ g·(x_i − x_j) over the neighbours j that pass `use`; p = 0 (no
  // tension) when there are none.
  const auto extrapolate = [&](std::size_t i, const auto& use, bool& any_interior) {
    double wsum = 0, source = 0;
    any_interior = false;
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
      const std::size_t j = nb.indices[k];
      if (!use(j)) continue;
      any_interior = any_interior || (kinds_[j] == FreeNode::interior && ops.weights[k] > 0);
      double hydrostatic = 0;
      for (std::size_t d = 0; d < dim; ++d)
        hydrostatic += rho * g[d] * (positions_[dim * i + d] - positions_[dim * j + d]);
      wsum += ops.weights[k];
      source += ops.weights[k] * (p[j] + hydrostatic);
    }
    return wsum > 0 ? std::max(source / wsum, 0.0) : 0.0;
  };
  const auto known = [&](std::size_t j) {
    return kinds_[j] == FreeNode::surface || (kinds_[j] == FreeNode::interior && last_kinds_[j] == FreeNode::interior);
  };
  const auto newly_interior = [&](std::size_t i) {
    return history && kinds_[i] == FreeNode::interior && last_kinds_[i] != FreeNode::interior;
  };
  // Two passes, so that each reads only values the other does not write.
  std::vector<double> estimate(kinds_.size(), 0.0);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    bool any_interior = false;
    if (newly_interior(i)) estimate[i] = extrapolate(i, known, any_interior);
  }
  for (std::size_t i = 0; i < kinds_.size(); ++i)
    if (newly_interior(i)) p[i] = estimate[i];
      // Walls as the PPE's wall rows: over interior and surface neighbours, p = 0 when the wall node
      // sees no interior node (it stands above the fluid).
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (kinds_[i] != FreeNode::wall && kinds_[i] != FreeNode::corner) continue;
    bool below_surface = false;
    const double value = extrapolate(
        i, [&](std::size_t j) { return kinds_[j] == FreeNode::interior || kinds_[j] == FreeNode::surface; },
        below_surface);
    p[i] = below_surface ? value : 0.0;
  }
}

void FreeSurfaceSolver::keep_off_boundaries(std::size_t i, double t, std::span<double> velocity) {
  const auto dim = static_cast<std::size_t>(dim_);
  const double clearance = params_.wall_clearance * params_.spacing;
  double normal[3] = {0, 0, 0}, wall_velocity[3] = {0, 0, 0};
  for (const auto& b : boundaries_) {
    double distance = 0;
    if (!b->distance(std::span<const double>(&positions_[dim * i], dim), t, distance, std::span<double>(normal, dim)))
      continue;
    if (distance >= clearance) continue;
    for (std::size_t d = 0; d < dim; ++d) positions_[dim * i + d] += (clearance - distance) * normal[d];
    if (velocity.empty()) continue;
    // Held off the wall, a node must not keep running into it: drop the approach velocity
    // relative to the wall.
    b->velocity(t, std::span<double>(wall_velocity, dim));
    double approach = 0;
    for (std::size_t d = 0; d < dim; ++d) approach += normal[d] * (velocity[dim * i + d] - wall_velocity[d]);
    if (approach < 0)
      for (std::size_t d = 0; d < dim; ++d) velocity[dim * i + d] -= approach * normal[d];
  }
}

// The step is linear in (u_{n−1}, p_{n−1}) once its matrices are fixed (operators,
// classification, μ): u* = M⁻¹(ρu − δt⟨∇p⟩), φ = P⁻¹ rhs(u*, p), u' = u* − δt/ρ ⟨∇φ⟩, p' = p + φ,
// with wall and splash rows homogeneous. Power iteration from a pseudo-random start finds its
// largest growth factor; pressure is measured in velocity units δt p/(ρΔ).
void FreeSurfaceSolver::probe_step_map(const KrylovSettings& velocity_settings, const KrylovSettings& pressure_settings,
                                       FreeSurfaceStats& stats) {
  const auto dim = static_cast<std::size_t>(dim_);
  const std::size_t n = kinds_.size();
  const NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  const double dt = params_.time_step, rho = params_.density;
  const double pressure_scale = dt / (rho * params_.spacing);
  const auto moving = [&](std::size_t i) { return kinds_[i] == FreeNode::interior || kinds_[i] == FreeNode::surface; };
  std::vector<double> u(dim * n, 0.0), p(n, 0.0), predicted(dim * n), rhs(n), component(n), phi(n), grad(dim * n),
      div(n);
  std::uint64_t state = 0x9E3779B97F4A7C15ULL;
  const auto random = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (!moving(i)) continue;
    for (std::size_t d = 0; d < dim; ++d) u[dim * i + d] = random();
    if (kinds_[i] == FreeNode::interior) p[i] = random() / pressure_scale;
  }
  const auto normalise = [&] {
    double sum = 0;
    for (double v : u) sum += v * v;
    for (double v : p) sum += pressure_scale * pressure_scale * v * v;
    const double norm = std::sqrt(sum);
    for (double& v : u) v /= norm;
    for (double& v : p) v /= norm;
    return norm;
  };
  normalise();
  KrylovSettings velocity = velocity_settings, pressure = pressure_settings;
  velocity.relative_tolerance = pressure.relative_tolerance = 1e-10;
  velocity.absolute_tolerance = pressure.absolute_tolerance = 0.0;
  const int iterations = params_.stability_probe_iterations;
  double log_growth = 0;
  int counted = 0;
  for (int it = 0; it < iterations; ++it) {
    gradient(nb, ops, p, grad);
    for (std::size_t d = 0; d < dim; ++d) {
      for (std::size_t i = 0; i < n; ++i) {
        rhs[i] = moving(i) ? rho * u[dim * i + d] - dt * grad[dim * i + d] : 0.0;
        component[i] = u[dim * i + d];
      }
      bicgstab(momentum_matrix_, rhs, component, velocity, krylov_);
      for (std::size_t i = 0; i < n; ++i) predicted[dim * i + d] = moving(i) ? component[i] : 0.0;
    }
    divergence(nb, ops, predicted, div);
    for (std::size_t i = 0; i < n; ++i) {
      if (kinds_[i] == FreeNode::interior) {
        rhs[i] = rho / dt * div[i];
      } else if (kinds_[i] == FreeNode::wall || kinds_[i] == FreeNode::corner) {
        double source = 0;  // Σ w_j p_j of the wall row (its off-diagonal is −w_j)
        for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k)
          source -= pressure_matrix_.off_diagonal[k] * p[nb.indices[k]];
        rhs[i] = source - p[i];
      } else {
        rhs[i] = -p[i];
      }
    }
    std::fill(phi.begin(), phi.end(), 0.0);
    bicgstab(pressure_matrix_, rhs, phi, pressure, krylov_);
    gradient(nb, ops, phi, grad);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t d = 0; d < dim; ++d)
        u[dim * i + d] = moving(i) ? predicted[dim * i + d] - dt / rho * grad[dim * i + d] : 0.0;
      p[i] += phi[i];
    }
    const double growth = normalise();
    if (2 * it >= iterations) {
      log_growth += std::log(growth);
      ++counted;
    }
  }
  stats.step_map_growth = std::exp(log_growth / std::max(counted, 1));
  double largest = -1;
  for (std::size_t i = 0; i < n; ++i) {
    double a = pressure_scale * pressure_scale * p[i] * p[i];
    for (std::size_t d = 0; d < dim; ++d) a += u[dim * i + d] * u[dim * i + d];
    if (a > largest) {
      largest = a;
      stats.step_map_node = i;
    }
  }
}

FreeSurfaceStats FreeSurfaceSolver::step() {
  const auto dim = static_cast<std::size_t>(dim_);
  const std::size_t n = kinds_.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  const double dt = params_.time_step, rho = params_.density;
  const std::vector<double>& g = params_.gravity;
  const double g_norm = std::sqrt(std::inner_product(g.begin(), g.end(), g.begin(), 0.0));
  const NeighbourList& nb = neighbours_;
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
  KrylovSettings velocity_settings{params_.velocity_tolerance,
                                   params_.velocity_tolerance * rho * std::max(g_norm * dt, 1e-12) * sqrt_n,
                                   params_.max_iterations,
                                   {}};
  LuPreconditioner momentum_lu;
  if (params_.velocity_preconditioner == Preconditioner::sparse_lu && dim_ == 2 &&
      momentum_lu.factorise(momentum_matrix_))
    velocity_settings.preconditioner = momentum_lu.apply();
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
    auto result =
        bicgstab(momentum_matrix_, std::span<const double>(&rhs_[d * n], n), component_, velocity_settings, krylov_);
    if (!result.converged && velocity_amg && !velocity_hierarchy_fresh) {
      // A hierarchy kept from earlier steps no longer fits the matrix: rebuild it, solve again.
      velocity_amg_.setup(momentum_matrix_);
      velocity_hierarchy_fresh = true;
      ++stats.repeated_solves;
      for (std::size_t i = 0; i < n; ++i) component_[i] = velocity_[dim * i + d];
      stats.velocity_iterations += result.iterations;
      result =
          bicgstab(momentum_matrix_, std::span<const double>(&rhs_[d * n], n), component_, velocity_settings, krylov_);
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
        bool below_surface = false;
        for (std::size_t k = begin; k < end; ++k) {
          const FreeNode kj = kinds_[nb.indices[k]];
          if (kj == FreeNode::interior || kj == FreeNode::surface) wsum += ops.weights[k];
          below_surface = below_surface || (kj == FreeNode::interior && ops.weights[k] > 0);
        }
        if (!below_surface) wsum = 0;
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
  KrylovSettings pressure_settings{
      params_.pressure_tolerance,
      params_.pressure_tolerance * rho * std::max(g_norm, 1e-12) / params_.spacing * sqrt_n,
      params_.max_iterations,
      {}};
  LuPreconditioner pressure_lu;
  if (params_.pressure_preconditioner == Preconditioner::sparse_lu && dim_ == 2 &&
      pressure_lu.factorise(pressure_matrix_))
    pressure_settings.preconditioner = pressure_lu.apply();
  const bool pressure_amg = params_.pressure_preconditioner == Preconditioner::amg;
  bool pressure_hierarchy_fresh = false;
  if (pressure_amg) {
    pressure_hierarchy_fresh = pressure_amg_.prepare(pressure_matrix_);
    pressure_settings.preconditioner = pressure_amg_.as_preconditioner();
  }
  auto pressure_result = bicgstab(pressure_matrix_, rhs_, increment_, pressure_settings, krylov_);
  const auto repeat_pressure_solve = [&] {
    ++stats.repeated_solves;
    increment_.assign(n, 0.0);
    const int failed_iterations = pressure_result.iterations;
    pressure_result = bicgstab(pressure_matrix_, rhs_, increment_, pressure_settings, krylov_);
    pressure_result.iterations += failed_iterations;
  };
  if (!pressure_result.converged && pressure_amg && !pressure_hierarchy_fresh) {
    // As for the velocity: the kept hierarchy was built for an older cloud and classification.
    pressure_amg_.setup(pressure_matrix_);
    repeat_pressure_solve();
  }
  LuPreconditioner pressure_direct;  // outlives pressure_settings' use in the stability probe
  if (!pressure_result.converged && !(pressure_result.relative_residual < 1e3 * params_.pressure_tolerance) &&
      dim_ == 2 && params_.pressure_preconditioner != Preconditioner::sparse_lu &&
      pressure_direct.factorise(pressure_matrix_)) {
    // Last resort in 2D: the exact factors as the preconditioner (seconds at 200 000 nodes).
    pressure_settings.preconditioner = pressure_direct.apply();
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
    const FloatingGroups floating = floating_groups(pressure_matrix_);
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

void FreeSurfaceSolver::reorder(std::span<const double> grad_u) {
  const auto dim = static_cast<std::size_t>(dim_);
  const std::size_t n = kinds_.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  shift_.assign(dim * n, 0.0);
  if (params_.pbd_iterations == 0) return;
  const NeighbourList& nb = neighbours_;
  const double h = support_radius_, rho0 = rest_density_;
  const double max_shift = params_.pbd_max_shift * params_.spacing;
  const auto movable = [&](std::size_t i) { return kinds_[i] == FreeNode::interior || kinds_[i] == FreeNode::surface; };
  const double h2 = h * h;
  std::vector<double> lambda(n, 0.0), step(dim * n, 0.0);
  pair_dw_.resize(nb.pair_count());
  const std::span<double> pair_dw(pair_dw_);  // ∇W/(r ρ₀) of each pair within h, else 0
  for (int iteration = 0; iteration < params_.pbd_iterations; ++iteration) {
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      lambda[i] = 0.0;
      if (!movable(i)) continue;
      double density = weight(0.0, h), grad_i[3] = {0, 0, 0}, squares = 0;
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
        const std::size_t j = nb.indices[k];
        pair_dw[k] = 0.0;
        const double r2 = squared_distance(&positions_[dim * i], &positions_[dim * j], dim);
        if (r2 >= h2) continue;  // the skin's pairs: W = 0
        const double r = std::sqrt(r2);
        density += weight(r, h);
        if (r <= 0) continue;
        const double dw = weight_derivative(r, h) / r / rho0;  // ∇_i W_ij / ρ₀ = dw (x_i − x_j)
        pair_dw[k] = dw;
        for (std::size_t d = 0; d < dim; ++d) grad_i[d] += dw * (positions_[dim * i + d] - positions_[dim * j + d]);
        if (movable(j)) squares += dw * dw * r * r;  // |∇_j C_i|² (fixed nodes cannot help)
      }
      double constraint = density / rho0 - 1.0;
      // The surface's kernel sum is truncated by the void: only compression is corrected there.
      if (kinds_[i] == FreeNode::surface) constraint = std::max(constraint, 0.0);
      double denominator = squares;
      for (std::size_t d = 0; d < dim; ++d) denominator += grad_i[d] * grad_i[d];
      lambda[i] = denominator > 0 ? -constraint / denominator : 0.0;
    }
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      for (std::size_t d = 0; d < dim; ++d) step[dim * i + d] = 0.0;
      if (!movable(i)) continue;
      double shift[3] = {0, 0, 0};
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
        const double dw = pair_dw[k];  // the positions have not moved since λ
        if (dw == 0.0) continue;
        const std::size_t j = nb.indices[k];
        const double factor = (lambda[i] + lambda[j]) * dw * params_.pbd_stiffness;
        for (std::size_t d = 0; d < dim; ++d) shift[d] += factor * (positions_[dim * i + d] - positions_[dim * j + d]);
      }
      double length = 0;
      for (std::size_t d = 0; d < dim; ++d) length += shift[d] * shift[d];
      length = std::sqrt(length);
      const double scale = length > max_shift ? max_shift / length : 1.0;
      for (std::size_t d = 0; d < dim; ++d) step[dim * i + d] = scale * shift[d];
    }
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      if (!movable(i)) continue;
      double before[3] = {0, 0, 0};
      for (std::size_t d = 0; d < dim; ++d) {
        before[d] = positions_[dim * i + d];
        positions_[dim * i + d] += step[dim * i + d];
      }
      keep_off_boundaries(i, time_, {});
      for (std::size_t d = 0; d < dim; ++d) shift_[dim * i + d] += positions_[dim * i + d] - before[d];
    }
  }
  // Velocities follow the shift to first order (LDD §3.2: interpolation after reordering).
  if (!params_.pbd_velocity_correction) return;
  const std::size_t dd = dim * dim;
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (!movable(i)) continue;
    for (std::size_t a = 0; a < dim; ++a) {
      double du = 0;
      for (std::size_t b = 0; b < dim; ++b) du += grad_u[dd * i + a * dim + b] * shift_[dim * i + b];
      velocity_[dim * i + a] += du;
      previous_velocity_[dim * i + a] += du;
    }
  }
}

}  // namespace rheosim::ldd
