#pragma once
// Nonlinear least squares for the analysis of flow curves (rheometer/analysis.hpp): a
// Levenberg–Marquardt solver with simple lower bounds, the parameter statistics taken from the
// Jacobian at the optimum, and the Student t distribution for the intervals. Pure numerics.
//
// Parameters live in two spaces. A physical value p (a viscosity, a yield stress) is moved by the
// solver in its *fit coordinate* θ, chosen per parameter by a ParameterScale:
//   free      p = θ                       any real
//   at_least  p = θ,        θ ≥ origin    bounded; the solver projects onto the bound
//   log       p = origin + e^θ            p > origin (scale parameters: η, k, λ, n)
//   square    p = origin + θ², θ ≥ 0      bounded at origin with a smooth model there (Casson:
//                                         τ = (√τ_y + √(η_p γ̇))² is smooth in √τ_y, not in τ_y)
// Standard errors and t intervals are computed for θ (where the model is fitted) and mapped to p:
// the interval through the monotone map p(θ) after clipping to θ's domain, the standard error by
// the delta method, se_p = |dp/dθ| se_θ.
#include <cstddef>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace rheosim::rheometer {

// A closed interval [lower, upper]; NaN bounds when it could not be computed.
struct Interval {
  double lower = std::numeric_limits<double>::quiet_NaN();
  double upper = std::numeric_limits<double>::quiet_NaN();
  [[nodiscard]] bool contains(double x) const { return lower <= x && x <= upper; }
  [[nodiscard]] bool is_finite() const;
  [[nodiscard]] double width() const { return upper - lower; }
};

// How a physical parameter maps to the coordinate the solver moves (see the file comment).
struct ParameterScale {
  enum class Kind { free, at_least, log, square };
  Kind kind = Kind::free;
  double origin = 0;  // the bound (at_least, square) or the excluded lower limit (log)

  static ParameterScale unbounded() { return {Kind::free, 0}; }
  static ParameterScale at_least(double bound) { return {Kind::at_least, bound}; }
  static ParameterScale positive(double above = 0) { return {Kind::log, above}; }
  static ParameterScale squared(double bound = 0) { return {Kind::square, bound}; }

  [[nodiscard]] double value(double coordinate) const;       // p(θ)
  [[nodiscard]] double coordinate(double value) const;       // θ(p); p outside the domain is clamped into it
  [[nodiscard]] double derivative(double coordinate) const;  // dp/dθ
  [[nodiscard]] double coordinate_lower_bound() const;       // −∞, origin or 0
  // Maps an interval of θ to one of p: clip to θ's domain, then p(θ) (monotone increasing).
  [[nodiscard]] Interval value_interval(Interval coordinates) const;
};

struct LeastSquaresOptions {
  int max_iterations = 500;           // accepted plus rejected trial steps
  double step_tolerance = 1e-12;      // stop when every |Δθ_j| ≤ tol (1 + |θ_j|)
  double cost_tolerance = 1e-15;      // stop when actual and predicted relative cost reductions ≤ tol
  double gradient_tolerance = 1e-13;  // stop when every |cos(r, J_j)| ≤ tol (MINPACK's gtol)
  double initial_damping = 1e-3;      // λ₀, relative to the column-norm scaling D (MINPACK)
};

// Residuals r(θ) (size m) and, when `jacobian` is not null, ∂r/∂θ (m × n) at θ.
using ResidualFunction =
    std::function<void(std::span<const double> theta, Eigen::VectorXd& residuals, Eigen::MatrixXd* jacobian)>;

struct LeastSquaresSolution {
  std::vector<double> coordinates;  // θ at the optimum
  Eigen::VectorXd residuals;        // r(θ)
  Eigen::MatrixXd jacobian;         // ∂r/∂θ at θ
  double sum_of_squares = 0;        // Σ r²
  std::vector<bool> at_bound;       // θ_j on its lower bound
  bool converged = false;
  int iterations = 0;       // trial steps taken
  std::string stop_reason;  // which test stopped the solver
};

// Minimises Σ r_i(θ)² from `start` with θ_j ≥ lower_bounds[j] (−∞ for none; an empty span means
// unbounded) by Levenberg–Marquardt: steps solve min ‖J δ + r‖² + λ‖D δ‖² (D: running maxima of
// the column norms of J, MINPACK), bound parameters that the gradient pushes outwards are held,
// trial points are projected onto the bounds, and λ follows the gain ratio (Nielsen's update).
// The start is clamped onto the bounds. Throws std::invalid_argument for no parameters, no
// residuals or bounds of the wrong size; as many parameters as residuals (or more) is allowed:
// the statistics then report no degrees of freedom.
[[nodiscard]] LeastSquaresSolution solve_least_squares(const ResidualFunction& residuals, std::size_t residual_count,
                                                       std::span<const double> start,
                                                       std::span<const double> lower_bounds = {},
                                                       const LeastSquaresOptions& options = {});

// Statistics of a least-squares optimum in the fit coordinates θ.
struct ParameterStatistics {
  int degrees_of_freedom = 0;                                           // m − n
  double residual_variance = std::numeric_limits<double>::quiet_NaN();  // s² = Σr²/(m − n); NaN when m ≤ n
  int rank = 0;                                                         // numerical rank of the column-scaled Jacobian
  bool is_singular = false;                                             // rank < n (then the covariance is NaN)
  Eigen::MatrixXd covariance;                                           // s² (JᵀJ)⁻¹
  std::vector<double> std_errors;                                       // √diag
  Eigen::MatrixXd correlation;                                          // cov_ij / (se_i se_j)
  double t_quantile = std::numeric_limits<double>::quiet_NaN();         // t_{(1+c)/2, m−n}
  std::vector<Interval> intervals;                                      // θ_j ± t se_j
};

// Covariance from the Jacobian at the optimum, scaled by the residual variance; Student t
// intervals at `confidence` with m − n degrees of freedom. The rank is found from the SVD of J
// with unit-norm columns (relative singular-value threshold `rank_tolerance`).
[[nodiscard]] ParameterStatistics parameter_statistics(const Eigen::MatrixXd& jacobian,
                                                       const Eigen::VectorXd& residuals,
                                                       std::span<const double> coordinates, double confidence = 0.95,
                                                       double rank_tolerance = 1e-10);

// Student t distribution with ν > 0 degrees of freedom (ν need not be an integer).
[[nodiscard]] double student_t_cdf(double t, double dof);
[[nodiscard]] double student_t_quantile(double probability, double dof);  // probability in (0, 1)
// Regularised incomplete beta function I_x(a, b), a, b > 0, x in [0, 1].
[[nodiscard]] double regularized_incomplete_beta(double x, double a, double b);

}  // namespace rheosim::rheometer
