#pragma once
// coupling::Coupler: advances LIGGGHTS and the transient fluid solver together (CD §3–4).
// One coupling step (coupling/src/coupling_step.hpp, the order the shear cell's loop takes too):
//   1. DEM: N = coupling_interval LIGGGHTS steps with the fluid forces of the previous step held
//      fixed (fix external, dem::Engine::set_external_forces);
//   2. void fraction ε from the new particle positions (VoidFractionField; volume conserved to
//      round-off, floor + redistribution reported) → TransientSolver::set_void_fraction;
//   3. forces: the fluid (u_f, ∇p, ∇·τ, μ, ε) interpolated to the particles (FluidSampler), the
//      force models (forces.hpp) evaluated, the totals set in LIGGGHTS for the next N steps, and
//      the reaction (drag split into f and the implicit K, exchange.hpp) set as the fluid's
//      momentum source;
//   4. fluid: TransientSolver::advance(Δt_CFD).
// CFD δt = coupling interval × DEM δt (CD §4: 1e-5 s = 100 × 1e-7 s) is checked at construction
// (std::invalid_argument naming both values). The DEM and the fluid must see the same gravity
// (the fluid's hydrostatic ∇p carries the particles' buoyancy through CD eq. 34); with a
// RheometerScene this is checked, and the fluid's top plate follows the scene's Ω every step.
//
// The wall time of each part is accumulated in CostSplit (for summary.json). Torques per step:
// fluid torque on the top plate (TransientSolver, the conservative wall flux) and the particle
// contact torque (RheometerScene's mesh stress, mean of the torque blocks finished during the
// step, else the instantaneous value; 0 without a scene).
//
// One MPI rank only (the void fraction is not reduced over ranks yet): the constructor checks
// that this rank owns every particle.
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rheosim/coupling/exchange.hpp"
#include "rheosim/coupling/forces.hpp"
#include "rheosim/coupling/void_fraction.hpp"
#include "rheosim/dem/engine.hpp"
#include "rheosim/dem/rheometer_scene.hpp"
#include "rheosim/fluid/transient.hpp"

namespace rheosim::coupling {

struct CostSplit;
namespace detail {
template <class Loop, class Record>
void take_coupling_step(Loop& loop, bool with_particles, Record& record, CostSplit& cost);  // coupling_step.hpp
}  // namespace detail

struct CouplerSettings {
  int coupling_interval = 100;                            // N DEM steps per fluid step, >= 1
  double fluid_time_step = 0.0;                           // Δt_CFD [s] > 0, must equal N × DEM δt
  double time_step_tolerance = 1e-6;                      // relative mismatch allowed in that check
  std::string void_fraction = "divided";                  // centre | divided
  double void_fraction_floor = 0.3;                       // ε_min in (0, 1)
  std::vector<std::string> forces = seed_force_models();  // force model names (forces.hpp)
  // Time constant of the ∇p filter in fluid steps (fluid_fields.hpp: the projection pressure's
  // answer to ∂ε/∂t, fed back explicitly, is unstable for neutrally buoyant particles); 0 = off.
  double pressure_gradient_filter_steps = 50.0;
  // ρ_p [kg/m³] for the drag-relaxation diagnostic (m/(β Δt)); 0: taken from the scene, else off.
  double particle_density = 0.0;
};

// Accumulated wall time per part of the coupling step [s].
struct CostSplit {
  double dem = 0.0;
  double void_fraction = 0.0;
  double forces = 0.0;  // interpolation, force models, exchange, handing forces to LIGGGHTS
  double fluid = 0.0;
  double near_field = 0.0;  // near-field models inside the DEM steps, not counted in dem
  std::int64_t steps = 0;
  // Coupling steps whose fluid step broke the fluid's Courant limit and was split into
  // substeps (the coupling forces held over them), and the most substeps one needed.
  std::int64_t fluid_split_steps = 0;
  int max_fluid_substeps = 1;
  // Coupling steps on which some cell held more solid than the void-fraction floor allows (its
  // excess moved to neighbours: ε changed locally), steps on which not all of it could be placed
  // (ε clamped, solid volume not conserved), and the smallest ε before the floor.
  std::int64_t void_fraction_floor_steps = 0;
  std::int64_t void_fraction_clamped_steps = 0;
  double min_raw_void_fraction = 1.0;
  [[nodiscard]] double total() const { return dem + void_fraction + forces + fluid + near_field; }
  // (void fraction + forces) / DEM: the coupling overhead, kept below 25 %.
  [[nodiscard]] double coupling_overhead() const { return dem > 0.0 ? (void_fraction + forces) / dem : 0.0; }
};

struct CouplingStepRecord {
  double time = 0.0;            // fluid time after the step [s]
  double fluid_torque = 0.0;    // top plate, fluid part [N·m]
  double contact_torque = 0.0;  // top plate, particle contacts [N·m]
  // Fluid torque transmitted to the bottom plate [N·m]; fluid_torque − bottom_fluid_torque is
  // what the fluid hands to the particles (and on to their contacts) at steady state.
  double bottom_fluid_torque = 0.0;
  // Near-field parts (0 without particles.hydrodynamics), filled by run_point: plate
  // lubrication on the top plate, and the torque the particle stresslets transmit,
  // (1/H) Σ_p (x_p S_yz − y_p S_xz), which the fluid grid does not carry [N·m].
  // The rotation couples' part −Σ (x T_x + y T_y) / (2H) (near_field.hpp), likewise.
  double lubrication_torque = 0.0;
  double stresslet_torque = 0.0;
  double couple_torque = 0.0;
  [[nodiscard]] double total_torque() const {
    return fluid_torque + contact_torque + lubrication_torque + stresslet_torque + couple_torque;
  }
};

struct CouplingStepReport {
  CouplingStepRecord record;
  fluid::StepReport fluid;
  VoidFractionReport void_fraction;
  ExchangeBalance balance;
  // min_p m_p/(β_p Δt_CFD): the drag on a particle is explicit over the coupling interval, which
  // is stable and accurate when this is well above 1 (0 when unknown).
  double drag_relaxation_steps = 0.0;
};

class Coupler {
 public:
  // With a rheometer scene: contact torque, plate speed and gravity come from it.
  Coupler(CouplerSettings settings, dem::RheometerScene& scene, fluid::TransientSolver& fluid);
  // With a bare engine (tests, other containers): no contact torque.
  Coupler(CouplerSettings settings, dem::Engine& engine, fluid::TransientSolver& fluid);
  ~Coupler();
  Coupler(const Coupler&) = delete;
  Coupler& operator=(const Coupler&) = delete;
  Coupler(Coupler&&) = delete;
  Coupler& operator=(Coupler&&) = delete;

