// coupling::Coupler: start-up checks (CFD δt = N × DEM δt, gravity), and one short run on a
// dem::RheometerScene: torque series (fluid + contact parts), cost split, plate speed.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "coupling_test_support.hpp"
#include "rheosim/core/units.hpp"
#include "rheosim/coupling/coupler.hpp"

namespace rheosim::coupling {
namespace {

using ::testing::HasSubstr;

class CouplerTest : public ::testing::Test {
 protected:
  testing::RunFolder folder_;
};

// Coupling every 100 DEM steps of the test scene (1e-6 s), so the CFD step is 1e-4 s.
CouplerSettings matching_settings() {
  CouplerSettings settings;
  settings.coupling_interval = 100;
  settings.fluid_time_step = 1e-4;
  return settings;
}

fluid::TransientParams gap_fluid(double gravity) {
  fluid::TransientParams fp;
  fp.grid = {.radius = 0.002, .gap = 0.0005, .radial_cells = 4, .azimuthal_cells = 8, .axial_cells = 2};
  fp.density = 1000;
  fp.rheology = testing::newtonian(1e-3);
  fp.axial_gravity = gravity;
  return fp;
}

TEST_F(CouplerTest, FluidTimeStepMustBeTheCouplingIntervalTimesTheDemStep) {
  fluid::TransientSolver fluid(gap_fluid(0.0));
  dem::Engine engine({.run_directory = folder_.path()});
  testing::make_box(engine, 0.002, 0.0005, 1e-6, 0.0,
                    {{.x = 0.001, .y = 0, .z = 2.5e-4, .diameter = 1e-4, .density = 1000}});
  CouplerSettings settings;
  settings.coupling_interval = 100;
  settings.fluid_time_step = 2e-4;  // 100 × 1e-6 = 1e-4
  try {
    Coupler coupler(settings, engine, fluid);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("coupling interval 100"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("0.0001 s"));
  }
  settings.fluid_time_step = 1e-4;
  EXPECT_NO_THROW(Coupler(settings, engine, fluid));
  settings.coupling_interval = 0;
  EXPECT_THROW(Coupler(settings, engine, fluid), std::invalid_argument);
  settings.coupling_interval = 100;
  settings.void_fraction = "nowhere";
  EXPECT_ANY_THROW(Coupler(settings, engine, fluid));
}

dem::RheometerScene::Params scene_params(const std::filesystem::path& dir) {
  dem::RheometerScene::Params p;
  p.geometry = {.radius = 0.002, .gap = 0.0005};
  p.particles = {.volume_fraction = 0.05,
                 .diameter = 1e-4,
                 .density = 1000,
                 .youngs_modulus = 1e7,
                 .poisson_ratio = 0.33,
                 .restitution = 0.9,
                 .friction = 0.3};
  p.rim_shear_rate = 20.0;
  p.time_step = 1e-6;
  p.torque_sample_interval = 50;
  p.run_directory = dir;
  return p;
}

TEST_F(CouplerTest, GravityMustMatchBetweenDemAndFluid) {
  dem::RheometerScene scene(scene_params(folder_.path()));
  fluid::TransientSolver fluid(gap_fluid(0.0));  // the scene has standard gravity
  CouplerSettings settings = matching_settings();
  try {
    Coupler coupler(settings, scene, fluid);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("gravity"));
  }
}

TEST_F(CouplerTest, RunsOnARheometerSceneAndReportsTorquesAndCost) {
  dem::RheometerScene scene(scene_params(folder_.path()));
  fluid::TransientSolver fluid(gap_fluid(-core::units::standard_gravity));
  CouplerSettings settings = matching_settings();
  Coupler coupler(settings, scene, fluid);
  EXPECT_DOUBLE_EQ(fluid.params().top_angular_velocity, scene.angular_velocity());
  for (int s = 0; s < 5; ++s) {
    const CouplingStepReport& r = coupler.step();
    EXPECT_LT(r.void_fraction.relative_error, 1e-13);
    EXPECT_LT(r.balance.relative_error, 1e-13);
    EXPECT_GT(r.drag_relaxation_steps, 1.0);
  }
  ASSERT_EQ(coupler.torque_series().size(), 5u);
  EXPECT_NEAR(coupler.time(), 5e-4, 1e-15);
  EXPECT_GT(coupler.torque_series().back().fluid_torque, 0.0);
  EXPECT_TRUE(std::isfinite(coupler.torque_series().back().contact_torque));
  const CostSplit& c = coupler.cost();
  EXPECT_EQ(c.steps, 5);
  EXPECT_GT(c.dem, 0.0);
  EXPECT_GT(c.void_fraction, 0.0);
  EXPECT_GT(c.forces, 0.0);
  EXPECT_GT(c.fluid, 0.0);
  EXPECT_EQ(c.void_fraction_floor_steps, 0);  // the default floor 0.3 is not reached here
  EXPECT_EQ(c.void_fraction_clamped_steps, 0);
  EXPECT_GT(scene.total_particle_count(), 100);
  // The plate speed follows the scene.
  scene.set_shear_rate(40.0);
  coupler.step();
  EXPECT_DOUBLE_EQ(fluid.params().top_angular_velocity, scene.angular_velocity());
}

TEST_F(CouplerTest, VoidFractionFloorIsCountedWhenItActs) {
  // A floor of ε_min = 0.99 makes every cell holding more than 1 % solid over-full: the floor
  // moves volume on every step, and the cost split counts those steps and the raw ε reached.
  dem::RheometerScene scene(scene_params(folder_.path()));
  fluid::TransientSolver fluid(gap_fluid(-core::units::standard_gravity));
  CouplerSettings settings = matching_settings();
  settings.void_fraction_floor = 0.99;
  Coupler coupler(settings, scene, fluid);
  for (int s = 0; s < 3; ++s) coupler.step();
  const CostSplit& c = coupler.cost();
  EXPECT_GE(c.void_fraction_floor_steps, c.steps);  // the start-up update counts too
  EXPECT_LT(c.min_raw_void_fraction, 0.99);
}

TEST_F(CouplerTest, AFluidStepOverItsCourantLimitIsSplitAndCounted) {
  // The coupling's fluid step (interval × DEM step) breaks a deliberately tight Courant limit
  // once the plate drives the liquid: the step is split into substeps, not failed, and the
  // time still advances by whole coupling steps.
  dem::RheometerScene scene(scene_params(folder_.path()));
  fluid::TransientParams fp = gap_fluid(-core::units::standard_gravity);
  fp.max_courant = 2e-4;
  fluid::TransientSolver fluid(fp);
  CouplerSettings settings = matching_settings();
  Coupler coupler(settings, scene, fluid);
  for (int s = 0; s < 5; ++s) EXPECT_NO_THROW(coupler.step());
  EXPECT_NEAR(coupler.time(), 5e-4, 1e-12);
  EXPECT_GT(coupler.cost().fluid_split_steps, 0);
  EXPECT_GE(coupler.cost().max_fluid_substeps, 2);
  // The same run under the default limit (no split): the fluid torque agrees.
  testing::RunFolder other;
  dem::RheometerScene reference_scene(scene_params(other.path()));
  fluid::TransientSolver reference_fluid(gap_fluid(-core::units::standard_gravity));
  Coupler reference(settings, reference_scene, reference_fluid);
  for (int s = 0; s < 5; ++s) reference.step();
  EXPECT_EQ(reference.cost().fluid_split_steps, 0);
  const double split = coupler.torque_series().back().fluid_torque;
  const double whole = reference.torque_series().back().fluid_torque;
  std::printf("fluid torque after 5 coupling steps: split %.6e, whole %.6e N m (%+.3f %%)\n", split, whole,
              100.0 * (split / whole - 1.0));
  EXPECT_NEAR(split, whole, 0.02 * std::abs(whole));
}

}  // namespace
}  // namespace rheosim::coupling
