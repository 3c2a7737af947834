
#include "rheosim/core/case.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <utility>

#include "rheosim/core/units.hpp"

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

FluidProperties read_fluid(const Section& root) {
  return read_fluid_properties(root.section({"fluid", "the liquid (matrix) phase", "-"}));
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
constexpr double ldd_bytes_per_node = 8192.0;
constexpr double ldd_seconds_per_node_step = 2e-6;
// time.step: auto keeps max|u|δt/Δ at this for the scene's velocity scale (automatic_ldd_time_step).
constexpr double ldd_auto_courant = 0.25;
struct LddSizeEstimate {
  double nodes = 0, bytes = 0, steps = 0, node_steps = 0;
};
LddSizeEstimate estimate_ldd_size(const LddCase& l) {
  const double d = l.spacing;
  double nodes = 0;
  if (const auto* c = std::get_if<CavityScene>(&l.scene)) {
    nodes = (c->size[0] / d + 1) * (c->size[1] / d + 1);
  } else if (const auto* b = std::get_if<DamBreakScene>(&l.scene)) {
    nodes = b->reservoir[0] * b->reservoir[1] / (d * d) + 3.0 * (b->channel_length + 2.0 * b->reservoir[1]) / d;
  } else if (const auto* s = std::get_if<SlumpScene>(&l.scene)) {
    const double big = 0.5 * s->cone_bottom_diameter, small = 0.5 * s->cone_top_diameter;
    const double cone = std::numbers::pi * s->cone_height * (big * big + big * small + small * small) / 3.0;
    const double floor = std::pow(4.0 * s->cone_bottom_diameter, 2);  // the spread's reach, two wall layers
    nodes = cone / (d * d * d) + 2.0 * floor / (d * d);
  } else if (const auto* k = std::get_if<ColumnScene>(&l.scene)) {
    nodes = (k->size[0] / d + 1) * (k->size[1] / d + 5);
  }
  LddSizeEstimate e;
  e.nodes = nodes;
  e.bytes = nodes * ldd_bytes_per_node;
  e.steps = l.end_time / l.time_step;
  e.node_steps = e.nodes * e.steps;
  return e;
}

// time.step: auto. The viscous term is implicit (LDD eq. 19) and sets no limit; the step keeps
// the advective Courant number max|u|δt/Δ at ldd_auto_courant for the scene's velocity scale:
// the lid speed of a cavity, and for the free-surface scenes the front speed 2√(|g|H) of a
// collapse of the fluid's height H (the shallow-water dam-break front, Ritter 1892), or a mould's
// lift speed if faster. Rounded down to two significant digits.
std::pair<double, std::string> automatic_ldd_time_step(const LddCase& l) {
  double g = 0;
  for (double c : l.gravity) g += c * c;
  g = std::sqrt(g);
  double speed = 0;
  std::string scale;
  const auto collapse = [&](double height) {
    speed = 2.0 * std::sqrt(g * height);
    scale = fmt::format("U = 2√(|g|H) = {:.3g} m/s, the front speed of a collapse of height H = {:.3g} m", speed,
                        height);
  };
  if (const auto* c = std::get_if<CavityScene>(&l.scene)) {
    speed = std::abs(c->lid_velocity);
    scale = fmt::format("U = the lid speed {:.3g} m/s", speed);
  } else if (const auto* b = std::get_if<DamBreakScene>(&l.scene)) {
    collapse(b->reservoir[1]);
  } else if (const auto* k = std::get_if<ColumnScene>(&l.scene)) {
    collapse(k->size[1] + k->wave_amplitude);
  } else if (const auto* s = std::get_if<SlumpScene>(&l.scene)) {
    collapse(s->cone_height);
    if (s->lift_velocity > speed) {
      speed = s->lift_velocity;
      scale = fmt::format("U = the mould's lift speed {:.3g} m/s", speed);
    }
  }
  if (!(speed > 0)) speed = 1.0, scale = "U = 1 m/s (the scene has no velocity scale)";
  const double exact = ldd_auto_courant * l.spacing / speed;
  const double decade = std::pow(10.0, std::floor(std::log10(exact)) - 1.0);
  const double dt = std::floor(exact / decade) * decade;
  return {dt, fmt::format("auto: δt = {:.2g} s ≤ {} Δ/U, {}", dt, ldd_auto_courant, scale)};
}

double physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 1e300;
}

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