  // One coupling step (see the header). Throws fluid::StepError / dem::EngineError from the
  // solvers (the fluid state is then the one before the step; the DEM has advanced).
  const CouplingStepReport& step();
  // Steps until the fluid time reaches end_time (within half a step).
  void run_until(double end_time);

  [[nodiscard]] const CostSplit& cost() const { return cost_; }
  [[nodiscard]] const std::vector<CouplingStepRecord>& torque_series() const { return series_; }
  [[nodiscard]] const CouplingStepReport& last() const { return last_; }
  [[nodiscard]] const CouplerSettings& settings() const { return settings_; }
  [[nodiscard]] double time() const;

  // This step's state, for diagnostics and tests.
  [[nodiscard]] const VoidFractionField& void_fraction() const { return void_fraction_; }
  [[nodiscard]] const std::vector<ParticleSample>& samples() const { return samples_; }
  [[nodiscard]] const std::vector<ParticleForce>& forces() const { return forces_; }
  [[nodiscard]] const MomentumExchange& exchange() const { return exchange_; }
  [[nodiscard]] dem::Engine& engine() { return *engine_; }
  [[nodiscard]] fluid::TransientSolver& fluid() { return *fluid_; }

 private:
  Coupler(CouplerSettings settings, dem::RheometerScene* scene, dem::Engine& engine, fluid::TransientSolver& fluid);
  ParticleView particles() const;
  // The phases of step() (header comment), in take_coupling_step's order.
  template <class Loop, class Record>
  friend void detail::take_coupling_step(Loop& loop, bool with_particles, Record& record, CostSplit& cost);
  void advance_particles(CouplingStepRecord& record);
  void update_void_fraction(bool reset = false);
  void update_forces(CouplingStepRecord& record);
  void advance_fluid(CouplingStepRecord& record);
  fluid::StepReport fluid_step(double dt);  // split into substeps where the Courant limit asks

  CouplerSettings settings_;
  dem::RheometerScene* scene_;
  dem::Engine* engine_;
  fluid::TransientSolver* fluid_;
  std::unique_ptr<const VoidFractionScheme> scheme_;
  std::vector<std::unique_ptr<const ForceModel>> models_;
  VoidFractionField void_fraction_;
  FluidSampler sampler_;
  MomentumExchange exchange_;
  std::vector<ParticleSample> samples_;
  std::vector<ParticleForce> forces_;
  std::vector<double> dem_forces_;
  std::vector<CouplingStepRecord> series_;
  CouplingStepReport last_;
  CostSplit cost_;
  std::size_t torque_samples_seen_ = 0;
};

}  // namespace rheosim::coupling
