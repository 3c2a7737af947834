#pragma once
// One suspension shear-rate point of the virtual rheometer: a
// dem::RheometerScene and a fluid::TransientSolver on the same gap, coupled by
// coupling::Coupler, run until the plate torque is steady, for rheometer/run.cpp to report
// (summary.json: torque, torque_fluid, torque_contact, cost split).
//
// Steady state (SteadyStateDetector): the strain γ = γ̇_R t is the clock. The torque series
// (fluid + contact, one value per coupling step) is averaged over the last strain window Δγ and
// the window before it; the point is steady when the two means differ by at most
// relative_tolerance × |mean| and the standard error of the last window (batch means over 5
// sub-windows, so correlated samples are not over-counted) is at most relative_tolerance ×
// |mean|. The reported torque is the last window's mean ± its standard error. The run also stops
// at max_strain (converged = false then).
//
// φ = 0 runs the fluid alone on the same grid and time step (N × the DEM step the particles
// would have), the same-grid reference for the suspension's torque increase (no LIGGGHTS).
//
// Near-field hydrodynamics (`hydrodynamics`, a case's particles.hydrodynamics): the model runs on every DEM step
// through coupling::NearFieldStepHook (implicit, see near_field.hpp) with the solved fluid as the
// ambient flow (per cell: the velocity gradient of the cell-centred velocities, with the
// cylindrical metric terms, in Cartesian components at the particle). The plate torque is then
// fluid + contact + plate lubrication + what the stresslets and the particles' rotation couples
// transmit through the liquid (the grid does not carry them; near_field.hpp), each reported.
//
// The fluid starts from the creeping Couette profile u_θ = Ω r z/H (the steady single-phase
// state), the particles from the scene's placement at rest.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "rheosim/core/case.hpp"
#include "rheosim/coupling/coupler.hpp"
#include "rheosim/coupling/drag.hpp"
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/dem/particles.hpp"

namespace rheosim::coupling {

struct SteadyStateSettings {
  double strain_window = 1.0;        // Δγ of one averaging window [-] > 0
  double relative_tolerance = 0.02;  // > 0
  double min_strain = 2.0;           // no decision before this strain (>= 2 windows is enforced)
  double max_strain = 20.0;          // stop here even if not steady
};

struct SteadyEstimate {
  bool steady = false;
  double mean = 0.0;            // over the last window
  double standard_error = 0.0;  // of that mean (batch means)
  double previous_mean = 0.0;   // over the window before
  std::size_t samples = 0;      // in the last window
};

class SteadyStateDetector {
 public:
  SteadyStateDetector(SteadyStateSettings settings, double rim_shear_rate);  // γ̇_R > 0
  void add(double time, double value);
  [[nodiscard]] SteadyEstimate estimate() const;
  [[nodiscard]] double strain() const;  // γ̇_R t of the last sample
  [[nodiscard]] bool done() const;      // steady (after min_strain) or past max_strain

 private:
  SteadyStateSettings settings_;
  double shear_rate_;
  std::vector<double> times_, values_;
};

struct SuspensionPointSettings {
  core::PlateGeometry geometry{};
  core::FluidProperties fluid{};
  dem::ParticleProperties particles{};
  DragLaw drag = DragLaw::di_felice;  // particles.drag
  NearFieldSettings hydrodynamics{};  // particles.hydrodynamics; no terms: the seed's drag only
  double rim_shear_rate = 0.0;        // γ̇_R [1/s] > 0
  // Fluid grid and model.
  int radial_cells = 8, azimuthal_cells = 8, axial_cells = 2;
  bool inertia = true;
  bool gravity = true;  // standard gravity along −z in both DEM and fluid
  // DEM time step: explicit, or this fraction of the Rayleigh time.
  std::optional<double> dem_time_step = std::nullopt;
  double time_step_fraction = 0.3;
  // Coupling: interval, void fraction, forces (fluid_time_step is derived: N × DEM δt). The drag
  // law in forces must be `drag`: force_models(drag) (run_point checks).
  CouplerSettings coupling{};
  SteadyStateSettings steady{};
  std::uint64_t seed = 1;
  std::filesystem::path run_directory{};  // for LIGGGHTS' files
  // Called about every 1 % of max_strain with (strain reached, max_strain), for live progress.
  std::function<void(double, double)> on_strain{};
};

struct SuspensionPoint {
  double shear_rate = 0.0;            // γ̇_R [1/s]
  double torque = 0.0;                // fluid + contact, mean over the last window [N·m]
  double torque_error = 0.0;          // its standard error [N·m]
  double torque_fluid = 0.0;          // mean fluid part [N·m]
  double torque_contact = 0.0;        // mean contact part [N·m]
  double torque_lubrication = 0.0;    // mean plate lubrication part [N·m] (near field)
  double torque_stresslet = 0.0;      // mean stresslet part [N·m] (near field)
  double torque_couple = 0.0;         // mean rotation-couple part [N·m] (near field)
  int max_near_field_iterations = 0;  // conjugate-gradient iterations of the implicit near field
  double bottom_torque_fluid = 0.0;   // mean fluid torque on the bottom plate [N·m]
  bool converged = false;
  double strain = 0.0;  // γ̇_R t at the end
  std::int64_t particles = 0;
  double fluid_time_step = 0.0, dem_time_step = 0.0;
  std::vector<CouplingStepRecord> series;  // per coupling step
  CostSplit cost;
  VoidFractionReport void_fraction;  // last step
  double wall_time = 0.0;            // [s]
};

// Runs one point. Throws std::invalid_argument for bad settings, dem::EngineError or
// fluid::StepError from the solvers.
[[nodiscard]] SuspensionPoint run_point(const SuspensionPointSettings& settings);

}  // namespace rheosim::coupling
