#include <fmt/format.h>

#include "rheosim/core/units.hpp"
#include "rheosim/ldd/case.hpp"

namespace rheosim::ldd {

namespace units = core::units;

namespace {

std::string list(const std::vector<double>& values) {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : ", ") + fmt::format("{}", v);
  return "[" + out + "]";
}

struct SceneDescriber {
  std::string operator()(const CavityScene& c) const {
    std::string out = fmt::format("  cavity {} × {} m, lid velocity {} m/s", c.size[0], c.size[1], c.lid_velocity);
    if (c.skew_angle != 0) out += fmt::format(", skew angle {}°", units::degrees_from_radians(c.skew_angle));
    return out + "\n";
  }
  std::string operator()(const DamBreakScene& d) const {
    return fmt::format("  dam break: reservoir {} × {} m, channel {} m\n", d.reservoir[0], d.reservoir[1],
                       d.channel_length);
  }
  std::string operator()(const SlumpScene& s) const {
    return fmt::format("  slump cone: height {} m, bottom diameter {} m, top diameter {} m, lift {} m/s\n",
                       s.cone_height, s.cone_bottom_diameter, s.cone_top_diameter, s.lift_velocity);
  }
  std::string operator()(const ColumnScene& c) const {
    return fmt::format("  resting column {} × {} m\n", c.size[0], c.size[1]);
  }
};

std::string describe_wall(const WallSettings& w) {
  const char* side = w.fluid_inside ? "fluid inside" : "fluid outside";
  if (w.type == "plane") return fmt::format("  wall: plane through {} m, normal {}\n", list(w.point), list(w.normal));
  if (w.type == "box") return fmt::format("  wall: box {} … {} m, {}\n", list(w.lower), list(w.upper), side);
  if (w.type == "cylinder")
    return fmt::format("  wall: cylinder base {} m, axis {}, radius {} m, height {} m, {}\n", list(w.base),
                       list(w.axis), w.radius, w.height, side);
  return fmt::format("  wall: {} {} (scale {} m per unit), {}\n", w.type, w.file, w.scale, side);
}

std::string describe_solver(const SolverSettings& s, bool cavity) {
  const auto preconditioner = [](const std::optional<Preconditioner>& p) {
    return p ? std::string(name_of(*p)) : std::string("auto");
  };
  std::string out =
      fmt::format("  solver: {}PPE tolerance {}, velocity tolerance {}, threads {}\n",
                  cavity ? std::string("lattice reordering, ") : std::string(), s.pressure_tolerance,
                  s.velocity_tolerance, s.threads == 0 ? std::string("default") : std::to_string(s.threads));
  out += fmt::format("  preconditioners: PPE {}, velocity {} (auto: the scene's default, docs/ldd.md)\n",
                     preconditioner(s.pressure_preconditioner), preconditioner(s.velocity_preconditioner));
  if (cavity) out += fmt::format("  lattice interpolation: {}\n", name_of(s.interpolation));
  if (!cavity)
    out += fmt::format(
        "  free surface: {} PBD sweeps per step (velocity: {}, surface nodes: {}), moment-matrix rcond {} "
        "(pseudo-inverse), {} "
        "(surface), surface detection {}, dry walls {}, {} gradient, viscous force {}, surface pressure {}\n",
        s.pbd_sweeps, s.pbd_velocity_correction ? "taylor" : "none",
        s.pbd_surface_tangential ? "tangential shift" : "full shift", s.moment_rcond, s.surface_moment_rcond,
        s.surface_umbrella ? "umbrella" : "local",
        s.dry_walls == DryWalls::exclude       ? "at p = 0, excluded from gradients"
        : s.dry_walls == DryWalls::extrapolate ? "at the fluid's extrapolated pressure (walls unclipped)"
                                               : "at p = 0, in gradients",
        s.gradient == GradientChoice::renormalised       ? "renormalised (eq. 14)"
        : s.gradient == GradientChoice::surface_anchored ? "centred, eq. 14 on free-surface nodes,"
                                                         : "centred",
        s.full_viscous_stress ? "∇·(2μE)" : "∇·(μ∇u)", s.surface_normal_stress ? "2μ n·E·n" : "0");
  if (!cavity && s.pressure_amg != AmgAggregation::smoothed)
    out += s.pressure_amg == AmgAggregation::plain
               ? "  PPE AMG: plain aggregation\n"
               : fmt::format(
                     "  PPE AMG: smoothed aggregation until a fresh hierarchy needs more than {} iterations, "
                     "then plain\n",
                     auto_aggregation_switch_iterations);
  if (!cavity && s.wall_face_shear_rate)
    out += "  wall viscosity: the law at the mean shear rate of each fluid node and wall node it couples to\n";
  return out;
}

}  // namespace

std::string describe(const Case& c) {
  const CaseSettings& l = c.settings;
  std::string out = fmt::format("  name: {}\n  input sha256: {}\n", c.name, c.sha256);
  out += fmt::format("  LDD {}D {} scene\n", l.dimension, l.scene_type);
  out += std::visit(SceneDescriber{}, l.scene);
  for (const WallSettings& w : l.walls) out += describe_wall(w);
  out += core::describe_fluid(l.fluid);
  out += fmt::format("  gravity: {} m/s²\n  spacing Δ {} m, h/Δ {}\n  time step {} s, end {} s ({} steps)\n",
                     list(l.gravity), l.spacing, l.smoothing_ratio, l.time_step, l.end_time,
                     static_cast<long long>(l.end_time / l.time_step + 0.5));
  if (!l.time_step_rule.empty()) out += fmt::format("  time step {}\n", l.time_step_rule);
  if (l.steady_tolerance > 0) out += fmt::format("  stops at steady state (residual < {})\n", l.steady_tolerance);
  return out + describe_solver(l.solver, std::holds_alternative<CavityScene>(l.scene));
}

}  // namespace rheosim::ldd
