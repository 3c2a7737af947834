#pragma once
// Flow-curve analysis of parallel-plate data: what a rheologist reads.
// Pure numerics on SI values; no I/O. The steps, in the order a sweep applies them per φ:
//
//   1. rim_stress_curve      torque T(γ̇_R) → apparent and plate-corrected rim stress
//   2. fit_flow_curve        Newtonian … Carreau fitted to (γ̇_R, τ_R), relative residuals,
//                            standard errors, t intervals, correlations, AIC, warnings
//   3. estimate_yield_stress Bingham intercept, Casson intercept, Herschel–Bulkley τ_y and the
//                            seed's torque-line intercept (CD §4), kept apart
//   4. analyze_relative_viscosity   η_r(φ) against Einstein, Batchelor, Krieger–Dougherty
//                            (φ_m fitted) and Maron–Pierce (φ_m fitted)
//   5. check_validity        gap Reynolds, particle Reynolds and Stokes numbers, H/d
//
// Definitions used throughout (γ̇_R = ΩR/H, CD §2.2):
//   apparent rim stress  τ_app = 2T/(πR³)                     (the Newtonian rim stress)
//   corrected rim stress τ_R   = T/(2πR³) (3 + n′),  n′ = d ln T / d ln γ̇_R
// The correction is exact for any law τ(γ̇): T = 2πR³ γ̇_R⁻³ ∫₀^γ̇_R τ(γ̇) γ̇² dγ̇ gives
// d(T γ̇_R³)/dγ̇_R = 2πR³ τ(γ̇_R) γ̇_R²; its accuracy is that of n′.
#include <cstddef>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "rheosim/rheometer/flow_models.hpp"
#include "rheosim/rheometer/least_squares.hpp"
#include "rheosim/rheometer/plate.hpp"

