#pragma once
// The analysis of a finished rheometer run or sweep, written into its summary.json
// (points, fits, yield_stress, relative_viscosity; docs/report.md). It applies analysis.hpp to the
// measured points, one flow curve ("series") per (fluid, φ):
//
//   points[i]            + log_slope n′ (± se), apparent_stress, rim_stress (plate-corrected),
//                          apparent_viscosity, viscosity (τ_R/γ̇_R), validity {numbers, flags,
//                          messages}
//   series[]             label, fluid, volume_fraction, points used, best model by AICc, the
//                          seed's torque line (CD §4), warnings (e.g. too few points)
//   fits[]               every flow model per series: parameters with standard errors and 95 %
//                          intervals, correlation matrix, AIC/AICc, Δ and Akaike weight,
//                          relative residuals, warnings
//   yield_stress[]       per series: Bingham intercept, Casson intercept, Herschel–Bulkley and
//                          the seed's torque intercept, each with its interval, kept apart
//   relative_viscosity   per fluid: η_r(φ) ± se at a reference shear rate (the largest measured:
//                          the seed compares at 100 1/s) from each φ's best fit, against
//                          Einstein, Batchelor, Krieger–Dougherty and Maron–Pierce (φ_m fitted)
//
// Nothing here runs a solver or writes a file; the report (report.hpp) reads the result.
#include <optional>
#include <span>
#include <vector>

#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/plate.hpp"
#include "rheosim/rheometer/sweep_summary.hpp"

namespace rheosim::rheometer {

struct RunAnalysisInputs {
  ParallelPlate plate;
  std::vector<NamedFluid> fluids;                         // every liquid named by the points
  std::optional<coupling::SuspendedParticles> particles;  // for the particle validity numbers (φ > 0)
};

// What the flow analysis adds to a summary besides the points' own keys.
struct FlowAnalysis {
  std::vector<SeriesRecord> series;
  std::vector<FitRecord> fits;
  std::vector<YieldRecord> yield_stress;
  std::vector<RelativeViscosityRecord> relative_viscosity;
};

// Analyses the converged points with a positive torque, one flow curve per (fluid, φ) in order
// of first appearance: fills each such point's log_slope … used_in_fits and returns the rest; a
// series or correlation that cannot be analysed gets a warning instead of numbers. Throws
// std::invalid_argument without fluids.
[[nodiscard]] FlowAnalysis analyse_flow_curves(std::span<SweepPointRecord> points, const RunAnalysisInputs& inputs);

}  // namespace rheosim::rheometer
