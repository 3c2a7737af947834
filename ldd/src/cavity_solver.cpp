#include "rheosim/ldd/cavity_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include <fmt/format.h>

namespace rheosim::ldd {

CavitySolver::CavitySolver(SolverParams params, std::vector<std::shared_ptr<const Boundary>> walls, NodeCloud cloud)
    : Solver(std::move(params)) {
  if (params_.dimension != 2)
    throw std::invalid_argument(
        fmt::format("LDD cavity: dimension = {} is out of range, expected 2", params_.dimension));
  if (params_.velocity_preconditioner == Preconditioner::sparse_lu)
    throw std::invalid_argument("LDD cavity: velocity_preconditioner = sparse LU is not offered (jacobi or amg)");
  kinds_ = std::move(cloud.kinds);
  normals_ = std::move(cloud.normals);
  positions_ = std::move(cloud.positions);
  const std::size_t n = kinds_.size();
  if (positions_.size() != 2 * n || normals_.size() != 2 * n || cloud.boundary.size() != n)
    throw std::invalid_argument("LDD cavity: node cloud arrays have inconsistent sizes");
  // The walls do not move: each wall node keeps its wall's surface velocity (the lid's slides).
  wall_velocities_.assign(2 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const int b = cloud.boundary[i];
    if (b < 0) continue;
    if (static_cast<std::size_t>(b) >= walls.size())
      throw std::invalid_argument("LDD cavity: a wall node names a boundary that does not exist");
    walls[static_cast<std::size_t>(b)]->surface_velocity(0.0, std::span<double>(&wall_velocities_[2 * i], 2));
  }
  velocity_ = wall_velocities_;  // the fluid at rest (its nodes name no wall)
  previous_velocity_ = velocity_;
  pressure_.assign(n, 0.0);
  shear_rate_.assign(n, 0.0);
  viscosity_.assign(n, params_.rheology->viscosity(0.0));
  // Once: the nodes return to their lattice places every step.
  neighbours_ = numerics::find_neighbours(positions_, 2, support_radius_ + params_.neighbour_skin * params_.spacing);

  if (fluid_node_count() == 0) throw std::invalid_argument("LDD cavity: the cloud has no fluid nodes");
}

SolverState CavitySolver::state() const {
  SolverState s = common_state();
  s.momentum_increment = momentum_increment_;
  s.older_momentum_increment = older_momentum_increment_;
  return s;
}

void CavitySolver::restore(SolverState state) {
  const std::size_t values = 2 * node_count();
  for (const std::vector<double>* increment : {&state.momentum_increment, &state.older_momentum_increment})
    if (!increment->empty() && increment->size() != values)
      throw std::invalid_argument(
          fmt::format("LDD cavity state: a momentum increment of {} values for {} nodes", increment->size(), values));
  restore_common_state(state, "LDD cavity");
  momentum_increment_ = std::move(state.momentum_increment);
  older_momentum_increment_ = std::move(state.older_momentum_increment);
  next_momentum_increment_.clear();
  operators_valid_ = false;  // rebuilt from the restored cloud and neighbour list
  lattice_fit_ = QuadraticFit{};
  pressure_lu_ = numerics::SparseLu{};
}

CavitySolver::~CavitySolver() = default;
CavitySolver::CavitySolver(CavitySolver&&) noexcept = default;
CavitySolver& CavitySolver::operator=(CavitySolver&&) noexcept = default;

std::vector<double> CavitySolver::sample_velocity(std::span<const double> points) const {
  const std::size_t n = kinds_.size();
  Operators rebuilt;
  const Operators* ops = &operators_;
  if (!operators_valid_) {
    rebuilt = build_operators(positions_, 2, neighbours_, OperatorSettings{support_radius_});
    ops = &rebuilt;
  }
  std::vector<double> grad(4 * n, 0.0), component(n), g(2 * n);
  for (std::size_t d = 0; d < 2; ++d) {
    for (std::size_t i = 0; i < n; ++i) component[i] = velocity_[2 * i + d];
    gradient(neighbours_, *ops, component, g);
    for (std::size_t i = 0; i < n; ++i) {
      grad[4 * i + 2 * d] = g[2 * i];
      grad[4 * i + 2 * d + 1] = g[2 * i + 1];
    }
  }
  const std::size_t count = points.size() / 2;
  std::vector<double> out(2 * count, std::numeric_limits<double>::quiet_NaN());
  const double h = support_radius_;
  // Bucket the nodes into cells of size h so each point scans 3×3 cells.
  double lo[2] = {positions_[0], positions_[1]}, hi[2] = {positions_[0], positions_[1]};
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t d = 0; d < 2; ++d) {
      lo[d] = std::min(lo[d], positions_[2 * i + d]);
      hi[d] = std::max(hi[d], positions_[2 * i + d]);
    }
  const auto cells_along = [&](std::size_t d) { return static_cast<std::size_t>((hi[d] - lo[d]) / h) + 1; };
  const std::size_t cx = cells_along(0), cy = cells_along(1);
  const auto cell_of = [&](double v, std::size_t d, std::size_t cells) {
    const double c = std::floor((v - lo[d]) / h);
    return static_cast<std::ptrdiff_t>(std::clamp(c, -1.0, static_cast<double>(cells)));
  };
  std::vector<std::size_t> start(cx * cy + 1, 0), order(n);
  for (std::size_t i = 0; i < n; ++i)
    ++start[static_cast<std::size_t>(cell_of(positions_[2 * i], 0, cx) +
                                     cell_of(positions_[2 * i + 1], 1, cy) * static_cast<std::ptrdiff_t>(cx)) +
            1];
  for (std::size_t c = 0; c < cx * cy; ++c) start[c + 1] += start[c];
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    order[fill[static_cast<std::size_t>(cell_of(positions_[2 * i], 0, cx) +
                                        cell_of(positions_[2 * i + 1], 1, cy) * static_cast<std::ptrdiff_t>(cx))]++] =
        i;
  for (std::size_t p = 0; p < count; ++p) {
    const double px = points[2 * p], py = points[2 * p + 1];
    const std::ptrdiff_t ix = cell_of(px, 0, cx), iy = cell_of(py, 1, cy);
    double wsum = 0, su = 0, sv = 0;
    for (std::ptrdiff_t jy = iy - 1; jy <= iy + 1; ++jy)
      for (std::ptrdiff_t jx = ix - 1; jx <= ix + 1; ++jx) {
        if (jx < 0 || jy < 0 || jx >= static_cast<std::ptrdiff_t>(cx) || jy >= static_cast<std::ptrdiff_t>(cy))
          continue;
        const auto c = static_cast<std::size_t>(jx + jy * static_cast<std::ptrdiff_t>(cx));
        for (std::size_t m = start[c]; m < start[c + 1]; ++m) {
          const std::size_t j = order[m];
          const double dx = px - positions_[2 * j], dy = py - positions_[2 * j + 1];
          const double w = weight(std::hypot(dx, dy), h);
          if (w <= 0) continue;
          const double* gj = &grad[4 * j];
          wsum += w;
          su += w * (velocity_[2 * j] + gj[0] * dx + gj[1] * dy);
          sv += w * (velocity_[2 * j + 1] + gj[2] * dx + gj[3] * dy);
        }
      }
    if (wsum > 0) {
      out[2 * p] = su / wsum;
      out[2 * p + 1] = sv / wsum;
    }
  }
  return out;
}

}  // namespace rheosim::ldd
