// Particle diameters from a size distribution (see size_distribution.hpp).
#include "rheosim/dem/size_distribution.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "portable_random.hpp"
#include "rheosim/core/units.hpp"

namespace rheosim::dem {
namespace {

using Type = SizeDistribution::Type;

void check(const SizeDistribution& s, double median, double solid_volume) {
  if (!(std::isfinite(solid_volume) && solid_volume >= 0.0))
    throw std::invalid_argument(
        fmt::format("sample_diameters: solid_volume = {} is out of range, expected >= 0", solid_volume));
  if (s.type == Type::discrete) {
    if (s.classes < 1 || s.classes > SizeDistribution::max_classes)
      throw std::invalid_argument(
          fmt::format("size distribution: {} classes, expected 1 to {}", s.classes, SizeDistribution::max_classes));
    double sum = 0.0;
    for (std::size_t k = 0; k < static_cast<std::size_t>(s.classes); ++k) {
      if (!(s.diameters[k] > 0.0) || !(s.volume_fractions[k] >= 0.0))
        throw std::invalid_argument(fmt::format("size distribution: class {} has d = {} m, share {}", k, s.diameters[k],
                                                s.volume_fractions[k]));
      sum += s.volume_fractions[k];
    }
    if (std::abs(sum - 1.0) > 1e-6)
      throw std::invalid_argument(fmt::format("size distribution: volume fractions add up to {}, expected 1", sum));
    return;
  }
  if (s.type == Type::none) {
    if (!(median > 0.0))
      throw std::invalid_argument(fmt::format("sample_diameters: diameter = {} m, expected > 0", median));
    return;
  }
  if (!(s.min_diameter > 0.0 && s.min_diameter <= s.max_diameter && std::isfinite(s.max_diameter)))
    throw std::invalid_argument(
        fmt::format("size distribution: bounds [{}, {}] m, expected 0 < min <= max", s.min_diameter, s.max_diameter));
  if (s.type == Type::lognormal) {
    if (!(s.geometric_std >= 1.0 && std::isfinite(s.geometric_std)))
      throw std::invalid_argument(fmt::format("size distribution: geometric_std = {}, expected >= 1", s.geometric_std));
    if (!(median >= s.min_diameter && median <= s.max_diameter))
      throw std::invalid_argument(fmt::format("size distribution: median {} m outside the bounds [{}, {}] m", median,
                                              s.min_diameter, s.max_diameter));
  }
}

}  // namespace

std::vector<double> sample_diameters(const SizeDistribution& s, double median, double solid_volume,
                                     std::uint64_t seed) {
  check(s, median, solid_volume);
  detail::PortableRandom random(seed);
  std::vector<double> out;
  if (s.type == Type::none) {  // equal spheres of the median diameter
    out.assign(static_cast<std::size_t>(std::llround(solid_volume / core::units::sphere_volume(median))), median);
    return out;
  }
  if (s.type == Type::discrete) {
    for (std::size_t k = 0; k < static_cast<std::size_t>(s.classes); ++k) {
      const auto n = static_cast<std::size_t>(
          std::llround(s.volume_fractions[k] * solid_volume / core::units::sphere_volume(s.diameters[k])));
      out.insert(out.end(), n, s.diameters[k]);
    }
    for (std::size_t i = out.size(); i > 1; --i) std::swap(out[i - 1], out[random.below(i)]);  // Fisher–Yates
    return out;
  }
  // Number-weighted median of the lognormal (Hatch–Choate: d50,number = d50,volume e^(−3 ln² σ_g)).
  const double log_sigma = std::log(s.geometric_std);
  const double log_median = std::log(median) - 3.0 * log_sigma * log_sigma;
  const auto draw = [&]() {
    if (s.type == Type::uniform || s.min_diameter == s.max_diameter)
      return s.min_diameter + (s.max_diameter - s.min_diameter) * random.uniform();
    for (;;) {  // rejection outside the truncation bounds
      const double d = std::exp(log_median + log_sigma * random.normal());
      if (d >= s.min_diameter && d <= s.max_diameter) return d;
    }
  };
  double filled = 0.0;
  for (;;) {
    const double d = draw();
    const double v = core::units::sphere_volume(d);
    if (filled + 0.5 * v > solid_volume) break;  // adding it would overshoot by more than v/2
    out.push_back(d);
    filled += v;
  }
  return out;
}

double smallest_diameter(const ParticleProperties& p) {
  const auto& s = p.size_distribution;
  if (s.type == Type::none) return p.diameter;
  return s.type == Type::discrete && s.classes > 0 ? s.diameters.front() : s.min_diameter;
}

double largest_diameter(const ParticleProperties& p) {
  const auto& s = p.size_distribution;
  if (s.type == Type::none) return p.diameter;
  return s.type == Type::discrete && s.classes > 0 ? s.diameters[static_cast<std::size_t>(s.classes - 1)]
                                                   : s.max_diameter;
}

}  // namespace rheosim::dem
