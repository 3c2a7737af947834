#pragma once
// What both LDD solvers hold alike for their node cloud (solver.hpp, free_surface.hpp): the
// fields, the neighbour list and operators of the current cloud, the two linear systems with
// their preconditioners and workspaces, the clock and the phase timings. Each solver derives
// from it and adds what its scenes need.
#include <cstddef>
#include <span>
#include <vector>

#include "rheosim/ldd/node_cloud.hpp"
#include "rheosim/ldd/operators.hpp"
#include "rheosim/ldd/step.hpp"
#include "rheosim/numerics/amg.hpp"
#include "rheosim/numerics/krylov.hpp"
#include "rheosim/numerics/neighbours.hpp"

namespace rheosim::ldd {

// What one step hands to the next: the content of a run's checkpoint (checkpoint.cpp). Restored
// into a solver built from the same scene and parameters, the run continues bit for bit (kept AMG
// hierarchies are rebuilt from the matrix of their last set-up).
struct SolverState {
  double time = 0;
  std::size_t steps = 0;
  bool first_step = true;  // the first advection is first order (no u_{n−1} yet)
  std::vector<double> positions, velocity, previous_velocity, pressure, shear_rate, viscosity;
  std::vector<NodeKind> kinds;
  numerics::NeighbourList neighbours;  // the list the next step uses
  PhaseTimes times;                    // wall time per phase so far
  numerics::AmgState pressure_amg, velocity_amg;
  // The cavity's momentum initial guess: u* − u of the last two committed solves (empty: none).
  std::vector<double> momentum_increment, older_momentum_increment;
};

class NodeState {
 public:
  [[nodiscard]] std::size_t node_count() const { return kinds_.size(); }
  [[nodiscard]] std::span<const NodeKind> kinds() const { return kinds_; }
  [[nodiscard]] bool is_fluid(std::size_t i) const { return kinds_[i] <= NodeKind::splash; }
  // Interior or surface: a fluid node with its operators, in the solves (splash nodes fly ballistically).
  [[nodiscard]] bool is_continuum(std::size_t i) const {
    return kinds_[i] == NodeKind::interior || kinds_[i] == NodeKind::surface;
  }
  [[nodiscard]] std::size_t fluid_node_count() const;
  [[nodiscard]] double time() const { return time_; }
  [[nodiscard]] std::size_t steps() const { return steps_; }
  [[nodiscard]] std::span<const double> positions() const { return positions_; }    // interleaved [m]
  [[nodiscard]] std::span<const double> velocity() const { return velocity_; }      // [m/s]
  [[nodiscard]] std::span<const double> pressure() const { return pressure_; }      // [Pa]
  [[nodiscard]] std::span<const double> shear_rate() const { return shear_rate_; }  // γ̇ [1/s]
  [[nodiscard]] std::span<const double> viscosity() const { return viscosity_; }    // μ(γ̇) [Pa·s]
  [[nodiscard]] const PhaseTimes& phase_times() const { return times_; }

 protected:
  NodeState() = default;

  // The state every solver keeps alike (no momentum increments).
  [[nodiscard]] SolverState common_state() const;
  // Checks `state` against this cloud (`who` names the solver in the message) and takes its
  // common part. Throws std::invalid_argument naming the mismatch (node count, a wall node
  // turned fluid or back, a neighbour list or a kept AMG matrix that does not fit), before
  // anything is changed.
  void restore_common_state(SolverState& state, int dimension, const char* who);
  // ∇u (eq. 14) of a velocity field on the current operators: per node ∂u_a/∂x_b at
  // out[dimension² i + dimension a + b].
  void velocity_gradient_of(std::span<const double> u, std::span<double> out, int dimension) const;

  std::vector<NodeKind> kinds_;
  std::vector<double> positions_, velocity_, previous_velocity_, pressure_, shear_rate_, viscosity_;
  std::vector<double> normals_;  // inward unit normal of wall nodes (0 for fluid nodes)
  double support_radius_ = 0;    // h [m]
  double rest_density_ = 0;      // ρ₀ of the PBD constraint (kernel sum, dimensionless)
  double time_ = 0;
  std::size_t steps_ = 0;
  bool first_step_ = true;  // the first advection is first order (no u_{n−1} yet)
  numerics::NeighbourList neighbours_;
  Operators operators_;
  PhaseTimes times_;
  numerics::KrylovWorkspace krylov_;
  numerics::AmgPreconditioner pressure_amg_, velocity_amg_;
  numerics::StencilMatrix pressure_matrix_, momentum_matrix_;
  // Work buffers reused across steps.
  std::vector<double> velocity_gradient_, divergence_, pressure_gradient_, rhs_, new_velocity_, component_;
  std::vector<double> increment_;     // φ = p_n − p_{n−1}
  std::vector<double> shift_;         // this step's PBD displacement per node
  std::vector<double> new_pressure_;  // p_n until the step commits
};

}  // namespace rheosim::ldd
