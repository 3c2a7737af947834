// Optional particle size distribution: the case keys
// particles.size_distribution {type: uniform | lognormal | discrete}, the diameters drawn to
// fill φ (within 1 %), their placement without overlaps, and the scene holding them.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "rheosim/core/config.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/units.hpp"
#include "rheosim/dem/mpi_session.hpp"
#include "rheosim/dem/particles.hpp"
#include "rheosim/dem/placement.hpp"
#include "rheosim/dem/rheometer_scene.hpp"
#include "rheosim/dem/size_distribution.hpp"

namespace rheosim::dem {
namespace {

namespace fs = std::filesystem;
using core::units::pi;
using ::testing::HasSubstr;

constexpr double plate_radius = 2e-3;
constexpr double gap = 5e-4;
const double gap_volume = pi * plate_radius * plate_radius * gap;

// The `particles:` section of a case whose plates are `gap` apart, read by dem's own reader;
// every key of it must have been asked for.
ParticleProperties particles_of(const std::string& particles_yaml) {
  const core::Document doc = core::Document::from_string(particles_yaml, "case.yaml");
  ParticleProperties out =
      read_particles(doc.root().section({"particles", "the particles", "-"}), gap, /*with_volume_fraction=*/true);
  doc.check_all_keys_known();
  return out;
}

core::ConfigError parse_error(const std::string& particles_yaml) {
  try {
    (void)particles_of(particles_yaml);
  } catch (const core::ConfigError& e) {
    return e;
  }
  ADD_FAILURE() << "expected a ConfigError for:\n" << particles_yaml;
  return core::ConfigError({});
}

double solid_volume(const std::vector<double>& d) {
  double v = 0.0;
  for (const double di : d) v += core::units::sphere_volume(di);
  return v;
}

// Every pair at least r_i + r_j apart and every sphere inside the gap (brute force).
void expect_no_overlaps(const Placement& p) {
  const std::size_t n = p.count;
  ASSERT_EQ(p.diameters.size(), n);
  const auto& x = p.centres;
  for (std::size_t i = 0; i < n; ++i) {
    const double ri = 0.5 * p.diameters[i];
    ASSERT_GE(x[3 * i + 2], ri);
    ASSERT_LE(x[3 * i + 2], gap - ri);
    ASSERT_LE(std::hypot(x[3 * i], x[3 * i + 1]), plate_radius - ri);
    for (std::size_t j = i + 1; j < n; ++j) {
      const double dx = x[3 * i] - x[3 * j];
      const double dy = x[3 * i + 1] - x[3 * j + 1];
      const double dz = x[3 * i + 2] - x[3 * j + 2];
      ASSERT_GE(std::sqrt(dx * dx + dy * dy + dz * dz), ri + 0.5 * p.diameters[j]) << i << " " << j;
    }
  }
}

// ------------------------------------------------------------------------------ case file

TEST(SizeDistributionCase, AbsentMeansMonodisperse) {
  const auto p = particles_of("particles: {volume_fraction: 0.1, diameter: 1.0e-4, density: 1000}\n");
  EXPECT_EQ(p.size_distribution.type, SizeDistribution::Type::none);
  EXPECT_EQ(smallest_diameter(p), 1e-4);
  EXPECT_EQ(largest_diameter(p), 1e-4);
}

TEST(SizeDistributionCase, ReadsTheThreeTypes) {
  auto p = particles_of(
      "particles:\n  volume_fraction: 0.2\n  diameter: 1.0e-4\n  density: 1000\n"
      "  size_distribution: {type: uniform, min_diameter: 8.0e-5, max_diameter: 1.2e-4}\n");
  EXPECT_EQ(p.size_distribution.type, SizeDistribution::Type::uniform);
  EXPECT_EQ(smallest_diameter(p), 8e-5);
  EXPECT_EQ(largest_diameter(p), 1.2e-4);

  p = particles_of(
      "particles:\n  volume_fraction: 0.2\n  diameter: 1.0e-4\n  density: 1000\n"
      "  size_distribution: {type: lognormal, geometric_std: 1.1}\n");
  EXPECT_EQ(p.size_distribution.type, SizeDistribution::Type::lognormal);
  EXPECT_DOUBLE_EQ(p.size_distribution.geometric_std, 1.1);
  EXPECT_DOUBLE_EQ(smallest_diameter(p), 1e-4 / 1.21);  // default truncation d50 σ_g^∓2
  EXPECT_DOUBLE_EQ(largest_diameter(p), 1e-4 * 1.21);

  p = particles_of(
      "particles:\n  volume_fraction: 0.2\n  diameter: 1.0e-4\n  density: 1000\n"
      "  size_distribution: {type: discrete, diameters: [8.0e-5, 1.0e-4, 1.2e-4], volume_fractions: [0.25, 0.5, "
      "0.25]}\n");
  EXPECT_EQ(p.size_distribution.type, SizeDistribution::Type::discrete);
  EXPECT_EQ(p.size_distribution.classes, 3);
  EXPECT_EQ(smallest_diameter(p), 8e-5);
  EXPECT_EQ(largest_diameter(p), 1.2e-4);
}

TEST(SizeDistributionCase, BadInputNamesTheKey) {
  const std::string head = "particles:\n  volume_fraction: 0.2\n  diameter: 1.0e-4\n  density: 1000\n";
  auto e = parse_error(head + "  size_distribution: {type: gaussian}\n");
  EXPECT_EQ(e.details().key_path, "particles.size_distribution.type");
  e = parse_error(head +
                  "  size_distribution: {type: discrete, diameters: [8.0e-5, 1.0e-4], volume_fractions: [0.5, 0.6]}\n");
  EXPECT_EQ(e.details().key_path, "particles.size_distribution.volume_fractions");
  e = parse_error(head + "  size_distribution: {type: uniform, min_diameter: 1.1e-4, max_diameter: 1.2e-4}\n");
  EXPECT_THAT(e.what(), HasSubstr("outside the distribution's range"));
  e = parse_error(head + "  size_distribution: {type: uniform, min_diameter: 8.0e-5, max_diameter: 6.0e-4}\n");
  EXPECT_THAT(e.what(), HasSubstr("do not fit in the gap"));
  e = parse_error(head +
                  "  size_distribution: {type: lognormal, geometric_std: 1.1, max_diameter: 1.0e-4, "
                  "min_diamter: 5.0e-5}\n");
  EXPECT_EQ(e.details().key_path, "particles.size_distribution.min_diamter");  // unknown key, suggestion
}

// ------------------------------------------------------------------------------- sampling

TEST(SampleDiameters, FillsTheSolidVolumeWithinOnePercent) {
  const double target = 0.3 * gap_volume;
  const SizeDistribution uniform{.type = SizeDistribution::Type::uniform, .min_diameter = 8e-5, .max_diameter = 1.2e-4};
  const SizeDistribution lognormal{.type = SizeDistribution::Type::lognormal,
                                   .min_diameter = 1e-4 / 1.44,
                                   .max_diameter = 1.44e-4,
                                   .geometric_std = 1.2};
  const SizeDistribution discrete{.type = SizeDistribution::Type::discrete,
                                  .classes = 2,
                                  .diameters = {8e-5, 1.2e-4},
                                  .volume_fractions = {0.3, 0.7}};
  for (const auto& s : {uniform, lognormal, discrete}) {
    const auto d = sample_diameters(s, 1e-4, target, 7);
    EXPECT_NEAR(solid_volume(d), target, 0.01 * target);
    for (const double di : d) {
      EXPECT_GE(di, s.type == SizeDistribution::Type::discrete ? 8e-5 : s.min_diameter);
      EXPECT_LE(di, s.type == SizeDistribution::Type::discrete ? 1.2e-4 : s.max_diameter);
    }
    EXPECT_EQ(sample_diameters(s, 1e-4, target, 7), d);  // same seed, same diameters
  }
  // Discrete: the volume shares as asked (up to the rounding of the class counts).
  const auto d = sample_diameters(discrete, 1e-4, target, 7);
  std::vector<double> small;
  for (const double di : d)
    if (di == 8e-5) small.push_back(di);
  EXPECT_NEAR(solid_volume(small) / solid_volume(d), 0.3, 0.005);
}

// The volume-median of the drawn lognormal is d50 (volume basis), its spread σ_g.
TEST(SampleDiameters, LognormalHasTheVolumeMedianAndSpread) {
  const SizeDistribution s{.type = SizeDistribution::Type::lognormal,
                           .min_diameter = 1e-4 / 16.0,
                           .max_diameter = 1.6e-3,
                           .geometric_std = 1.3};
  auto d = sample_diameters(s, 1e-4, 2e4 * core::units::sphere_volume(1e-4), 11);
  std::sort(d.begin(), d.end());
  const double total = solid_volume(d);
  double cumulative = 0.0;
  double d16 = 0.0;
  double d50 = 0.0;
  double d84 = 0.0;
  for (const double di : d) {
    cumulative += core::units::sphere_volume(di);
    if (d16 == 0.0 && cumulative >= 0.1587 * total) d16 = di;
    if (d50 == 0.0 && cumulative >= 0.5 * total) d50 = di;
    if (d84 == 0.0 && cumulative >= 0.8413 * total) d84 = di;
  }
  EXPECT_NEAR(d50, 1e-4, 0.02e-4);
  EXPECT_NEAR(std::sqrt(d84 / d16), 1.3, 0.03);
}

// ------------------------------------------------------------------------------ placement

TEST(PolydispersePlacement, NoOverlapsAndPhiWithinOnePercent) {
  // A wide distribution (±20 %) up to φ = 0.3, a narrow one (−10 %) at φ = 0.5: the lattice
  // spaced for d_max holds 0.65 (d_mean/d_max)³ of solid here.
  const SizeDistribution wide{.type = SizeDistribution::Type::uniform, .min_diameter = 7e-5, .max_diameter = 1.1e-4};
  const SizeDistribution narrow{.type = SizeDistribution::Type::uniform, .min_diameter = 9e-5, .max_diameter = 1e-4};
  for (const double phi : {0.1, 0.3, 0.5}) {
    const auto d = sample_diameters(phi < 0.4 ? wide : narrow, 1e-4, phi * gap_volume, 5);
    const auto p =
        place_particles({.plate_radius = plate_radius, .gap = gap, .diameter = 1e-4, .seed = 5, .diameters = d});
    EXPECT_EQ(p.count, d.size());
    EXPECT_EQ(p.diameters, d);
    EXPECT_NEAR(p.volume_fraction, phi, 0.01 * phi) << "φ = " << phi;
    expect_no_overlaps(p);
  }
}

TEST(PolydispersePlacement, TooWideAtHighPhiIsRefusedWithAReason) {
  // Sites are spaced for the largest sphere: 0.05–0.4 mm at φ = 0.5 cannot be placed.
  const SizeDistribution s{.type = SizeDistribution::Type::uniform, .min_diameter = 5e-5, .max_diameter = 4e-4};
  const auto d = sample_diameters(s, 1e-4, 0.5 * gap_volume, 5);
  try {
    (void)place_particles({.plate_radius = plate_radius, .gap = gap, .diameter = 1e-4, .diameters = d});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("narrower size distribution"));
  }
}

// ---------------------------------------------------------------------------------- scene

TEST(PolydisperseScene, HoldsTheDrawnSpheres) {
  MpiSession::ensure();
  if (MpiSession::world_size() > 1) GTEST_SKIP() << "single-rank test";
  const fs::path dir = fs::temp_directory_path() / fmt::format("rheosim_test_psd_{}", ::getpid());
  auto q = particles_of(
      "particles:\n  volume_fraction: 0.3\n  diameter: 1.0e-4\n  density: 1000\n"
      "  size_distribution: {type: lognormal, geometric_std: 1.1}\n");
  {
    RheometerScene scene({.geometry = {.radius = plate_radius, .gap = gap},
                          .particles = q,
                          .rim_shear_rate = 100.0,
                          .gravity = std::nullopt,
                          .run_directory = dir});
    ASSERT_TRUE(scene.placement().has_value());
    const auto& placed = *scene.placement();
    EXPECT_NEAR(placed.volume_fraction, 0.3, 0.003);
    EXPECT_EQ(scene.total_particle_count(), static_cast<std::int64_t>(placed.count));
    // Time step from the smallest sphere (t_R ∝ r).
    EXPECT_NEAR(scene.rayleigh_time() / scene.time_step(), 1.0 / 0.3, 1e-12);
    scene.advance(0);
    const auto ids = scene.engine().ids();
    const auto r = scene.engine().radii();
    for (std::size_t i = 0; i < ids.size(); ++i)
      ASSERT_DOUBLE_EQ(2.0 * r[i], placed.diameters[static_cast<std::size_t>(ids[i] - 1)]);
    const auto [lo, hi] = std::minmax_element(r.begin(), r.end());
    EXPECT_LT(*lo, *hi);
    scene.advance(200);  // runs with mixed sizes
  }
  if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace rheosim::dem
