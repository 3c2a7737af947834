#pragma once
// Runs a `kind: rheometer` case and writes its run folder:
//   case.yaml      the input deck as given
//   summary.json   every point: torque (with and without inertia), closed form, errors, Re
//   torque.csv     the same table, one row per (fluid, shear rate)
//   fields.h5      converged fields per point (ω, p, u_r, u_z, μ, γ̇ on the (r, z) grid)
//   report.html    the report with its plots (NAME.gp → NAME.png/.svg) and data CSVs
//                  (rheometer/report.hpp); summary.json also holds the flow-curve analysis
//                  of each fluid (rheometer/run_analysis.hpp)
#include <filesystem>

#include "rheosim/core/log.hpp"
#include "rheosim/rheometer/case.hpp"

namespace rheosim::rheometer {

struct RunOutcome {
  std::filesystem::path summary;  // summary.json
  int points = 0;
  int failed_points = 0;  // points whose solve did not converge (state saved, reported)
};

// Single-phase rheometry (no `particles:`). Throws core::RunError for failures that stop the
// whole run (I/O); a point that does not converge is recorded as failed and the run goes on.
RunOutcome run_single_phase(const Case& c, const std::filesystem::path& out_dir, const core::Log& log);

}  // namespace rheosim::rheometer
