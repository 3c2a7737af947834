
#include "rheosim/core/case.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <utility>

#include "rheosim/core/config.hpp"

namespace rheosim::core {

namespace {

// Values must be strictly increasing: a repeated point is almost always a typo.
void require_increasing(const Section& s, std::string_view key, const std::vector<double>& values) {
  for (std::size_t i = 1; i < values.size(); ++i)
    if (!(values[i] > values[i - 1]))
      s.fail(key, fmt::format("entry {} ({}) does not exceed entry {} ({})", i, values[i], i - 1, values[i - 1]),
             "a strictly increasing list", "sort the list and remove repeated values");
}

FluidProperties read_fluid_properties(const Section& fluid) {
  FluidProperties out;
  out.density = fluid.number({"density", "fluid density", "kg/m³"}, Range::positive());
  out.rheology = make_rheology(fluid.section({"rheology", "viscosity law {model: name, parameters}", "-"}));
  return out;
}

// `fluid: {...}` or, for single-phase comparisons, `fluids: [{name: ..., density, rheology}, ...]`.
std::vector<NamedFluid> read_fluids(const Section& root) {
  const KeyInfo list_key{"fluids", "a list of named liquids, each {name, density, rheology}", "-"};
  if (!root.has("fluids")) return {{"fluid", read_fluid(root)}};
  if (root.has("fluid"))
    root.fail("fluids", "both 'fluid' and 'fluids' are given", "one of them", "keep 'fluid' for one liquid");
  std::vector<NamedFluid> out;
  for (const Section& item : root.sections(list_key)) {
    NamedFluid f{item.text({"name", "fluid name (used in tables and plots)", "-"}), read_fluid_properties(item)};
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

PlateGeometry read_plate_geometry(const Section& root) {
  const Section g = root.section({"geometry", "rheometer geometry", "-"});
  (void)g.choice({"type", "geometry type", "-"}, {"parallel_plate"});
  PlateGeometry out;
  out.radius = g.number({"radius", "plate radius R", "m"}, Range::positive());
  out.gap = g.number({"gap", "plate gap H", "m"}, Range::positive());
  if (out.gap >= out.radius)
    g.fail("gap", fmt::format("gap {} m is not smaller than the radius {} m", out.gap, out.radius),
           "a gap H < R (parallel-plate rheometry assumes H << R)");
  return out;
}

// particles.size_distribution (see SizeDistribution); d is particles.diameter.
SizeDistribution read_size_distribution(const Section& s, double d, const PlateGeometry& geometry) {
  SizeDistribution out;
  const std::string type = s.choice({"type", "size distribution", "-"}, {"uniform", "lognormal", "discrete"});
  const KeyInfo min_key{"min_diameter", "smallest particle diameter", "m"};
  const KeyInfo max_key{"max_diameter", "largest particle diameter", "m"};
  std::string bounds_key = "max_diameter";
  if (type == "uniform") {
    out.type = SizeDistribution::Type::uniform;
    out.min_diameter = s.number(min_key, Range::positive());
    out.max_diameter = s.number(max_key, Range::positive());
    if (!(out.min_diameter < out.max_diameter))
      s.fail("max_diameter",
             fmt::format("max_diameter {} m is not above min_diameter {} m", out.max_diameter, out.min_diameter),
             "min_diameter < max_diameter", "for equal spheres omit size_distribution");
  } else if (type == "lognormal") {
    out.type = SizeDistribution::Type::lognormal;
    out.geometric_std = s.number({"geometric_std", "geometric standard deviation σ_g of the volume distribution", "-"},
                                 Range::closed(1.0, 3.0));
    // Default truncation: d50 σ_g^∓2, which holds 95 % of the (untruncated) volume.
    const double spread = out.geometric_std * out.geometric_std;
    out.min_diameter = s.number_or(min_key, d / spread, Range::positive());
    out.max_diameter = s.number_or(max_key, d * spread, Range::positive());
  } else {
    out.type = SizeDistribution::Type::discrete;
    const auto max_classes = static_cast<std::size_t>(SizeDistribution::max_classes);
    const auto diameters =
        s.numbers({"diameters", "diameter of each size class", "m"}, Range::positive(), 1, max_classes);
    require_increasing(s, "diameters", diameters);
    const auto shares = s.numbers({"volume_fractions", "share of the particle volume in each class", "-"},
                                  Range::closed(0.0, 1.0), diameters.size(), diameters.size());
    out.classes = static_cast<int>(diameters.size());
    std::copy(diameters.begin(), diameters.end(), out.diameters.begin());
    std::copy(shares.begin(), shares.end(), out.volume_fractions.begin());
    double sum = 0;
    for (const double w : shares) sum += w;
    if (std::abs(sum - 1.0) > 1e-6)
      s.fail("volume_fractions", fmt::format("the shares add up to {}", sum),
             "shares of the solid volume adding up to 1", "divide each share by their sum");
    out.min_diameter = diameters.front();
    out.max_diameter = diameters.back();
    bounds_key = "diameters";
  }
  if (!(out.min_diameter <= d && d <= out.max_diameter))
    s.fail(bounds_key,
           fmt::format("particles.diameter {} m is outside the distribution's range [{}, {}] m", d, out.min_diameter,
                       out.max_diameter),
           "a range that contains particles.diameter (the representative, volume-median size)");
  if (out.max_diameter >= geometry.gap)
    s.fail(bounds_key,
           fmt::format("the largest particles ({} m) do not fit in the gap of {} m", out.max_diameter, geometry.gap),
           "every diameter smaller than the gap");
  return out;
}

// Memory and time an LDD case needs, estimated from its geometry before anything is allocated.
// Per node, measured peak memory: 6.1 kB (2D cavity, with its sparse LU), 2.5 kB (2D dam break),
// 4.7 kB (3D slump) — 8 kB bounds them; per node and step about 2 µs (the 50 000-node dam break,
// 109 ms per step on two threads, docs/performance.md).
// particles.hydrodynamics (see Hydrodynamics): model `none` or terms joined by '+'.
Hydrodynamics read_hydrodynamics(const Section& s) {
  Hydrodynamics out;
  out.specified = true;
  const std::vector<std::string> terms{"lubrication",     "none",        "repulsion",
                                       "single_particle", "stokes_drag", "stresslet"};
  const std::string model = s.text({"model", "near-field terms, e.g. lubrication+stresslet", "-"});
  std::size_t start = 0;
  while (start <= model.size()) {
    const std::size_t end = std::min(model.find('+', start), model.size());
    const std::string term = model.substr(start, end - start);
    if (std::find(terms.begin(), terms.end(), term) == terms.end())
      s.fail("model", fmt::format("unknown near-field term '{}' in '{}'", term, model),
             "none, or terms joined by '+' from: lubrication, repulsion, single_particle, stokes_drag, stresslet",
             "e.g. 'model: lubrication+stresslet'");
    if (term == "lubrication") out.lubrication = true;
    if (term == "stresslet" || term == "single_particle") out.single_particle = true;
    if (term == "stokes_drag") out.stokes_drag = true;
    if (term == "repulsion") out.repulsion = true;
    start = end + 1;
  }
  if (out.repulsion && !out.lubrication)
    s.fail("model", fmt::format("'{}' has repulsion without lubrication", model), "repulsion together with lubrication",
           "the repulsion acts on the lubrication gap list, e.g. 'model: lubrication+stresslet+repulsion'");
  out.roughness = s.number_or({"roughness", "roughness length δ/ā regularising the lubrication gap", "-"},
                              out.roughness, Range::closed(1e-6, 0.1));
  out.lubrication_cutoff = s.number_or({"lubrication_cutoff", "gap h_c/ā below which lubrication acts", "-"},
                                       out.lubrication_cutoff, Range::open_closed(out.roughness, 1.0));
  if (out.repulsion) {
    out.repulsion_force =
        s.number({"repulsion_force", "repulsion F_R0 at contact (stress scale F_R0/(6πa²))", "N"}, Range::positive());
    out.repulsion_length = s.number_or({"repulsion_length", "repulsion decay length λ/ā", "-"}, out.repulsion_length,
                                       Range::closed(1e-3, out.lubrication_cutoff / 5.0));
  }
  if (out.single_particle) {
    const std::string stresslet_viscosity =
        s.choice_or({"stresslet_viscosity", "matrix viscosity in the stresslet", "-"}, name_of(out.stresslet_viscosity),
                    {name_of(StressletViscosity::homogenized), name_of(StressletViscosity::secant)});
    if (stresslet_viscosity == name_of(StressletViscosity::secant))
      out.stresslet_viscosity = StressletViscosity::secant;
  }
  return out;
}

ParticleProperties read_particles(const Section& p, const PlateGeometry& geometry, bool with_volume_fraction) {
  ParticleProperties out;
  if (with_volume_fraction)
    out.volume_fraction = p.number({"volume_fraction", "particle volume fraction φ", "-"}, Range::closed(0.0, 0.5));
  out.diameter = p.number({"diameter", "particle diameter d", "m"}, Range::positive());
  out.density = p.number({"density", "particle density", "kg/m³"}, Range::positive());
  out.youngs_modulus =
      p.number_or({"youngs_modulus", "Young's modulus E", "Pa"}, out.youngs_modulus, Range::positive());
  out.poisson_ratio =
      p.number_or({"poisson_ratio", "Poisson ratio ν", "-"}, out.poisson_ratio, Range::closed_open(0.0, 0.5));
  out.restitution =
      p.number_or({"restitution", "coefficient of restitution e", "-"}, out.restitution, Range::open_closed(0.0, 1.0));
  out.friction = p.number_or({"friction", "Coulomb friction coefficient", "-"}, out.friction, Range::closed(0.0, 10.0));
  if (out.diameter >= geometry.gap)
    p.fail("diameter", fmt::format("particles of {} m do not fit in the gap of {} m", out.diameter, geometry.gap),
           "a particle diameter smaller than the gap (H/d >= 10 for a continuum stress)");
  const KeyInfo distribution_key{"size_distribution", "spread of particle diameters (omit for equal spheres)", "-"};
  if (auto s = p.optional_section(distribution_key))
    out.size_distribution = read_size_distribution(*s, out.diameter, geometry);
  const KeyInfo hydrodynamics_key{"hydrodynamics", "near-field hydrodynamics (omit for drag only)", "-"};
  if (auto s = p.optional_section(hydrodynamics_key)) out.hydrodynamics = read_hydrodynamics(*s);
  const KeyInfo drag_key{"drag", "fluid–particle drag law (omit for auto)", "-"};
  std::string drag = "auto";
  if (auto s = p.optional_section(drag_key))
    drag = s->choice({"model", "drag law", "-"},
                     {"auto", name_of(DragLaw::di_felice), name_of(DragLaw::schiller_naumann)});
  out.drag_automatic = drag == "auto";
  if (drag == name_of(DragLaw::schiller_naumann) || (out.drag_automatic && out.hydrodynamics.lubrication))
    out.drag = DragLaw::schiller_naumann;
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
  require_increasing(root, "shear_rates", out.shear_rates);
  const KeyInfo particles_key{"particles", "suspended particles (omit for a single fluid)", "-"};
  if (auto p = root.optional_section(particles_key)) out.particles = read_particles(*p, out.geometry, !is_sweep);
  const std::string model =
      root.choice_or({"model", "suspension model (auto | lees_edwards | walled_box | full_disk | shear_cell)", "-"},
                     "auto", {"auto", "lees_edwards", "walled_box", "full_disk", "shear_cell"});
  out.suspension_model = model == "full_disk"      ? RheometerCase::SuspensionModel::full_disk
                         : model == "shear_cell"   ? RheometerCase::SuspensionModel::shear_cell
                         : model == "lees_edwards" ? RheometerCase::SuspensionModel::lees_edwards
                         : model == "walled_box"   ? RheometerCase::SuspensionModel::walled_box
                                                   : RheometerCase::SuspensionModel::automatic;
  return out;
}

SweepCase read_sweep(const Section& root) {
  SweepCase out;
  out.rheometer = read_rheometer(root, true);
  out.volume_fractions =
      root.numbers({"volume_fractions", "particle volume fractions φ", "-"}, Range::closed(0.0, 0.5));
  require_increasing(root, "volume_fractions", out.volume_fractions);
  const bool needs_particles =
      std::any_of(out.volume_fractions.begin(), out.volume_fractions.end(), [](double phi) { return phi > 0; });
  if (needs_particles && !out.rheometer.particles)
    root.fail("volume_fractions", "volume fractions above 0 need a 'particles:' section",
              "a 'particles:' section with diameter, density and contact properties",
              "add 'particles: {diameter: 2.0e-4, density: 1000}'");
  return out;
}

}  // namespace

FluidProperties read_fluid(const Section& section) {
  return read_fluid_properties(section.section({"fluid", "the liquid (matrix) phase", "-"}));
}

std::filesystem::path CaseFile::directory() const { return std::filesystem::path(header_.file).parent_path(); }

void CaseFile::require_kind(const std::vector<std::string>& kinds, std::string_view reader) const {
  if (std::find(kinds.begin(), kinds.end(), header_.kind) != kinds.end()) return;
  std::string names;
  for (const auto& k : kinds) names += (names.empty() ? "" : " or ") + k;
  root().fail("kind", fmt::format("{} reads {} cases, not '{}'", reader, names, header_.kind), names);
}

CaseFile CaseFile::parse(std::string_view text, const std::string& name) {
  Document doc = Document::from_string(text, name);
  const Section root = doc.root();
  CaseHeader h;
  h.file = name;
  h.text = doc.text();
  h.sha256 = sha256_hex(h.text);
  h.name = root.text_or({"name", "case name", "-"}, std::filesystem::path(name).stem().string());
  h.description = root.text_or({"description", "free-text description", "-"}, "");
  h.kind = root.choice({"kind", "case kind", "-"}, {"rheometer", "sweep", "ldd"});
  return CaseFile(std::move(doc), std::move(h));
}

CaseFile CaseFile::open(const std::string& path) {
  const Document doc = Document::from_file(path);
  return parse(doc.text(), path);
}

Case read_case(const CaseFile& file) {
  file.require_kind({"rheometer", "sweep"}, "the rheometer");
  Case out;
  static_cast<CaseHeader&>(out) = file.header();
  if (out.kind == "rheometer")
    out.spec = read_rheometer(file.root(), false);
  else
    out.spec = read_sweep(file.root());
  file.check_all_keys_known();
  return out;
}

Case parse_case(std::string_view text, const std::string& name) { return read_case(CaseFile::parse(text, name)); }

Case load_case(const std::string& path) { return read_case(CaseFile::open(path)); }

}  // namespace rheosim::core