namespace rheosim::rheometer {

// ---------------------------------------------------------------------------------------------
// 1. Rim stress with the plate correction

// τ_app = 2T/(πR³) [Pa].
[[nodiscard]] double apparent_rim_stress(const ParallelPlate& plate, double torque);
// τ_R = T/(2πR³)(3 + n′) [Pa].
[[nodiscard]] double corrected_rim_stress(const ParallelPlate& plate, double torque, double log_slope);

struct LocalSlopeOptions {
  // Points on each side of the evaluation point; near the ends the window keeps its size
  // (2·half_window + 1 points, or all points if fewer) and shifts inwards.
  int half_window = 2;
};

// d ln y / d ln x at every point from a local weighted least-squares polynomial in ln x:
// quadratic when the window has >= 3 points, else the straight line through the two points.
// Weights: tricube kernel w = (1 − (|Δ|/(2 Δ_max))³)³ of the distance Δ in ln x from the
// evaluation point (Δ_max: the window's largest), so the centre counts most and the window's
// far end about 2/3; times 1/σ²(ln y) when relative errors of y are given. The fit is exact
// (to round-off) wherever ln y is a quadratic in ln x, so n′ of a power law is exact.
// x must be positive and distinct (any order), y positive. Results in the input order.
struct LocalSlopes {
  std::vector<double> slope;      // d ln y / d ln x
  std::vector<double> std_error;  // from the local fit's weighted residuals; NaN without spare points
};
[[nodiscard]] LocalSlopes local_log_slopes(std::span<const double> x, std::span<const double> y,
                                           std::span<const double> relative_errors = {},
                                           const LocalSlopeOptions& options = {});

struct RimStressCurve {
  std::vector<double> rim_shear_rate;       // γ̇_R [1/s], as given
  std::vector<double> torque;               // T [N·m], as given
  std::vector<double> log_slope;            // n′ = d ln T / d ln γ̇_R
  std::vector<double> log_slope_std_error;  // of n′ (NaN when the window has no spare points)
  std::vector<double> apparent_stress;      // τ_app = 2T/(πR³) [Pa]
  std::vector<double> corrected_stress;     // τ_R = T/(2πR³)(3 + n′) [Pa]
  std::vector<double> apparent_viscosity;   // τ_app/γ̇_R [Pa·s]
  std::vector<double> corrected_viscosity;  // τ_R/γ̇_R [Pa·s]
};

// Needs >= 2 points with positive, distinct rates and positive torques (std::invalid_argument
// otherwise). torque_relative_errors (σ_T/T per point, optional) weight the local slope fits.
[[nodiscard]] RimStressCurve rim_stress_curve(const ParallelPlate& plate, std::span<const double> rim_shear_rate,
                                              std::span<const double> torque,
                                              std::span<const double> torque_relative_errors = {},
                                              const LocalSlopeOptions& options = {});

// ---------------------------------------------------------------------------------------------
// 2. Flow-curve fits

enum class FitWarningKind {
  not_converged,                 // the solver stopped without meeting a convergence test
  no_degrees_of_freedom,         // n − p < 1: no residual variance, no standard errors
  singular_jacobian,             // parameters not separately identifiable at the optimum
  high_correlation,              // |ρ_ij| > FitOptions::correlation_limit
  large_relative_error,          // se/|p| > FitOptions::relative_error_limit
  at_bound,                      // a bounded parameter sits on its bound (e.g. τ_y = 0)
  yield_stress_not_significant,  // the yield stress interval includes 0
};
[[nodiscard]] std::string_view to_string(FitWarningKind kind);

struct FitWarning {
  FitWarningKind kind;
  std::string parameter;  // empty for whole-fit warnings; "a,b" for a correlated pair
  std::string message;    // one sentence, with the numbers
};

struct FitOptions {
  LeastSquaresOptions solver;         // tolerances of the Levenberg–Marquardt solver
  double confidence = 0.95;           // of the intervals, in (0, 1)
  double correlation_limit = 0.99;    // |ρ| above this warns
  double relative_error_limit = 1.0;  // se/|p| above this warns (100 %)
};

// One fitted flow curve. Standard errors, covariance and intervals come from the Jacobian at the
// optimum scaled by s² = Σr²/(n − p), r_i = (τ_model,i − τ_i)/τ_i: computed in each parameter's
// fit coordinate θ (ln p for scale parameters; flow_models.hpp), intervals θ ± t_{0.975,n−p} se_θ
// mapped back to p, standard errors by the delta method. AIC = n ln(Σr²/n) + 2k and
// AICc = AIC + 2k(k + 1)/(n − k − 1) (+∞ when n − k − 1 <= 0) with k = p + 1 (the p
// parameters and the residual variance); only differences between fits to the same data mean
// anything.
struct FitResult {
  std::shared_ptr<const FlowModel> model;
  std::string model_name;
  std::vector<std::string> parameter_names;
  std::vector<std::string> units;
  std::vector<double> params;      // physical values
  std::vector<double> std_errors;  // NaN when n − p < 1, the Jacobian is singular, or dp/dθ = 0
                                   // (Casson's τ_y at 0: read the interval)
  std::vector<Interval> ci95;      // at FitOptions::confidence (95 % by default)
  Eigen::MatrixXd covariance;      // of params (delta method)
  Eigen::MatrixXd correlation;     // of params (available even when n − p < 1)
  Eigen::MatrixXd fit_covariance;  // of the fit coordinates θ (used by predict())
  std::vector<double> residuals;   // relative: (τ_model − τ)/τ, in data order
  std::vector<double> shear_rate;  // the data fitted
  std::vector<double> stress;
  int points = 0;                                                  // n
  int degrees_of_freedom = 0;                                      // n − p
  double sum_of_squares = 0;                                       // Σ r²
  double residual_std = std::numeric_limits<double>::quiet_NaN();  // s = √(Σr²/(n − p)): relative scatter
  double aic = std::numeric_limits<double>::quiet_NaN();
  double aicc = std::numeric_limits<double>::quiet_NaN();
  double t_quantile = std::numeric_limits<double>::quiet_NaN();
  double min_shear_rate = 0;  // the data range; predict() flags extrapolation beyond it
  double max_shear_rate = 0;
  bool converged = false;
  int iterations = 0;
  std::string stop_reason;
  std::vector<FitWarning> warnings;

