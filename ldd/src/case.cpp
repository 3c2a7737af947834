#include "rheosim/ldd/case.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <utility>

#include "rheosim/core/config.hpp"
#include "rheosim/core/units.hpp"

namespace rheosim::ldd {

using core::KeyInfo;
using core::Range;
using core::Section;
namespace units = core::units;

namespace {

// The case file's word for each value of a choice: the one table the reader, describe() and
// the name lookups share.
template <class Value>
struct Named {
  std::string_view name;
  Value value;
};
constexpr std::array<Named<Preconditioner>, 3> preconditioner_names{
    {{"jacobi", Preconditioner::jacobi}, {"lu", Preconditioner::sparse_lu}, {"amg", Preconditioner::amg}}};
constexpr std::array<Named<LatticeInterpolation>, 3> interpolation_names{
    {{"quadratic", LatticeInterpolation::quadratic},
     {"shepard", LatticeInterpolation::shepard},
     {"gradient_corrected", LatticeInterpolation::gradient_corrected}}};
constexpr std::array<Named<GradientChoice>, 4> gradient_names{{{"auto", GradientChoice::automatic},
                                                               {"centred", GradientChoice::centred},
                                                               {"renormalised", GradientChoice::renormalised},
                                                               {"surface_anchored", GradientChoice::surface_anchored}}};
constexpr std::array<Named<DryWalls>, 3> dry_walls_names{
    {{"include", DryWalls::include}, {"exclude", DryWalls::exclude}, {"extrapolate", DryWalls::extrapolate}}};
constexpr std::array<Named<AmgAggregation>, 3> aggregation_names{
    {{"smoothed", AmgAggregation::smoothed}, {"plain", AmgAggregation::plain}, {"auto", AmgAggregation::automatic}}};

template <class Value, std::size_t N>
std::optional<Value> value_named(const std::array<Named<Value>, N>& table, std::string_view name) {
  for (const auto& entry : table)
    if (entry.name == name) return entry.value;
  return std::nullopt;
}
template <class Value, std::size_t N>
std::string_view name_in(const std::array<Named<Value>, N>& table, Value value) {
  for (const auto& entry : table)
    if (entry.value == value) return entry.name;
  return "?";
}
template <class Value, std::size_t N>
std::vector<std::string> names_in(const std::array<Named<Value>, N>& table) {
  std::vector<std::string> out;
  for (const auto& entry : table) out.emplace_back(entry.name);
  return out;
}
// An optional key naming one of the table's values; the error lists them and suggests the nearest.
template <class Value, std::size_t N>
Value choice_or(const Section& s, const KeyInfo& key, Value fallback, const std::array<Named<Value>, N>& table) {
  return *value_named(table, s.choice_or(key, std::string(name_in(table, fallback)), names_in(table)));
}

constexpr double ldd_bytes_per_node = 8192.0;
constexpr double ldd_seconds_per_node_step = 2e-6;
// time.step: auto keeps max|u|δt/Δ at this for the scene's velocity scale (automatic_ldd_time_step).
constexpr double ldd_auto_courant = 0.25;
struct LddSizeEstimate {
  double nodes = 0, bytes = 0, steps = 0, node_steps = 0;
};
LddSizeEstimate estimate_ldd_size(const CaseSettings& l) {
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
std::pair<double, std::string> automatic_ldd_time_step(const CaseSettings& l) {
  const double g = l.gravity_magnitude();
  double speed = 0;
  std::string scale;
  const auto collapse = [&](double height) {
    speed = 2.0 * std::sqrt(g * height);
    scale =
        fmt::format("U = 2√(|g|H) = {:.3g} m/s, the front speed of a collapse of height H = {:.3g} m", speed, height);
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

std::array<double, 2> read_pair(const Section& s, const KeyInfo& key) {
  const auto v = s.numbers(key, Range::positive(), 2, 2);
  return {v[0], v[1]};
}

WallSettings read_wall(const Section& w, int dimension, const std::filesystem::path& case_dir) {
  WallSettings out;
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

// solver: — keys only the free-surface solver reads are refused for a cavity rather than ignored.
SolverSettings read_solver_settings(const Section& s, std::string_view scene_type) {
  SolverSettings v;
  const bool cavity = is_cavity(scene_type);
  v.threads = s.integer_or({"threads", "OpenMP threads (0: OMP_NUM_THREADS or all cores)", "-"}, v.threads, 0, 1024);
  v.pressure_tolerance = s.number_or({"pressure_tolerance", "relative residual of the pressure solve", "-"},
                                     v.pressure_tolerance, Range::open(0.0, 0.1));
  v.velocity_tolerance = s.number_or({"velocity_tolerance", "relative residual of the velocity solve", "-"},
                                     v.velocity_tolerance, Range::open(0.0, 0.1));
  v.max_iterations = s.integer_or({"max_iterations", "iterations per linear solve", "-"}, v.max_iterations, 1, 1000000);
  v.interpolation = choice_or(s, {"interpolation", "lattice reordering: how the velocity returns to the lattice", "-"},
                              v.interpolation, interpolation_names);
  v.max_courant = s.number_or({"max_courant", "Courant number max|u|δt/Δ treated as divergence", "-"}, v.max_courant,
                              Range::open_closed(0.0, 100.0));
  v.pbd_sweeps =
      s.integer_or({"pbd_sweeps", "free surface: volume-keeping PBD sweeps per step", "-"}, v.pbd_sweeps, 0, 100);
  v.moment_rcond =
      s.number_or({"moment_rcond", "free surface: moment-matrix conditioning below which it is pseudo-inverted", "-"},
                  v.moment_rcond, Range::open(0.0, 1.0));
  v.surface_moment_rcond = s.number_or(
      {"surface_moment_rcond", "free surface: moment-matrix conditioning below which a node is surface", "-"},
      v.surface_moment_rcond, Range::open(0.0, 1.0));
  v.gradient = choice_or(s,
                         {"gradient",
                          "gradient operator (centred: about the neighbours' centroid; renormalised: LDD eq. 14; "
                          "surface_anchored: centred, eq. 14 on free-surface nodes)",
                          "-"},
                         v.gradient, gradient_names);
  if (cavity && (v.gradient == GradientChoice::centred || v.gradient == GradientChoice::surface_anchored))
    s.fail("gradient",
           "a cavity's wall rows impose n·∇p through the wall node's own gradient, which the centred gradient "
           "leaves out",
           "auto or renormalised");
  // A key with two named values, the first the default: whether the case chose the second.
  const auto second_of_two = [&](const KeyInfo& key, const char* first, const char* second) {
    return s.choice_or(key, first, {first, second}) == second;
  };
  v.pbd_velocity_correction = !second_of_two(
      {"pbd_velocity", "free surface: velocity after a PBD shift δx (taylor: u + ⟨∇u⟩·δx; none: unchanged)", "-"},
      "taylor", "none");
  v.pbd_surface_tangential = second_of_two(
      {"pbd_surface", "free surface: PBD shift of surface nodes (full; tangential: its outward-normal part removed)",
       "-"},
      "full", "tangential");
  v.surface_umbrella = second_of_two({"surface_detection",
                                      "free surface: classification (local: the node's own neighbours; umbrella: a "
                                      "node flagged only by an empty cone or its centroid offset must also see an "
                                      "open void Δ beyond it)",
                                      "-"},
                                     "local", "umbrella");
  v.dry_walls = choice_or(s,
                          {"dry_walls",
                           "free surface: pressure of the wall nodes above the surface (no interior fluid within h) "
                           "and whether fluid gradients use it",
                           "-"},
                          v.dry_walls, dry_walls_names);
  v.full_viscous_stress = second_of_two(
      {"viscous_stress", "free surface: viscous force (laplacian: ∇·(μ∇u); full: ∇·(2μE))", "-"}, "laplacian", "full");
  v.surface_normal_stress = second_of_two({"surface_stress",
                                           "free surface: pressure of surface nodes (none: p = 0; normal: p = 2μ "
                                           "n·E·n, the viscous normal stress)",
                                           "-"},
                                          "none", "normal");
  v.wall_face_shear_rate = second_of_two({"wall_viscosity",
                                          "free surface: viscosity between a fluid and a wall node (mean: the mean of "
                                          "the two; face_shear_rate: the law at the mean of their shear rates)",
                                          "-"},
                                         "mean", "face_shear_rate");
  const auto preconditioner = [&](const KeyInfo& key) -> std::optional<Preconditioner> {
    std::vector<std::string> names = names_in(preconditioner_names);
    names.insert(names.begin(), "auto");
    return value_named(preconditioner_names, s.choice_or(key, "auto", names));
  };
  v.pressure_preconditioner =
      preconditioner({"pressure_preconditioner", "preconditioner of the pressure solve (auto: the scene's)", "-"});
  v.velocity_preconditioner =
      preconditioner({"velocity_preconditioner", "preconditioner of the velocity solve (auto: the scene's)", "-"});
  v.pressure_amg = choice_or(s, {"pressure_amg", "aggregation of the pressure solve's AMG (free-surface scenes)", "-"},
                             v.pressure_amg, aggregation_names);
  for (const char* key : {"pressure_amg", "pbd_sweeps", "pbd_velocity", "pbd_surface", "surface_detection", "dry_walls",
                          "moment_rcond", "surface_moment_rcond", "viscous_stress", "surface_stress", "wall_viscosity"})
    if (cavity && s.has(key))
      s.fail(
          key,
          fmt::format("a {} scene does not read it (free-surface scenes only: dam_break, slump, column)", scene_type),
          "leave it out", "docs/ldd.md, Case keys");
  if (cavity && v.velocity_preconditioner == Preconditioner::sparse_lu)
    s.fail("velocity_preconditioner", "a cavity's velocity solve has no sparse-LU preconditioner",
           "auto, jacobi or amg");
  return v;
}

OutputSettings read_output_settings(const Section& o) {
  OutputSettings out;
  out.frame_interval = o.number_or({"frame_interval", "time between VTK frames (0: end/20)", "s"}, out.frame_interval,
                                   Range::closed(0.0, 1e30));
  out.probe_interval = o.number_or({"probe_interval", "time between centre-line samples (0: end/200)", "s"},
                                   out.probe_interval, Range::closed(0.0, 1e30));
  return out;
}

CaseSettings read_settings(const Section& root, const std::filesystem::path& case_dir) {
  CaseSettings out;
  out.dimension = root.integer({"dimension", "spatial dimension", "-"}, 2, 3);
  const Section scene = root.section({"scene", "the LDD scene", "-"});
  out.scene_type =
      scene.choice({"type", "scene type", "-"}, {"cavity", "skewed_cavity", "dam_break", "slump", "column"});
  const auto require_dimension = [&](int wanted) {
    if (out.dimension != wanted)
      root.fail("dimension", fmt::format("a {} scene is {}D, not {}D", out.scene_type, wanted, out.dimension),
                fmt::format("dimension: {}", wanted));
  };
  if (is_cavity(out.scene_type)) {
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
    if (s.cone_top_diameter > s.cone_bottom_diameter)  // equal: a cylinder (Pashias et al. 1996)
      cone.fail("top_diameter", "the top diameter is larger than the bottom diameter",
                fmt::format("a top diameter <= {} m", s.cone_bottom_diameter));
    s.lift_velocity = scene.number({"lift_velocity", "mould lift speed", "m/s"}, Range::positive());
    out.scene = s;
    if (scene.has("walls"))
      for (const Section& w : scene.sections({"walls", "extra solid walls (plane, box, cylinder, stl)", "-"}))
        out.walls.push_back(read_wall(w, out.dimension, case_dir));
  } else {
    require_dimension(2);  // the column scene builds a 2D box
    ColumnScene c;
    c.size = read_pair(scene, {"size", "column width and height", "m"});
    c.wave_amplitude =
        scene.number_or({"wave_amplitude", "initial surface H + A cos(πx/W), the first sloshing mode (0: flat)", "m"},
                        c.wave_amplitude, Range::closed(0.0, 0.5 * c.size[1]));
    out.scene = c;
  }
  out.fluid = core::read_fluid(root);
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
  out.settle_energy_ratio = time.number_or(
      {"settle_energy_ratio",
       "slump: stop when the kinetic energy falls below this share of its peak after the mould has cleared; 0: never",
       "-"},
      out.settle_energy_ratio, Range::closed(0.0, 1.0));
  out.arrest_stress_tolerance = time.number_or(
      {"arrest_stress_tolerance",
       "dam break, slump of a yield-stress law: the end state is arrested when no node's stress exceeds (1 + this) "
       "times the yield stress",
       "-"},
      out.arrest_stress_tolerance, Range::closed(0.0, 1.0));
  out.arrest_hold_time = time.number_or(
      {"stop_at_arrest",
       "dam break, slump of a yield-stress law: stop once the end state's yield test has held over this long, after "
       "the material has yielded; 0: never",
       "s"},
      out.arrest_hold_time, Range::non_negative());
  if (out.arrest_hold_time > 0) {
    const bool arrest_scene = out.scene_type == "dam_break" || out.scene_type == "slump";
    if (!arrest_scene || !(out.fluid.rheology->yield_stress() > 0))
      time.fail("stop_at_arrest",
                fmt::format("a {} scene of a {} law never arrests", out.scene_type, out.fluid.rheology->name()),
                "0 (never) unless the scene is a dam_break or slump of a law with a yield stress");
  }
  if (const auto s = root.optional_section({"solver", "LDD solver settings", "-"}))
    out.solver = read_solver_settings(*s, out.scene_type);
  if (const auto o = root.optional_section({"output", "LDD output settings", "-"}))
    out.output = read_output_settings(*o);
  return out;
}

}  // namespace

bool is_cavity(std::string_view scene_type) { return scene_type == "cavity" || scene_type == "skewed_cavity"; }

double CaseSettings::gravity_magnitude() const {
  double sum = 0;
  for (double c : gravity) sum += c * c;
  return std::sqrt(sum);
}

Case read_case(const core::CaseFile& file) {
  file.require_kind({"ldd"}, "the LDD solver");
  Case out;
  static_cast<core::CaseHeader&>(out) = file.header();
  out.settings = read_settings(file.root(), file.directory());
  file.check_all_keys_known();
  return out;
}

Case parse_case(std::string_view text, const std::string& name) {
  return ldd::read_case(core::CaseFile::parse(text, name));
}

Case load_case(const std::string& path) { return ldd::read_case(core::CaseFile::open(path)); }

std::optional<Preconditioner> preconditioner_named(std::string_view name) {
  return value_named(preconditioner_names, name);
}
std::optional<LatticeInterpolation> lattice_interpolation_named(std::string_view name) {
  return value_named(interpolation_names, name);
}
std::string_view name_of(Preconditioner p) { return name_in(preconditioner_names, p); }
std::string_view name_of(LatticeInterpolation i) { return name_in(interpolation_names, i); }
std::string_view name_of(GradientChoice g) { return name_in(gradient_names, g); }

}  // namespace rheosim::ldd
