// Resumable sweeps over fluids × φ × γ̇_R (rheometer/sweep.hpp).
#include "rheosim/rheometer/sweep.hpp"
#include "rheosim/rheometer/box_point.hpp"
#include "rheosim/rheometer/shear_cell.hpp"
#include "rheosim/rheometer/sweep_summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "rheosim/core/error.hpp"
#include "rheosim/core/progress.hpp"
#include "rheosim/core/run_summary.hpp"
#include "rheosim/core/version.hpp"
#include "rheosim/coupling/forces.hpp"
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/coupling/suspension_point.hpp"
#include "rheosim/dem/contact.hpp"
#include "rheosim/fluid/swirl.hpp"
#include "rheosim/rheometer/plate.hpp"
#include "rheosim/rheometer/report.hpp"
#include "rheosim/rheometer/run_analysis.hpp"
#include "swirl_params.hpp"

namespace rheosim::rheometer {

namespace fs = std::filesystem;

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

core::Hdf5Dataset field(const std::string& name, std::vector<std::size_t> shape, const std::vector<double>& data,
                        const std::string& unit) {
  core::Hdf5Dataset d;
  d.path = "fields/" + name;
  d.shape = std::move(shape);
  d.data = data;
  d.unit = unit;
  return d;
}

const NamedFluid& fluid_named(const RheometerCase& r, const std::string& name) {
  for (const auto& f : r.fluids)
    if (f.name == name) return f;
  throw std::invalid_argument(fmt::format("sweep point names fluid '{}', which the case does not list", name));
}

// The numbers of a PointResult as HDF5 attributes, by name (one list for store and load).
struct NumberField {
  const char* name;
  double PointResult::*member;
  bool optional = false;  // may be absent (points of models without it): NaN when loaded
};
constexpr NumberField number_fields[] = {
    {"torque", &PointResult::torque},
    {"torque_fluid", &PointResult::torque_fluid},
    {"torque_contact", &PointResult::torque_contact},
    {"torque_lubrication", &PointResult::torque_lubrication, true},
    {"torque_stresslet", &PointResult::torque_stresslet, true},
    {"torque_couple", &PointResult::torque_couple, true},
    {"torque_std_error", &PointResult::torque_std_error},
    {"torque_creeping", &PointResult::torque_creeping},
    {"torque_analytic", &PointResult::torque_analytic},
    {"torque_grid", &PointResult::torque_grid, true},
    {"torque_half_grid", &PointResult::torque_half_grid, true},
    {"strain", &PointResult::strain},
    {"wall_time", &PointResult::wall_time},
    {"cost_dem", &PointResult::cost_dem},
    {"cost_void_fraction", &PointResult::cost_void_fraction},
    {"cost_forces", &PointResult::cost_forces},
    {"cost_fluid", &PointResult::cost_fluid},
    {"cost_near_field", &PointResult::cost_near_field, true},
    {"normal_force", &PointResult::normal_force, true},
    {"n1", &PointResult::n1, true},
    {"n2", &PointResult::n2, true},
};

// N1 − N2 at the rim rate from the plates' normal force over a series of rates (one fluid and
// φ): N1 − N2 = (F/πR²)(2 + d ln F/d ln γ̇_R) = (2F + γ̇_R dF/dγ̇_R)/(πR²), the derivative
// from the neighbouring rates (one-sided at the ends), valid for either sign of F.
void add_normal_stress_differences(std::vector<SweepPointRecord>& points, double radius) {
  std::map<std::pair<std::string, double>, std::vector<SweepPointRecord*>> series;
  for (auto& p : points)
    if (p.converged && p.normal_force) series[{p.fluid, p.volume_fraction}].push_back(&p);
  const double area = std::acos(-1.0) * radius * radius;
  for (auto& [key, list] : series) {
    if (list.size() < 2) continue;
    std::sort(list.begin(), list.end(), [](const auto* a, const auto* b) { return a->shear_rate < b->shear_rate; });
    const auto rate = [&](std::size_t k) { return list[k]->shear_rate; };
    const auto force = [&](std::size_t k) { return *list[k]->normal_force; };
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::size_t lo = k == 0 ? 0 : k - 1, hi = k + 1 == list.size() ? k : k + 1;
      const double slope = (force(hi) - force(lo)) / (rate(hi) - rate(lo));
      list[k]->n1_minus_n2 = (2.0 * force(k) + rate(k) * slope) / area;
    }
  }
}

