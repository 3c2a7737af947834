#pragma once
// The vocabulary both LDD solvers share: their settings, statistics, phase timings and divergence
// error. StepParams: the settings every LDD step reads, whatever its scene (LDD §3.2): the material, the resolution,
// the time step, the linear solves, the PBD and the divergence guard. The lattice cavity's
// SolverParams (solver.hpp) and the free surface's FreeSurfaceParams (free_surface.hpp) extend it
// with their scenes' own settings; where a free surface needs another default, FreeSurfaceParams'
// constructor sets it.
#include <cstddef>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "rheosim/core/rheology.hpp"
#include "rheosim/ldd/preconditioner.hpp"
#include "rheosim/numerics/amg.hpp"
#include "rheosim/numerics/krylov.hpp"

namespace rheosim::ldd {

struct StepParams {
  double density = 1.0;                            // ρ [kg/m³], > 0
  std::shared_ptr<const core::Rheology> rheology;  // μ(γ̇), not null
  std::vector<double> gravity{0.0, 0.0};           // F_ext/ρ = g [m/s²], one entry per dimension
  double spacing = 0;                              // Δ [m], > 0
  double smoothing_ratio = 1.6;                    // h/Δ, [1.2, 3]
  double time_step = 0;                            // δt [s], > 0
  double pressure_tolerance = 1e-6;                // BiCGStab relative residual of the PPE (eq. 17), (0, 1)
  double velocity_tolerance = 1e-8;                // BiCGStab relative residual of eq. 19, (0, 1)
  int max_iterations = 2000;                       // per linear solve, >= 1
  int pbd_iterations = 2;                          // PBD sweeps per step (0: no reordering)
  double pbd_stiffness = 0.5;                      // fraction of the PBD shift applied per sweep, (0, 1]
  double pbd_max_shift = 0.05;                     // per sweep, in units of Δ, (0, 0.5]
  double wall_clearance = 0.5;                     // min fluid-node distance to a wall, units of Δ, (0, 1)
  double max_courant = 1.0;                        // stop (diverged) when max|u| δt/Δ exceeds this, > 0
  double neighbour_skin = 0.2;                     // search radius h + skin·Δ, [0, 1] (PBD moves nodes)
  // Preconditioners of the PPE and eq. 19 (each solver's header says which it offers).
  Preconditioner pressure_preconditioner = Preconditioner::sparse_lu;
  Preconditioner velocity_preconditioner = Preconditioner::jacobi;
  numerics::AmgSettings pressure_amg, velocity_amg;  // when the preconditioner is amg

  // Throws std::invalid_argument "<solver>: <field> = <value> is out of range, expected <range>"
  // for the first field out of its range (gravity: one entry per dimension).
  void check(std::string_view solver, std::size_t dimension) const;
};

// Thrown by a solver's step() when the solution diverges (NaN, Courant number, failed solves).
// The solver's state is the last good step's.
class DivergenceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What one step reports, whatever the scene (each solver extends it with its own).
struct StepStats {
  int pressure_iterations = 0;   // BiCGStab iterations (a direct LU solve counts as 1)
  double pressure_residual = 0;  // relative
  int velocity_iterations = 0;   // all components
  double velocity_residual = 0;  // relative, the largest of the components'
  double max_speed = 0;          // [m/s]
  double courant = 0;            // max|u| δt/Δ
  double max_pbd_shift = 0;      // largest PBD displacement this step, in units of Δ
  // The step's pressure / velocity solve did not converge and was accepted (its residual below
  // 1000× the tolerance; beyond that the step stops as diverged).
  bool pressure_accepted_unconverged = false, velocity_accepted_unconverged = false;
};

// Phase 5 of both steps, before anything is committed: what the checks read.
struct StepCheck {
  double next_time = 0;             // [s]
  std::size_t step = 0;             // this step's number
  bool finite = true;               // every new velocity and pressure
  double max_speed = 0;             // over the nodes that limit the Courant number [m/s]
  numerics::KrylovResult pressure;  // the PPE's solve
  bool velocity_converged = true;   // eq. 19's solves (their residual is in the stats)
  // What the solver adds to a message: where the fastest node is (" at a wall node at …"), and
  // after "… after N iterations " why a pressure solve may have failed ("(tolerance 1e-6)").
  std::function<std::string()> where_fastest, pressure_failure;
};
// Sets stats' max_speed, courant and accepted-unconverged flags; throws DivergenceError for a
// non-finite value, a Courant number above params.max_courant, or a solve 10³ above its tolerance.
void check_step(const StepCheck& check, const StepParams& params, StepStats& stats);

// Wall-clock seconds per phase, accumulated over all steps (for the benchmark and summary.json).
struct PhaseTimes {
  double neighbours = 0, operators = 0, rheology = 0, pressure = 0, momentum = 0, advection = 0, reordering = 0;
  friend bool operator==(const PhaseTimes&, const PhaseTimes&) = default;
  [[nodiscard]] double total() const {
    return neighbours + operators + rheology + pressure + momentum + advection + reordering;
  }
};

}  // namespace rheosim::ldd
