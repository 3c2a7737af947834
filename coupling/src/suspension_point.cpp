#include "rheosim/coupling/suspension_point.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "rheosim/core/units.hpp"
#include "rheosim/coupling/fluid_fields.hpp"
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/coupling/void_fraction.hpp"
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
  fp.grid = {.radius = s.geometry.radius,
             .gap = s.geometry.gap,
             .radial_cells = s.radial_cells,
             .azimuthal_cells = s.azimuthal_cells,
             .axial_cells = s.axial_cells};
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

// The point's torque: the detector's estimate over its last window, with the strain reached.
void set_steady_torque(const SteadyStateDetector& detector, double rim_shear_rate, SuspensionPoint& out) {
  out.shear_rate = rim_shear_rate;
  const SteadyEstimate e = detector.estimate();
  out.torque = e.mean;
  out.torque_error = e.standard_error;
  out.converged = e.steady;
  out.strain = detector.strain();
}

void fill_window_means(const SuspensionPointSettings& s, SuspensionPoint& out) {
  const double window_start = out.series.back().time - s.steady.strain_window / s.rim_shear_rate;
  CouplingStepRecord sum;
  std::size_t n = 0;
  for (const CouplingStepRecord& r : out.series)
    if (r.time > window_start) {
      sum.fluid_torque += r.fluid_torque;
      sum.contact_torque += r.contact_torque;
      sum.bottom_fluid_torque += r.bottom_fluid_torque;
      sum.lubrication_torque += r.lubrication_torque;
      sum.stresslet_torque += r.stresslet_torque;
      sum.couple_torque += r.couple_torque;
      ++n;
    }
  const double inv = n ? 1.0 / static_cast<double>(n) : 0.0;
  out.torque_fluid = sum.fluid_torque * inv;
  out.torque_contact = sum.contact_torque * inv;
  out.bottom_torque_fluid = sum.bottom_fluid_torque * inv;
  out.torque_lubrication = sum.lubrication_torque * inv;
  out.torque_stresslet = sum.stresslet_torque * inv;
  out.torque_couple = sum.couple_torque * inv;
}

// The solved fluid as the near-field models' ambient flow. Per cell, the velocity gradient of the
// cell-centred velocities (FluidCellFields: ∂_r, (1/r)∂_θ, ∂_z of each component) with the
// cylindrical metric terms, G_rθ −= u_θ/r and G_θθ += u_r/r; at a point it is turned into
// Cartesian components at the point's θ, and the velocity is the cell value plus G·(r − r_c,
// 0, z − z_c). Exact for the torsional flow u_θ = Ωrz/H (E_θz = Ωr/(2H), E_rθ = 0).
class DiskAmbientFlow {
 public:
  explicit DiskAmbientFlow(const fluid::CylindricalGrid& grid)
      : grid_(&grid), fields_(grid), locator_(grid), gradient_(9 * grid.cell_count(), 0.0) {
    for (CellVectorField* g : {&grad_r_, &grad_t_, &grad_z_}) g->resize(grid.cell_count());
  }

  void update(const fluid::TransientSolver& solver) {
    fields_.update(solver);
    const CellVectorField& u = fields_.velocity();
    fields_.gradient(u.radial, grad_r_);
    fields_.gradient(u.azimuthal, grad_t_);
    fields_.gradient(u.axial, grad_z_);
    const std::size_t nt = grid_->azimuthal_cells(), nz = grid_->axial_cells();
    for (std::size_t c = 0; c < grid_->cell_count(); ++c) {
      const double r = grid_->radial_centres()[c / (nt * nz)];
      double* g = &gradient_[9 * c];
      g[0] = grad_r_.radial[c], g[1] = grad_r_.azimuthal[c] - u.azimuthal[c] / r, g[2] = grad_r_.axial[c];
      g[3] = grad_t_.radial[c], g[4] = grad_t_.azimuthal[c] + u.radial[c] / r, g[5] = grad_t_.axial[c];
      g[6] = grad_z_.radial[c], g[7] = grad_z_.azimuthal[c], g[8] = grad_z_.axial[c];
    }
  }

  [[nodiscard]] AmbientSample operator()(const Vector3& x) const {
    const std::size_t c = locator_.locate(x).cell;
    const std::size_t nt = grid_->azimuthal_cells(), nz = grid_->axial_cells();
    const double r = std::hypot(x[0], x[1]);
    const double cs = r > 0.0 ? x[0] / r : 1.0, sn = r > 0.0 ? x[1] / r : 0.0;
    const double dr = r - grid_->radial_centres()[c / (nt * nz)];
    const double dz = x[2] - grid_->axial_centres()[c % nz];
    const double* g = &gradient_[9 * c];
    const CellVectorField& u = fields_.velocity();
    const double ur = u.radial[c] + g[0] * dr + g[2] * dz;
    const double ut = u.azimuthal[c] + g[3] * dr + g[5] * dz;
    const double uz = u.axial[c] + g[6] * dr + g[8] * dz;
    AmbientSample out;
    out.velocity = {cs * ur - sn * ut, sn * ur + cs * ut, uz};
    // G_cart = Q G_cyl Qᵀ, Q = [e_r e_θ e_z] in Cartesian columns.
    const double q[9] = {cs, -sn, 0.0, sn, cs, 0.0, 0.0, 0.0, 1.0};
    double qg[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) qg[3 * i + j] = q[3 * i] * g[j] + q[3 * i + 1] * g[3 + j] + q[3 * i + 2] * g[6 + j];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        out.velocity_gradient[3 * i + j] =
            qg[3 * i] * q[3 * j] + qg[3 * i + 1] * q[3 * j + 1] + qg[3 * i + 2] * q[3 * j + 2];
    return out;
  }

