// One coupled point in the periodic shear cell (see shear_cell_point.hpp for the model).
#include "rheosim/coupling/shear_cell_point.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "rheosim/core/config.hpp"
#include "rheosim/core/units.hpp"
#include "rheosim/coupling/drag.hpp"
#include "rheosim/coupling/forces.hpp"
#include "rheosim/coupling/void_fraction.hpp"
#include "rheosim/dem/contact.hpp"
#include "rheosim/fluid/couette_column.hpp"
#include "rheosim/fluid/grid.hpp"

#include "coupling_step.hpp"

namespace rheosim::coupling {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

void check_settings(const ShearCellPointSettings& s) {
  const auto fail = [](std::string_view field, double value, std::string_view expected) {
    throw std::invalid_argument(
        fmt::format("ShearCellPointSettings::{} = {} is out of range, expected {}", field, value, expected));
  };
  if (!(std::isfinite(s.gap) && s.gap > 0.0)) fail("gap", s.gap, "> 0");
  if (!(std::isfinite(s.shear_rate) && s.shear_rate > 0.0)) fail("shear_rate", s.shear_rate, "> 0");
  if (!s.fluid.rheology) throw std::invalid_argument("ShearCellPointSettings::fluid.rheology is null");
  if (!(s.fluid.density > 0.0)) fail("fluid.density", s.fluid.density, "> 0");
  if (s.axial_cells < 1) fail("axial_cells", s.axial_cells, ">= 1");
  if (s.coupling_interval < 1) fail("coupling_interval", s.coupling_interval, ">= 1");
  if (!(s.void_fraction_floor > 0.0 && s.void_fraction_floor < 1.0))
    fail("void_fraction_floor", s.void_fraction_floor, "(0, 1)");
}

// Mean of the values and the standard error of the mean from `batches` consecutive batch means.
std::pair<double, double> batch_mean(const std::vector<double>& values, std::size_t batches) {
  if (values.empty()) return {0.0, 0.0};
  double mean = 0.0;
  for (const double v : values) mean += v;
  mean /= static_cast<double>(values.size());
  if (values.size() < batches) return {mean, std::abs(mean)};
  double variance = 0.0;
  for (std::size_t b = 0; b < batches; ++b) {
    const std::size_t lo = b * values.size() / batches, hi = (b + 1) * values.size() / batches;
    double m = 0.0;
    for (std::size_t i = lo; i < hi; ++i) m += values[i];
    m /= static_cast<double>(hi - lo);
    variance += (m - mean) * (m - mean);
  }
  variance /= static_cast<double>(batches - 1);
  return {mean, std::sqrt(variance / static_cast<double>(batches))};
}

struct WindowMeans {
  double fluid_top = 0.0, contact_top = 0.0, lubrication_top = 0.0, stresslet = 0.0, couple = 0.0, bottom = 0.0,
         bulk = 0.0;
  ShearCellBulkParts parts;
};

WindowMeans window_means(const std::vector<ShearCellStepRecord>& series, double from_time) {
  WindowMeans m;
  std::size_t n = 0;
  for (const auto& r : series)
    if (r.time >= from_time) {
      m.fluid_top += r.fluid_top;
      m.contact_top += r.contact_top;
      m.lubrication_top += r.lubrication_top;
      m.stresslet += r.stresslet;
      m.couple += r.couple;
      m.bottom += r.fluid_bottom + r.contact_bottom + r.lubrication_bottom + r.stresslet + r.couple;
      m.bulk += r.bulk;
      auto& p = m.parts;
      const auto& q = r.parts;
      for (auto [to, from] : {std::pair{&p.fluid, q.fluid},
                              {&p.stresslet, q.stresslet},
                              {&p.couple, q.couple},
                              {&p.pair_lubrication, q.pair_lubrication},
                              {&p.pair_lubrication_antisymmetric, q.pair_lubrication_antisymmetric},
                              {&p.plate_lubrication, q.plate_lubrication},
                              {&p.pair_contact, q.pair_contact},
                              {&p.plate_contact, q.plate_contact},
                              {&p.drag, q.drag}})
        *to += from;
      ++n;
    }
  auto& p = m.parts;
  if (n > 0)
    for (double* x : {&m.fluid_top, &m.contact_top, &m.lubrication_top, &m.stresslet, &m.couple, &m.bottom, &m.bulk,
                      &p.fluid, &p.stresslet, &p.couple, &p.pair_lubrication, &p.pair_lubrication_antisymmetric,
                      &p.plate_lubrication, &p.pair_contact, &p.plate_contact, &p.drag})
      *x /= static_cast<double>(n);
  return m;
}

}  // namespace