std::array<double, 2> read_pair(const Section& s, const KeyInfo& key) {
  const auto v = s.numbers(key, Range::positive(), 2, 2);
  return {v[0], v[1]};
}

LddWall read_wall(const Section& w, int dimension, const std::filesystem::path& case_dir) {
  LddWall out;
  const auto d = static_cast<std::size_t>(dimension);
  out.type = w.choice({"type", "wall type", "-"}, {"plane", "box", "cylinder", "stl"});
  if ((out.type == "cylinder" || out.type == "stl") && dimension != 3)
    w.fail("type", fmt::format("a {} wall is 3D, the case is {}D", out.type, dimension),
           "dimension: 3 or a plane/box wall");
  if (out.type != "plane")
    out.fluid_inside = w.choice_or({"fluid", "which side of the wall the fluid is on", "-"}, "inside",
                                   {"inside", "outside"}) == "inside";
  if (out.type == "plane") {
    out.point = w.numbers({"point", "a point on the plane", "m"}, Range::any(), d, d);
    out.normal = w.numbers({"normal", "plane normal, pointing into the fluid", "-"}, Range::any(), d, d);
    double length = 0;
    for (double v : out.normal) length += v * v;
    if (!(length > 1e-24)) w.fail("normal", "the plane normal is zero", "a non-zero vector");
  } else if (out.type == "box") {
    out.lower = w.numbers({"lower", "box corner with the smallest coordinates", "m"}, Range::any(), d, d);
    out.upper = w.numbers({"upper", "box corner with the largest coordinates", "m"}, Range::any(), d, d);
    for (std::size_t k = 0; k < d; ++k)
      if (!(out.upper[k] > out.lower[k]))
        w.fail("upper", fmt::format("upper[{}] = {} m is not above lower[{}] = {} m", k, out.upper[k], k, out.lower[k]),
               "upper > lower in every coordinate");
  } else if (out.type == "cylinder") {
    out.base = w.numbers({"base", "centre of the bottom cap", "m"}, Range::any(), 3, 3);
    out.axis = w.numbers_or({"axis", "axis direction (bottom to top)", "-"}, {0.0, 0.0, 1.0}, Range::any(), 3, 3);
    double length = 0;
    for (double v : out.axis) length += v * v;
    if (!(length > 1e-24)) w.fail("axis", "the cylinder axis is zero", "a non-zero vector");
    out.radius = w.number({"radius", "cylinder radius", "m"}, Range::positive());
    out.height = w.number({"height", "cylinder height along the axis", "m"}, Range::positive());
  } else {
    const std::string file = w.text({"file", "STL file (ASCII or binary), relative to the case file", "-"});
    const std::filesystem::path path =
        std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : case_dir / file;
    if (!std::filesystem::is_regular_file(path))
      w.fail("file", fmt::format("STL file '{}' does not exist", path.string()), "an existing STL file",
             "paths are relative to the case file's directory");
    out.file = path.string();
    out.scale = w.number_or({"scale", "metres per STL length unit", "m"}, out.scale, Range::positive());
  }
  return out;
}