  [[nodiscard]] bool has_warning(FitWarningKind kind) const;
  [[nodiscard]] std::size_t index(std::string_view parameter) const;  // throws std::out_of_range
  [[nodiscard]] double value(std::string_view parameter) const { return params[index(parameter)]; }
};

// Fits `model` to (γ̇, τ) (positive, finite; >= 1 point; std::invalid_argument otherwise) from each
// of the model's initial guesses and keeps the lowest Σr² (converged fits first).
[[nodiscard]] FitResult fit_flow_curve(std::shared_ptr<const FlowModel> model, std::span<const double> shear_rate,
                                       std::span<const double> stress, const FitOptions& options = {});
[[nodiscard]] FitResult fit_flow_curve(std::string_view model_name, std::span<const double> shear_rate,
                                       std::span<const double> stress, const FitOptions& options = {});
// Every named model (all built-in models when `model_names` is empty).
[[nodiscard]] std::vector<FitResult> fit_flow_curves(std::span<const std::string> model_names,
                                                     std::span<const double> shear_rate, std::span<const double> stress,
                                                     const FitOptions& options = {});

// Model comparison by AICc, best first, with Akaike weights. A model whose AICc is infinite (too
// few points: n − k − 1 <= 0) ranks last with Δ = ∞ and weight 0. When fewer than two models
// have a finite AICc, plain AIC ranks the models with n − p >= 1 and the others rank last.
struct ModelRanking {
  std::string model_name;
  std::size_t fit_index = 0;  // into the span passed in
  double aic = 0;
  double aicc = 0;
  double delta = 0;   // criterion − best
  double weight = 0;  // exp(−Δ/2) / Σ exp(−Δ/2)
};
[[nodiscard]] std::vector<ModelRanking> rank_by_aic(std::span<const FitResult> fits);

// The fitted curve at one shear rate, with the standard error and confidence band of the mean
// curve (delta method in the fit coordinates). is_extrapolated is true outside the fitted
// range [min_shear_rate, max_shear_rate]; then `warning` says so.
struct FlowPrediction {
  double shear_rate = 0;
  double stress = 0;  // [Pa]
  double stress_std_error = std::numeric_limits<double>::quiet_NaN();
  Interval stress_ci95;  // at the fit's confidence
  double viscosity = 0;  // τ/γ̇ [Pa·s]
  double viscosity_std_error = std::numeric_limits<double>::quiet_NaN();
  bool is_extrapolated = false;
  std::string warning;
};
[[nodiscard]] FlowPrediction predict(const FitResult& fit, double shear_rate);

// ---------------------------------------------------------------------------------------------
// 3. Yield stress, several estimates kept apart

struct YieldStressEstimate {
  std::string method;  // "bingham_intercept", "casson_intercept", "herschel_bulkley", "torque_intercept"
  double value = std::numeric_limits<double>::quiet_NaN();      // τ_y [Pa]
  double std_error = std::numeric_limits<double>::quiet_NaN();  // [Pa]
  Interval ci95;
  bool is_significant = false;  // the interval excludes 0 (lower bound > 0)
  bool converged = false;
  std::vector<std::string> warnings;
};

// The yield-stress parameter of a fit of a model that has one (Bingham, Casson, HB).
[[nodiscard]] YieldStressEstimate yield_stress_from_fit(const FitResult& fit, std::string method);

// The seed's method (CD §4, Fig. 7): a straight line T = T₀ + b γ̇_R by ordinary least squares,
// extrapolated to γ̇_R = 0. A rate-independent (plastic) stress τ_y gives T = 2πR³τ_y/3, so
//   τ_y = 3T₀/(2πR³),  and for a Bingham fluid T = 2πR³(τ_y/3 + η_p γ̇_R/4) exactly,
//   η_p = 2b/(πR³).
// Intervals: t_{0.975, n−2} with the usual straight-line standard errors (n >= 3 for them).
// The intercept is not constrained: a negative τ_y says the torque line does not support one.
struct TorqueLineFit {
  double intercept = 0;  // T₀ [N·m]
  double slope = 0;      // b [N·m·s]
  double intercept_std_error = std::numeric_limits<double>::quiet_NaN();
  double slope_std_error = std::numeric_limits<double>::quiet_NaN();
  double plastic_viscosity = 0;  // 2b/(πR³) [Pa·s]
  Interval plastic_viscosity_ci95;
  std::vector<double> residuals;  // T − line [N·m]
  YieldStressEstimate yield_stress;
};
[[nodiscard]] TorqueLineFit fit_torque_line(const ParallelPlate& plate, std::span<const double> rim_shear_rate,
                                            std::span<const double> torque, double confidence = 0.95);

struct YieldStressEstimates {
  YieldStressEstimate bingham_intercept;  // Bingham fit to (γ̇_R, τ_R)
  YieldStressEstimate casson_intercept;   // Casson fit to (γ̇_R, τ_R)
  YieldStressEstimate herschel_bulkley;   // HB fit to (γ̇_R, τ_R)
  YieldStressEstimate torque_intercept;   // the seed's torque line (fit_torque_line)
  [[nodiscard]] std::vector<YieldStressEstimate> all() const;
};

// All four from a torque curve: rim_stress_curve, then the three fits on the corrected stress,
// then the torque line on the raw torque.
[[nodiscard]] YieldStressEstimates estimate_yield_stress(const ParallelPlate& plate,
                                                         std::span<const double> rim_shear_rate,
                                                         std::span<const double> torque,
                                                         const FitOptions& options = {});

// ---------------------------------------------------------------------------------------------
// 4. Relative viscosity η_r(φ)

struct RelativeViscosityPoint {
  double volume_fraction = 0;     // φ
  double relative_viscosity = 1;  // η_r = η/η_f
  double std_error = 0;           // of η_r; 0 when unknown
};

// η_r = η/η_f with first-order error propagation for independent errors:
// σ_r = η_r √((σ/η)² + (σ_f/η_f)²).
[[nodiscard]] RelativeViscosityPoint relative_viscosity(double volume_fraction, double viscosity,
                                                        double viscosity_std_error, double fluid_viscosity,
                                                        double fluid_viscosity_std_error = 0);
// The same from two fitted flow curves evaluated at one shear rate (predict()): η and its
// standard error from the suspension's fit, η_f and its standard error from the liquid's
// (an unavailable, NaN, standard error counts as unknown: 0).
[[nodiscard]] RelativeViscosityPoint relative_viscosity(double volume_fraction, const FlowPrediction& suspension,
                                                        const FlowPrediction& fluid);

// Correlations (φ < φ_m for the last two).
[[nodiscard]] double einstein_relative_viscosity(double phi);   // 1 + 2.5φ
[[nodiscard]] double batchelor_relative_viscosity(double phi);  // 1 + 2.5φ + 6.2φ²
[[nodiscard]] double krieger_dougherty_relative_viscosity(double phi, double max_packing,
                                                          double intrinsic_viscosity = 2.5);  // (1 − φ/φ_m)^(−[η]φ_m)
[[nodiscard]] double maron_pierce_relative_viscosity(double phi, double max_packing = 0.63);  // (1 − φ/φ_m)^(−2)
// Measured non-Brownian suspensions (φ < φ_m):
// Boyer, Guazzelli & Pouliquen, PRL 107 (2011) 188301, the μ(J) fit of their pressure-imposed
// rheometry: J = (φ_m/φ − 1)², μ(J) = μ1 + (μ2 − μ1)/(1 + I0/J) + J + (5/2)φ_m J^½, η_r = μ/J,
// with μ1 = 0.32, μ2 = 0.7, I0 = 0.005 and their jamming fraction φ_m = 0.585 (another φ_m
// gives the same law's shape around another jamming point); its particle pressure is Π = η_f γ̇/J.
inline constexpr double boyer_jamming_fraction = 0.585;
[[nodiscard]] double boyer_relative_viscosity(double phi, double jamming_fraction = boyer_jamming_fraction);
[[nodiscard]] double boyer_friction_coefficient(double phi, double jamming_fraction = boyer_jamming_fraction);  // τ/Π
// Zarraga, Hill & Leighton, J. Rheol. 44 (2000) 185: η_r = e^(−2.34φ)/(1 − φ/0.62)³.
[[nodiscard]] double zarraga_relative_viscosity(double phi);

// A correlation compared with the data: residuals are normalised by σ_i when every point has a
// positive std_error, else relative ((model − η_r)/η_r).
struct CorrelationComparison {
  std::string name;  // "einstein", "batchelor", "krieger_dougherty", "maron_pierce"
  std::vector<double> predicted;
  std::vector<double> residuals;
  double sum_of_squares = 0;  // χ² with σ_i, else Σ relative²
  // For the two with a fitted maximum packing fraction φ_m (NaN otherwise):
  double max_packing = std::numeric_limits<double>::quiet_NaN();
  double max_packing_std_error = std::numeric_limits<double>::quiet_NaN();
  Interval max_packing_ci95;  // t interval in ln(φ_m − φ_max,data), mapped back
  double intrinsic_viscosity = std::numeric_limits<double>::quiet_NaN();  // [η] used (KD)
  int degrees_of_freedom = 0;
  double aic = std::numeric_limits<double>::quiet_NaN();  // n ln(SS/n) + 2k, k = fitted + 1
  bool converged = true;
  std::vector<std::string> warnings;
};

// φ_m by weighted least squares (weights as above), kept above the largest φ of the data; the
// covariance is scaled by the residual variance (needs >= 2 points for an interval).
[[nodiscard]] CorrelationComparison fit_krieger_dougherty(std::span<const RelativeViscosityPoint> points,
                                                          double intrinsic_viscosity = 2.5,
                                                          const FitOptions& options = {});
[[nodiscard]] CorrelationComparison fit_maron_pierce(std::span<const RelativeViscosityPoint> points,
                                                     const FitOptions& options = {});

struct RelativeViscosityAnalysis {
  std::vector<RelativeViscosityPoint> points;
  CorrelationComparison einstein;
  CorrelationComparison batchelor;
  CorrelationComparison krieger_dougherty;  // φ_m fitted, [η] = 2.5
  CorrelationComparison maron_pierce;       // φ_m fitted
};
[[nodiscard]] RelativeViscosityAnalysis analyze_relative_viscosity(std::span<const RelativeViscosityPoint> points,
                                                                   const FitOptions& options = {});

// ---------------------------------------------------------------------------------------------
// 5. Validity of a measured point

struct ValidityLimits {
  double max_gap_reynolds = 1.0;       // secondary flow becomes O(1) (docs/openfoam.md)
  double max_particle_reynolds = 0.1;  // inertia at the particle scale negligible
  double max_stokes = 0.1;             // particles follow the flow (viscous, not inertial, collisions)
  double min_gap_to_diameter = 10.0;   // the sample is a continuum across the gap
};

struct PointConditions {
  double rim_shear_rate = 0;     // γ̇_R [1/s]
  double density = 0;            // of the sample (suspension) ρ [kg/m³]
  double viscosity = 0;          // of the sample at γ̇_R, e.g. τ_R/γ̇_R [Pa·s]
  double fluid_density = 0;      // of the suspending liquid ρ_f; 0: use `density`
  double fluid_viscosity = 0;    // of the suspending liquid at γ̇_R η_f; 0: use `viscosity`
  double particle_diameter = 0;  // d [m]; 0: single phase (particle checks pass)
  double particle_density = 0;   // ρ_p [kg/m³]
};

// Definitions (Ω = γ̇_R H/R):
//   gap Reynolds number       Re_gap = ρ Ω H²/η          (sample density and viscosity)
//   particle Reynolds number  Re_p   = ρ_f γ̇_R d²/η_f    (at the rim, where γ̇ is largest)
//   Stokes number             St     = ρ_p γ̇_R d²/η_f
//   gap-to-particle ratio     H/d >= 10
struct PointValidity {
  double gap_reynolds = 0;
  double particle_reynolds = 0;
  double stokes = 0;
  double gap_to_diameter = std::numeric_limits<double>::infinity();
  bool gap_reynolds_ok = true;
  bool particle_reynolds_ok = true;
  bool stokes_ok = true;
  bool gap_to_diameter_ok = true;
  std::vector<std::string> messages;  // one per failed check, with the numbers
  [[nodiscard]] bool is_valid() const {
    return gap_reynolds_ok && particle_reynolds_ok && stokes_ok && gap_to_diameter_ok;
  }
};
[[nodiscard]] PointValidity check_validity(const ParallelPlate& plate, const PointConditions& point,
                                           const ValidityLimits& limits = {});

}  // namespace rheosim::rheometer