double couette_stress(const core::FluidProperties& fluid, double shear_rate) {
  return fluid.rheology->stress(shear_rate);
}

NearFieldScene make_near_field_scene(const dem::ShearCellScene& scene) {
  NearFieldScene s;
  const double u = scene.plate_velocity();
  s.plates.push_back({.z = 0.0, .faces_up = true, .velocity_at = {}});
  s.plates.push_back({.z = scene.params().gap, .faces_up = false, .velocity_at = [u](const Vector3&) {
                        return Vector3{u, 0.0, 0.0};
                      }});
  s.periodic = {true, true, false};
  const auto low = scene.box_low();
  const auto high = scene.box_high();
  s.box_low = {low[0], low[1], low[2]};
  s.box_high = {high[0], high[1], high[2]};
  return s;
}

namespace {

// The cell's LIGGGHTS scene for `count` particles (none at φ = 0), with the pair-virial fix the
// bulk-stress cross-check reads; records the DEM step, particles and φ in out.
std::unique_ptr<dem::ShearCellScene> make_scene(const ShearCellPointSettings& settings, std::size_t count,
                                                ShearCellPoint& out) {
  std::unique_ptr<dem::ShearCellScene> scene;
  const auto& q = settings.particles;
  if (count > 0) {
    const double g = core::units::standard_gravity;
    std::optional<std::array<double, 3>> gravity;
    if (settings.gravity) gravity = std::array<double, 3>{0.0, 0.0, -(1.0 - settings.fluid.density / q.density) * g};
    scene = std::make_unique<dem::ShearCellScene>(
        dem::ShearCellScene::Params{.gap = settings.gap,
                                    .cell_length = settings.cell_length,
                                    .cell_width = settings.cell_width,
                                    .particles = q,
                                    .shear_rate = settings.shear_rate,
                                    .time_step_fraction = settings.time_step_fraction,
                                    .time_step = settings.dem_time_step,
                                    .gravity = gravity,
                                    .seed = settings.seed,
                                    .run_directory = settings.run_directory,
                                    .stress_sample_interval = settings.coupling_interval});
    out.dem_time_step = scene->time_step();
    out.particles = scene->total_particle_count();
    out.volume_fraction = scene->volume_fraction();
    // Pair contact virial (LIGGGHTS' pressure tensor, virial part, xz), averaged over each
    // coupling interval, for the bulk-stress cross-check.
    scene->engine().commands({"compute rheosim_cell_temp all temp",
                              "compute rheosim_cell_pressure all pressure rheosim_cell_temp virial",
                              fmt::format("fix rheosim_cell_virial all ave/time 1 {0} {0} c_rheosim_cell_pressure[5]",
                                          settings.coupling_interval)});
  } else {
    // The column alone runs at the step the particles would have (as run_point does at φ = 0).
    const double rayleigh = q.diameter > 0.0 && q.density > 0.0 && q.youngs_modulus > 0.0
                                ? dem::rayleigh_time({.radius = 0.5 * q.diameter,
                                                      .density = q.density,
                                                      .youngs_modulus = q.youngs_modulus,
                                                      .poisson_ratio = q.poisson_ratio})
                                : 1e-7 / 0.3;
    out.dem_time_step = settings.dem_time_step ? *settings.dem_time_step : settings.time_step_fraction * rayleigh;
  }
  return scene;
}

// The point's stress and its parts from the run's series (out.series), at the detector's end.
void set_steady_stress(const SteadyStateDetector& detector, double time, const ShearCellPointSettings& settings,
                       ShearCellPoint& out) {
  const auto estimate = detector.estimate();
  out.converged = estimate.steady;
  out.strain = detector.strain();
  // Steady: the detector's last window. Not steady by max_strain (a dense suspension whose stress
  // wanders over several strain units, e.g. with lubrication at φ = 0.3): the last window's mean
  // and batch error understate that wandering, so the second half of the run is used instead,
  // with the standard error of 5 batch means.
  double from_time = time - settings.steady.strain_window / settings.shear_rate;
  if (estimate.steady) {
    out.stress = estimate.mean;
    out.stress_error = estimate.standard_error;
  } else {
    from_time = 0.5 * time;
    std::vector<double> values;
    for (const auto& r : out.series)
      if (r.time >= from_time) values.push_back(r.total_top());
    const auto [mean, error] = batch_mean(values, 5);
    out.stress = mean;
    out.stress_error = error;
  }
  const auto means = window_means(out.series, from_time);
  out.stress_fluid = means.fluid_top;
  out.stress_contact = means.contact_top;
  out.stress_lubrication = means.lubrication_top;
  out.stress_stresslet = means.stresslet;
  out.stress_couple = means.couple;
  out.bottom_stress = means.bottom;
  out.bulk_stress = means.bulk;
  out.bulk_parts = means.parts;
}

// One coupling step of the shear cell, phase by phase as coupling::Coupler's (coupler.hpp):
// the particles over the coupling interval, the layers' void fraction, the fluid forces on the
// particles and their reaction on the column, the bulk stress from the virial, then the column.
class ShearCellCoupling {
 public:
  ShearCellCoupling(const ShearCellPointSettings& settings, dem::ShearCellScene* scene, fluid::CouetteColumn& column,
                    NearFieldStepHook* hook, ShearCellPoint& out)
      : settings_(settings),
        scene_(scene),
        column_(column),
        hook_(hook),
        out_(out),
        area_(settings.cell_length * settings.cell_width),
        cell_volume_(area_ * settings.gap),
        box_volume_(scene ? area_ * (scene->box_high()[2] - scene->box_low()[2]) : 0.0),
        // One-cell-wide cylindrical grid of N_z layers around the cell's centre: the void-fraction
        // schemes' sub-points and plate mirroring are reused as they are; only the z index matters.
        grid_({.radius = 0.5 * std::hypot(settings.cell_length, settings.cell_width) +
                         2.0 * std::max(settings.particles.diameter, settings.gap),
               .gap = settings.gap,
               .radial_cells = 1,
               .azimuthal_cells = 1,
               .axial_cells = settings.axial_cells}),
        locator_(grid_),
        scheme_(make_void_fraction_scheme(settings.void_fraction)),
        solid_(column.layers()) {
    // The disk's force models (forces.hpp) by name: the drag law and CD eq. 35's viscous force.
    // No pressure-gradient force: the column carries no ∇p along the plates, and the buoyancy is
    // in the particles' reduced gravity.
    models_.push_back(make_force_model(name_of(settings.drag)));
    if (settings.viscous_force) models_.push_back(make_force_model(ViscousForce::model_name));
  }

