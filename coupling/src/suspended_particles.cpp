#include "rheosim/coupling/suspended_particles.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <string>
#include <vector>

namespace rheosim::coupling {

namespace {

using core::KeyInfo;
using core::Range;
using core::Section;

// particles.hydrodynamics: model `none` or terms joined by '+'.
NearFieldSettings read_hydrodynamics(const Section& s) {
  NearFieldSettings out;
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
    if (term == "lubrication") out.terms.lubrication = true;
    if (term == "stresslet" || term == "single_particle") out.terms.single_particle = true;
    if (term == "stokes_drag") out.terms.stokes_drag = true;
    if (term == "repulsion") out.terms.repulsion = true;
    start = end + 1;
  }
  if (out.terms.repulsion && !out.terms.lubrication)
    s.fail("model", fmt::format("'{}' has repulsion without lubrication", model), "repulsion together with lubrication",
           "the repulsion acts on the lubrication gap list, e.g. 'model: lubrication+stresslet+repulsion'");
  out.roughness = s.number_or({"roughness", "roughness length δ/ā regularising the lubrication gap", "-"},
                              out.roughness, Range::closed(1e-6, 0.1));
  out.lubrication_cutoff = s.number_or({"lubrication_cutoff", "gap h_c/ā below which lubrication acts", "-"},
                                       out.lubrication_cutoff, Range::open_closed(out.roughness, 1.0));
  if (out.terms.repulsion) {
    out.repulsion_force =
        s.number({"repulsion_force", "repulsion F_R0 at contact (stress scale F_R0/(6πa²))", "N"}, Range::positive());
    out.repulsion_length = s.number_or({"repulsion_length", "repulsion decay length λ/ā", "-"}, out.repulsion_length,
                                       Range::closed(1e-3, out.lubrication_cutoff / 5.0));
  }
  if (out.terms.single_particle) {
    const std::string stresslet_viscosity =
        s.choice_or({"stresslet_viscosity", "matrix viscosity in the stresslet", "-"}, name_of(out.stresslet_viscosity),
                    {name_of(StressletViscosity::homogenized), name_of(StressletViscosity::secant)});
    if (stresslet_viscosity == name_of(StressletViscosity::secant))
      out.stresslet_viscosity = StressletViscosity::secant;
  }
  return out;
}

}  // namespace

SuspendedParticles read_suspended_particles(const Section& p, double gap, bool with_volume_fraction) {
  SuspendedParticles out;
  static_cast<dem::ParticleProperties&>(out) = dem::read_particles(p, gap, with_volume_fraction);
  const KeyInfo hydrodynamics_key{"hydrodynamics", "near-field hydrodynamics (omit for drag only)", "-"};
  if (auto s = p.optional_section(hydrodynamics_key)) {
    out.hydrodynamics = read_hydrodynamics(*s);
    out.hydrodynamics_given = true;
  }
  const KeyInfo drag_key{"drag", "fluid–particle drag law (omit for auto)", "-"};
  std::string drag = "auto";
  if (auto s = p.optional_section(drag_key))
    drag = s->choice({"model", "drag law", "-"},
                     {"auto", name_of(DragLaw::di_felice), name_of(DragLaw::schiller_naumann)});
  out.drag_automatic = drag == "auto";
  if (drag == name_of(DragLaw::schiller_naumann) || (out.drag_automatic && out.hydrodynamics.terms.lubrication))
    out.drag = DragLaw::schiller_naumann;
  return out;
}

std::string describe(const SuspendedParticles& p, double gap) {
  std::string out = fmt::format(
      "  particles: diameter {} m, density {} kg/m³, E {} Pa, ν {}, restitution {}, friction {}, H/d {:.3g}\n",
      p.diameter, p.density, p.youngs_modulus, p.poisson_ratio, p.restitution, p.friction, gap / p.diameter);
  using Type = dem::SizeDistribution::Type;
  if (const auto& s = p.size_distribution; s.type == Type::uniform)
    out += fmt::format("  size distribution: uniform in [{}, {}] m\n", s.min_diameter, s.max_diameter);
  else if (s.type == Type::lognormal)
    out += fmt::format("  size distribution: lognormal by volume, d50 {} m, σ_g {}, truncated to [{}, {}] m\n",
                       p.diameter, s.geometric_std, s.min_diameter, s.max_diameter);
  else if (s.type == Type::discrete)
    out += fmt::format("  size distribution: {} classes, diameters [{}] m, volume shares [{}]\n", s.classes,
                       fmt::join(s.diameters.begin(), s.diameters.begin() + s.classes, ", "),
                       fmt::join(s.volume_fractions.begin(), s.volume_fractions.begin() + s.classes, ", "));
  if (const auto& h = p.hydrodynamics; h.terms.any())
    out += fmt::format("  near-field hydrodynamics:{}{}{}{}, roughness δ/ā {}, lubrication cutoff h/ā {}{}{}\n",
                       h.terms.lubrication ? " lubrication" : "", h.terms.single_particle ? " stresslet" : "",
                       h.terms.stokes_drag ? " stokes_drag" : "", h.terms.repulsion ? " repulsion" : "", h.roughness,
                       h.lubrication_cutoff,
                       h.terms.repulsion
                           ? fmt::format(", repulsion F_R0 {} N, λ/ā {}", h.repulsion_force, h.repulsion_length)
                           : std::string{},
                       h.terms.single_particle ? fmt::format(", stresslet viscosity {}", name_of(h.stresslet_viscosity))
                                               : std::string{});
  out += fmt::format("  drag: {}{}\n", name_of(p.drag),
                     !p.drag_automatic              ? ""
                     : p.drag == DragLaw::di_felice ? " (auto: no lubrication, so the seed's law)"
                                                    : " (auto: lubrication carries the crowding, so the isolated "
                                                      "sphere's drag)");
  return out;
}

}  // namespace rheosim::coupling
