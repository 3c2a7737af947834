#include <fmt/format.h>

#include "rheosim/core/case.hpp"
#include "rheosim/core/units.hpp"

namespace rheosim::core {

namespace {

std::string list(const std::vector<double>& values) {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : ", ") + fmt::format("{}", v);
  return "[" + out + "]";
}

std::string describe_fluid(const FluidProperties& fluid) {
  std::string out = fmt::format("  fluid: density {} kg/m³, rheology {}", fluid.density, fluid.rheology->name());
  for (const auto& p : fluid.rheology->parameters()) out += fmt::format(", {} {} {}", p.name, p.value, p.unit);
  return out + "\n";
}

std::string describe_rheometer(const RheometerCase& r) {
  std::string out =
      fmt::format("  geometry: parallel plates, radius {} m, gap {} m\n", r.geometry.radius, r.geometry.gap);
  for (const auto& f : r.fluids) {
    if (r.fluids.size() > 1) out += fmt::format("  [{}]\n", f.name);
    out += describe_fluid(f.properties);
  }
  out += fmt::format(
      "  solver: {} × {} cells (r × z), radial grading {}, axial stretching {}, inertia {}{}\n", r.solver.radial_cells,
      r.solver.axial_cells, r.solver.radial_grading, r.solver.axial_stretching, r.solver.inertia ? "on" : "off",
      r.solver.inertia && r.solver.extrapolate ? " (Richardson torque over this grid and half its cells)" : "");
  out += fmt::format("  rim shear rates: {} 1/s\n", list(r.shear_rates));
  if (r.particles) {
    using M = RheometerCase::SuspensionModel;
    out += fmt::format("  suspension model: {}\n", r.suspension_model == M::full_disk      ? "full_disk"
                                                   : r.suspension_model == M::shear_cell   ? "shear_cell"
                                                   : r.suspension_model == M::lees_edwards ? "lees_edwards"
                                                   : r.suspension_model == M::walled_box   ? "walled_box"
                                                                                           : "auto");
  }
  if (const auto& p = r.particles) {
    out += fmt::format(
        "  particles: diameter {} m, density {} kg/m³, E {} Pa, ν {}, restitution {}, friction {}, H/d {:.3g}\n",
        p->diameter, p->density, p->youngs_modulus, p->poisson_ratio, p->restitution, p->friction,
        r.geometry.gap / p->diameter);
    if (const auto* s = &p->size_distribution; s->type != SizeDistribution::Type::none) {
      using Type = SizeDistribution::Type;
      if (s->type == Type::uniform)
        out += fmt::format("  size distribution: uniform in [{}, {}] m\n", s->min_diameter, s->max_diameter);
      else if (s->type == Type::lognormal)
        out += fmt::format("  size distribution: lognormal by volume, d50 {} m, σ_g {}, truncated to [{}, {}] m\n",
                           p->diameter, s->geometric_std, s->min_diameter, s->max_diameter);
      else
        out += fmt::format("  size distribution: {} classes, diameters {} m, volume shares {}\n", s->classes,
                           list({s->diameters.begin(), s->diameters.begin() + s->classes}),
                           list({s->volume_fractions.begin(), s->volume_fractions.begin() + s->classes}));
    }
    if (const auto& h = p->hydrodynamics; h.any())
      out += fmt::format(
          "  near-field hydrodynamics:{}{}{}{}, roughness δ/ā {}, lubrication cutoff h/ā {}{}{}\n",
          h.lubrication ? " lubrication" : "", h.single_particle ? " stresslet" : "",
          h.stokes_drag ? " stokes_drag" : "", h.repulsion ? " repulsion" : "", h.roughness, h.lubrication_cutoff,
          h.repulsion ? fmt::format(", repulsion F_R0 {} N, λ/ā {}", h.repulsion_force, h.repulsion_length)
                      : std::string{},
          h.single_particle ? fmt::format(", stresslet viscosity {}", name_of(h.stresslet_viscosity)) : std::string{});
    out += fmt::format("  drag: {}{}\n", name_of(p->drag),
                       !p->drag_automatic              ? ""
                       : p->drag == DragLaw::di_felice ? " (auto: no lubrication, so the seed's law)"
                                                       : " (auto: lubrication carries the crowding, so the isolated "
                                                         "sphere's drag)");
  } else {
    out += "  particles: none (single phase)\n";
  }
  return out;
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

std::string describe_wall(const LddWall& w) {
  const char* side = w.fluid_inside ? "fluid inside" : "fluid outside";
  if (w.type == "plane") return fmt::format("  wall: plane through {} m, normal {}\n", list(w.point), list(w.normal));
  if (w.type == "box") return fmt::format("  wall: box {} … {} m, {}\n", list(w.lower), list(w.upper), side);
  if (w.type == "cylinder")
    return fmt::format("  wall: cylinder base {} m, axis {}, radius {} m, height {} m, {}\n", list(w.base),
                       list(w.axis), w.radius, w.height, side);
  return fmt::format("  wall: {} {} (scale {} m per unit), {}\n", w.type, w.file, w.scale, side);
}

}  // namespace

std::string describe(const Case& c) {
  std::string out = fmt::format("  name: {}\n  input sha256: {}\n", c.name, c.sha256);
  if (const auto* r = std::get_if<RheometerCase>(&c.spec)) {
    out += describe_rheometer(*r);
    if (r->particles) out += fmt::format("  volume fraction: {}\n", r->particles->volume_fraction);
  } else if (const auto* s = std::get_if<SweepCase>(&c.spec)) {
    out += describe_rheometer(s->rheometer);
    out += fmt::format("  volume fractions: {} ({} points)\n", list(s->volume_fractions),
                       s->volume_fractions.size() * s->rheometer.shear_rates.size());
  } else {
    const auto& l = std::get<LddCase>(c.spec);
    out += fmt::format("  LDD {}D {} scene\n", l.dimension, l.scene_type);
    out += std::visit(SceneDescriber{}, l.scene);
    for (const LddWall& w : l.walls) out += describe_wall(w);
    out += describe_fluid(l.fluid);
    out += fmt::format("  gravity: {} m/s²\n  spacing Δ {} m, h/Δ {}\n  time step {} s, end {} s ({} steps)\n",
                       list(l.gravity), l.spacing, l.smoothing_ratio, l.time_step, l.end_time,
                       static_cast<long long>(l.end_time / l.time_step + 0.5));
    if (!l.time_step_rule.empty()) out += fmt::format("  time step {}\n", l.time_step_rule);
    if (l.steady_tolerance > 0) out += fmt::format("  stops at steady state (residual < {})\n", l.steady_tolerance);
    // Free-surface scenes reorder by PBD (the line below), whatever solver.reordering says.
    const bool cavity = std::holds_alternative<CavityScene>(l.scene);
    out += fmt::format("  solver: {}PPE tolerance {}, velocity tolerance {}, threads {}\n",
                       cavity ? l.solver.reordering + " reordering, " : std::string(), l.solver.pressure_tolerance,
                       l.solver.velocity_tolerance,
                       l.solver.threads == 0 ? std::string("default") : std::to_string(l.solver.threads));
    out += fmt::format("  preconditioners: PPE {}, velocity {} (auto: the scene's default, docs/ldd.md)\n",
                       l.solver.pressure_preconditioner, l.solver.velocity_preconditioner);
    if (cavity && l.solver.reordering == "lattice")
      out += fmt::format("  lattice interpolation: {}\n", l.solver.interpolation);
    if (!cavity)
      out += fmt::format(
          "  free surface: {} PBD sweeps per step (velocity: {}), moment-matrix rcond {} (pseudo-inverse), {} "
          "(surface), dry walls {}, {} gradient\n",
          l.solver.pbd_sweeps, l.solver.pbd_velocity, l.solver.moment_rcond, l.solver.surface_moment_rcond,
          l.solver.dry_walls == "exclude" ? "excluded from gradients" : "in gradients",
          l.solver.gradient == "renormalised"       ? "renormalised (eq. 14)"
          : l.solver.gradient == "surface_anchored" ? "centred, eq. 14 on free-surface nodes,"
                                                    : "centred");
  }
  return out;
}

}  // namespace rheosim::core