  // One coupling step of the point's fluid time step (out.fluid_time_step) ending at `time`
  // (coupling_step.hpp): its record.
  ShearCellStepRecord step(double time) {
    ShearCellStepRecord record;
    detail::take_coupling_step(*this, scene_ != nullptr, record, out_.cost);
    record.time = time;
    return record;
  }

  [[nodiscard]] double near_field_seconds() const { return near_field_seconds_; }

 private:
  template <class Loop, class Record>
  friend void detail::take_coupling_step(Loop& loop, bool with_particles, Record& record, CostSplit& cost);

  // 1. LIGGGHTS over the coupling interval; the plates' contact stress (mean over it).
  void advance_particles(ShearCellStepRecord& record) {
    scene_->advance(settings_.coupling_interval);
    const auto& sample = scene_->stress_series().back();
    record.contact_top = sample.top_shear;
    record.contact_bottom = sample.bottom_shear;
  }

  // 2. Void fraction of each layer (floored, the clamps counted), from the particles' shares.
  void update_void_fraction() {
    auto& engine = scene_->engine();
    const auto x = engine.positions();
    shifted_.assign(x.begin(), x.end());
    for (std::size_t i = 0; i < shifted_.size(); i += 3) {
      shifted_[i] -= 0.5 * settings_.cell_length;
      shifted_[i + 1] -= 0.5 * settings_.cell_width;
    }
    velocities_.assign(engine.velocities().begin(), engine.velocities().end());
    radii_.assign(engine.radii().begin(), engine.radii().end());
    scheme_->split(locator_, view(), map_);
    std::fill(solid_.begin(), solid_.end(), 0.0);
    for (const auto& share : map_.shares) solid_[share.cell] += share.volume;
    const auto eps = column_.void_fraction();
    bool clamped = false;
    for (std::size_t k = 0; k < column_.layers(); ++k) {
      const double raw = 1.0 - solid_[k] / column_.layer_volume();
      out_.cost.min_raw_void_fraction = std::min(out_.cost.min_raw_void_fraction, raw);
      clamped = clamped || raw < settings_.void_fraction_floor;
      eps[k] = std::max(settings_.void_fraction_floor, raw);
      out_.min_void_fraction = std::min(out_.min_void_fraction, eps[k]);
    }
    if (clamped) ++out_.cost.void_fraction_clamped_steps;
  }

