// Low-rate points of a yield-stress liquid with inertia on: the inertial Newton solve reaches a
// floor (the stiff regularised viscosity) above solver.tolerance. Such a point converges and
// says so (a warning with the floor), its torque equals the creeping torque to the size of the
// floor, and a sweep reports no false failure.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "rheosim/core/config.hpp"
#include "rheosim/core/log.hpp"
#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/plate.hpp"
#include "rheosim/rheometer/sweep.hpp"

namespace rheosim {
namespace {

TEST(YieldStressPoints, HighBinghamNumbersConvergeAtTheirFloorAndSaySo) {
  // Bingham μ_p = 1 Pa·s, τ_y = 40 Pa: Bingham numbers τ_y/(μ_p γ̇_R) = 40 … 0.4 over 1–100 1/s.
  const rheometer::Case c = rheometer::parse_case(R"(kind: sweep
name: bingham_sweep
geometry: {type: parallel_plate, radius: 0.015, gap: 0.0005}
fluid:
  density: 1000
  rheology: {model: bingham, plastic_viscosity: 1.0, yield_stress: 40, regularization: 1000}
shear_rates: [1, 2.5, 10, 25, 50, 100]
volume_fractions: [0]
solver: {inertia: true}
)",
                                                  "bingham_sweep.yaml");
  const auto& r = std::get<rheometer::SweepCase>(c.spec).rheometer;
  const std::filesystem::path out = std::filesystem::path("test-runs") / "bingham_sweep";
  std::filesystem::remove_all(out);
  const auto outcome = rheometer::run_sweep(c, out, core::Log::null(), rheometer::default_point_runners(r));
  EXPECT_EQ(outcome.failed_points, 0);
  std::ifstream in(out / "summary.json");
  const auto summary = nlohmann::json::parse(in);
  const rheometer::ParallelPlate plate{0.015, 0.0005};
  int at_floor = 0;
  for (const auto& p : summary["points"]) {
    ASSERT_TRUE(p["converged"].get<bool>()) << p.dump();
    const double rate = p["shear_rate"].get<double>();
    // The creeping solve against the closed form, the inertial one against the creeping (at
    // these Reynolds numbers, below 1e-3, inertia changes the torque by less than 1e-9).
    const auto exact = rheometer::closed_form_torque(plate, *r.fluid.rheology, rate);
    ASSERT_TRUE(exact.has_value());
    EXPECT_NEAR(p["torque_creeping"].get<double>(), *exact, 1e-7 * *exact) << rate;
    EXPECT_NEAR(p["torque"].get<double>(), p["torque_creeping"].get<double>(), 1e-5 * *exact) << rate;
    if (p.contains("warnings")) {
      ++at_floor;
      EXPECT_NE(p["warnings"][0].get<std::string>().find("accepted at its Newton floor"), std::string::npos);
    }
  }
  // The rule the solves bent is listed once per text in the summary, with its points.
  EXPECT_GT(at_floor, 0);
  EXPECT_FALSE(summary["warnings"].empty());
}

}  // namespace
}  // namespace rheosim
