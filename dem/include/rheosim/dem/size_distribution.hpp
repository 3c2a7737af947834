#pragma once
// Particle diameters drawn from the case file's size distribution (SizeDistribution,
// `particles.size_distribution`), for the rheometer scene.
//
// What is drawn
//   The spheres fill a given solid volume V_s = φ · π R² H. Distributions are on a volume
//   basis, as particle-size analysis reports them (sieving, laser diffraction):
//   - discrete: class k (diameter d_k, volume share w_k) gets n_k = round(w_k V_s / v_k)
//     spheres, v_k = π d_k³/6; exact shares up to the rounding of n_k.
//   - uniform: diameters uniform by number in [d_min, d_max].
//   - lognormal: the volume-weighted lognormal with median d50 (particles.diameter) and
//     geometric standard deviation σ_g, truncated to [d_min, d_max]. Numbers are drawn from the
//     number-weighted lognormal, which has the same σ_g and the median
//     d50 · exp(−3 ln² σ_g) (Hatch–Choate), with rejection outside [d_min, d_max].
//   For the continuous types spheres are drawn until the next one would overshoot V_s by more
//   than half its volume, so |Σ v_i − V_s| <= v_max / 2: with a few hundred particles φ is
//   well within 1 % of the target.
// The diameters come in the order drawn (discrete: shuffled), ready for place_particles.
//
// Randomness: PortableRandom (std::mt19937_64 with our own conversions), so a seed gives the
// same diameters everywhere.
#include <cstdint>
#include <vector>

#include "rheosim/dem/particles.hpp"

namespace rheosim::dem {

// Diameters [m] whose spheres fill solid_volume [m³] >= 0. `median` is particles.diameter
// (the lognormal's volume median). Throws std::invalid_argument for an inconsistent distribution.
[[nodiscard]] std::vector<double> sample_diameters(const SizeDistribution& distribution, double median,
                                                   double solid_volume, std::uint64_t seed);

// Smallest and largest diameter a particle set may hold [m]: the distribution's bounds, or
// particles.diameter for equal spheres.
[[nodiscard]] double smallest_diameter(const ParticleProperties& particles);
[[nodiscard]] double largest_diameter(const ParticleProperties& particles);

}  // namespace rheosim::dem
