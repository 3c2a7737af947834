#include <fmt/format.h>

#include "rheosim/core/case.hpp"

namespace rheosim::core {

namespace {

std::string list(const std::vector<double>& values) {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : ", ") + fmt::format("{}", v);
  return "[" + out + "]";
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

}  // namespace

std::string describe_fluid(const FluidProperties& fluid) {
  std::string out = fmt::format("  fluid: density {} kg/m³, rheology {}", fluid.density, fluid.rheology->name());
  for (const auto& p : fluid.rheology->parameters()) out += fmt::format(", {} {} {}", p.name, p.value, p.unit);
  return out + "\n";
}

std::string describe(const Case& c) {
  std::string out = fmt::format("  name: {}\n  input sha256: {}\n", c.name, c.sha256);
  if (const auto* r = std::get_if<RheometerCase>(&c.spec)) {
    out += describe_rheometer(*r);
    if (r->particles) out += fmt::format("  volume fraction: {}\n", r->particles->volume_fraction);
  } else {
    const auto& s = std::get<SweepCase>(c.spec);
    out += describe_rheometer(s.rheometer);
    out += fmt::format("  volume fractions: {} ({} points)\n", list(s.volume_fractions),
                       s.volume_fractions.size() * s.rheometer.shear_rates.size());
  }
  return out;
}

}  // namespace rheosim::core
