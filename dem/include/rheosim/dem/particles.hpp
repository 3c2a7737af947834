#pragma once
// The solid phase of a suspension as the DEM sees it: sphere size (or size distribution),
// density and the Hertz–Mindlin contact properties. The `particles:` section of a rheometer
// case; coupling adds the hydrodynamic keys of the same section (coupling/particles.hpp).
#include <array>

#include "rheosim/core/config.hpp"

namespace rheosim::dem {

// particles.size_distribution: the spread of sphere diameters (absent: all spheres have d).
// Sizes are given as a rheologist reads a particle-size analysis (volume basis): a lognormal
// by its volume-median d50 (= particles.diameter) and geometric standard deviation σ_g, a
// uniform range, or sieve classes with the share of the solid volume in each.
// Trivially copyable on purpose (fixed arrays, no std::vector/optional): GCC 12 reports false
// maybe-uninitialized warnings for such members in designated initialisers of the enclosing
// structs, which -Werror would turn into build failures wherever particles are initialised.
struct SizeDistribution {
  enum class Type { none, uniform, lognormal, discrete };  // none: monodisperse
  static constexpr int max_classes = 16;
  Type type = Type::none;
  double min_diameter = 0;   // [m] uniform: lower bound; lognormal: truncation; discrete: first class
  double max_diameter = 0;   // [m] uniform: upper bound; lognormal: truncation; discrete: last class
  double geometric_std = 1;  // σ_g [-] of the volume-weighted lognormal, in [1, 3]
  int classes = 0;           // discrete: number of classes, [1, max_classes]
  std::array<double, max_classes> diameters{};         // [m] discrete classes, increasing
  std::array<double, max_classes> volume_fractions{};  // [-] discrete: share of the solid volume per class, sum 1
};

struct ParticleProperties {       // particles: (CD §4 defaults)
  double volume_fraction = 0;     // φ [-], [0, 0.5]; a sweep sets it per point
  double diameter = 0;            // d [m], < gap; with a size distribution the representative
                                  // (volume-median) diameter used for H/d, Re_p and St
  double density = 0;             // ρ_p [kg/m³]
  double youngs_modulus = 3.0e9;  // E [Pa]
  double poisson_ratio = 0.33;    // ν [-]
  double restitution = 0.9;       // e [-]
  double friction = 0.3;          // μ_c [-], Coulomb friction coefficient
  // Last, and not a std::optional (see SizeDistribution); type none (the default): monodisperse.
  SizeDistribution size_distribution{};
};

// Reads the DEM keys of a `particles:` section (diameter, density, contact properties,
// size_distribution; volume_fraction when with_volume_fraction) for spheres between plates a
// gap [m] apart; a diameter that does not fit is a ConfigError at its key.
[[nodiscard]] ParticleProperties read_particles(const core::Section& particles, double gap, bool with_volume_fraction);

}  // namespace rheosim::dem
