#pragma once
// summary.json of a rheometer sweep (sweep.cpp writes it, the flow analysis adds series, fits,
// yield stresses and η_r), read back as typed values. Every key a sweep always writes is
// required: a missing or mistyped one is a core::ConfigError naming the file and the key's path
// ("points[3].shear_rate"). What only some points, methods or analyses have is std::optional
// (absent or null in the file): the closed form, the validity checks, normal forces, a fit's
// statistics that did not exist.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rheosim/core/run_summary.hpp"

namespace rheosim::rheometer {

using MaybeNumber = std::optional<double>;

struct Interval95 {
  MaybeNumber lower, upper;
  friend bool operator==(const Interval95&, const Interval95&) = default;
};

// The dimensionless checks of a point (analysis.hpp, PointValidity).
struct PointChecks {
  MaybeNumber gap_reynolds, particle_reynolds, stokes, gap_to_diameter;
  bool gap_reynolds_ok = true, particle_reynolds_ok = true, stokes_ok = true, gap_to_diameter_ok = true;
  bool valid = false;
  std::vector<std::string> messages;
  friend bool operator==(const PointChecks&, const PointChecks&) = default;
};

struct PointCost {  // a CFD-DEM point's wall time by part [s]
  double dem = 0, void_fraction = 0, forces = 0, fluid = 0;
  double coupling_overhead = 0;  // (void fraction + forces) / DEM
  MaybeNumber near_field;
  friend bool operator==(const PointCost&, const PointCost&) = default;
};

// One point as the sweep writes it (to_json) and reads it back. A value the point's method does
// not give is empty; to_json knows which keys are always written (null when empty) and which only
// when known.
struct SweepPointRecord {
  std::string fluid;
  double volume_fraction = 0;  // φ (absent in a single-phase summary: 0)
  double shear_rate = 0;       // rim γ̇_R [1/s]
  bool converged = false;
  std::string method;               // how the point was computed
  std::string model, model_reason;  // the suspension model chosen, and why (empty for a liquid)
  std::string failure;              // a failed point: why it has no result
  // A converged point.
  MaybeNumber angular_velocity;                                     // Ω [rad/s]
  double torque = 0;                                                // [N·m]
  MaybeNumber torque_fluid, torque_contact;                         // its parts
  MaybeNumber torque_lubrication, torque_stresslet, torque_couple;  // near-field parts
  MaybeNumber torque_std_error, torque_grid, torque_half_grid;      // steady-state error; extrapolation
  MaybeNumber torque_creeping, inertia_effect, torque_quadrature;   // creeping solve, closed form by quadrature
  MaybeNumber torque_analytic, rel_error, creeping_rel_error;       // closed form and the errors against it
  std::vector<std::string> warnings;                                // rules this point bent
  MaybeNumber gap_reynolds_number, strain, estimated_error, wall_time, iterations;
  std::optional<PointCost> cost;
  // The flow-curve analysis of its series (run_analysis.hpp; all six or none, by apparent_stress).
  MaybeNumber log_slope, log_slope_std_error, apparent_stress, rim_stress, apparent_viscosity, viscosity;
  std::optional<PointChecks> validity;
  std::optional<bool> used_in_fits;
  // Methods that give the plates' normal force [N]; N1 − N2 [Pa] from it; the model's N1, N2 [Pa].
  MaybeNumber normal_force, n1_minus_n2, n1, n2;
  friend bool operator==(const SweepPointRecord&, const SweepPointRecord&) = default;
};

struct TorqueLine {                 // the seed's T = T₀ + b γ̇_R (CD §4)
  double intercept = 0, slope = 0;  // [N·m], [N·m·s]
  MaybeNumber intercept_std_error, slope_std_error;
  double plastic_viscosity = 0;  // 2b/(πR³) [Pa·s]
  Interval95 plastic_viscosity_ci95;
  std::vector<double> residuals;  // T − line [N·m]
  friend bool operator==(const TorqueLine&, const TorqueLine&) = default;
};

struct SeriesRecord {  // one flow curve: a fluid at one φ
  std::string label, fluid;
  double volume_fraction = 0;
  std::size_t points = 0;                    // finished points
  std::optional<std::size_t> fitted_points;  // those the fits use (absent: fewer than 2 points)
  std::optional<std::string> best_model;     // by AICc, when fitted
  std::optional<TorqueLine> torque_line;
  std::vector<std::string> warnings;
  friend bool operator==(const SeriesRecord&, const SeriesRecord&) = default;
};

struct FitParameter {
  std::string name, symbol, unit;
  MaybeNumber value, std_error;
  Interval95 ci95;
  friend bool operator==(const FitParameter&, const FitParameter&) = default;
};

struct FitWarningRecord {
  std::string kind, parameter, message;  // analysis.hpp FitWarning
  friend bool operator==(const FitWarningRecord&, const FitWarningRecord&) = default;
};

struct FitRecord {  // one flow model fitted to one series
  std::string label, fluid;
  double volume_fraction = 0;
  std::string model, equation;
  bool converged = false;
  long long iterations = 0;
  std::string stop_reason;
  long long points = 0;
  long long degrees_of_freedom = 0;  // n − p, negative with more parameters than points
  MaybeNumber residual_std, sum_of_squares, aic, aicc;
  double min_shear_rate = 0, max_shear_rate = 0;
  std::vector<FitParameter> parameters;
  std::vector<std::vector<MaybeNumber>> correlation;  // of the parameters
  std::vector<double> shear_rate;
  std::vector<MaybeNumber> residuals;  // relative, per shear rate
  std::vector<FitWarningRecord> warnings;
  std::size_t rank = 0;  // by AICc, 1 the best
  MaybeNumber delta, akaike_weight;
  friend bool operator==(const FitRecord&, const FitRecord&) = default;
};

struct YieldRecord {  // one yield-stress estimate of one series
  std::string label, fluid;
  double volume_fraction = 0;
  std::string method;
  MaybeNumber value, std_error;
  Interval95 ci95;
  bool significant = false, converged = false;
  std::vector<std::string> warnings;
  MaybeNumber akaike_weight;  // of the fit it comes from (absent for the torque line)
  friend bool operator==(const YieldRecord&, const YieldRecord&) = default;
};

struct RelativeViscosityPointRecord {
  double volume_fraction = 0;
  MaybeNumber relative_viscosity, std_error;
  MaybeNumber viscosity, viscosity_std_error;  // the suspension's, at the reference rate [Pa·s]
  std::string std_error_source;
  std::string model;  // the fit whose viscosity it uses
  friend bool operator==(const RelativeViscosityPointRecord&, const RelativeViscosityPointRecord&) = default;
};

struct CorrelationRecord {  // an η_r(φ) correlation fitted to the points
  std::string name;
  std::vector<MaybeNumber> predicted;  // η_r at each point's φ
  MaybeNumber sum_of_squares, max_packing, max_packing_std_error;
  Interval95 max_packing_ci95;
  MaybeNumber intrinsic_viscosity;
  long long degrees_of_freedom = 0;
  MaybeNumber aic;
  bool converged = false;
  std::vector<std::string> warnings;
  friend bool operator==(const CorrelationRecord&, const CorrelationRecord&) = default;
};

struct RelativeViscosityRecord {  // η_r(φ) of one liquid; only fluid and warnings when nothing was fitted
  std::string fluid;
  MaybeNumber reference_shear_rate;
  std::string liquid_viscosity_source;
  MaybeNumber liquid_viscosity, liquid_viscosity_std_error;
  std::vector<RelativeViscosityPointRecord> points;
  std::vector<CorrelationRecord> correlations;
  std::vector<std::string> warnings;
  friend bool operator==(const RelativeViscosityRecord&, const RelativeViscosityRecord&) = default;
};

struct SweepGridRecord {  // the swirl solve's grid (φ = 0 points)
  long long radial_cells = 0, axial_cells = 0;
  double radial_grading = 1, axial_stretching = 0;
  bool extrapolate = false;  // Richardson extrapolation from a half grid
  std::string applies_to;    // which points it serves
  friend bool operator==(const SweepGridRecord&, const SweepGridRecord&) = default;
};

struct RuleBent {  // a rule points bent, and how many
  std::string warning;
  std::size_t points = 0;
  friend bool operator==(const RuleBent&, const RuleBent&) = default;
};

struct SweepSummary {
  core::SummaryHead head;      // kind "sweep" (every rheometer case runs as a sweep)
  double radius = 0, gap = 0;  // [m]
  std::optional<SweepGridRecord> grid;
  bool inertia = true;
  std::vector<double> volume_fractions, shear_rates;  // the sweep's φ and rim rates [1/s]
  std::size_t points_total = 0, points_failed = 0;
  std::optional<std::size_t> points_resumed;  // read back from an interrupted run's point store
  double wall_time = 0;                       // [s]
  std::vector<SweepPointRecord> points;
  std::vector<RuleBent> warnings;
  std::vector<SeriesRecord> series;
  std::vector<FitRecord> fits;
  std::vector<YieldRecord> yield_stress;
  std::vector<RelativeViscosityRecord> relative_viscosity;
  friend bool operator==(const SweepSummary&, const SweepSummary&) = default;
};

// Each record as summary.json holds it; read_sweep_summary reads the same keys back.
[[nodiscard]] nlohmann::ordered_json to_json(const SweepPointRecord& point);
[[nodiscard]] nlohmann::ordered_json to_json(const SeriesRecord& series);
[[nodiscard]] nlohmann::ordered_json to_json(const FitRecord& fit);
[[nodiscard]] nlohmann::ordered_json to_json(const YieldRecord& yield);
[[nodiscard]] nlohmann::ordered_json to_json(const RelativeViscosityRecord& relative_viscosity);
// The whole file: the head every run writes (core/run_summary.hpp), then the keys above.
[[nodiscard]] nlohmann::ordered_json to_json(const SweepSummary& summary);

// Reads <run_dir>/summary.json; ConfigError when it is missing, of another kind of run (an LDD
// run's is refused by name), or lacks (or mistypes) a required key, naming it.
[[nodiscard]] SweepSummary read_sweep_summary(const std::filesystem::path& run_dir);

}  // namespace rheosim::rheometer
