#include "rheosim/coupling/coupler.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "coupling_step.hpp"

namespace rheosim::coupling {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

void check_settings(const CouplerSettings& s) {
  if (!(std::isfinite(s.pressure_gradient_filter_steps) && s.pressure_gradient_filter_steps >= 0.0))
    throw std::invalid_argument(
        fmt::format("coupling: pressure_gradient_filter_steps = {} is out of range, expected a finite value >= 0",
                    s.pressure_gradient_filter_steps));
  if (s.coupling_interval < 1)
    throw std::invalid_argument(
        fmt::format("coupling: coupling_interval = {} is out of range, expected an integer >= 1", s.coupling_interval));
  if (!(std::isfinite(s.fluid_time_step) && s.fluid_time_step > 0.0))
    throw std::invalid_argument(fmt::format(
        "coupling: fluid_time_step = {} s is out of range, expected a finite value > 0", s.fluid_time_step));
  if (!(s.time_step_tolerance > 0.0 && s.time_step_tolerance < 1.0))
    throw std::invalid_argument("coupling: time_step_tolerance must be in (0, 1)");
  if (s.forces.empty()) throw std::invalid_argument("coupling: no force models given (e.g. di_felice)");
}

}  // namespace

Coupler::Coupler(CouplerSettings settings, dem::RheometerScene& scene, fluid::TransientSolver& fluid)
    : Coupler(std::move(settings), &scene, scene.engine(), fluid) {}

Coupler::Coupler(CouplerSettings settings, dem::Engine& engine, fluid::TransientSolver& fluid)
    : Coupler(std::move(settings), nullptr, engine, fluid) {}

Coupler::~Coupler() = default;

Coupler::Coupler(CouplerSettings settings, dem::RheometerScene* scene, dem::Engine& engine,
                 fluid::TransientSolver& fluid)
    : settings_((check_settings(settings), std::move(settings))),
      scene_(scene),
      engine_(&engine),
      fluid_(&fluid),
      scheme_(make_void_fraction_scheme(settings_.void_fraction)),
      void_fraction_(fluid.grid(), settings_.void_fraction_floor),
      sampler_(fluid.grid()),
      exchange_(fluid.grid()) {
  for (const std::string& name : settings_.forces) models_.push_back(make_force_model(name));
  sampler_.set_pressure_gradient_filter(settings_.pressure_gradient_filter_steps * settings_.fluid_time_step);
  // CFD δt = coupling interval × DEM δt (CD §4).
  const double dem_step = engine.time_step();
  const double expected = settings_.coupling_interval * dem_step;
  if (std::abs(settings_.fluid_time_step - expected) > settings_.time_step_tolerance * settings_.fluid_time_step)
    throw std::invalid_argument(fmt::format(
        "coupling: the fluid time step {:g} s must equal the coupling interval {} × the DEM time step {:g} s = {:g} s; "
        "set the fluid time step to {:g} s or the coupling interval to {}",
        settings_.fluid_time_step, settings_.coupling_interval, dem_step, expected, expected,
        std::llround(settings_.fluid_time_step / dem_step)));
  if (static_cast<std::int64_t>(engine.particle_count()) != engine.total_particle_count())
    throw std::invalid_argument("coupling: runs on one MPI rank only (this rank does not own every particle)");
  if (scene_) {
    const auto& gravity = scene_->params().gravity;
    const double gz = gravity ? (*gravity)[2] : 0.0;
    if (gravity && ((*gravity)[0] != 0.0 || (*gravity)[1] != 0.0))
      throw std::invalid_argument("coupling: gravity must point along the rheometer axis (z)");
    if (std::abs(gz - fluid.params().axial_gravity) > 1e-12 * std::max(1.0, std::abs(gz)))
      throw std::invalid_argument(fmt::format(
          "coupling: DEM gravity g_z = {} m/s² but fluid axial_gravity = {} m/s²; they must be equal (the fluid's "
          "hydrostatic pressure gives the particles their buoyancy)",
          gz, fluid.params().axial_gravity));
    if (settings_.particle_density == 0.0) settings_.particle_density = scene_->params().particles.density;
    fluid_->set_top_angular_velocity(scene_->angular_velocity());
    torque_samples_seen_ = scene_->torque_series().size();
  }
  // Initial state: ε of the initial packing with no change in time, forces of the initial fluid.
  auto start = Clock::now();
  update_void_fraction(true);
  cost_.void_fraction += seconds_since(start);
  start = Clock::now();
  CouplingStepRecord initial;
  update_forces(initial);
  cost_.forces += seconds_since(start);
}

ParticleView Coupler::particles() const {
  return {.positions = engine_->positions(), .velocities = engine_->velocities(), .radii = engine_->radii()};
}

double Coupler::time() const { return fluid_->time(); }