  // 3. The forces and their reaction (the column's sources start from zero each step), and the
  // bulk stress of the particles.
  void update_forces(ShearCellStepRecord& record) {
    column_.clear_sources();
    add_particle_stress(record, apply_forces());
  }

  // 4. The column's step; the plates' fluid stress and the fluid's part of the bulk stress.
  void advance_fluid(ShearCellStepRecord& record) {
    column_.advance(out_.fluid_time_step);
    record.fluid_top = column_.wall_stress_top();
    record.fluid_bottom = column_.wall_stress_bottom();
    record.bulk += column_.mean_fluid_stress();
    record.parts.fluid = column_.mean_fluid_stress();
  }

  // The fluid at each particle from the column as it is now (u_f interpolated in z; ε, μ and
  // ∂z τ weighted by the volume shares), the force models' forces handed to LIGGGHTS, the drag's
  // reaction to the column's layers. Returns the drag's virial Σ −(z_p − z_layer) F_x: the fluid
  // forces act at the particle and react at the layer.
  double apply_forces() {
    const ParticleView particles = view();
    const std::size_t n = particles.size();
    const auto eps = column_.void_fraction();
    samples_.resize(n);
    for (std::size_t p = 0; p < n; ++p) {
      ParticleSample& s = samples_[p];
      s.position = {shifted_[3 * p], shifted_[3 * p + 1], shifted_[3 * p + 2]};
      s.velocity = particles.velocity(p);
      s.diameter = 2.0 * radii_[p];
      s.volume = sphere_volume_from_radius(radii_[p]);
      s.fluid_velocity = column_.velocity_at(shifted_[3 * p + 2]);
      double eps_p = 0.0, mu_p = 0.0, div_x = 0.0, div_y = 0.0;
      for (const auto& share : map_.of(p)) {
        const double w = share.volume / s.volume;
        eps_p += w * eps[share.cell];
        mu_p += w * column_.cell_viscosity(share.cell);
        div_x += w * column_.div_tau_x(share.cell);
        div_y += w * column_.div_tau_y(share.cell);
      }
      s.void_fraction = eps_p;
      s.viscosity = mu_p;
      s.stress_divergence = {div_x, div_y, 0.0};
    }
    compute_forces(models_, FluidConstants{.density = settings_.fluid.density}, samples_, particle_forces_);
    forces_.resize(3 * n);
    double drag_virial = 0.0;
    for (std::size_t p = 0; p < n; ++p) {
      const ParticleSample& s = samples_[p];
      const Vector3 f = particle_forces_[p].total(s);
      for (std::size_t c = 0; c < 3; ++c) forces_[3 * p + c] = f[c];
      const double beta = particle_forces_[p].drag_coefficient;
      for (const auto& share : map_.of(p)) {
        column_.add_reaction(share.cell, beta * share.volume / s.volume, s.fluid_velocity, s.velocity);
        drag_virial -= share.volume / s.volume * (s.position[2] - column_.centre(share.cell)) * forces_[3 * p];
      }
    }
    scene_->engine().set_external_forces(forces_);
    return drag_virial;
  }

  // Bulk (Batchelor) stress from the particle virial, for the cross-check of the plate reading:
  // pair contacts (LIGGGHTS), plate contacts as pairs with the contact point a below/above the
  // centre, the fluid forces' offset, and the near field's virial and plate stresses.
  void add_particle_stress(ShearCellStepRecord& record, double drag_virial) {
    const double a = 0.5 * settings_.particles.diameter;
    const double pair_contact = -scene_->engine().fix_scalar("rheosim_cell_virial") * box_volume_;
    record.bulk =
        (pair_contact + a * area_ * (record.contact_top + record.contact_bottom) + drag_virial) / cell_volume_;
    record.parts.pair_contact = pair_contact / cell_volume_;
    record.parts.plate_contact = a * area_ * (record.contact_top + record.contact_bottom) / cell_volume_;
    record.parts.drag = drag_virial / cell_volume_;
    if (!hook_) return;
    const NearFieldStepHook::Means m = hook_->take_means();
    record.lubrication_top = -m.plate_forces[1][0] / area_;
    record.lubrication_bottom = m.plate_forces[0][0] / area_;
    record.stresslet = m.stresslet_sum[4] / cell_volume_;
    record.couple = 0.5 * m.rotation_torque_sum[1] / cell_volume_;
    // Force x, lever z (the plates' momentum balance), plus the stresslets.
    record.bulk += (m.lubrication_virial_full[2] + m.stresslet_sum[4]) / cell_volume_ + record.couple;
    // Plate gaps have a z lever only, so their full xz is twice their symmetric xz.
    const double plate_full = 2.0 * m.plate_virial[4];
    const double pair_symmetric = m.lubrication_virial[4] - m.plate_virial[4];
    record.parts.pair_lubrication = pair_symmetric / cell_volume_;
    record.parts.pair_lubrication_antisymmetric =
        (m.lubrication_virial_full[2] - plate_full - pair_symmetric) / cell_volume_;
    record.parts.plate_lubrication = plate_full / cell_volume_;
    record.parts.stresslet = record.stresslet;
    record.parts.couple = record.couple;
    near_field_seconds_ += m.seconds;
    out_.max_near_field_iterations = std::max(out_.max_near_field_iterations, m.max_solver_iterations);
  }

