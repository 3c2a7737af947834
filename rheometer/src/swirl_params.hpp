#pragma once
// The steady swirl solver's settings for one liquid of a rheometer case (private to rheometer/:
// the single-point run and the sweep's liquid points build the same solver).
#include "rheosim/core/case.hpp"
#include "rheosim/fluid/swirl.hpp"

namespace rheosim::rheometer {

inline fluid::SwirlParams swirl_params(const core::RheometerCase& r, const core::FluidProperties& fluid, bool inertia) {
  fluid::SwirlParams p;
  p.grid = {r.geometry.radius, r.geometry.gap, r.solver.radial_cells, 1, r.solver.axial_cells, r.solver.radial_grading};
  p.density = fluid.density;
  p.rheology = fluid.rheology;
  p.inertia = inertia;
  p.tolerance = r.solver.tolerance;
  p.max_iterations = r.solver.max_iterations;
  return p;
}

}  // namespace rheosim::rheometer
