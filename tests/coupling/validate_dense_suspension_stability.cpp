// A neutrally buoyant suspension at φ = 0.3 with the seed's particles (d = 200 µm, E = 3 GPa) on a
// 3 mm disk, coupled with drag + pressure-gradient + viscous forces at the seed's interval (100).
// Without the ∇p filter (coupling/fluid_fields.hpp) the explicit −V_p∇p feedback of the
// projection pressure's ∂ε/∂t answer blows up within a strain of 2 (the solver refuses the step
// on its Courant guard); with the default filter the same run stays calm and
// its torque lies above the liquid's.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "coupling_test_support.hpp"
#include "rheosim/coupling/suspension_point.hpp"
#include "rheosim/fluid/transient.hpp"

namespace rheosim::coupling {
namespace {

SuspensionPointSettings dense_point(const std::filesystem::path& folder, double max_strain) {
  SuspensionPointSettings s;
  s.geometry = {.radius = 0.003, .gap = 0.0005};
  s.fluid = {.density = 1000, .rheology = testing::newtonian(1e-3)};
  s.particles = {.volume_fraction = 0.3,
                 .diameter = 2e-4,
                 .density = 1000,
                 .youngs_modulus = 3e9,
                 .poisson_ratio = 0.33,
                 .restitution = 0.9,
                 .friction = 0.3};
  s.rim_shear_rate = 100.0;
  s.radial_cells = 8;
  s.azimuthal_cells = 8;
  s.axial_cells = 2;
  s.coupling.coupling_interval = 100;
  // Run to max_strain without an early stop: the test is about stability over that window.
  s.steady = {
      .strain_window = max_strain / 2, .relative_tolerance = 1e-9, .min_strain = max_strain, .max_strain = max_strain};
  s.seed = 2;  // the placement of `rheosim run`'s second point (seed 1 + point index)
  s.run_directory = folder;
  return s;
}

TEST(DenseSuspensionStability, UnfilteredPressureGradientFeedbackBlowsUp) {
  testing::RunFolder folder;
  // The growth is exponential, but its onset follows the particles' chaotic paths: a change of
  // round-off in the pressure solve has moved it past a strain of 1, hence a window of 2.
  SuspensionPointSettings s = dense_point(folder.path(), 2.0);
  s.coupling.pressure_gradient_filter_steps = 0.0;
  try {
    (void)run_point(s);
    FAIL() << "expected the unfiltered run to be refused on its Courant guard";
  } catch (const fluid::StepError& e) {
    EXPECT_EQ(e.kind(), fluid::StepFailure::courant_exceeded) << e.what();
  }
}

TEST(DenseSuspensionStability, FilteredRunStaysCalmOverAStrainOfOne) {
  testing::RunFolder folder;
  const SuspensionPoint p = run_point(dense_point(folder.path(), 1.0));
  EXPECT_NEAR(p.strain, 1.0, 0.01);
  ASSERT_GT(p.particles, 900);  // φ = 0.3 of the 3 mm × 0.5 mm gap: ~1 000 spheres of 200 µm
  const double omega = 100.0 * 0.0005 / 0.003;
  const double liquid = std::numbers::pi * 1e-3 * omega * std::pow(0.003, 4) / (2 * 0.0005);
  EXPECT_GT(p.torque, liquid);
  EXPECT_LT(p.torque, 10 * liquid);
  for (const CouplingStepRecord& r : p.series) {
    ASSERT_TRUE(std::isfinite(r.fluid_torque) && std::isfinite(r.contact_torque));
    // Torque fluctuations stay on the scale of the liquid's torque (they were 100× it as the
    // unfiltered loop grew).
    EXPECT_LT(std::abs(r.fluid_torque), 10 * liquid);
  }
}

}  // namespace
}  // namespace rheosim::coupling