void Coupler::update_void_fraction(bool reset) {
  last_.void_fraction = void_fraction_.update(*scheme_, particles());
  if (last_.void_fraction.capped_cells > 0) ++cost_.void_fraction_floor_steps;
  if (last_.void_fraction.unplaced_volume > 0.0) ++cost_.void_fraction_clamped_steps;
  cost_.min_raw_void_fraction = std::min(cost_.min_raw_void_fraction, last_.void_fraction.min_void_fraction_raw);
  if (reset)
    fluid_->reset_void_fraction(void_fraction_.void_fraction());
  else
    fluid_->set_void_fraction(void_fraction_.void_fraction());
}

void Coupler::update_forces(CouplingStepRecord& /*record: the disk's forces add nothing to it*/) {
  sampler_.sample(*fluid_, void_fraction_, particles(), samples_);
  compute_forces(models_, FluidConstants{.density = fluid_->params().density}, samples_, forces_);
  dem_forces_.resize(3 * samples_.size());
  double relaxation = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < samples_.size(); ++p) {
    const Vector3 f = forces_[p].total(samples_[p]);
    for (std::size_t d = 0; d < 3; ++d) dem_forces_[3 * p + d] = f[d];
    if (forces_[p].drag_coefficient > 0.0)
      relaxation = std::min(relaxation, settings_.particle_density * samples_[p].volume /
                                            (forces_[p].drag_coefficient * settings_.fluid_time_step));
  }
  last_.drag_relaxation_steps = std::isfinite(relaxation) ? relaxation : 0.0;
  engine_->set_external_forces(dem_forces_);
  exchange_.build(void_fraction_.map(), samples_, forces_, &sampler_.cell_fields().velocity());
  last_.balance = exchange_.balance(void_fraction_.map(), samples_, forces_);
  fluid_->set_momentum_source(exchange_.source());
}

const CouplingStepReport& Coupler::step() {
  CouplingStepRecord record;
  detail::take_coupling_step(*this, true, record, cost_);
  last_.record = record;
  series_.push_back(record);
  return last_;
}

// 1. LIGGGHTS over the coupling interval; the contact torque on the top plate: the mean of the
// torque blocks the scene finished in it, else its instantaneous value (0 without a scene).
void Coupler::advance_particles(CouplingStepRecord& record) {
  if (!scene_) {
    engine_->run(settings_.coupling_interval);
    return;
  }
  scene_->advance(settings_.coupling_interval);
  const auto series = scene_->torque_series();
  if (series.size() > torque_samples_seen_) {
    double sum = 0.0;
    for (std::size_t s = torque_samples_seen_; s < series.size(); ++s) sum += series[s].torque;
    record.contact_torque = sum / static_cast<double>(series.size() - torque_samples_seen_);
  } else {
    record.contact_torque = scene_->torque();
  }
  torque_samples_seen_ = series.size();
  fluid_->set_top_angular_velocity(scene_->angular_velocity());
}

// 4. The fluid step and the plates' fluid torques.
void Coupler::advance_fluid(CouplingStepRecord& record) {
  last_.fluid = fluid_step(settings_.fluid_time_step);
  record.time = fluid_->time();
  record.fluid_torque = last_.fluid.torque;
  record.bottom_fluid_torque = last_.fluid.bottom_torque;
}

// The fluid step comes from the DEM step times the coupling interval; where the flow makes it
// break the fluid's own Courant limit, the step is covered by substeps that hold 0.8 of it
// (shrunk again whenever one is refused, as the flow speeds up within the step), the coupling
// forces held (the void fraction's change falls in the first); the split is counted.
fluid::StepReport Coupler::fluid_step(double dt) {
  try {
    return fluid_->advance(dt);
  } catch (const fluid::StepError& e) {
    if (e.kind() != fluid::StepFailure::courant_exceeded) throw;
    constexpr int max_substeps = 1000;
    const double limit = 0.8 * fluid_->params().max_courant;
    double substep = dt * limit / e.report().courant, remaining = dt;
    int substeps = 0;
    fluid::StepReport report;
    while (remaining > 1e-12 * dt) {
      const double h = std::min(substep, remaining);
      try {
        report = fluid_->advance(h);
        remaining -= h;
        ++substeps;
      } catch (const fluid::StepError& refused) {
        if (refused.kind() != fluid::StepFailure::courant_exceeded || substeps >= max_substeps) throw;
        substep = h * limit / refused.report().courant;
      }
      if (substeps >= max_substeps && remaining > 1e-12 * dt)
        throw fluid::StepError(fluid::StepFailure::courant_exceeded,
                               fmt::format("the fluid step of {:.3g} s needs more than {} substeps to hold its Courant "
                                           "limit (last substep {:.3g} s)",
                                           dt, max_substeps, substep),
                               report);
    }
    ++cost_.fluid_split_steps;
    cost_.max_fluid_substeps = std::max(cost_.max_fluid_substeps, substeps);
    report.time_step = dt;
    return report;
  }
}

void Coupler::run_until(double end_time) {
  while (fluid_->time() < end_time - 0.5 * settings_.fluid_time_step) step();
}

}  // namespace rheosim::coupling
