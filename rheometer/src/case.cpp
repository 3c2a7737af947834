#include "rheosim/rheometer/case.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <utility>

namespace rheosim::rheometer {

namespace {

using core::KeyInfo;
using core::Range;
using core::Section;
using Model = RheometerCase::SuspensionModel;

constexpr std::array suspension_models{Model::automatic, Model::lees_edwards, Model::walled_box, Model::full_disk,
                                       Model::shear_cell};

// `fluid: {...}` or, for single-phase comparisons, `fluids: [{name: ..., density, rheology}, ...]`.
std::vector<NamedFluid> read_fluids(const Section& root) {
  const KeyInfo list_key{"fluids", "a list of named liquids, each {name, density, rheology}", "-"};
  if (!root.has("fluids")) return {{"fluid", core::read_fluid(root)}};
  if (root.has("fluid"))
    root.fail("fluids", "both 'fluid' and 'fluids' are given", "one of them", "keep 'fluid' for one liquid");
  std::vector<NamedFluid> out;
  for (const Section& item : root.sections(list_key)) {
    NamedFluid f{item.text({"name", "fluid name (used in tables and plots)", "-"}), core::read_fluid_properties(item)};
    for (const auto& other : out)
      if (other.name == f.name) item.fail("name", "the name '" + f.name + "' is used twice", "unique fluid names");
    out.push_back(std::move(f));
  }
  return out;
}

FluidSolverSettings read_solver(const Section& root) {
  FluidSolverSettings out;
  const auto s = root.optional_section({"solver", "fluid solver settings", "-"});
  if (!s) return out;
  out.radial_cells = s->integer_or({"radial_cells", "radial cells N_r", "-"}, out.radial_cells, 2, 4000);
  out.axial_cells = s->integer_or({"axial_cells", "axial cells N_z", "-"}, out.axial_cells, 2, 2000);
  out.radial_grading = s->number_or({"radial_grading", "last/first radial cell width", "-"}, out.radial_grading,
                                    Range::closed(0.01, 100.0));
  out.axial_stretching = s->number_or({"axial_stretching", "tanh clustering of axial cells towards the plates", "-"},
                                      out.axial_stretching, Range::closed(0.0, 5.0));
  out.inertia = s->boolean_or({"inertia", "solve with fluid inertia (false: creeping limit)", "-"}, out.inertia);
  out.extrapolate = s->boolean_or(
      {"extrapolate", "report the Richardson torque over this grid and half its cells", "-"}, out.extrapolate);
  // The half grid must exist: the solver's grid sequencing needs even counts >= 8.
  if (out.extrapolate)
    for (const auto& [key, cells] :
         {std::pair{"radial_cells", out.radial_cells}, std::pair{"axial_cells", out.axial_cells}})
      if (cells < 8 || cells % 2 != 0)
        s->fail(key, fmt::format("{} = {} cannot be halved for extrapolate: true", key, cells), "an even number >= 8",
                "use an even cell count, or extrapolate: false");
  out.tolerance =
      s->number_or({"tolerance", "relative change per iteration", "-"}, out.tolerance, Range::open(0.0, 1e-2));
  out.max_iterations = s->integer_or({"max_iterations", "nonlinear iterations", "-"}, out.max_iterations, 1, 100000);
  return out;
}

core::PlateGeometry read_plate_geometry(const Section& root) {
  const Section g = root.section({"geometry", "rheometer geometry", "-"});
  (void)g.choice({"type", "geometry type", "-"}, {"parallel_plate"});
  core::PlateGeometry out;
  out.radius = g.number({"radius", "plate radius R", "m"}, Range::positive());
  out.gap = g.number({"gap", "plate gap H", "m"}, Range::positive());
  if (out.gap >= out.radius)
    g.fail("gap", fmt::format("gap {} m is not smaller than the radius {} m", out.gap, out.radius),
           "a gap H < R (parallel-plate rheometry assumes H << R)");
  return out;
}

RheometerCase read_rheometer(const Section& root, bool is_sweep) {
  RheometerCase out;
  out.geometry = read_plate_geometry(root);
  out.fluids = read_fluids(root);
  out.fluid = out.fluids.front().properties;
  if (out.fluids.size() > 1 && (is_sweep || root.has("particles")))
    root.fail("fluids", "several fluids are only for single-phase rheometry", "one 'fluid:' with particles",
              "run one case per fluid");
  out.solver = read_solver(root);
  out.shear_rates = root.numbers({"shear_rates", "rim shear rates γ̇_R = ΩR/H", "1/s"}, Range::positive());
  core::require_increasing(root, "shear_rates", out.shear_rates);
  const KeyInfo particles_key{"particles", "suspended particles (omit for a single fluid)", "-"};
  if (auto p = root.optional_section(particles_key))
    out.particles = coupling::read_suspended_particles(*p, out.geometry.gap, !is_sweep);
  std::vector<std::string> names;
  for (const Model m : suspension_models) names.emplace_back(name_of(m));
  const std::string model =
      root.choice_or({"model", "suspension model (auto | lees_edwards | walled_box | full_disk | shear_cell)", "-"},
                     name_of(Model::automatic), names);
  for (const Model m : suspension_models)
    if (model == name_of(m)) out.suspension_model = m;
  return out;
}

SweepCase read_sweep(const Section& root) {
  SweepCase out;
  out.rheometer = read_rheometer(root, true);
  out.volume_fractions =
      root.numbers({"volume_fractions", "particle volume fractions φ", "-"}, Range::closed(0.0, 0.5));
  core::require_increasing(root, "volume_fractions", out.volume_fractions);
  const bool needs_particles =
      std::any_of(out.volume_fractions.begin(), out.volume_fractions.end(), [](double phi) { return phi > 0; });
  if (needs_particles && !out.rheometer.particles)
    root.fail("volume_fractions", "volume fractions above 0 need a 'particles:' section",
              "a 'particles:' section with diameter, density and contact properties",
              "add 'particles: {diameter: 2.0e-4, density: 1000}'");
  return out;
}

std::string describe_rheometer(const RheometerCase& r) {
  std::string out =
      fmt::format("  geometry: parallel plates, radius {} m, gap {} m\n", r.geometry.radius, r.geometry.gap);
  for (const auto& f : r.fluids) {
    if (r.fluids.size() > 1) out += fmt::format("  [{}]\n", f.name);
    out += core::describe_fluid(f.properties);
  }
  out += fmt::format(
      "  solver: {} × {} cells (r × z), radial grading {}, axial stretching {}, inertia {}{}\n", r.solver.radial_cells,
      r.solver.axial_cells, r.solver.radial_grading, r.solver.axial_stretching, r.solver.inertia ? "on" : "off",
      r.solver.inertia && r.solver.extrapolate ? " (Richardson torque over this grid and half its cells)" : "");
  out += fmt::format("  rim shear rates: {} 1/s\n", fmt::format("[{}]", fmt::join(r.shear_rates, ", ")));
  if (r.particles) {
    out += fmt::format("  suspension model: {}\n", name_of(r.suspension_model));
    out += coupling::describe(*r.particles, r.geometry.gap);
  } else {
    out += "  particles: none (single phase)\n";
  }
  return out;
}

}  // namespace

const char* name_of(RheometerCase::SuspensionModel model) {
  switch (model) {
    case Model::lees_edwards:
      return "lees_edwards";
    case Model::walled_box:
      return "walled_box";
    case Model::full_disk:
      return "full_disk";
    case Model::shear_cell:
      return "shear_cell";
    case Model::automatic:
      break;
  }
  return "auto";
}

Case read_case(const core::CaseFile& file) {
  file.require_kind({"rheometer", "sweep"}, "the rheometer");
  Case out;
  static_cast<core::CaseHeader&>(out) = file.header();
  if (out.kind == "rheometer")
    out.spec = read_rheometer(file.root(), false);
  else
    out.spec = read_sweep(file.root());
  file.check_all_keys_known();
  return out;
}

Case as_sweep(const Case& c) {
  const auto* r = std::get_if<RheometerCase>(&c.spec);
  if (!r) return c;
  Case sweep = c;
  sweep.kind = "sweep";
  const double phi = r->particles ? r->particles->volume_fraction : 0.0;
  sweep.spec = SweepCase{*r, phi > 0 ? std::vector<double>{0.0, phi} : std::vector<double>{0.0}};
  return sweep;
}

Case parse_case(std::string_view text, const std::string& name) { return read_case(core::CaseFile::parse(text, name)); }

Case load_case(const std::string& path) { return read_case(core::CaseFile::open(path)); }

std::string describe(const Case& c) {
  std::string out = fmt::format("  name: {}\n  input sha256: {}\n", c.name, c.sha256);
  if (const auto* r = std::get_if<RheometerCase>(&c.spec)) {
    out += describe_rheometer(*r);
    if (r->particles) out += fmt::format("  volume fraction: {}\n", r->particles->volume_fraction);
  } else {
    const auto& s = std::get<SweepCase>(c.spec);
    out += describe_rheometer(s.rheometer);
    out += fmt::format("  volume fractions: {} ({} points)\n", fmt::format("[{}]", fmt::join(s.volume_fractions, ", ")),
                       s.volume_fractions.size() * s.rheometer.shear_rates.size());
  }
  return out;
}

}  // namespace rheosim::rheometer