std::string point_label(const SweepPoint& p, bool several_fluids) {
  return fmt::format("{}φ {:g}, {:g} 1/s", several_fluids ? p.fluid + ", " : "", p.volume_fraction, p.rim_shear_rate);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Point runners

PointRunner make_swirl_point_runner(const RheometerCase& rheometer) {
  return [r = rheometer](const SweepPoint& point, const PointProgressCallback&) {
    const auto& named = fluid_named(r, point.fluid);
    const auto& fluid = named.properties;
    const ParallelPlate plate = ParallelPlate::from(r.geometry);
    const double rate = point.rim_shear_rate;
    const double omega = plate.angular_velocity(rate);
    const fluid::SwirlSolver creeping(swirl_params(r, fluid, false));
    const fluid::SwirlResult stokes = creeping.solve(omega);
    fluid::SwirlResult full = stokes;
    if (r.solver.inertia) full = fluid::SwirlSolver(swirl_params(r, fluid, true)).solve(omega);

    PointResult out;
    out.method = r.solver.inertia ? "steady axisymmetric swirl solve with inertia" : "steady creeping swirl solve";
    out.converged = stokes.converged && full.converged;
    out.failure = !stokes.converged ? stokes.failure : full.failure;
    out.torque = reported_torque(r, full);
    out.torque_fluid = out.torque;
    out.torque_contact = 0.0;
    out.torque_creeping = stokes.torque;
    if (out.torque != full.torque) {
      out.torque_grid = full.torque;
      out.torque_half_grid = full.coarse_torque;
    }
    out.torque_analytic = closed_form_torque(plate, *fluid.rheology, rate).value_or(nan);
    out.iterations = full.iterations + (r.solver.inertia ? stokes.iterations : 0);
    out.wall_time = full.wall_time + (r.solver.inertia ? stokes.wall_time : 0.0);
    out.warnings = swirl_warnings(r, stokes, full);
    const auto& grid = creeping.grid();
    const std::size_t nr = grid.radial_cells(), nz = grid.axial_cells();
    const auto& s = full.state;
    out.fields.push_back(field("angular_velocity", {nr, nz}, s.angular_velocity, "rad/s"));
    out.fields.push_back(field("viscosity", {nr, nz}, s.viscosity, "Pa s"));
    out.fields.push_back(field("shear_rate", {nr, nz}, s.shear_rate, "1/s"));
    out.fields.push_back(field("pressure", {nr, nz}, s.pressure, "Pa"));
    out.fields.push_back(field("radial_velocity", {nr + 1, nz}, s.radial_velocity, "m/s"));
    out.fields.push_back(field("axial_velocity", {nr, nz + 1}, s.axial_velocity, "m/s"));
    const auto centres = [](std::span<const double> x) { return std::vector<double>(x.begin(), x.end()); };
    out.fields.push_back(field("radial_centres", {nr}, centres(grid.radial_centres()), "m"));
    out.fields.push_back(field("axial_centres", {nz}, centres(grid.axial_centres()), "m"));
    return out;
  };
}

PointRunner make_unavailable_suspension_runner() {
  return [](const SweepPoint& point, const PointProgressCallback&) {
    PointResult out;
    out.method = "CFD-DEM suspension";
    out.failure = fmt::format(
        "φ = {:g} needs the CFD-DEM coupling (fluid + LIGGGHTS particles), which is not built yet in rheosim {}; "
        "no torque was computed for this point",
        point.volume_fraction, core::version);
    return out;
  };
}

PointRunners default_point_runners(const RheometerCase& rheometer) {
  return {make_swirl_point_runner(rheometer), make_unavailable_suspension_runner()};
}

SuspensionCostEstimate estimate_suspension_cost(const RheometerCase& r, double volume_fraction, double rim_shear_rate,
                                                double max_strain) {
  SuspensionCostEstimate e;
  if (!r.particles) return e;
  const auto& p = *r.particles;
  const double pi = std::acos(-1.0);
  const double gap_volume = pi * r.geometry.radius * r.geometry.radius * r.geometry.gap;
  e.particles = volume_fraction * gap_volume / (pi * p.diameter * p.diameter * p.diameter / 6);
  const coupling::SuspensionPointSettings defaults;
  const double dem_step = defaults.time_step_fraction *
                          dem::rayleigh_time({0.5 * p.diameter, p.density, p.youngs_modulus, p.poisson_ratio});
  e.dem_steps = max_strain / (rim_shear_rate * dem_step);
  constexpr double particle_steps_per_second = 1.5e7;  // one core, CD §4 scene (docs/performance.md)
  constexpr double coupling_overhead = 1.2;            // void fraction + forces + fluid, measured 5–17 %
  // Near field: about ×10 the DEM time per step with the seed's particles (docs/performance.md).
  const double near_field = p.hydrodynamics.terms.any() ? 10.0 : 1.0;
  e.wall_time = e.particles * e.dem_steps / particle_steps_per_second * coupling_overhead * near_field;
  return e;
}

PointRunner make_coupled_suspension_runner(const RheometerCase& rheometer, fs::path work_dir, double budget_seconds,
                                           std::vector<double> volume_fractions) {
  using Model = RheometerCase::SuspensionModel;
  PointRunner disk = make_full_disk_suspension_runner(rheometer, work_dir, budget_seconds);
  PointRunner cell = make_shear_cell_suspension_runner(rheometer, work_dir);
  PointRunner box = make_box_suspension_runner(rheometer, std::move(volume_fractions));
  return [r = rheometer, budget_seconds, disk = std::move(disk), cell = std::move(cell), box = std::move(box)](
             const SweepPoint& point, const PointProgressCallback& progress) {
    const ModelChoice choice = choose_suspension_model(r, point.volume_fraction, budget_seconds);
    PointResult out;
    if (choice.model == Model::lees_edwards || choice.model == Model::walled_box) {
      out = box(point, progress);
    } else if (choice.model == Model::full_disk) {
      out = disk(point, progress);
    } else if (choice.cell_study_seconds > budget_seconds) {  // like the disk: fail at once, say why
      out.method = "periodic shear cell";
      out.failure = fmt::format(
          "CFD-DEM point not started: the shear-cell study of φ = {:g} is estimated at {:.3g} h on one core, above "
          "the point budget of {:g} s (particles of d = {:g} m in a cell of max(8 d, 3 H)); raise it with `rheosim "
          "run --point-budget SECONDS`",
          point.volume_fraction, choice.cell_study_seconds / 3600.0, budget_seconds, r.particles->diameter);
    } else {
      out = cell(point, progress);
    }
    out.model = name_of(choice.model);
    out.model_reason = out.model_reason.empty() ? choice.reason : choice.reason + "; " + out.model_reason;
    return out;
  };
}

namespace {

// The coupled point's settings for one sweep point of the full disk (the fluid grid is
// coupling::SuspensionPointSettings' own, 8 × 8 × 2, not the case's `solver:` grid, which is the
// φ = 0 swirl solver's: unresolved CFD-DEM needs cells wider than a particle, docs/coupling.md).
coupling::SuspensionPointSettings full_disk_settings(const RheometerCase& r, const SweepPoint& point,
                                                     const fs::path& work) {
  coupling::SuspensionPointSettings s;
  s.geometry = r.geometry;
  s.fluid = fluid_named(r, point.fluid).properties;
  s.particles = *r.particles;  // the solid; its drag and near field follow
  s.particles.volume_fraction = point.volume_fraction;
  s.drag = r.particles->drag;
  s.hydrodynamics = r.particles->hydrodynamics;
  s.coupling.forces = coupling::force_models(s.drag);
  s.rim_shear_rate = point.rim_shear_rate;
  s.inertia = r.solver.inertia;
  s.seed = 1 + point.index;
  s.run_directory = work / fmt::format("point_{:04d}", point.index);
  return s;
}

// The rules a coupled point bent: split fluid steps, void-fraction floors and clamps, near-field
// solves stopped at their cap.
std::vector<std::string> full_disk_warnings(const coupling::SuspensionPoint& p,
                                            const coupling::SuspensionPointSettings& s) {
  std::vector<std::string> warnings;
  if (p.cost.fluid_split_steps > 0)
    warnings.push_back(fmt::format(
        "fluid: {} of {} coupling steps broke the fluid's Courant limit and were split into up to {} substeps "
        "(fluid step {:.3g} s)",
        p.cost.fluid_split_steps, p.cost.steps, p.cost.max_fluid_substeps, p.fluid_time_step));
  if (p.cost.void_fraction_floor_steps > 0)
    warnings.push_back(fmt::format(
        "void fraction: on {} of {} coupling steps some cells held more solid than the floor ε_min = {:g} allows "
        "(ε down to {:.3g} before the floor); their excess was moved to neighbouring cells",
        p.cost.void_fraction_floor_steps, p.cost.steps, s.coupling.void_fraction_floor, p.cost.min_raw_void_fraction));
  if (p.cost.void_fraction_clamped_steps > 0)
    warnings.push_back(fmt::format(
        "void fraction: on {} of {} coupling steps the excess over the floor could not all be placed; ε was "
        "clamped there and the grid carries less solid than the particles",
        p.cost.void_fraction_clamped_steps, p.cost.steps));
  if (const int cap = coupling::NearFieldSettings{}.max_solver_iterations; p.max_near_field_iterations >= cap)
    warnings.push_back(
        fmt::format("near field: implicit solves stopped at their iteration cap ({}) on some DEM "
                    "steps; their forces are the last iterate's",
                    cap));
  return warnings;
}

// The coupled point's result into `out`: torque and its parts, the rules it bent, the torque
// series as the point's fields, its costs.
void take_full_disk_point(const coupling::SuspensionPoint& p, const coupling::SuspensionPointSettings& s,
                          PointResult& out) {
  const bool near_field = s.hydrodynamics.terms.any();
  out.method += fmt::format("; DEM step {:.3g} s, fluid step {:.3g} s ({} DEM steps){}", p.dem_time_step,
                            p.fluid_time_step, s.coupling.coupling_interval,
                            p.cost.fluid_split_steps > 0
                                ? fmt::format(", split into up to {} substeps where it broke the fluid's Courant "
                                              "limit",
                                              p.cost.max_fluid_substeps)
                                : std::string());
  out.converged = p.converged;
  if (!p.converged)
    out.failure = fmt::format("torque not steady within {:g} strain units (last window {:.4g} ± {:.2g} N·m)",
                              s.steady.max_strain, p.torque, p.torque_error);
  out.torque = p.torque;
  out.torque_fluid = p.torque_fluid;
  out.torque_contact = p.torque_contact;
  if (near_field) {
    out.torque_lubrication = p.torque_lubrication;
    out.torque_stresslet = p.torque_stresslet;
    out.torque_couple = p.torque_couple;
  }
  out.torque_std_error = p.torque_error;
  out.warnings = full_disk_warnings(p, s);
  out.strain = p.strain;
  out.iterations = static_cast<int>(p.cost.steps);
  out.wall_time = p.wall_time;
  std::vector<double> time, fluid, contact, lubrication, stresslet, couple;
  for (const auto& rec : p.series) {
    time.push_back(rec.time);
    fluid.push_back(rec.fluid_torque);
    contact.push_back(rec.contact_torque);
    lubrication.push_back(rec.lubrication_torque);
    stresslet.push_back(rec.stresslet_torque);
    couple.push_back(rec.couple_torque);
  }
  out.fields.push_back(field("time", {time.size()}, time, "s"));
  out.fields.push_back(field("torque_fluid", {fluid.size()}, fluid, "N m"));
  out.fields.push_back(field("torque_contact", {contact.size()}, contact, "N m"));
  if (near_field) {
    out.fields.push_back(field("torque_lubrication", {lubrication.size()}, lubrication, "N m"));
    out.fields.push_back(field("torque_stresslet", {stresslet.size()}, stresslet, "N m"));
    out.fields.push_back(field("torque_couple", {couple.size()}, couple, "N m"));
    out.cost_near_field = p.cost.near_field;
  }
  out.cost_dem = p.cost.dem;
  out.cost_void_fraction = p.cost.void_fraction;
  out.cost_forces = p.cost.forces;
  out.cost_fluid = p.cost.fluid;
}

}  // namespace

PointRunner make_full_disk_suspension_runner(const RheometerCase& rheometer, fs::path work_dir, double budget_seconds) {
  return [r = rheometer, work = std::move(work_dir), budget_seconds](const SweepPoint& point,
                                                                     const PointProgressCallback& progress) {
    PointResult out;
    out.method =
        fmt::format("CFD-DEM (transient 3D fluid + LIGGGHTS, {} drag){}, steady over a strain window",
                    r.particles ? coupling::name_of(r.particles->drag) : "no",
                    r.particles && r.particles->hydrodynamics.terms.any() ? " with near-field hydrodynamics" : "");
    if (!r.particles) {
      out.failure = fmt::format("φ = {:g} needs a particles: section (diameter, density, contact properties)",
                                point.volume_fraction);
      return out;
    }
    const double max_strain = coupling::SuspensionPointSettings{}.steady.max_strain;
    const auto cost = estimate_suspension_cost(r, point.volume_fraction, point.rim_shear_rate, max_strain);
    if (cost.wall_time > budget_seconds) {
      out.failure = fmt::format(
          "CFD-DEM point not started: about {:.3g} particles × {:.3g} DEM steps (to strain {:g}) ≈ {:.3g} h on one "
          "core, above the point budget of {:g} s; raise it with `rheosim run --point-budget SECONDS` or shrink the "
          "disk (the cost scales with R²)",
          cost.particles, cost.dem_steps, max_strain, cost.wall_time / 3600, budget_seconds);
      return out;
    }
    coupling::SuspensionPointSettings s = full_disk_settings(r, point, work);
    out.method += fmt::format(
        "; CFD-DEM fluid grid {} × {} × {} (r × θ × z; the case's solver: grid is the φ = 0 "
        "swirl solver's)",
        s.radial_cells, s.azimuthal_cells, s.axial_cells);
    try {
      fs::create_directories(s.run_directory);
      if (progress) s.on_strain = [&progress](double strain, double limit) { progress({strain, limit}); };
      const coupling::SuspensionPoint p = coupling::run_point(s);
      take_full_disk_point(p, s, out);
      if (progress) progress({p.strain, p.strain});
    } catch (const std::exception& e) {
      out.failure = fmt::format("CFD-DEM point failed: {}", e.what());
    }
    return out;
  };
}

std::vector<SweepPoint> sweep_points(const SweepCase& sweep) {
  std::vector<SweepPoint> points;
  for (const auto& f : sweep.rheometer.fluids)
    for (double phi : sweep.volume_fractions)
      for (double rate : sweep.rheometer.shear_rates) points.push_back({points.size(), f.name, phi, rate});
  return points;
}

// ---------------------------------------------------------------------------------------------
// Point store

PointStore::PointStore(fs::path run_dir, std::string input_sha256)
    : directory_(std::move(run_dir) / "points"), input_sha256_(std::move(input_sha256)) {
  fs::create_directories(directory_);
  for (const auto& entry : fs::directory_iterator(directory_)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with(".") && name.find(".tmp-") != std::string::npos) {
      fs::remove(entry.path());  // a write cut short by a kill: never renamed, never valid
      continue;
    }
    if (entry.path().extension() != ".h5") continue;
    std::string stored_sha;
    for (const auto& a : core::read_hdf5_attributes(entry.path()))
      if (a.name == "input_sha256") stored_sha = std::get<std::string>(a.value);
    if (stored_sha != input_sha256_) {
      core::ConfigError::Details d;
      d.where = core::FileLocation{entry.path().string(), 0, 0};
      d.key_path = "input_sha256";
      d.problem = fmt::format("this folder holds sweep points of another input deck (sha256 {}, this deck {})",
                              stored_sha.substr(0, 12), input_sha256_.substr(0, 12));
      d.expected = "a folder holding no points, or points of this very deck (resume)";
      d.hint = fmt::format("run into a new --out folder, or delete {} to start this deck afresh", directory_.string());
      throw core::ConfigError(d);
    }
  }
}

