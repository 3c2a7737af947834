// coupling/suspension_box.hpp: settings are checked, the placement fills the box at φ without
// overlaps, and the stress bookkeeping gives Einstein's 1 + 2.5φ exactly when no pair interacts,
// in the Lees–Edwards box and on the plates of the walled box.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "rheosim/coupling/suspension_box.hpp"

namespace rheosim::coupling {
namespace {

SuspensionBoxSettings short_run(double phi) {
  SuspensionBoxSettings s;
  s.volume_fraction = phi;
  s.particles = 40;
  s.warmup_strain = 0.2;
  s.min_averaging_strain = 0.4;
  s.max_strain = 1.0;
  s.block_strain = 0.1;
  return s;
}

TEST(SuspensionBox, RejectsSettingsOutOfRange) {
  auto s = short_run(0.1);
  s.volume_fraction = 0.7;
  EXPECT_THROW((void)run_suspension_box(s), std::invalid_argument);
  s = short_run(0.1);
  s.particles = 5;
  EXPECT_THROW((void)run_suspension_box(s), std::invalid_argument);
  s = short_run(0.1);
  s.volume_shares = {0.5};
  EXPECT_THROW((void)run_suspension_box(s), std::invalid_argument);
  s = short_run(0.1);
  s.max_strain = 0.5;  // not more than warm-up + minimum averaging
  EXPECT_THROW((void)run_suspension_box(s), std::invalid_argument);
}

TEST(SuspensionBox, IsolatedSpheresGiveEinstein) {
  // 40 spheres at φ = 0.001: the box is 51 radii wide, so no pair comes within the
  // lubrication cutoff in one strain unit; σ_xz = μγ̇(1 + 2.5φ) and no normal stress.
  const auto r = run_suspension_box(short_run(0.001));
  EXPECT_EQ(r.particles, 40);
  EXPECT_NEAR(r.volume_fraction, 0.001, 1e-12);
  EXPECT_NEAR(r.relative_viscosity.mean, 1.0 + 2.5 * 0.001, 1e-9);
  EXPECT_NEAR(r.n1.mean, 0.0, 1e-12);
  EXPECT_NEAR(r.n2.mean, 0.0, 1e-12);
  EXPECT_EQ(r.mean_contacts_per_particle, 0.0);
  // Every implicit solve met its tolerance (the spheres move with the flow: V' = 0).
  EXPECT_EQ(r.solves_at_iteration_cap, 0);
}

TEST(SuspensionBox, StressletScalesWithItsViscosity) {
  auto s = short_run(0.001);
  s.stresslet_viscosity_ratio = 0.5;
  EXPECT_NEAR(run_suspension_box(s).relative_viscosity.mean, 1.0 + 1.25 * 0.001, 1e-9);
}

TEST(SuspensionBox, DensePlacementHasNoOverlapAndShears) {
  // φ = 0.5: the placement relaxes the random overlaps; a short run shears it without diverging,
  // with contacts, and stress above the liquid's.
  auto s = short_run(0.5);
  s.particles = 60;
  const auto r = run_suspension_box(s);
  EXPECT_NEAR(r.volume_fraction, 0.5, 1e-12);
  EXPECT_GT(r.relative_viscosity.mean, 2.0);
  EXPECT_LT(r.max_overlap, 0.05);
  EXPECT_GT(r.mean_contacts_per_particle, 0.0);
  EXPECT_FALSE(r.converged);  // one strain unit is far too short for the tolerance
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.front().find("tolerance"), std::string::npos) << r.warnings.front();
}

TEST(SuspensionBox, WalledBoxRejectsAGapTheSpheresDoNotFit) {
  auto s = short_run(0.1);
  s.wall_gap = 2.0;  // H/a: a sphere would touch both plates
  EXPECT_THROW((void)run_suspension_box(s), std::invalid_argument);
  s.wall_gap = 1000.0;  // 40 spheres between plates 500 d apart: a side of 0.9 a
  EXPECT_THROW((void)run_suspension_box(s), std::invalid_argument);
}

TEST(SuspensionBox, WalledBoxOfIsolatedSpheresGivesEinsteinOnThePlates) {
  // 40 spheres at φ = 0.001 between plates 40 a apart, a lubrication cutoff of 0.01 a: nothing
  // interacts, the spheres ride the liquid, and the plates read μγ̇ over the harmonic mean of
  // 1 + 2.5φ(z) — Einstein's 1 + 2.5φ to O(φ²). The one-way box (linear liquid, virial) gives
  // it exactly. A slip of the plate reading's units or of the couple's half would show here.
  auto s = short_run(0.001);
  s.wall_gap = 40.0;
  s.lubrication_cutoff = 0.01;
  const auto r = run_suspension_box(s);
  EXPECT_NEAR(r.box_height, 40.0, 1e-12);
  EXPECT_NEAR(r.volume_fraction, 0.001, 1e-12);
  EXPECT_NEAR(r.relative_viscosity.mean, 1.0 + 2.5 * 0.001, 2e-5);
  EXPECT_NEAR(r.core_shear_rate, 1.0, 1e-3);
  // The layer within ā of a plate holds less solid than the mean, so its liquid shears faster.
  EXPECT_GT(r.plate_shear_rate, 1.0);
  EXPECT_LT(r.plate_shear_rate, 1.0 + 2.0 * 2.5 * 0.001);
  EXPECT_EQ(r.mean_contacts_per_particle, 0.0);
  s.mean_flow_coupling = false;
  EXPECT_NEAR(run_suspension_box(s).relative_viscosity.mean, 1.0 + 2.5 * 0.001, 1e-9);
}

TEST(SuspensionBox, WalledBoxKeepsDenseSpheresBetweenThePlates) {
  // φ = 0.4 in a gap of 2.5 d: the plates' contacts hold the spheres in, no sphere passes a
  // plate (the run would throw), the overlaps stay small and the stress is above the liquid's.
  auto s = short_run(0.4);
  s.particles = 60;
  s.wall_gap = 5.0;
  const auto r = run_suspension_box(s);
  EXPECT_GT(r.relative_viscosity.mean, 2.0);
  EXPECT_LT(r.max_overlap, 0.05);
  EXPECT_GT(r.mean_contacts_per_particle, 0.0);
}

TEST(SuspensionBox, DefaultsFollowThePhysics) {
  // The contact stiffness of LF_DEM's practice; the strain step resolves the relaxation time of
  // inertial spheres.
  EXPECT_DOUBLE_EQ(default_contact_stiffness(0.5), 2000.0);
  SuspensionBoxSettings s;
  EXPECT_DOUBLE_EQ(default_strain_step(s), 5e-3);
  s.stokes_number = 0.004;
  EXPECT_DOUBLE_EQ(default_strain_step(s), 2e-3);
}

}  // namespace
}  // namespace rheosim::coupling
