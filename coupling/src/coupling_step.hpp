#pragma once
// One CFD-DEM coupling step (CD §3–4) in the order both coupled loops take it (coupler.cpp: the
// disk's 3D fluid; shear_cell_point.cpp: the periodic cell's column):
//   1. advance_particles     LIGGGHTS over the coupling interval, the fluid forces of the last
//                            step held (fix external), and what the plates' contacts carried;
//   2. update_void_fraction  ε of the new positions (the void-fraction scheme's volume split);
//   3. update_forces         the fluid at the particles, the force models' forces (forces.hpp)
//                            handed to LIGGGHTS for the next interval, their reaction to the fluid;
//   4. advance_fluid         the fluid step, and what the plates' fluid carried.
// Each loop writes its phases for its fluid; the wall time of each goes to its part of `cost`.
// Without particles (φ = 0) only the fluid steps.
#include <chrono>

#include "rheosim/coupling/coupler.hpp"

namespace rheosim::coupling::detail {

template <class Loop, class Record>
void take_coupling_step(Loop& loop, bool with_particles, Record& record, CostSplit& cost) {
  using Clock = std::chrono::steady_clock;
  const auto seconds_since = [](Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
  };
  if (with_particles) {
    auto start = Clock::now();
    loop.advance_particles(record);  // 1
    cost.dem += seconds_since(start);

    start = Clock::now();
    loop.update_void_fraction();  // 2
    cost.void_fraction += seconds_since(start);

    start = Clock::now();
    loop.update_forces(record);  // 3
    cost.forces += seconds_since(start);
  }
  const auto start = Clock::now();
  loop.advance_fluid(record);  // 4
  cost.fluid += seconds_since(start);
  ++cost.steps;
}

}  // namespace rheosim::coupling::detail
