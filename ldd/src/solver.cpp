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
  require(pbd_min_distance >= 0 && pbd_min_distance < 1, "pbd_min_distance", pbd_min_distance, "[0, 1)");
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
  rebuild_neighbours();

  // PBD rest density ρ₀: the kernel sum of the initial lattice's fluid nodes (median, so the
  // few near-corner nodes do not matter).
  std::vector<double> densities;
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_fluid(i)) continue;
    double rho = weight(0.0, support_radius_);
    for (std::size_t k = neighbours_.offsets[i]; k < neighbours_.offsets[i + 1]; ++k)
      rho += weight(neighbours_.distances[k], support_radius_);
    densities.push_back(rho);
  }
  if (densities.empty()) throw std::invalid_argument("LDD solver: the cloud has no fluid nodes");
  std::nth_element(densities.begin(), densities.begin() + static_cast<std::ptrdiff_t>(densities.size() / 2),
                   densities.end());
  rest_density_ = densities[densities.size() / 2];
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

void Solver::rebuild_neighbours() {
  neighbours_ = numerics::find_neighbours(positions_, 2, support_radius_ + params_.neighbour_skin * params_.spacing);
}

void Solver::keep_inside(std::size_t i, std::span<double> velocity) {
  const double clearance = params_.wall_clearance * params_.spacing;
  for (const auto& wall : walls_) {
    double distance = 0, normal[2] = {0, 0};
    if (!wall->distance(std::span<const double>(&positions_[2 * i], 2), time_, distance, normal)) continue;
    if (distance >= clearance) continue;
    positions_[2 * i] += (clearance - distance) * normal[0];
    positions_[2 * i + 1] += (clearance - distance) * normal[1];
    if (velocity.empty()) continue;
    // A node held off the wall must not keep running into it: drop the velocity component
    // towards the wall (a wall's own velocity, a lid's, is tangential: no normal part).
    const double approach = normal[0] * velocity[2 * i] + normal[1] * velocity[2 * i + 1];
    if (approach < 0) {
      velocity[2 * i] -= approach * normal[0];
      velocity[2 * i + 1] -= approach * normal[1];
    }
  }
}

void Solver::reorder(std::span<const double> grad_u) {
  const std::size_t n = kinds_.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  shift_.assign(2 * n, 0.0);
  if (params_.pbd_iterations == 0) return;
  const numerics::NeighbourList& nb = neighbours_;
  const double h = support_radius_, rho0 = rest_density_;
  const double max_shift = params_.pbd_max_shift * params_.spacing;
  const double min_distance = params_.pbd_min_distance * params_.spacing;
  std::vector<double> lambda(n, 0.0), step(2 * n, 0.0);
  for (int iteration = 0; iteration < params_.pbd_iterations; ++iteration) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      if (!is_fluid(i)) continue;
      double density = weight(0.0, h), gx = 0, gy = 0, squares = 0;
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
        const std::size_t j = nb.indices[k];
        const double dx = positions_[2 * i] - positions_[2 * j], dy = positions_[2 * i + 1] - positions_[2 * j + 1];
        const double r = std::hypot(dx, dy);
        density += weight(r, h);
        if (r <= 0) continue;
        const double dw = weight_derivative(r, h) / r / rho0;  // ∇_i W_ij / ρ₀ = dw · (x_i − x_j)
        gx += dw * dx;
        gy += dw * dy;
        squares += dw * dw * r * r;  // |∇_j C_i|²
      }
      const double constraint = density / rho0 - 1.0;
      const double denominator = gx * gx + gy * gy + squares;
      lambda[i] = denominator > 0 ? -constraint / denominator : 0.0;
    }
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      if (!is_fluid(i)) continue;
      double sx = 0, sy = 0;
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
        const std::size_t j = nb.indices[k];
        const double dx = positions_[2 * i] - positions_[2 * j], dy = positions_[2 * i + 1] - positions_[2 * j + 1];
        const double r = std::hypot(dx, dy);
        if (r <= 0) continue;
        const double dw = weight_derivative(r, h) / r / rho0;
        sx += (lambda[i] + lambda[j]) * dw * dx;
        sy += (lambda[i] + lambda[j]) * dw * dy;
      }
      sx *= params_.pbd_stiffness;
      sy *= params_.pbd_stiffness;
      // Minimum-distance constraint: nearly coincident nodes make the operators stiff.
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
        const std::size_t j = nb.indices[k];
        const double dx = positions_[2 * i] - positions_[2 * j], dy = positions_[2 * i + 1] - positions_[2 * j + 1];
        const double r = std::hypot(dx, dy);
        if (r >= min_distance || r <= 0) continue;
        const double share = is_fluid(j) ? 0.5 : 1.0;
        sx += share * (min_distance - r) * dx / r;
        sy += share * (min_distance - r) * dy / r;
      }
      const double length = std::hypot(sx, sy);
      if (length > max_shift) {
        sx *= max_shift / length;
        sy *= max_shift / length;
      }
      step[2 * i] = sx;
      step[2 * i + 1] = sy;
    }
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      if (!is_fluid(i)) continue;
      const double x0 = positions_[2 * i], y0 = positions_[2 * i + 1];
      positions_[2 * i] += step[2 * i];
      positions_[2 * i + 1] += step[2 * i + 1];
      keep_inside(i, {});
      shift_[2 * i] += positions_[2 * i] - x0;
      shift_[2 * i + 1] += positions_[2 * i + 1] - y0;
    }
  }
  // Carry the velocities to the shifted places (first-order Taylor, LDD §3.2 interpolation).
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (!is_fluid(i)) continue;
    const double sx = shift_[2 * i], sy = shift_[2 * i + 1];
    const double* g = &grad_u[4 * i];
    const double du = g[0] * sx + g[1] * sy, dv = g[2] * sx + g[3] * sy;
    velocity_[2 * i] += du;
    velocity_[2 * i + 1] += dv;
    previous_velocity_[2 * i] += du;
    previous_velocity_[2 * i + 1] += dv;
  }
}

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