fs::path PointStore::file(const SweepPoint& point) const {
  return directory_ / fmt::format("point_{:04d}.h5", point.index);
}

fs::path PointStore::failure_file(const SweepPoint& point) const {
  return directory_ / fmt::format("point_{:04d}.failed.h5", point.index);
}

void PointStore::store(const SweepPoint& point, const PointResult& result) const {
  write(file(point), point, result);
  fs::remove(failure_file(point));  // an earlier failure of the point is superseded
}

void PointStore::store_failure(const SweepPoint& point, const PointResult& result) const {
  write(failure_file(point), point, result);
}

void PointStore::write(const fs::path& path, const SweepPoint& point, const PointResult& result) const {
  core::Hdf5Content content;
  content.attributes = {{"input_sha256", input_sha256_},
                        {"fluid", point.fluid},
                        {"method", result.method},
                        {"model", result.model},
                        {"model_reason", result.model_reason},
                        {"estimated_error", result.estimated_error},
                        {"index", static_cast<double>(point.index)},
                        {"volume_fraction", point.volume_fraction},
                        {"shear_rate", point.rim_shear_rate},
                        {"iterations", static_cast<double>(result.iterations)},
                        {"converged", result.converged ? 1.0 : 0.0}};
  std::string warnings;
  for (const auto& w : result.warnings) warnings += (warnings.empty() ? "" : "\n") + w;
  if (!warnings.empty()) content.attributes.push_back({"warnings", warnings});
  for (const auto& f : number_fields) content.attributes.push_back({f.name, result.*(f.member)});
  content.datasets = result.fields;
  if (!result.failure.empty()) content.attributes.push_back({"failure", result.failure});
  core::write_hdf5(path, content);
}

