#include "rheosim/ldd/solver.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "rheosim/numerics/row_blocks.hpp"

namespace rheosim::ldd {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

const char* kind_name(NodeKind k) {
  switch (k) {
    case NodeKind::interior:
      return "interior";
    case NodeKind::surface:
      return "free-surface";
    case NodeKind::splash:
      return "splash";
    case NodeKind::wall:
      return "wall";
    case NodeKind::corner:
      return "corner";
    default:
      return "idle wall";
  }
}

void Solver::velocity_gradient_of(std::span<const double> u, std::span<double> out) const {
  const auto dim = static_cast<std::size_t>(params_.dimension);
  const std::size_t dd = dim * dim;
  const numerics::NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  numerics::for_balanced_rows(nb.offsets, [&](std::size_t i) {
    double grad[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};  // grad[a·dim + b] = ∂u_a/∂x_b
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
      const std::size_t j = nb.indices[k];
      for (std::size_t a = 0; a < dim; ++a) {
        const double du = u[dim * j + a] - u[dim * i + a];
        for (std::size_t b = 0; b < dim; ++b) grad[a * dim + b] += ops.gradient[k * dim + b] * du;
      }
    }
    for (std::size_t c = 0; c < dd; ++c) out[dd * i + c] = grad[c];
  });
}

Solver::Solver(SolverParams params) : params_(std::move(params)) {
  params_.check();
  pressure_amg_ = numerics::AmgPreconditioner(params_.pressure_amg);
  velocity_amg_ = numerics::AmgPreconditioner(params_.velocity_amg);
  support_radius_ = params_.smoothing_ratio * params_.spacing;
}

StepStats Solver::step() {
  StepStats stats;
  const double next_time = time_ + params_.time_step;

  auto t0 = Clock::now();
  update_operators(stats);  // 1
  times_.operators += seconds_since(t0);

  t0 = Clock::now();
  update_viscosity();  // 2
  times_.rheology += seconds_since(t0);

  t0 = Clock::now();
  const bool velocity_converged = solve_momentum(next_time, stats);  // 3
  times_.momentum += seconds_since(t0);

  t0 = Clock::now();
  const numerics::KrylovResult pressure = solve_pressure(stats);  // 4
  const Correction correction = correct_velocity();
  times_.pressure += seconds_since(t0);

  check_divergence(next_time, correction, pressure, velocity_converged, stats);  // 5

  t0 = Clock::now();
  commit_and_advect(next_time);  // 6
  times_.advection += seconds_since(t0);
  time_ = next_time;
  ++steps_;

  reorder(stats);  // 7
  return stats;
}

void Solver::check_divergence(double next_time, const Correction& correction, const numerics::KrylovResult& pressure,
                              bool velocity_converged, StepStats& stats) const {
  StepCheck check;
  check.next_time = next_time;
  check.step = steps_ + 1;
  check.finite = correction.finite;
  check.max_speed = correction.max_speed;
  check.pressure = pressure;
  check.velocity_converged = velocity_converged;
  check.where_fastest = [&] {
    const std::size_t at = correction.fastest;
    return fmt::format(" at {} node at {}, {} neighbours", a_kind(kinds_[at]), place(at),
                       neighbours_.offsets[at + 1] - neighbours_.offsets[at]);
  };
  check.pressure_failure = [&] { return pressure_failure(stats); };
  check_step(check, params_, stats);
}

std::string Solver::place(std::size_t node) const {
  const auto dim = static_cast<std::size_t>(params_.dimension);
  return fmt::format("({:.4g}, {:.4g}{})", positions_[dim * node], positions_[dim * node + 1],
                     dim == 3 ? fmt::format(", {:.4g}", positions_[dim * node + 2]) : std::string());
}

std::string a_kind(NodeKind k) {
  const std::string name = kind_name(k);
  return (name.front() == 'i' ? "an " : "a ") + name;
}

double Solver::kinetic_energy() const {
  const auto dim = static_cast<std::size_t>(params_.dimension);
  double sum = 0;
  for (std::size_t i = 0; i < kinds_.size(); ++i)
    if (is_fluid(i))
      for (std::size_t d = 0; d < dim; ++d) sum += velocity_[dim * i + d] * velocity_[dim * i + d];
  return 0.5 * params_.density * sum * std::pow(params_.spacing, params_.dimension);
}

std::size_t Solver::fluid_node_count() const {
  std::size_t count = 0;
  for (std::size_t i = 0; i < kinds_.size(); ++i) count += is_fluid(i) ? 1 : 0;
  return count;
}

SolverState Solver::common_state() const {
  SolverState s;
  s.time = time_;
  s.steps = steps_;
  s.first_step = first_step_;
  s.positions = positions_;
  s.velocity = velocity_;
  s.previous_velocity = previous_velocity_;
  s.pressure = pressure_;
  s.shear_rate = shear_rate_;
  s.viscosity = viscosity_;
  s.kinds = kinds_;
  s.neighbours = neighbours_;
  s.times = times_;
  s.pressure_amg = pressure_amg_.state();
  s.velocity_amg = velocity_amg_.state();
  return s;
}

void Solver::restore_common_state(SolverState& state, const char* who) {
  const int dimension = params_.dimension;
  const std::size_t n = kinds_.size(), nd = static_cast<std::size_t>(dimension) * n;
  const auto fits = [](const std::vector<double>& v, std::size_t size) { return v.size() == size; };
  if (state.kinds.size() != n || !fits(state.positions, nd) || !fits(state.velocity, nd) ||
      !fits(state.previous_velocity, nd) || !fits(state.pressure, n) || !fits(state.shear_rate, n) ||
      !fits(state.viscosity, n))
    throw std::invalid_argument(
        fmt::format("{} state: its arrays do not fit this cloud of {} nodes in {}D", who, n, dimension));
  for (std::size_t i = 0; i < n; ++i)
    if ((state.kinds[i] <= NodeKind::splash) != is_fluid(i) || state.kinds[i] > NodeKind::idle_wall)
      throw std::invalid_argument(fmt::format("{} state: node {} is {} node in the state but {} here", who, i,
                                              a_kind(state.kinds[i]), is_fluid(i) ? "fluid" : "a wall"));
  const numerics::NeighbourList& nb = state.neighbours;
  bool list_fits = nb.offsets.size() == n + 1 && nb.offsets.front() == 0 && nb.offsets.back() == nb.indices.size() &&
                   nb.distances.size() == nb.indices.size();
  for (std::size_t i = 0; list_fits && i < n; ++i) list_fits = nb.offsets[i] <= nb.offsets[i + 1];
  for (std::size_t k = 0; list_fits && k < nb.indices.size(); ++k) list_fits = nb.indices[k] < n;
  if (!list_fits) throw std::invalid_argument(fmt::format("{} state: its neighbour list does not fit the cloud", who));
  for (const numerics::AmgState* amg : {&state.pressure_amg, &state.velocity_amg})
    if (!amg->empty() && (amg->diagonal.size() != n || amg->offsets.size() != n + 1))
      throw std::invalid_argument(fmt::format("{} state: a kept AMG set-up matrix does not fit the cloud", who));
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
  times_ = state.times;
}

}  // namespace rheosim::ldd
