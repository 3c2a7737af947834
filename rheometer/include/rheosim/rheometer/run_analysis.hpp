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
#include <vector>

#include <nlohmann/json.hpp>

#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/plate.hpp"

namespace rheosim::rheometer {

struct RunAnalysisInputs {
  ParallelPlate plate;
  std::vector<NamedFluid> fluids;                         // every liquid named by the points
  std::optional<coupling::SuspendedParticles> particles;  // for the particle validity numbers (φ > 0)
};

// `summary["points"]` holds objects with fluid (default: the first fluid), volume_fraction
// (default 0), shear_rate, torque, converged and optionally torque_std_error. Adds the keys above;
// a series or correlation that cannot be analysed gets a warning instead of numbers.
void add_flow_analysis(nlohmann::ordered_json& summary, const RunAnalysisInputs& inputs);

}  // namespace rheosim::rheometer