std::optional<PointResult> PointStore::load(const SweepPoint& point) const {
  const fs::path path = file(point);
  if (!fs::exists(path)) return std::nullopt;
  std::map<std::string, std::variant<double, std::string>> a;
  for (auto& attribute : core::read_hdf5_attributes(path)) a[attribute.name] = attribute.value;
  const auto number = [&](const std::string& name) {
    const auto it = a.find(name);
    if (it == a.end() || !std::holds_alternative<double>(it->second))
      throw core::RunError(
          fmt::format("{}: attribute '{}' is missing; delete the file to recompute the point", path.string(), name));
    return std::get<double>(it->second);
  };
  const auto text = [&](const std::string& name) {
    const auto it = a.find(name);
    return it != a.end() && std::holds_alternative<std::string>(it->second) ? std::get<std::string>(it->second)
                                                                            : std::string();
  };
  if (text("fluid") != point.fluid || number("volume_fraction") != point.volume_fraction ||
      number("shear_rate") != point.rim_shear_rate)
    throw core::RunError(fmt::format("{} holds fluid '{}', φ {}, {} 1/s, not point {} of this sweep; delete it",
                                     path.string(), text("fluid"), number("volume_fraction"), number("shear_rate"),
                                     point.index));
  PointResult r;
  r.converged = number("converged") != 0;
  r.method = text("method");
  r.model = text("model");
  r.model_reason = text("model_reason");
  if (const auto it = a.find("estimated_error"); it != a.end() && std::holds_alternative<double>(it->second))
    r.estimated_error = std::get<double>(it->second);
  r.iterations = static_cast<int>(number("iterations"));
  for (std::string rest = text("warnings"); !rest.empty();) {
    const std::size_t end = rest.find('\n');
    r.warnings.push_back(rest.substr(0, end));
    rest = end == std::string::npos ? std::string() : rest.substr(end + 1);
  }
  for (const auto& f : number_fields) r.*(f.member) = f.optional && !a.contains(f.name) ? nan : number(f.name);
  return r;
}

