// The CFD-DEM point runner (make_coupled_suspension_runner) through a real sweep on a small disk:
// fluid solver + LIGGGHTS coupled, next to the liquid's point of the same sweep.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "rheosim/core/log.hpp"
#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/plate.hpp"
#include "rheosim/rheometer/sweep.hpp"

namespace fs = std::filesystem;
using namespace rheosim;

TEST(CoupledSuspensionRunner, SmallDiskPointGivesFluidPlusContactTorque) {
  // R = 3 mm keeps the point to tens of seconds (about 340 particles of the CD §4 size at φ = 0.1).
  const rheometer::Case c = rheometer::parse_case(R"(kind: sweep
geometry: {type: parallel_plate, radius: 0.003, gap: 0.0005}
fluid:
  density: 1000
  rheology: {model: newtonian, viscosity: 1.0e-3}
shear_rates: [100]
volume_fractions: [0]
particles: {diameter: 2.0e-4, density: 1000, hydrodynamics: {model: none}}
)",
                                                  "coupled_point");
  const auto& sweep = std::get<rheometer::SweepCase>(c.spec);
  const fs::path out = fs::path("test-runs") / "coupled_point";
  fs::remove_all(out);
  auto runners = rheometer::default_point_runners(sweep.rheometer);
  runners.suspension = rheometer::make_coupled_suspension_runner(sweep.rheometer, out / "dem", 600.0);
  const auto outcome = rheometer::run_sweep(c, out, core::Log::null(), runners);
  EXPECT_EQ(outcome.points, 1);

  const rheometer::PointStore store(out, c.sha256);
  const auto liquid = store.load({0, "fluid", 0.0, 100.0});
  ASSERT_TRUE(liquid.has_value());
  const rheometer::SweepPoint suspension_point{1, "fluid", 0.1, 100.0};
  const rheometer::PointResult direct = runners.suspension(suspension_point, {});
  std::printf(
      "coupled point: converged=%d torque=%.4e ± %.2e (fluid %.4e, contact %.4e), liquid %.4e, strain %.1f, "
      "wall %.1f s %s\n",
      direct.converged, direct.torque, direct.torque_std_error, direct.torque_fluid, direct.torque_contact,
      liquid->torque, direct.strain, direct.wall_time, direct.failure.c_str());
  ASSERT_TRUE(std::isfinite(direct.torque)) << direct.failure;
  EXPECT_NEAR(direct.torque, direct.torque_fluid + direct.torque_contact, 1e-9 * std::abs(direct.torque));
  EXPECT_GT(direct.strain, 0.0);
  // The particles add stress. How much is not checked here: on the default 8 × 8 × 2 grid the
  // ratio comes out near 2 at φ = 0.1 against the seed's 1.05, a grid effect under study
  // (docs/coupling.md), so only the sign of the change is asserted.
  EXPECT_GT(direct.torque, liquid->torque);
  EXPECT_TRUE(direct.converged) << direct.failure;
}
