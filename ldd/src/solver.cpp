#include "rheosim/ldd/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <type_traits>
#include <utility>

#include <fmt/format.h>

namespace rheosim::ldd {

namespace {

void require(bool ok, const char* field, double value, const char* range) {
  if (!ok)
    throw std::invalid_argument(fmt::format("LDD solver: {} = {} is out of range, expected {}", field, value, range));
}

}  // namespace

void SolverParams::check() const {
  StepParams::check("LDD solver", 2);
  require(velocity_scale > 0, "velocity_scale", velocity_scale, "> 0 m/s");
  require(length_scale > 0, "length_scale", length_scale, "> 0 m");
  if (velocity_preconditioner == Preconditioner::sparse_lu)
    throw std::invalid_argument("LDD solver: velocity_preconditioner = sparse LU is not offered (jacobi or amg)");
}

Solver::Solver(SolverParams params, std::vector<std::shared_ptr<const Boundary>> walls, NodeCloud cloud)
    : params_(std::move(params)), walls_(std::move(walls)), wall_velocities_(std::move(cloud.wall_velocities)) {
  kinds_ = std::move(cloud.kinds);
  normals_ = std::move(cloud.normals);
  positions_ = std::move(cloud.positions);
  params_.check();
  pressure_amg_ = numerics::AmgPreconditioner(params_.pressure_amg);
  velocity_amg_ = numerics::AmgPreconditioner(params_.velocity_amg);
  const std::size_t n = kinds_.size();
  if (positions_.size() != 2 * n || normals_.size() != 2 * n || wall_velocities_.size() != 2 * n)
    throw std::invalid_argument("LDD solver: node cloud arrays have inconsistent sizes");
  support_radius_ = params_.smoothing_ratio * params_.spacing;
  velocity_.assign(2 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (!is_fluid(i)) {
      velocity_[2 * i] = wall_velocities_[2 * i];
      velocity_[2 * i + 1] = wall_velocities_[2 * i + 1];
    }
  previous_velocity_ = velocity_;
  pressure_.assign(n, 0.0);
  shear_rate_.assign(n, 0.0);
  viscosity_.assign(n, params_.rheology->viscosity(0.0));
  // Once: the nodes return to their lattice places every step.
  neighbours_ = numerics::find_neighbours(positions_, 2, support_radius_ + params_.neighbour_skin * params_.spacing);

  if (fluid_node_count() == 0) throw std::invalid_argument("LDD solver: the cloud has no fluid nodes");
}

SolverState Solver::state() const {
  SolverState s = common_state();
  s.momentum_increment = momentum_increment_;
  s.older_momentum_increment = older_momentum_increment_;
  return s;
}

void Solver::restore(SolverState state) {
  const std::size_t values = 2 * node_count();
  for (const std::vector<double>* increment : {&state.momentum_increment, &state.older_momentum_increment})
    if (!increment->empty() && increment->size() != values)
      throw std::invalid_argument(
          fmt::format("LDD cavity state: a momentum increment of {} values for {} nodes", increment->size(), values));
  restore_common_state(state, 2, "LDD cavity");
  momentum_increment_ = std::move(state.momentum_increment);
  older_momentum_increment_ = std::move(state.older_momentum_increment);
  next_momentum_increment_.clear();
  operators_valid_ = false;  // rebuilt from the restored cloud and neighbour list
  lattice_fit_ = QuadraticFit{};
  pressure_lu_ = numerics::SparseLu{};
}

Solver::~Solver() = default;
Solver::Solver(Solver&&) noexcept = default;
Solver& Solver::operator=(Solver&&) noexcept = default;

std::vector<double> Solver::sample_velocity(std::span<const double> points) const {
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

double Solver::kinetic_energy() const {
  double sum = 0;
  for (std::size_t i = 0; i < kinds_.size(); ++i)
    if (is_fluid(i)) sum += velocity_[2 * i] * velocity_[2 * i] + velocity_[2 * i + 1] * velocity_[2 * i + 1];
  return 0.5 * params_.density * sum * params_.spacing * params_.spacing;
}

}  // namespace rheosim::ldd