// ---------------------------------------------------------------------------------------------
// The sweep

namespace {

// Every point of the sweep: read back from the store when an earlier run finished it (counted in
// outcome.reused_points), else run now and stored the moment it finishes (outcome.computed_points).
std::vector<std::optional<PointResult>> compute_points(const RheometerCase& r, const std::vector<SweepPoint>& points,
                                                       const PointStore& store, const core::Log& log,
                                                       const PointRunners& runners, SweepOutcome& outcome) {
  const bool several_fluids = r.fluids.size() > 1;
  std::vector<std::optional<PointResult>> results(points.size());
  for (const auto& p : points)
    if ((results[p.index] = store.load(p))) ++outcome.reused_points;
  if (outcome.reused_points > 0)
    log.info("resuming: {} of {} points are stored in {}; computing the other {}", outcome.reused_points, points.size(),
             store.directory().string(), points.size() - static_cast<std::size_t>(outcome.reused_points));

  core::ProgressOptions progress_options;
  progress_options.initial_done = static_cast<std::size_t>(outcome.reused_points);
  core::Progress progress = core::Progress::for_stderr("sweep", points.size(), progress_options);
  std::size_t done = static_cast<std::size_t>(outcome.reused_points);
  std::set<std::string> failure_reasons;  // a message shared by many points is shown once
  std::set<std::string> warning_texts;    // likewise for warnings
  for (const auto& point : points) {
    if (results[point.index]) continue;
    const std::string label = point_label(point, several_fluids);
    const bool is_suspension = point.volume_fraction > 0;
    progress.update(done, fmt::format("{}: {}", label, is_suspension ? "starting" : "steady solve (no strain)"));
    const PointProgressCallback report = [&](const PointProgress& pp) {
      progress.update(done, std::isfinite(pp.target_strain)
                                ? fmt::format("{}: strain {:.2f} of {:.2f}", label, pp.strain, pp.target_strain)
                                : fmt::format("{}: strain {:.2f}", label, pp.strain));
    };
    PointResult result;
    try {
      const PointRunner& runner = is_suspension ? runners.suspension : runners.single_phase;
      if (!runner) throw std::logic_error("no point runner for this kind of point");
      result = runner(point, report);
    } catch (const std::exception& e) {
      result = PointResult{};
      result.failure = e.what();
    }
    if (result.converged && !std::isfinite(result.torque)) {
      result.converged = false;
      result.failure = "the point runner returned no finite torque";
    }
    ++outcome.computed_points;
    if (!result.model.empty())
      log.info("{}: model {}{}: {}", label, result.model,
               std::isfinite(result.estimated_error)
                   ? fmt::format(" (estimated error {:.2g} %)", 100.0 * result.estimated_error)
                   : std::string(),
               result.model_reason);
    for (const auto& w : result.warnings)
      if (warning_texts.insert(w).second) log.warn("{}: {}", label, w);
    if (result.converged) {
      store.store(point, result);  // at once: a kill after this line keeps the point
      log.debug("{}: torque {:.6e} N m ({}, {} iterations)", label, result.torque, result.method, result.iterations);
    } else {
      if (!result.fields.empty()) store.store_failure(point, result);  // its last iterate, for diagnosis
      if (failure_reasons.insert(result.failure).second)
        log.error("{} failed: {}{}", label, result.failure,
                  result.fields.empty()
                      ? std::string()
                      : fmt::format("; its last iterate is in {}", store.failure_file(point).string()));
      else
        log.debug("{} failed: {}", label, result.failure);  // the same reason as an earlier point
    }
    result.fields.clear();  // stored; the summary needs only the numbers
    results[point.index] = std::move(result);
    progress.update(++done, label);
  }
  progress.finish();
  return results;
}

// summary.json (the points in sweep order, then the analysis), torque.csv, sweep.h5 and the
// report; counts the failed points into outcome.
void write_sweep_results(const Case& c, const std::vector<SweepPoint>& points,
                         const std::vector<std::optional<PointResult>>& results,
                         std::chrono::steady_clock::time_point start, const fs::path& out_dir, SweepOutcome& outcome) {
  const auto& sweep = std::get<SweepCase>(c.spec);
  const auto& r = sweep.rheometer;
  const ParallelPlate plate = ParallelPlate::from(r.geometry);
  // summary.json: the points in sweep order, then the analysis.
  std::vector<SweepPointRecord> records;
  core::CsvTable table({{"volume_fraction", ""},
                        {"shear_rate", "1/s"},
                        {"torque", "N m"},
                        {"torque_std_error", "N m"},
                        {"torque_creeping", "N m"},
                        {"torque_analytic", "N m"},
                        {"rel_error", ""},
                        {"gap_reynolds_number", ""},
                        {"iterations", ""},
                        {"wall_time", "s"},
                        {"converged", ""}},
                       core::CsvTable::Column{"fluid", ""});
  core::Hdf5Content sweep_h5;
  std::map<std::string, std::vector<double>> columns;
  for (const auto& point : points) {
    const PointResult& res = *results[point.index];
    const auto& fluid = fluid_named(r, point.fluid).properties;
    SweepPointRecord record;
    record.fluid = point.fluid;
    record.volume_fraction = point.volume_fraction;
    record.shear_rate = point.rim_shear_rate;
    record.converged = res.converged;
    record.method = res.method;
    record.model = res.model;
    record.model_reason = res.model_reason;
    if (res.converged) {
      const double rel_error = (res.torque - res.torque_analytic) / res.torque_analytic;
      const double reynolds = plate.gap_reynolds_number(fluid.density, point.rim_shear_rate,
                                                        fluid.rheology->viscosity(point.rim_shear_rate));
      const auto finite = core::finite_or_empty;
      record.angular_velocity = plate.angular_velocity(point.rim_shear_rate);
      record.torque = res.torque;
      record.torque_fluid = finite(res.torque_fluid);
      record.torque_contact = finite(res.torque_contact);
      record.torque_lubrication = finite(res.torque_lubrication);
      record.torque_stresslet = finite(res.torque_stresslet);
      record.torque_couple = finite(res.torque_couple);
      record.torque_std_error = finite(res.torque_std_error);
      if (std::isfinite(res.torque_grid)) {
        record.torque_grid = res.torque_grid;
        record.torque_half_grid = res.torque_half_grid;
      }
      record.torque_creeping = finite(res.torque_creeping);
      if (std::isfinite(res.torque_creeping)) record.inertia_effect = res.torque / res.torque_creeping - 1.0;
      if (point.volume_fraction == 0)  // the creeping closed form by quadrature, for laws without one in closed form
        record.torque_quadrature = creeping_torque(plate, *fluid.rheology, point.rim_shear_rate);
      if (std::isfinite(res.torque_analytic)) {
        record.torque_analytic = res.torque_analytic;
        record.rel_error = rel_error;
        record.creeping_rel_error = finite((res.torque_creeping - res.torque_analytic) / res.torque_analytic);
      }
      if (std::isfinite(res.normal_force)) {
        record.normal_force = res.normal_force;
        record.n1 = finite(res.n1);
        record.n2 = finite(res.n2);
      }
      record.warnings = res.warnings;
      record.gap_reynolds_number = reynolds;
      record.strain = finite(res.strain);
      record.estimated_error = finite(res.estimated_error);
      record.iterations = res.iterations;
      record.wall_time = res.wall_time;
      if (std::isfinite(res.cost_dem)) {
        const double overhead = res.cost_dem > 0 ? (res.cost_void_fraction + res.cost_forces) / res.cost_dem : 0.0;
        record.cost = PointCost{res.cost_dem, res.cost_void_fraction,     res.cost_forces, res.cost_fluid,
                                overhead,     finite(res.cost_near_field)};
      }
      table.add_row({point.volume_fraction, point.rim_shear_rate, res.torque, res.torque_std_error, res.torque_creeping,
                     res.torque_analytic, rel_error, reynolds, static_cast<double>(res.iterations), res.wall_time, 1.0},
                    point.fluid);
    } else {
      record.failure = res.failure;
      table.add_row({point.volume_fraction, point.rim_shear_rate, nan, nan, nan, nan, nan, nan,
                     static_cast<double>(res.iterations), res.wall_time, 0.0},
                    point.fluid);
    }
    records.push_back(std::move(record));
    columns["volume_fraction"].push_back(point.volume_fraction);
    columns["shear_rate"].push_back(point.rim_shear_rate);
    columns["converged"].push_back(res.converged ? 1.0 : 0.0);
    for (const auto& f : number_fields) columns[f.name].push_back(res.*(f.member));
    if (!res.converged) ++outcome.failed_points;
  }

  SweepSummary summary;
  summary.head = core::summary_head_of(c, "sweep");  // a one-φ rheometer case runs as a sweep too
  summary.radius = r.geometry.radius;
  summary.gap = r.geometry.gap;
  summary.grid = SweepGridRecord{
      r.solver.radial_cells,   r.solver.axial_cells,
      r.solver.radial_grading, r.solver.axial_stretching,
      r.solver.extrapolate,    "the φ = 0 points (steady swirl solve); a CFD-DEM point names its grid in method"};
  summary.inertia = r.solver.inertia;
  summary.volume_fractions = sweep.volume_fractions;
  summary.shear_rates = r.shear_rates;
  summary.points_total = static_cast<std::size_t>(outcome.points);
  summary.points_failed = static_cast<std::size_t>(outcome.failed_points);
  summary.points_resumed = static_cast<std::size_t>(outcome.reused_points);
  summary.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  add_normal_stress_differences(records, r.geometry.radius);
  FlowAnalysis analysis = analyse_flow_curves(records, {plate, r.fluids, r.particles});
  summary.points = std::move(records);
  {  // every rule a point bent, with how many points bent it
    std::map<std::string, std::size_t> counts;
    for (const auto& point : points)
      for (const auto& w : results[point.index]->warnings) ++counts[w];
    for (const auto& [text, count] : counts) summary.warnings.push_back({text, count});
  }
  summary.series = std::move(analysis.series);
  summary.fits = std::move(analysis.fits);
  summary.yield_stress = std::move(analysis.yield_stress);
  summary.relative_viscosity = std::move(analysis.relative_viscosity);

  for (auto& [name, values] : columns) {
    core::Hdf5Dataset d;
    d.path = "points/" + name;
    d.shape = {values.size()};
    d.data = values;
    sweep_h5.datasets.push_back(d);
  }
  sweep_h5.attributes = {{"case", c.name}, {"input_sha256", c.sha256}};
  core::write_hdf5(out_dir / "sweep.h5", sweep_h5);
  core::write_csv(out_dir / "torque.csv", table);
  core::write_json(out_dir / "summary.json", to_json(summary));
  write_report(out_dir);
}

}  // namespace

SweepOutcome run_sweep(const Case& c, const fs::path& out_dir, const core::Log& log, const PointRunners& runners) {
  const auto& sweep = std::get<SweepCase>(c.spec);
  const auto start = std::chrono::steady_clock::now();
  fs::create_directories(out_dir);
  const PointStore store(out_dir, c.sha256);
  core::write_atomically(out_dir / "case.yaml", [&](std::ostream& os) { os << c.text; });
  const std::vector<SweepPoint> points = sweep_points(sweep);
  SweepOutcome outcome;
  outcome.points = static_cast<int>(points.size());
  const auto results = compute_points(sweep.rheometer, points, store, log, runners, outcome);
  write_sweep_results(c, points, results, start, out_dir, outcome);
  outcome.summary = out_dir / "summary.json";
  return outcome;
}

}  // namespace rheosim::rheometer
