#include "rheosim/dem/particles.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace rheosim::dem {

namespace {

using core::KeyInfo;
using core::Range;
using core::Section;

// particles.size_distribution (see SizeDistribution); d is particles.diameter.
SizeDistribution read_size_distribution(const Section& s, double d, double gap) {
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
    core::require_increasing(s, "diameters", diameters);
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
  if (out.max_diameter >= gap)
    s.fail(bounds_key, fmt::format("the largest particles ({} m) do not fit in the gap of {} m", out.max_diameter, gap),
           "every diameter smaller than the gap");
  return out;
}

}  // namespace

ParticleProperties read_particles(const Section& p, double gap, bool with_volume_fraction) {
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
  if (out.diameter >= gap)
    p.fail("diameter", fmt::format("particles of {} m do not fit in the gap of {} m", out.diameter, gap),
           "a particle diameter smaller than the gap (H/d >= 10 for a continuum stress)");
  const KeyInfo distribution_key{"size_distribution", "spread of particle diameters (omit for equal spheres)", "-"};
  if (auto s = p.optional_section(distribution_key))
    out.size_distribution = read_size_distribution(*s, out.diameter, gap);
  return out;
}

}  // namespace rheosim::dem
