#include "rheosim/coupling/suspension_point.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "rheosim/core/units.hpp"
#include "rheosim/dem/contact.hpp"
#include "rheosim/dem/rheometer_scene.hpp"
#include "rheosim/fluid/transient.hpp"

namespace rheosim::coupling {
namespace {

double mean_of(std::span<const double> v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

}  // namespace

SteadyStateDetector::SteadyStateDetector(SteadyStateSettings settings, double rim_shear_rate)
    : settings_(settings), shear_rate_(rim_shear_rate) {
  if (!(settings.strain_window > 0.0)) throw std::invalid_argument("steady state: strain_window must be > 0");
  if (!(settings.relative_tolerance > 0.0)) throw std::invalid_argument("steady state: relative_tolerance must be > 0");
  if (!(settings.max_strain > 0.0)) throw std::invalid_argument("steady state: max_strain must be > 0");
  if (!(std::isfinite(rim_shear_rate) && rim_shear_rate > 0.0))
    throw std::invalid_argument(fmt::format("steady state: rim shear rate {} must be > 0", rim_shear_rate));
}

void SteadyStateDetector::add(double time, double value) {
  times_.push_back(time);
  values_.push_back(value);
}

double SteadyStateDetector::strain() const { return times_.empty() ? 0.0 : shear_rate_ * times_.back(); }

SteadyEstimate SteadyStateDetector::estimate() const {
  SteadyEstimate out;
  if (times_.empty()) return out;
  const double end = times_.back();
  const double window = settings_.strain_window / shear_rate_;
  // Indices of the last window (t > end − window) and the one before it.
  const auto first_of = [&](double t) {
    return static_cast<std::size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin());
  };
  const std::size_t last_start = first_of(end - window);
  const std::size_t previous_start = first_of(end - 2.0 * window);
  const std::span<const double> all(values_);
  const auto last = all.subspan(last_start);
  const auto previous = all.subspan(previous_start, last_start - previous_start);
  out.samples = last.size();
  out.mean = mean_of(last);
  out.previous_mean = mean_of(previous);
  // Batch means over 5 sub-windows.
  constexpr std::size_t batches = 5;
  if (last.size() >= batches) {
    std::vector<double> means;
    for (std::size_t b = 0; b < batches; ++b) {
      const std::size_t lo = b * last.size() / batches, hi = (b + 1) * last.size() / batches;
      means.push_back(mean_of(last.subspan(lo, hi - lo)));
    }
    double variance = 0.0;
    for (const double m : means) variance += (m - out.mean) * (m - out.mean);
    variance /= static_cast<double>(batches - 1);
    out.standard_error = std::sqrt(variance / static_cast<double>(batches));
  } else {
    out.standard_error = std::abs(out.mean);  // too few samples to judge
  }
  const double scale = settings_.relative_tolerance * std::abs(out.mean);
  const bool enough = strain() >= std::max(settings_.min_strain, 2.0 * settings_.strain_window) && !previous.empty();
  out.steady = enough && std::abs(out.mean - out.previous_mean) <= scale && out.standard_error <= scale;
  return out;
}

bool SteadyStateDetector::done() const { return strain() >= settings_.max_strain || estimate().steady; }

namespace {

fluid::TransientParams gap_fluid(const SuspensionPointSettings& s, double angular_velocity) {
  fluid::TransientParams fp;
  fp.grid = {.radius = s.geometry.radius, .gap = s.geometry.gap, .radial_cells = s.radial_cells,
             .azimuthal_cells = s.azimuthal_cells, .axial_cells = s.axial_cells};
  fp.density = s.fluid.density;
  fp.rheology = s.fluid.rheology;
  fp.inertia = s.inertia;
  fp.top_angular_velocity = angular_velocity;
  fp.axial_gravity = s.gravity ? -core::units::standard_gravity : 0.0;
  return fp;
}

// Creeping Couette start: u_θ = Ω r z/H.
void start_from_couette(fluid::TransientSolver& fluid, double angular_velocity) {
  const fluid::CylindricalGrid& grid = fluid.grid();
  const std::size_t nr = grid.radial_cells(), nt = grid.azimuthal_cells(), nz = grid.axial_cells();
  std::vector<double> ur((nr + 1) * nt * nz, 0.0), ut(nr * nt * nz), uz(nr * nt * (nz + 1), 0.0);
  for (std::size_t i = 0; i < nr; ++i)
    for (std::size_t j = 0; j < nt; ++j)
      for (std::size_t k = 0; k < nz; ++k)
        ut[(i * nt + j) * nz + k] =
            angular_velocity * grid.radial_centres()[i] * grid.axial_centres()[k] / grid.params().gap;
  fluid.set_velocity(ur, ut, uz);
}

void fill_window_means(const SuspensionPointSettings& s, SuspensionPoint& out) {
  const double window_start = out.series.back().time - s.steady.strain_window / s.rim_shear_rate;
  double fluid_sum = 0.0, contact_sum = 0.0, bottom_sum = 0.0;
  std::size_t n = 0;
  for (const CouplingStepRecord& r : out.series)
    if (r.time > window_start) {
      fluid_sum += r.fluid_torque;
      contact_sum += r.contact_torque;
      bottom_sum += r.bottom_fluid_torque;
      ++n;
    }
  out.torque_fluid = n ? fluid_sum / static_cast<double>(n) : 0.0;
  out.torque_contact = n ? contact_sum / static_cast<double>(n) : 0.0;
  out.bottom_torque_fluid = n ? bottom_sum / static_cast<double>(n) : 0.0;
}

// φ = 0: the fluid alone on the same grid and time step (the suspension's reference).
SuspensionPoint run_fluid_only(const SuspensionPointSettings& s, std::chrono::steady_clock::time_point start) {
  const dem::ElasticSphere sphere{.radius = 0.5 * s.particles.diameter, .density = s.particles.density,
                                  .youngs_modulus = s.particles.youngs_modulus,
                                  .poisson_ratio = s.particles.poisson_ratio};
  const double dem_step = s.dem_time_step ? *s.dem_time_step : s.time_step_fraction * dem::rayleigh_time(sphere);
  const double omega = s.rim_shear_rate * s.geometry.gap / s.geometry.radius;  // Ω = γ̇_R H/R
  fluid::TransientSolver fluid(gap_fluid(s, omega));
  start_from_couette(fluid, omega);
  SuspensionPoint out;
  out.fluid_time_step = s.coupling.coupling_interval * dem_step;
  out.dem_time_step = dem_step;
  SteadyStateDetector detector(s.steady, s.rim_shear_rate);
  while (!detector.done()) {
    const auto t0 = std::chrono::steady_clock::now();
    const fluid::StepReport r = fluid.advance(out.fluid_time_step);
    out.cost.fluid += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++out.cost.steps;
    out.series.push_back({.time = r.time, .fluid_torque = r.torque, .contact_torque = 0.0,
                          .bottom_fluid_torque = r.bottom_torque});
    detector.add(r.time, r.torque);
  }
  out.shear_rate = s.rim_shear_rate;
  const SteadyEstimate e = detector.estimate();
  out.torque = e.mean;
  out.torque_error = e.standard_error;
  out.converged = e.steady;
  out.strain = detector.strain();
  fill_window_means(s, out);
  out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

SuspensionPoint run_point(const SuspensionPointSettings& s) {
  const auto start = std::chrono::steady_clock::now();
  if (!(std::isfinite(s.rim_shear_rate) && s.rim_shear_rate > 0.0))
    throw std::invalid_argument(fmt::format("run_point: rim shear rate {} 1/s must be > 0", s.rim_shear_rate));
  if (s.particles.volume_fraction == 0.0) return run_fluid_only(s, start);
  const double g = core::units::standard_gravity;

  dem::RheometerScene::Params scene_params;
  scene_params.geometry = s.geometry;
  scene_params.particles = s.particles;
  scene_params.rim_shear_rate = s.rim_shear_rate;
  scene_params.time_step_fraction = s.time_step_fraction;
  scene_params.time_step = s.dem_time_step;
  scene_params.gravity = s.gravity ? std::optional<std::array<double, 3>>(std::array<double, 3>{0.0, 0.0, -g})
                                   : std::nullopt;
  scene_params.seed = s.seed;
  scene_params.run_directory = s.run_directory;
  scene_params.torque_sample_interval = s.coupling.coupling_interval;
  dem::RheometerScene scene(scene_params);

  fluid::TransientSolver fluid(gap_fluid(s, scene.angular_velocity()));
  start_from_couette(fluid, scene.angular_velocity());

  CouplerSettings coupling = s.coupling;
  coupling.fluid_time_step = coupling.coupling_interval * scene.time_step();
  Coupler coupler(coupling, scene, fluid);
  SteadyStateDetector detector(s.steady, s.rim_shear_rate);
  double reported_strain = 0.0;
  while (!detector.done()) {
    const CouplingStepReport& r = coupler.step();
    detector.add(r.record.time, r.record.fluid_torque + r.record.contact_torque);
    if (s.on_strain && detector.strain() >= reported_strain + 0.01 * s.steady.max_strain) {
      reported_strain = detector.strain();
      s.on_strain(reported_strain, s.steady.max_strain);
    }
  }

  SuspensionPoint out;
  out.shear_rate = s.rim_shear_rate;
  const SteadyEstimate e = detector.estimate();
  out.torque = e.mean;
  out.torque_error = e.standard_error;
  out.converged = e.steady;
  out.strain = detector.strain();
  out.series = coupler.torque_series();
  fill_window_means(s, out);
  out.particles = scene.total_particle_count();
  out.fluid_time_step = coupling.fluid_time_step;
  out.dem_time_step = scene.time_step();
  out.cost = coupler.cost();
  out.void_fraction = coupler.last().void_fraction;
  out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace rheosim::coupling
