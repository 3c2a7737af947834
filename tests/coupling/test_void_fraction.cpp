// Void fraction (coupling/void_fraction.hpp): registry, the 29 sub-points, volume conservation
// for particles crossing cell faces, the axis, the plates and the rim, and the floor.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "rheosim/coupling/void_fraction.hpp"
#include "void_fraction/divided.hpp"

namespace rheosim::coupling {
namespace {

using ::testing::ElementsAre;

fluid::CylindricalGrid grid(int n_theta, double grading = 1.0) {
  return fluid::CylindricalGrid({.radius = 0.01,
                                 .gap = 0.002,
                                 .radial_cells = 6,
                                 .azimuthal_cells = n_theta,
                                 .axial_cells = 4,
                                 .radial_grading = grading});
}

struct Particles {
  std::vector<double> positions, radii;
  [[nodiscard]] ParticleView view() const { return {.positions = positions, .velocities = {}, .radii = radii}; }
  void add(double x, double y, double z, double r) {
    positions.insert(positions.end(), {x, y, z});
    radii.push_back(r);
  }
};

// Random particles anywhere, including overlapping the plates, the rim and the axis.
Particles random_particles(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> radius(0.0, 0.0102), angle(0.0, 2.0 * std::numbers::pi), height(-1e-4, 0.0021),
      size(5e-5, 2e-4);
  Particles p;
  for (int i = 0; i < n; ++i) {
    const double r = radius(rng), t = angle(rng);
    p.add(r * std::cos(t), r * std::sin(t), height(rng), size(rng));
  }
  p.add(0.0, 0.0, 0.001, 2e-4);       // on the axis
  p.add(1e-5, -2e-5, 0.0005, 2e-4);   // across the axis
  p.add(0.0, 0.0099, 1e-4, 2e-4);     // rim and bottom plate
  p.add(0.0, -0.0099, 0.0019, 2e-4);  // rim and top plate
  return p;
}

TEST(VoidFraction, RegistryHasBothSchemes) {
  EXPECT_THAT(builtin_void_fraction_schemes().names(), ElementsAre("centre", "divided"));
  EXPECT_EQ(make_void_fraction_scheme("divided")->name(), "divided");
  EXPECT_EQ(make_void_fraction_scheme("centre")->name(), "centre");
  EXPECT_ANY_THROW((void)make_void_fraction_scheme("devided"));
}

TEST(VoidFraction, DividedHasTwentyNinePointsAtTheShellCentroids) {
  const auto offsets = DividedVoidFraction::unit_offsets();
  ASSERT_EQ(offsets.size(), 29u);
  const auto radii = DividedVoidFraction::shell_radii();
  EXPECT_NEAR(radii[0], 0.6276, 1e-4);
  EXPECT_NEAR(radii[1], 0.9085, 1e-4);
  double sum[3] = {0, 0, 0};
  int inner = 0, outer = 0;
  for (const Vector3& o : offsets) {
    const double r = std::hypot(o[0], o[1], o[2]);
    inner += std::abs(r - radii[0]) < 1e-12;
    outer += std::abs(r - radii[1]) < 1e-12;
    for (int d = 0; d < 3; ++d) sum[d] += o[d];
  }
  EXPECT_EQ(inner, 14);
  EXPECT_EQ(outer, 14);
  for (const double s : sum) EXPECT_NEAR(s, 0.0, 1e-14);  // symmetric: the centroid stays at the centre
}

TEST(VoidFraction, VolumeIsConservedToRoundOffForEverySchemeAndGrid) {
  const Particles p = random_particles(400, 7);
  for (const int n_theta : {1, 2, 8}) {
    for (const double grading : {1.0, 0.5}) {
      const fluid::CylindricalGrid g = grid(n_theta, grading);
      for (const char* name : {"centre", "divided"}) {
        VoidFractionField field(g, 0.05);
        const VoidFractionReport& r = field.update(*make_void_fraction_scheme(name), p.view());
        EXPECT_LT(r.relative_error, 1e-13) << name << " N_θ=" << n_theta;
        EXPECT_GT(r.particle_volume, 0.0);
        double carried = 0.0;
        for (const double s : field.solid_volume()) carried += s;
        EXPECT_NEAR(carried, r.particle_volume, 1e-13 * r.particle_volume);
        if (std::string(name) == "divided") {
          EXPECT_GT(r.mapped_points, 0u);  // sub-points past the plates/rim
        }
      }
    }
  }
}

TEST(VoidFraction, CentreSchemePutsTheVolumeInTheCentresCell) {
  const fluid::CylindricalGrid g = grid(8);
  Particles p;
  p.add(0.0045 * std::cos(0.1), 0.0045 * std::sin(0.1), 0.0007, 1e-4);  // cell i = 2, j = 0, k = 1
  VoidFractionField field(g, 0.05);
  field.update(*make_void_fraction_scheme("centre"), p.view());
  const std::size_t cell = field.locator().cell_index(2, 0, 1);
  ASSERT_EQ(field.map().of(0).size(), 1u);
  EXPECT_EQ(field.map().of(0)[0].cell, cell);
  const double v = 4.0 / 3.0 * std::numbers::pi * 1e-12;
  EXPECT_NEAR(field.void_fraction()[cell], 1.0 - v / g.cell_volume(2, 1), 1e-15);
}

TEST(VoidFraction, DividedSplitsAParticleOnAnAxialFace) {
  const fluid::CylindricalGrid g = grid(8);
  Particles p;
  p.add(0.0045 * std::cos(0.3), 0.0045 * std::sin(0.3), 0.001, 1e-4);  // centred on the face z = H/2
  VoidFractionField field(g, 0.05);
  field.update(*make_void_fraction_scheme("divided"), p.view());
  const double v = 4.0 / 3.0 * std::numbers::pi * 1e-12;
  const double below = field.solid_volume()[field.locator().cell_index(2, 0, 1)];
  const double above = field.solid_volume()[field.locator().cell_index(2, 0, 2)];
  EXPECT_NEAR(below + above, v, 1e-13 * v);
  // Below the face: per shell the −z face point and 4 corners (10 of 29); the centre and the 4
  // in-plane points per shell lie on the face and count as above.
  EXPECT_NEAR(below / v, 10.0 / 29.0, 1e-12);
}

TEST(VoidFraction, FloorRedistributesTheExcessAndReportsIt) {
  const fluid::CylindricalGrid g = grid(8);
  Particles p;
  // Pack one cell (i = 3, j = 1, k = 2) far beyond the floor with small particles.
  const double r = 0.0058, t = 1.5 * g.azimuthal_width(), z = 0.00125;
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b)
      for (int c = 0; c < 4; ++c)
        p.add((r - 6e-4 + a * 2.4e-4) * std::cos(t - 0.2 + b * 0.08),
              (r - 6e-4 + a * 2.4e-4) * std::sin(t - 0.2 + b * 0.08), z - 1.8e-4 + c * 1.2e-4,
              1.5e-4);  // raw ε ≈ 0.47 in that cell
  VoidFractionField field(g, 0.6);
  const VoidFractionReport& rep = field.update(*make_void_fraction_scheme("centre"), p.view());
  EXPECT_LT(rep.min_void_fraction_raw, 0.5);
  EXPECT_GE(rep.min_void_fraction, 0.6 - 1e-12);
  EXPECT_GT(rep.capped_cells, 0u);
  EXPECT_GT(rep.redistributed_volume, 0.0);
  EXPECT_EQ(rep.unplaced_volume, 0.0);
  EXPECT_LT(rep.relative_error, 1e-13);
}

TEST(VoidFraction, LocatorMirrorsPointsOutsideTheDomain) {
  const fluid::CylindricalGrid g = grid(8);
  const CellLocator locator(g);
  const auto below = locator.locate({0.003, 0.0, -1e-4});
  EXPECT_TRUE(below.mapped);
  EXPECT_EQ(below.cell, locator.cell_index(1, 0, 0));
  const auto outside = locator.locate({0.0101, 1e-6, 0.0019});
  EXPECT_TRUE(outside.mapped);
  EXPECT_EQ(outside.cell, locator.cell_index(5, 0, 3));
  EXPECT_FALSE(locator.locate({-0.003, -1e-3, 0.001}).mapped);
}

// Cells are found by z/Δz, which a plate-clustered axial grid does not have.
TEST(VoidFraction, LocatorRejectsAStretchedAxialGrid) {
  const fluid::CylindricalGrid g(
      {.radius = 0.01, .gap = 0.002, .radial_cells = 6, .axial_cells = 4, .axial_stretching = 1.5});
  EXPECT_THROW(CellLocator{g}, std::invalid_argument);
}

TEST(VoidFraction, RejectsABadFloor) {
  EXPECT_THROW(VoidFractionField(grid(1), 0.0), std::invalid_argument);
  EXPECT_THROW(VoidFractionField(grid(1), 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace rheosim::coupling

namespace rheosim::coupling {
namespace {

// A ring whose wedges hold fewer than the threshold of particle volumes is averaged azimuthally
// (void_fraction.hpp, "Rings near the axis"); larger rings and the total are untouched.
TEST(VoidFraction, SmallAxisRingIsAveragedAroundTheAxis) {
  const fluid::CylindricalGrid g = grid(8);
  Particles p;
  p.add(3e-4, 2e-4, 0.00125, 2e-4);  // in the axis ring (Δr = 1.67 mm), one wedge, layer k = 2
  const double particle = sphere_volume_from_radius(2e-4);
  const double wedge = g.cell_volume(0, 2);  // 16 particle volumes; the next ring holds 48
  ASSERT_LT(wedge, 20 * particle);
  ASSERT_GT(g.cell_volume(1, 2), 20 * particle);
  const auto scheme = make_void_fraction_scheme("divided");

  VoidFractionField merged(g, 0.3, 100, 20.0);
  const VoidFractionReport& r = merged.update(*scheme, p.view());
  EXPECT_EQ(r.merged_rings, 1u);
  EXPECT_LT(r.relative_error, 1e-14);
  double ring = 0.0;
  for (std::size_t j = 0; j < 8; ++j) {
    const std::size_t c = merged.locator().cell_index(0, j, 2);
    EXPECT_NEAR(merged.solid_volume()[c], particle / 8, 1e-12 * particle);
    ring += merged.solid_volume()[c];
  }
  EXPECT_NEAR(ring, particle, 1e-12 * particle);

  VoidFractionField plain(g, 0.3, 100, 0.0);
  EXPECT_EQ(plain.update(*scheme, p.view()).merged_rings, 0u);
  // Without merging the particle's volume stays in the wedges its sub-points fall in.
  const std::size_t home = plain.locator().locate({3e-4, 2e-4, 0.00125}).cell;
  EXPECT_GT(plain.solid_volume()[home], 0.5 * particle);
  EXPECT_EQ(plain.solid_volume()[plain.locator().cell_index(0, 5, 2)], 0.0);  // the far side of the axis
  EXPECT_THROW(VoidFractionField(g, 0.3, 100, -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace rheosim::coupling