  [[nodiscard]] ParticleView view() const {
    return {.positions = shifted_, .velocities = velocities_, .radii = radii_};
  }

  const ShearCellPointSettings& settings_;
  dem::ShearCellScene* scene_;
  fluid::CouetteColumn& column_;
  NearFieldStepHook* hook_;
  ShearCellPoint& out_;
  double area_, cell_volume_, box_volume_;
  fluid::CylindricalGrid grid_;
  CellLocator locator_;
  std::unique_ptr<const VoidFractionScheme> scheme_;
  std::vector<std::unique_ptr<const ForceModel>> models_;
  ParticleCellMap map_;
  std::vector<ParticleSample> samples_;
  std::vector<ParticleForce> particle_forces_;
  std::vector<double> shifted_, velocities_, radii_, forces_, solid_;
  double near_field_seconds_ = 0.0;
};

}  // namespace

ShearCellPoint run_shear_cell_point(const ShearCellPointSettings& settings) {
  check_settings(settings);
  const auto start = Clock::now();
  const auto& q = settings.particles;
  const double area = settings.cell_length * settings.cell_width;
  const std::size_t count = q.volume_fraction > 0.0
                                ? dem::shear_cell_particle_count(settings.gap, settings.cell_length,
                                                                 settings.cell_width, q.diameter, q.volume_fraction)
                                : 0;

  ShearCellPoint out;
  out.shear_rate = settings.shear_rate;
  out.cell_length = settings.cell_length;
  out.cell_width = settings.cell_width;

  std::unique_ptr<dem::ShearCellScene> scene = make_scene(settings, count, out);
  const double dt = settings.coupling_interval * out.dem_time_step;
  out.fluid_time_step = dt;

  fluid::CouetteColumn column({.density = settings.fluid.density,
                               .rheology = settings.fluid.rheology,
                               .gap = settings.gap,
                               .layers = settings.axial_cells,
                               .plate_speed = settings.shear_rate * settings.gap,
                               .area = area});
  // Near field on every DEM step, in the column's flow (declared after the scene and the column,
  // so it is removed first).
  std::unique_ptr<NearFieldStepHook> hook;
  if (scene && settings.near_field)
    hook = std::make_unique<NearFieldStepHook>(scene->engine(), settings.near_field, make_near_field_scene(*scene),
                                               [&column](const Vector3& x) {
                                                 AmbientSample a;
                                                 a.velocity = column.velocity_at(x[2]);
                                                 const auto slope = column.slope_at(x[2]);
                                                 a.velocity_gradient[2] = slope[0];  // ∂u_x/∂z
                                                 a.velocity_gradient[5] = slope[1];  // ∂u_y/∂z
                                                 return a;
                                               });
  ShearCellCoupling coupling(settings, scene.get(), column, hook.get(), out);
  SteadyStateDetector detector(settings.steady, settings.shear_rate);
  double time = 0.0;
  while (!detector.done()) {
    time += dt;
    const ShearCellStepRecord record = coupling.step(time);
    if (!std::isfinite(record.total_top()))
      throw std::runtime_error(fmt::format("shear cell: wall stress is not finite at t = {:.6g} s", time));
    out.series.push_back(record);
    detector.add(time, record.total_top());
  }

  set_steady_stress(detector, time, settings, out);
  out.cost.near_field = coupling.near_field_seconds();  // spent inside the DEM steps
  out.cost.dem = std::max(0.0, out.cost.dem - coupling.near_field_seconds());
  out.wall_time = seconds_since(start);
  return out;
}

}  // namespace rheosim::coupling