LddCase read_ldd(const Section& root, const std::filesystem::path& case_dir) {
  LddCase out;
  out.dimension = root.integer({"dimension", "spatial dimension", "-"}, 2, 3);
  const Section scene = root.section({"scene", "the LDD scene", "-"});
  out.scene_type =
      scene.choice({"type", "scene type", "-"}, {"cavity", "skewed_cavity", "dam_break", "slump", "column"});
  const auto require_dimension = [&](int wanted) {
    if (out.dimension != wanted)
      root.fail("dimension", fmt::format("a {} scene is {}D, not {}D", out.scene_type, wanted, out.dimension),
                fmt::format("dimension: {}", wanted));
  };
  if (out.scene_type == "cavity" || out.scene_type == "skewed_cavity") {
    require_dimension(2);
    CavityScene c;
    c.size = read_pair(scene, {"size", "cavity width and height", "m"});
    c.lid_velocity = scene.number({"lid_velocity", "lid velocity", "m/s"}, Range::any());
    if (out.scene_type == "skewed_cavity")
      c.skew_angle = units::radians_from_degrees(
          scene.number({"skew_angle", "angle between lid and side walls", "degrees"}, Range::open(0.0, 180.0)));
    out.scene = c;
  } else if (out.scene_type == "dam_break") {
    require_dimension(2);  // the dam-break scene builds a 2D reservoir and channel
    DamBreakScene d;
    d.reservoir = read_pair(scene, {"reservoir", "reservoir length and height", "m"});
    d.channel_length = scene.number({"channel_length", "channel length", "m"}, Range::positive());
    if (d.channel_length <= d.reservoir[0])
      scene.fail("channel_length", "the channel is not longer than the reservoir",
                 fmt::format("a channel_length > reservoir length {} m", d.reservoir[0]));
    out.scene = d;
  } else if (out.scene_type == "slump") {
    require_dimension(3);
    const Section cone = scene.section({"cone", "the Abrams cone", "-"});
    SlumpScene s;
    s.cone_height = cone.number({"height", "cone height H₀", "m"}, Range::positive());
    s.cone_bottom_diameter = cone.number({"bottom_diameter", "cone bottom diameter D₀", "m"}, Range::positive());
    s.cone_top_diameter = cone.number({"top_diameter", "cone top diameter d₀", "m"}, Range::positive());
    if (s.cone_top_diameter >= s.cone_bottom_diameter)
      cone.fail("top_diameter", "the top diameter is not smaller than the bottom diameter",
                fmt::format("a top diameter < {} m", s.cone_bottom_diameter));
    s.lift_velocity = scene.number({"lift_velocity", "mould lift speed", "m/s"}, Range::positive());
    out.scene = s;
    if (scene.has("walls"))
      for (const Section& w : scene.sections({"walls", "extra solid walls (plane, box, cylinder, stl)", "-"}))
        out.walls.push_back(read_wall(w, out.dimension, case_dir));
  } else {
    require_dimension(2);  // the column scene builds a 2D box
    ColumnScene c;
    c.size = read_pair(scene, {"size", "column width and height", "m"});
    c.wave_amplitude = scene.number_or(
        {"wave_amplitude", "initial surface H + A cos(πx/W), the first sloshing mode (0: flat)", "m"},
        c.wave_amplitude, Range::closed(0.0, 0.5 * c.size[1]));
    out.scene = c;
  }
  out.fluid = read_fluid(root);
  out.gravity = root.numbers({"gravity", "gravitational acceleration, one entry per dimension", "m/s²"}, Range::any(),
                             static_cast<std::size_t>(out.dimension), static_cast<std::size_t>(out.dimension));
  const Section resolution = root.section({"resolution", "node spacing", "-"});
  out.spacing = resolution.number({"spacing", "node spacing Δ", "m"}, Range::positive());
  out.smoothing_ratio = resolution.number_or({"smoothing_ratio", "support radius over spacing h/Δ", "-"},
                                             out.smoothing_ratio, Range::closed(1.2, 3.0));
  const Section time = root.section({"time", "time stepping", "-"});
  const std::optional<double> step = time.number_or_word(
      {"step", "time step δt (auto: the advective limit, docs/ldd.md)", "s"}, "auto", Range::positive());
  if (step) {
    out.time_step = *step;
  } else {
    const auto [dt, rule] = automatic_ldd_time_step(out);
    out.time_step = dt;
    out.time_step_rule = rule;
  }
  out.end_time = time.number({"end", "end time", "s"}, Range::positive());
  if (out.end_time < out.time_step)
    time.fail("end", fmt::format("end time {} s is shorter than one step of {} s", out.end_time, out.time_step),
              "an end time of at least one time step");
  // A case that cannot fit the machine is refused here, before anything is allocated.
  const LddSizeEstimate size = estimate_ldd_size(out);
  const double memory = physical_memory_bytes();
  if (size.bytes > 0.8 * memory) {
    const double fitting = out.spacing * std::pow(size.bytes / (0.8 * memory), 1.0 / out.dimension);
    resolution.fail("spacing",
                    fmt::format("about {:.3g} nodes need about {:.3g} GiB ({:.0f} kB per node), more than 80 % of "
                                "this machine's {:.3g} GiB",
                                size.nodes, size.bytes / (1 << 30), ldd_bytes_per_node / 1024.0, memory / (1 << 30)),
                    fmt::format("a spacing of at least {:.3g} m on this machine", fitting),
                    "a coarser spacing, or a smaller scene");
  }
  if (size.node_steps * ldd_seconds_per_node_step > 365.0 * 86400.0)
    time.fail("step",
              fmt::format("about {:.3g} nodes × {:.3g} steps ≈ {:.3g} years of this machine", size.nodes, size.steps,
                          size.node_steps * ldd_seconds_per_node_step / (365.0 * 86400.0)),
              "a run of less than a year: a larger time step, a shorter end time or a coarser spacing");
  out.steady_tolerance = time.number_or(
      {"steady_tolerance", "stop when the centre-line rate of change (units of U²/L) drops below this; 0: never", "-"},
      out.steady_tolerance, Range::closed(0.0, 1.0));
  if (const auto s = root.optional_section({"solver", "LDD solver settings", "-"})) {
    LddSolverSettings& v = out.solver;
    v.threads = s->integer_or({"threads", "OpenMP threads (0: OMP_NUM_THREADS or all cores)", "-"}, v.threads, 0, 1024);
    v.pressure_tolerance = s->number_or({"pressure_tolerance", "relative residual of the pressure solve", "-"},
                                        v.pressure_tolerance, Range::open(0.0, 0.1));
    v.velocity_tolerance = s->number_or({"velocity_tolerance", "relative residual of the velocity solve", "-"},
                                        v.velocity_tolerance, Range::open(0.0, 0.1));
    v.max_iterations =
        s->integer_or({"max_iterations", "iterations per linear solve", "-"}, v.max_iterations, 1, 1000000);
    v.reordering =
        s->choice_or({"reordering", "node reordering after advection", "-"}, v.reordering, {"lattice", "density"});
    if ((out.scene_type == "cavity" || out.scene_type == "skewed_cavity") && v.reordering == "density")
      s->fail("reordering",
              "the density-constraint PBD reordering opens a void at one lid corner and piles nodes up at the "
              "other within ~0.2 L/U, and the cavity diverges (docs/ldd.md)",
              "lattice",
              "free-surface scenes always use the volume-keeping PBD; a cavity returns its nodes to the lattice");
    v.interpolation =
        s->choice_or({"interpolation", "lattice reordering: how the velocity returns to the lattice", "-"},
                     v.interpolation, {"quadratic", "shepard", "gradient_corrected"});
    v.max_courant = s->number_or({"max_courant", "Courant number max|u|δt/Δ treated as divergence", "-"}, v.max_courant,
                                 Range::open_closed(0.0, 100.0));
    v.pbd_sweeps =
        s->integer_or({"pbd_sweeps", "free surface: volume-keeping PBD sweeps per step", "-"}, v.pbd_sweeps, 0, 100);
    v.moment_rcond = s->number_or(
        {"moment_rcond", "free surface: moment-matrix conditioning below which it is pseudo-inverted", "-"},
        v.moment_rcond, Range::open(0.0, 1.0));
    v.surface_moment_rcond = s->number_or(
        {"surface_moment_rcond", "free surface: moment-matrix conditioning below which a node is surface", "-"},
        v.surface_moment_rcond, Range::open(0.0, 1.0));
    v.gradient = s->choice_or(
        {"gradient",
         "gradient operator (centred: about the neighbours' centroid; renormalised: LDD eq. 14; surface_anchored: "
         "centred, eq. 14 on free-surface nodes)",
         "-"},
        v.gradient, {"auto", "centred", "renormalised", "surface_anchored"});
    if ((out.scene_type == "cavity" || out.scene_type == "skewed_cavity") &&
        (v.gradient == "centred" || v.gradient == "surface_anchored"))
      s->fail("gradient",
              "a cavity's wall rows impose n·∇p through the wall node's own gradient, which the centred gradient "
              "leaves out",
              "auto or renormalised");
    v.pbd_velocity = s->choice_or(
        {"pbd_velocity", "free surface: velocity after a PBD shift δx (taylor: u + ⟨∇u⟩·δx; none: unchanged)", "-"},
        v.pbd_velocity, {"taylor", "none"});
    v.dry_walls = s->choice_or(
        {"dry_walls", "free surface: wall nodes above the surface (no interior fluid within h) in fluid gradients", "-"},
        v.dry_walls, {"include", "exclude"});
    v.pressure_preconditioner = s->choice_or({"pressure_preconditioner", "preconditioner of the pressure solve", "-"},
                                             v.pressure_preconditioner, {"auto", "jacobi", "lu", "amg"});
    v.velocity_preconditioner = s->choice_or({"velocity_preconditioner", "preconditioner of the velocity solve", "-"},
                                             v.velocity_preconditioner, {"auto", "jacobi", "lu", "amg"});
    v.pressure_amg =
        s->choice_or({"pressure_amg", "aggregation of the pressure solve's AMG (free-surface scenes)", "-"},
                     v.pressure_amg, {"smoothed", "plain"});
    const bool cavity = out.scene_type == "cavity" || out.scene_type == "skewed_cavity";
    // Keys only the free-surface solver reads: refused for a cavity rather than ignored.
    for (const char* key : {"pressure_amg", "pbd_sweeps", "pbd_velocity", "dry_walls", "moment_rcond", "surface_moment_rcond"})
      if (cavity && s->has(key))
        s->fail(key,
                fmt::format("a {} scene does not read it (free-surface scenes only: dam_break, slump, column)",
                            out.scene_type),
                "leave it out", "docs/ldd.md, Case keys");
    if (cavity && v.velocity_preconditioner == "lu")
      s->fail("velocity_preconditioner", "a cavity's velocity solve has no sparse-LU preconditioner",
              "auto, jacobi or amg");
  }
  if (const auto o = root.optional_section({"output", "LDD output settings", "-"})) {
    out.output.frame_interval = o->number_or({"frame_interval", "time between VTK frames (0: end/20)", "s"},
                                             out.output.frame_interval, Range::closed(0.0, 1e30));
    out.output.probe_interval = o->number_or({"probe_interval", "time between centre-line samples (0: end/200)", "s"},
                                             out.output.probe_interval, Range::closed(0.0, 1e30));
  }
  return out;
}

}  // namespace

std::string Case::kind() const {
  switch (spec.index()) {
    case 0:
      return "rheometer";
    case 1:
      return "sweep";
    default:
      return "ldd";
  }
}

Case parse_case(std::string_view text, const std::string& name) {
  const Document doc = Document::from_string(text, name);
  const Section root = doc.root();
  Case out;
  out.file = name;
  out.text = doc.text();
  out.sha256 = sha256_hex(out.text);
  out.name = root.text_or({"name", "case name", "-"}, std::filesystem::path(name).stem().string());
  out.description = root.text_or({"description", "free-text description", "-"}, "");
  const std::string kind = root.choice({"kind", "case kind", "-"}, {"rheometer", "sweep", "ldd"});
  if (kind == "rheometer")
    out.spec = read_rheometer(root, false);
  else if (kind == "sweep")
    out.spec = read_sweep(root);
  else
    out.spec = read_ldd(root, std::filesystem::path(name).parent_path());
  doc.check_all_keys_known();
  return out;
}

Case load_case(const std::string& path) {
  const Document doc = Document::from_file(path);
  return parse_case(doc.text(), path);
}

}  // namespace rheosim::core
