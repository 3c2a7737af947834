#pragma once
// The LDD solver (LDD §3.2): the node cloud and its fields, and the one time step every scene
// takes, Solver::step(), in seven phases:
//
//   1. update_operators   the operators of eqs. 13–16 on the current cloud (and what the scheme
//                         classifies on it);
//   2. update_viscosity   ∇u (eq. 14), E (eq. 4), γ̇ = √(2E:E) (eq. 5), μ(γ̇);
//   3. solve_momentum     semi-implicit momentum (eq. 19) with the previous pressure → u*;
//   4. solve_pressure     the PPE (eq. 17) for the increment φ = p_n − p_{n−1};
//      correct_velocity   p_n and u_n = u* − δt/ρ ⟨∇φ⟩;
//   5. check_divergence   NaN, Courant number, failed solves: DivergenceError, and the state of
//                         the last good step is kept (nothing is committed before this);
//   6. commit_and_advect  commit, advect (eq. 20), the clock moves;
//   7. reorder            keep the cloud ordered.
//
// Two schemes fill the phases: the lattice cavity (cavity_solver.hpp: a closed box, Neumann
// walls, nodes back on the lattice every step) and the free surface (free_surface.hpp: Lagrangian
// nodes classified every step, p = 0 on the surface, the PBD). They differ in their boundary rows,
// the classification and the reordering; the rest of the step, the node state, the checks, the
// statistics, the parameters and the checkpoint are this class's.
#include <cstddef>
#include <span>
#include <string>
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

class Solver {
 public:
  virtual ~Solver() = default;

  // Advances one time step δt. Throws DivergenceError (the last good step's state kept).
  StepStats step();

  [[nodiscard]] int dimension() const { return params_.dimension; }
  [[nodiscard]] const SolverParams& params() const { return params_; }
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

  // The state a checkpoint keeps. restore() takes a state of a solver built from the same scene
  // and parameters (throws std::invalid_argument naming a mismatch, before anything is changed);
  // the run then continues bit for bit.
  [[nodiscard]] virtual SolverState state() const = 0;
  virtual void restore(SolverState state) = 0;
  // Kinetic energy Σ ½ ρ |u|² Δ^d over fluid nodes [J, or J/m in 2D] (a lattice-volume estimate).
  [[nodiscard]] double kinetic_energy() const;

 protected:
  explicit Solver(SolverParams params);
  Solver(const Solver&) = default;
  Solver(Solver&&) noexcept = default;
  Solver& operator=(const Solver&) = default;
  Solver& operator=(Solver&&) noexcept = default;

  // What the velocity correction leaves for the divergence checks.
  struct Correction {
    bool finite = true;       // every new velocity and pressure finite
    double max_speed = 0;     // over the nodes that limit the Courant number [m/s]
    std::size_t fastest = 0;  // the node that has it
  };
  // The phases of step() (header comment), each scheme's.
  virtual void update_operators(StepStats& stats) = 0;
  virtual void update_viscosity() = 0;
  virtual bool solve_momentum(double next_time, StepStats& stats) = 0;  // into new_velocity_; converged?
  virtual numerics::KrylovResult solve_pressure(StepStats& stats) = 0;  // into increment_
  virtual Correction correct_velocity() = 0;                            // new_pressure_, new_velocity_
  virtual void commit_and_advect(double next_time) = 0;
  virtual void reorder(StepStats&) {}  // after the clock has moved; timed by the scheme
  // After "pressure solve failed … after N iterations ": why it may have failed.
  [[nodiscard]] virtual std::string pressure_failure(const StepStats& stats) const = 0;

  // The state every scheme keeps alike (no momentum increments).
  [[nodiscard]] SolverState common_state() const;
  // Checks `state` against this cloud (`who` names the solver in the message) and takes its
  // common part. Throws std::invalid_argument naming the mismatch (node count, a wall node
  // turned fluid or back, a neighbour list or a kept AMG matrix that does not fit), before
  // anything is changed.
  void restore_common_state(SolverState& state, const char* who);
  // "(x, y)" or "(x, y, z)" of a node, for messages.
  [[nodiscard]] std::string place(std::size_t node) const;
  // ∇u (eq. 14) of a velocity field on the current operators: per node ∂u_a/∂x_b at
  // out[dimension² i + dimension a + b].
  void velocity_gradient_of(std::span<const double> u, std::span<double> out) const;

  SolverParams params_;
  std::vector<NodeKind> kinds_;
  std::vector<double> positions_, velocity_, previous_velocity_, pressure_, shear_rate_, viscosity_;
  std::vector<double> normals_;  // inward unit normal of wall nodes (0 for fluid nodes)
  double support_radius_ = 0;    // h [m]
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
  std::vector<double> new_pressure_;  // p_n until the step commits

 private:
  // 5. The checks of step.hpp's check_step, with where the fastest node is.
  void check_divergence(double next_time, const Correction& correction, const numerics::KrylovResult& pressure,
                        bool velocity_converged, StepStats& stats) const;
};

}  // namespace rheosim::ldd
