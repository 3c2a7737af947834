#pragma once
// Runs one `kind: ldd` case into a folder (DESIGN §3). Cavity scenes (cavity, skewed_cavity) are
// built; the free-surface scenes (dam_break, slump, column) are not yet (issue 7 part 1).
//
// Files written to out_dir:
//   case.yaml                       the exact input
//   summary.json                    nodes, steps, ms_per_step, centerlines, status, wall time,
//                                   input sha256, phase timings
//   centerline_vertical.csv         y/S, u/U along the line ξ = W/2 (cavity coordinates)
//   centerline_horizontal.csv       x/W, v/U along the line η = S/2
//   residual.csv                    time, steady-state residual, kinetic energy, solver iterations
//   frames/nodes_NNNN.vtk           node cloud with velocity, pressure, shear rate, viscosity, kind
//   frames/field_NNNN.vtk           velocity and stream function ψ resampled on a 101² grid
//                                   (streamlines in ParaView: Stream Tracer, or contours of psi)
//   frames/nodes.vtk.series, frames/field.vtk.series, nodes.pvd   ParaView time-series indexes
//   field.vtk                       final velocity and stream function ψ on a structured grid
//                                   (ParaView: Stream Tracer or contours of psi for streamlines)
//   centerlines.gp, centerlines.png gnuplot script (kept to restyle) and its plot; streamlines.gp/.png
//   log.txt                         (written by the caller's Log)
// The steady-state residual is max over the centre-line probes of |Δu|/U per unit of L/U time
// between two samples. On divergence (NaN, Courant number, failed solves, residual > 1e3) the
// run stops, the last good state is written as a frame and summary.json says "diverged".
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "rheosim/core/case.hpp"
#include "rheosim/core/log.hpp"
#include "rheosim/ldd/solver.hpp"

namespace rheosim::ldd {

struct RunOutcome {
  std::string status;              // "steady" | "end_time" | "diverged"
  std::string message;             // why a diverged run stopped
  std::filesystem::path summary;   // summary.json
  std::size_t steps = 0;
  double ms_per_step = 0;
};

// Throws core::RunError for scenes that are not built yet; never throws for divergence (see
// RunOutcome::status).
RunOutcome run_case(const core::Case& c, const std::filesystem::path& out_dir, const core::Log& log);

// A cavity run without files, for validation tests and benchmarks: steps until end_time or until
// the steady residual (as above, sampled every 0.25 L/U) stays below steady_tolerance (0: never)
// for three samples, then returns the velocity at the probes, given as cavity-coordinate
// fractions (ξ/W, η/S) interleaved.
struct CavityResult {
  std::size_t nodes = 0, steps = 0;
  double time = 0, ms_per_step = 0, final_residual = 0;
  bool diverged = false;
  std::string message;
  std::vector<double> probe_velocity;  // u, v per probe [m/s]
  PhaseTimes phases;
};
[[nodiscard]] CavityResult simulate_cavity(const core::CavityScene& scene, const SolverParams& params, double end_time,
                                           double steady_tolerance, std::span<const double> probe_fractions);

}  // namespace rheosim::ldd
