#pragma once
// The steady swirl solver's settings for one liquid of a rheometer case (private to rheometer/:
// the sweep's liquid points build their solvers with it).
#include <string>
#include <vector>

#include <fmt/format.h>

#include "rheosim/fluid/swirl.hpp"
#include "rheosim/rheometer/case.hpp"

namespace rheosim::rheometer {

inline fluid::SwirlParams swirl_params(const RheometerCase& r, const core::FluidProperties& fluid, bool inertia) {
  fluid::SwirlParams p;
  p.grid = {r.geometry.radius,    r.geometry.gap,          r.solver.radial_cells,    1,
            r.solver.axial_cells, r.solver.radial_grading, r.solver.axial_stretching};
  p.density = fluid.density;
  p.rheology = fluid.rheology;
  p.inertia = inertia;
  p.tolerance = r.solver.tolerance;
  p.max_iterations = r.solver.max_iterations;
  return p;
}

// The torque a point reports: with `extrapolate`, the Richardson torque of the grid-sequenced
// solve (docs/performance.md: on plate-clustered grids both directions converge at second
// order from N_z = 8, so T + (T − T_2h)/3 is the accurate value); else this grid's torque.
// A solve whose half-grid start failed has no extrapolation and keeps its own torque.
inline double reported_torque(const RheometerCase& r, const fluid::SwirlResult& full) {
  const bool extrapolated = r.solver.inertia && r.solver.extrapolate && full.extrapolated_torque != 0.0;
  return extrapolated ? full.extrapolated_torque : full.torque;
}

// The warnings of a point's solves: each one accepted at its iteration's floor above the
// tolerance (fluid::SwirlResult::accepted_change) says so.
inline std::vector<std::string> swirl_warnings(const RheometerCase& r, const fluid::SwirlResult& creeping,
                                               const fluid::SwirlResult& inertial) {
  std::vector<std::string> out;
  const auto note = [&](const fluid::SwirlResult& s, const char* which) {
    if (s.converged && s.accepted_change > r.solver.tolerance)
      out.push_back(
          fmt::format("{} swirl solve accepted at its Newton floor: relative change {:.2g} over its last "
                      "five iterations, above solver.tolerance {:.2g}",
                      which, s.accepted_change, r.solver.tolerance));
  };
  note(creeping, "creeping");
  if (r.solver.inertia) note(inertial, "inertial");
  return out;
}

}  // namespace rheosim::rheometer
