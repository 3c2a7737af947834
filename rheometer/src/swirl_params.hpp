#pragma once
// The steady swirl solver's settings for one liquid of a rheometer case (private to rheometer/:
// the single-point run and the sweep's liquid points build the same solver).
#include "rheosim/core/case.hpp"
#include "rheosim/fluid/swirl.hpp"

namespace rheosim::rheometer {

inline fluid::SwirlParams swirl_params(const core::RheometerCase& r, const core::FluidProperties& fluid, bool inertia) {
  fluid::SwirlParams p;
  p.grid = {r.geometry.radius, r.geometry.gap, r.solver.radial_cells, 1, r.solver.axial_cells, r.solver.radial_grading,
            r.solver.axial_stretching};
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
inline double reported_torque(const core::RheometerCase& r, const fluid::SwirlResult& full) {
  const bool extrapolated = r.solver.inertia && r.solver.extrapolate && full.extrapolated_torque != 0.0;
  return extrapolated ? full.extrapolated_torque : full.torque;
}

}  // namespace rheosim::rheometer
