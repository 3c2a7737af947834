// A sweep through the shear-cell runner: `model: shear_cell` in the case,
// φ = 0 by the swirl solver and φ = 0.1 by the cell (CD §4 liquid and spheres, 0.5 mm gap,
// rates 25, 50, 100 1/s). summary.json records the model, the reason with the cell's choices
// (stiffness, size, the Stokes shortcut) and the estimated error; the drag-only suspension at
// φ = 0.1 has the liquid's torque (particles that follow the flow add no stress,
// docs/shear-cell.md) and the cell's creeping torque is within its estimated error of the
// liquid's (inertia included) — about 20 s.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "rheosim/core/log.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/sweep.hpp"

namespace fs = std::filesystem;
using namespace rheosim;

TEST(ShearCellSweep, SummaryRecordsModelReasonAndEstimatedError) {
  const rheometer::Case c = rheometer::parse_case(R"(kind: sweep
model: shear_cell
geometry: {type: parallel_plate, radius: 0.015, gap: 0.0005}
fluid:
  density: 1000
  rheology: {model: newtonian, viscosity: 1.0e-3}
shear_rates: [25, 50, 100]
volume_fractions: [0, 0.1]
particles: {diameter: 2.0e-4, density: 1000}
)",
                                                  "shear_cell_sweep");
  const auto& sweep = std::get<rheometer::SweepCase>(c.spec);
  const fs::path out = fs::path("test-runs") / "shear_cell_sweep";
  fs::remove_all(out);
  auto runners = rheometer::default_point_runners(sweep.rheometer);
  runners.suspension = rheometer::make_coupled_suspension_runner(sweep.rheometer, out / "dem", 600.0);
  const auto outcome = rheometer::run_sweep(c, out, core::Log::null(), runners);
  EXPECT_EQ(outcome.failed_points, 0);

  const auto summary = core::read_json(out / "summary.json");
  int cell_points = 0;
  for (const auto& p : summary["points"]) {
    if (p["volume_fraction"].get<double>() == 0.0) continue;
    ++cell_points;
    EXPECT_EQ(p["model"], "shear_cell");
    const std::string reason = p["model_reason"];
    EXPECT_NE(reason.find("model: shear_cell in the case file"), std::string::npos) << reason;
    EXPECT_NE(reason.find("linear local flow curve"), std::string::npos) << reason;
    EXPECT_NE(reason.find("DEM step"), std::string::npos) << reason;
    const double error = p["estimated_error"];
    EXPECT_TRUE(std::isfinite(error));
    EXPECT_LT(error, 0.03);
    // The liquid's point at the same rate.
    for (const auto& q : summary["points"]) {
      if (q["volume_fraction"].get<double>() != 0.0 || q["shear_rate"] != p["shear_rate"]) continue;
      EXPECT_NEAR(p["torque"].get<double>(), q["torque"].get<double>(),
                  std::max(1e-3, 2.0 * error) * q["torque"].get<double>());
    }
  }
  EXPECT_EQ(cell_points, 3);
}