 private:
  const fluid::CylindricalGrid* grid_;
  FluidCellFields fields_;
  CellLocator locator_;
  CellVectorField grad_r_, grad_t_, grad_z_;
  std::vector<double> gradient_;  // 9 per cell, row-major ∂u_i/∂x_j in (r, θ, z)
};

// The near-field model of the point's hydrodynamics, or null for drag only.
std::shared_ptr<const NearFieldModel> near_field_model(const SuspensionPointSettings& s) {
  if (!s.hydrodynamics.terms.any()) return nullptr;
  if (s.hydrodynamics.terms.stokes_drag)
    throw std::invalid_argument(
        "particles.hydrodynamics: stokes_drag is the drag on an imposed flow, for cells without a fluid solver; "
        "the CFD-DEM rheometer already applies the drag law of particles.drag — use lubrication and/or stresslet");
  return make_near_field_model(s.hydrodynamics, s.fluid.rheology);
}

// φ = 0: the fluid alone on the same grid and time step (the suspension's reference).
SuspensionPoint run_fluid_only(const SuspensionPointSettings& s, std::chrono::steady_clock::time_point start) {
  const dem::ElasticSphere sphere{.radius = 0.5 * s.particles.diameter,
                                  .density = s.particles.density,
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
    out.series.push_back(
        {.time = r.time, .fluid_torque = r.torque, .contact_torque = 0.0, .bottom_fluid_torque = r.bottom_torque});
    detector.add(r.time, r.torque);
  }
  set_steady_torque(detector, s.rim_shear_rate, out);
  fill_window_means(s, out);
  out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

SuspensionPoint run_point(const SuspensionPointSettings& s) {
  // particles.drag names the law; a different law in the force list would silently win.
  for (const std::string& name : s.coupling.forces)
    if (builtin_drag_models().contains(name) && name != name_of(s.drag))
      throw std::invalid_argument(
          fmt::format("coupling.forces lists the drag law {} but particles.drag is {} "
                      "(set it with coupling::force_models(particles.drag))",
                      name, name_of(s.drag)));
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
  scene_params.gravity =
      s.gravity ? std::optional<std::array<double, 3>>(std::array<double, 3>{0.0, 0.0, -g}) : std::nullopt;
  scene_params.seed = s.seed;
  scene_params.run_directory = s.run_directory;
  scene_params.torque_sample_interval = s.coupling.coupling_interval;
  dem::RheometerScene scene(scene_params);

  fluid::TransientSolver fluid(gap_fluid(s, scene.angular_velocity()));
  start_from_couette(fluid, scene.angular_velocity());

  CouplerSettings coupling = s.coupling;
  coupling.fluid_time_step = coupling.coupling_interval * scene.time_step();
  Coupler coupler(coupling, scene, fluid);

  // Near field (declared after the fluid and the scene: the hook goes first).
  const std::shared_ptr<const NearFieldModel> model = near_field_model(s);
  std::unique_ptr<DiskAmbientFlow> ambient;
  std::unique_ptr<NearFieldStepHook> hook;
  if (model) {
    ambient = std::make_unique<DiskAmbientFlow>(fluid.grid());
    ambient->update(fluid);
    NearFieldScene plates;
    plates.plates.push_back({.z = 0.0, .faces_up = true, .velocity_at = {}});
    plates.plates.push_back({.z = s.geometry.gap, .faces_up = false, .velocity_at = [&scene](const Vector3& x) {
                               const double w = scene.angular_velocity();  // read at call time
                               return Vector3{-w * x[1], w * x[0], 0.0};
                             }});
    hook = std::make_unique<NearFieldStepHook>(scene.engine(), model, std::move(plates),
                                               [flow = ambient.get()](const Vector3& x) { return (*flow)(x); });
  }

  SteadyStateDetector detector(s.steady, s.rim_shear_rate);
  std::vector<CouplingStepRecord> series;
  double reported_strain = 0.0, near_field_seconds = 0.0;
  int near_field_iterations = 0;
  while (!detector.done()) {
    CouplingStepRecord record = coupler.step().record;
    if (hook) {
      const NearFieldStepHook::Means m = hook->take_means();
      record.lubrication_torque = -m.plate_moments[1][2];  // drive torque, signed as the contact torque
      record.stresslet_torque = m.stresslet_axial_moment / s.geometry.gap;
      record.couple_torque = -0.5 * m.rotation_torque_radial_moment / s.geometry.gap;
      near_field_seconds += m.seconds;
      near_field_iterations = std::max(near_field_iterations, m.max_solver_iterations);
      ambient->update(fluid);
      if (!std::isfinite(record.lubrication_torque) || !std::isfinite(record.stresslet_torque))
        throw std::runtime_error(fmt::format("near-field torque is not finite at t = {:.6g} s", record.time));
    }
    series.push_back(record);
    detector.add(record.time, record.total_torque());
    if (s.on_strain && detector.strain() >= reported_strain + 0.01 * s.steady.max_strain) {
      reported_strain = detector.strain();
      s.on_strain(reported_strain, s.steady.max_strain);
    }
  }

  SuspensionPoint out;
  set_steady_torque(detector, s.rim_shear_rate, out);
  out.series = std::move(series);
  fill_window_means(s, out);
  out.max_near_field_iterations = near_field_iterations;
  out.particles = scene.total_particle_count();
  out.fluid_time_step = coupling.fluid_time_step;
  out.dem_time_step = scene.time_step();
  out.cost = coupler.cost();
  out.cost.near_field = near_field_seconds;  // spent inside the DEM steps
  out.cost.dem = std::max(0.0, out.cost.dem - near_field_seconds);
  out.void_fraction = coupler.last().void_fraction;
  out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace rheosim::coupling
