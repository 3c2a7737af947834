// Levenberg–Marquardt with lower bounds, parameter statistics and the Student t distribution
// (rheometer/least_squares.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "rheosim/rheometer/least_squares.hpp"

namespace rheosim::rheometer {

namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();
}  // namespace

bool Interval::is_finite() const { return std::isfinite(lower) && std::isfinite(upper); }

// ---------------------------------------------------------------------------------------------
// ParameterScale

double ParameterScale::value(double coordinate) const {
  switch (kind) {
    case Kind::free:
    case Kind::at_least:
      return coordinate;
    case Kind::log:
      return origin + std::exp(coordinate);
    case Kind::square:
      return origin + coordinate * coordinate;
  }
  return nan;
}

double ParameterScale::coordinate(double v) const {
  switch (kind) {
    case Kind::free:
      return v;
    case Kind::at_least:
      return std::max(v, origin);
    case Kind::log: {
      // p must exceed the origin: a value at or below it is moved just above.
      const double excess = v - origin;
      const double floor = 1e-300;
      return std::log(std::max(excess, floor));
    }
    case Kind::square:
      return std::sqrt(std::max(v - origin, 0.0));
  }
  return nan;
}

double ParameterScale::derivative(double coordinate) const {
  switch (kind) {
    case Kind::free:
    case Kind::at_least:
      return 1.0;
    case Kind::log:
      return std::exp(coordinate);
    case Kind::square:
      return 2.0 * coordinate;
  }
  return nan;
}

double ParameterScale::coordinate_lower_bound() const {
  switch (kind) {
    case Kind::free:
    case Kind::log:
      return -inf;
    case Kind::at_least:
      return origin;
    case Kind::square:
      return 0.0;
  }
  return nan;
}

Interval ParameterScale::value_interval(Interval coordinates) const {
  if (std::isnan(coordinates.lower) || std::isnan(coordinates.upper)) return {};
  const double bound = coordinate_lower_bound();
  const double lo = std::max(coordinates.lower, bound);
  const double hi = std::max(coordinates.upper, bound);
  return {value(lo), value(hi)};
}

// ---------------------------------------------------------------------------------------------
// Levenberg–Marquardt

namespace {

void evaluate_checked(const ResidualFunction& f, std::span<const double> theta, std::size_t m, Eigen::VectorXd& r,
                      Eigen::MatrixXd* jacobian) {
  f(theta, r, jacobian);
  if (static_cast<std::size_t>(r.size()) != m)
    throw std::invalid_argument("least squares: the residual function returned " + std::to_string(r.size()) +
                                " residuals, expected " + std::to_string(m));
  if (jacobian != nullptr &&
      (static_cast<std::size_t>(jacobian->rows()) != m || jacobian->cols() != static_cast<Eigen::Index>(theta.size())))
    throw std::invalid_argument("least squares: the Jacobian has the wrong shape");
}

bool all_finite(const Eigen::VectorXd& v) { return v.allFinite(); }

}  // namespace

LeastSquaresSolution solve_least_squares(const ResidualFunction& residuals, std::size_t residual_count,
                                         std::span<const double> start, std::span<const double> lower_bounds,
                                         const LeastSquaresOptions& options) {
  const std::size_t n = start.size();
  const std::size_t m = residual_count;
  if (n == 0) throw std::invalid_argument("least squares: no parameters");
  if (m == 0) throw std::invalid_argument("least squares: no residuals");
  if (!lower_bounds.empty() && lower_bounds.size() != n)
    throw std::invalid_argument("least squares: " + std::to_string(lower_bounds.size()) + " lower bounds for " +
                                std::to_string(n) + " parameters");
  if (options.max_iterations < 1) throw std::invalid_argument("least squares: max_iterations must be >= 1");

  std::vector<double> lower(n, -inf);
  if (!lower_bounds.empty()) std::copy(lower_bounds.begin(), lower_bounds.end(), lower.begin());

  LeastSquaresSolution out;
  std::vector<double> theta(start.begin(), start.end());
  for (std::size_t j = 0; j < n; ++j) theta[j] = std::max(theta[j], lower[j]);

  Eigen::VectorXd r;
  Eigen::MatrixXd jac;
  evaluate_checked(residuals, theta, m, r, &jac);
  int iterations = 0;  // trial steps
  auto finish = [&](bool converged, std::string reason) {
    out.coordinates = theta;
    out.residuals = r;
    out.jacobian = jac;
    out.sum_of_squares = r.squaredNorm();
    out.at_bound.assign(n, false);
    for (std::size_t j = 0; j < n; ++j) out.at_bound[j] = std::isfinite(lower[j]) && theta[j] <= lower[j];
    out.converged = converged;
    out.iterations = std::min(iterations, options.max_iterations);
    out.stop_reason = std::move(reason);
    return out;
  };
  if (!all_finite(r) || !jac.allFinite()) {
    finish(false, "residuals or Jacobian not finite at the start");
    out.sum_of_squares = inf;
    return out;
  }

  double cost = r.squaredNorm();
  Eigen::VectorXd scale = jac.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < scale.size(); ++j)
    if (!(scale[j] > 0)) scale[j] = 1.0;
  double damping = options.initial_damping;
  double growth = 2.0;

  while (true) {
    if (cost == 0.0) return finish(true, "residuals vanish");
    const Eigen::VectorXd gradient = jac.transpose() * r;
    // Parameters on their bound that the descent direction −g pushes outwards are held.
    std::vector<Eigen::Index> free;
    for (std::size_t j = 0; j < n; ++j) {
      const auto jj = static_cast<Eigen::Index>(j);
      if (!(std::isfinite(lower[j]) && theta[j] <= lower[j] && gradient[jj] > 0)) free.push_back(jj);
    }
    // Gradient test: the residual is orthogonal to every free column of J (cosine ≤ gtol).
    const double rnorm = std::sqrt(cost);
    double max_cosine = 0;
    for (const auto j : free) {
      const double cnorm = jac.col(j).norm();
      if (cnorm > 0) max_cosine = std::max(max_cosine, std::abs(gradient[j]) / (cnorm * rnorm));
    }
    if (free.empty() || max_cosine <= options.gradient_tolerance) return finish(true, "gradient");
    for (Eigen::Index j = 0; j < scale.size(); ++j) scale[j] = std::max(scale[j], jac.col(j).norm());

    const auto nf = static_cast<Eigen::Index>(free.size());
    const auto mi = static_cast<Eigen::Index>(m);
    while (true) {
      if (++iterations > options.max_iterations) return finish(false, "iteration limit");
      // min ‖J_F δ + r‖² + λ‖D_F δ‖² as one stacked linear least-squares problem.
      Eigen::MatrixXd a = Eigen::MatrixXd::Zero(mi + nf, nf);
      Eigen::VectorXd b = Eigen::VectorXd::Zero(mi + nf);
      for (Eigen::Index k = 0; k < nf; ++k) {
        a.col(k).head(mi) = jac.col(free[static_cast<std::size_t>(k)]);
        a(mi + k, k) = std::sqrt(damping) * scale[free[static_cast<std::size_t>(k)]];
      }
      b.head(mi) = -r;
      const Eigen::VectorXd step_free = a.colPivHouseholderQr().solve(b);

      std::vector<double> trial = theta;
      for (Eigen::Index k = 0; k < nf; ++k) {
        const auto j = static_cast<std::size_t>(free[static_cast<std::size_t>(k)]);
        trial[j] = std::max(theta[j] + step_free[k], lower[j]);
      }
      Eigen::VectorXd step(static_cast<Eigen::Index>(n));
      bool step_small = true;
      for (std::size_t j = 0; j < n; ++j) {
        step[static_cast<Eigen::Index>(j)] = trial[j] - theta[j];
        if (!(std::abs(trial[j] - theta[j]) <= options.step_tolerance * (1.0 + std::abs(theta[j])))) step_small = false;
      }
      // Reductions as sums of products, free of the cancellation in cost − cost′ (a large residual
      // held on a bound would otherwise hide the improvement of the others).
      const Eigen::VectorXd change = jac * step;
      const double predicted = -change.dot(2.0 * r + change);

      Eigen::VectorXd r_trial;
      Eigen::MatrixXd jac_trial;
      evaluate_checked(residuals, trial, m, r_trial, &jac_trial);
      const bool finite = all_finite(r_trial) && jac_trial.allFinite();
      const double cost_trial = finite ? r_trial.squaredNorm() : inf;
      const double actual = finite ? (r - r_trial).dot(r + r_trial) : -inf;
      const double gain = predicted > 0 ? actual / predicted : (actual > 0 ? 1.0 : -1.0);

      if (finite && gain > 1e-4) {
        theta = std::move(trial);
        r = std::move(r_trial);
        jac = std::move(jac_trial);
        const double previous = cost;
        cost = cost_trial;
        damping *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * gain - 1.0, 3));
        growth = 2.0;
        if (step_small) return finish(true, "step");
        if (actual <= options.cost_tolerance * previous && predicted <= options.cost_tolerance * previous)
          return finish(true, "cost");
        break;
      }
      // Rejected: a tiny step that cannot lower the cost means θ is optimal to round-off.
      if (step_small && finite) return finish(true, "step");
      damping *= growth;
      growth *= 2.0;
      if (damping > 1e30) return finish(false, "damping overflow (no descent found)");
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Statistics

ParameterStatistics parameter_statistics(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residuals,
                                         std::span<const double> coordinates, double confidence,
                                         double rank_tolerance) {
  const Eigen::Index m = jacobian.rows();
  const Eigen::Index n = jacobian.cols();
  if (static_cast<Eigen::Index>(coordinates.size()) != n || residuals.size() != m)
    throw std::invalid_argument("parameter_statistics: sizes of Jacobian, residuals and parameters differ");
  if (!(confidence > 0 && confidence < 1))
    throw std::invalid_argument("parameter_statistics: confidence must be in (0, 1)");

  ParameterStatistics s;
  s.degrees_of_freedom = static_cast<int>(m - n);
  if (s.degrees_of_freedom > 0)
    s.residual_variance = residuals.squaredNorm() / static_cast<double>(s.degrees_of_freedom);
  const auto un = static_cast<std::size_t>(n);
  s.covariance = Eigen::MatrixXd::Constant(n, n, nan);
  s.correlation = Eigen::MatrixXd::Constant(n, n, nan);
  s.std_errors.assign(un, nan);
  s.intervals.assign(un, Interval{});
  if (s.degrees_of_freedom > 0) s.t_quantile = student_t_quantile(0.5 * (1.0 + confidence), s.degrees_of_freedom);

  // Column scaling makes the rank test independent of the parameters' units.
  Eigen::VectorXd norms = jacobian.colwise().norm().transpose();
  bool usable = jacobian.allFinite();
  for (Eigen::Index j = 0; j < n; ++j)
    if (!(norms[j] > 0)) usable = false;
  if (!usable) {
    s.is_singular = true;
    s.rank = 0;
    return s;
  }
  const Eigen::MatrixXd scaled = jacobian * norms.cwiseInverse().asDiagonal();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  const double threshold = rank_tolerance * sv[0];
  s.rank = 0;
  for (Eigen::Index k = 0; k < sv.size(); ++k)
    if (sv[k] > threshold) ++s.rank;
  if (s.rank < n) {
    s.is_singular = true;
    return s;
  }
  // (JᵀJ)⁻¹ = N⁻¹ V Σ⁻² Vᵀ N⁻¹ with N the column norms.
  const Eigen::MatrixXd& v = svd.matrixV();
  const Eigen::MatrixXd inner = v * sv.cwiseInverse().cwiseAbs2().asDiagonal() * v.transpose();
  const Eigen::MatrixXd unscaled = norms.cwiseInverse().asDiagonal() * inner * norms.cwiseInverse().asDiagonal();
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      s.correlation(i, j) = unscaled(i, j) / std::sqrt(unscaled(i, i) * unscaled(j, j));
  if (s.degrees_of_freedom <= 0) return s;
  s.covariance = s.residual_variance * unscaled;
  for (std::size_t j = 0; j < un; ++j) {
    const auto jj = static_cast<Eigen::Index>(j);
    s.std_errors[j] = std::sqrt(s.covariance(jj, jj));
    s.intervals[j] = {coordinates[j] - s.t_quantile * s.std_errors[j], coordinates[j] + s.t_quantile * s.std_errors[j]};
  }
  return s;
}

// ---------------------------------------------------------------------------------------------
// Student t

namespace {

// Continued fraction of the incomplete beta function (modified Lentz).
double beta_continued_fraction(double x, double a, double b) {
  constexpr double tiny = 1e-300;
  constexpr double eps = 1e-16;
  const double qab = a + b;
  const double qap = a + 1.0;
  const double qam = a - 1.0;
  double c = 1.0;
  double d = 1.0 - qab * x / qap;
  if (std::abs(d) < tiny) d = tiny;
  d = 1.0 / d;
  double h = d;
  for (int k = 1; k <= 10000; ++k) {
    const double kk = k;
    const double k2 = 2.0 * kk;
    double aa = kk * (b - kk) * x / ((qam + k2) * (a + k2));
    d = 1.0 + aa * d;
    if (std::abs(d) < tiny) d = tiny;
    c = 1.0 + aa / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + kk) * (qab + kk) * x / ((a + k2) * (qap + k2));
    d = 1.0 + aa * d;
    if (std::abs(d) < tiny) d = tiny;
    c = 1.0 + aa / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < eps) break;
  }
  return h;
}

}  // namespace

double regularized_incomplete_beta(double x, double a, double b) {
  if (!(a > 0 && b > 0)) throw std::invalid_argument("regularized_incomplete_beta: a and b must be > 0");
  if (!(x >= 0 && x <= 1)) throw std::invalid_argument("regularized_incomplete_beta: x must be in [0, 1]");
  if (x == 0 || x == 1) return x;
  const double log_front =
      a * std::log(x) + b * std::log1p(-x) - (std::lgamma(a) + std::lgamma(b) - std::lgamma(a + b));
  if (x < (a + 1.0) / (a + b + 2.0)) return std::exp(log_front) * beta_continued_fraction(x, a, b) / a;
  return 1.0 - std::exp(log_front) * beta_continued_fraction(1.0 - x, b, a) / b;
}

double student_t_cdf(double t, double dof) {
  if (!(dof > 0)) throw std::invalid_argument("student_t_cdf: degrees of freedom must be > 0");
  if (std::isnan(t)) return nan;
  if (std::isinf(t)) return t > 0 ? 1.0 : 0.0;
  const double x = dof / (dof + t * t);
  const double tail = 0.5 * regularized_incomplete_beta(x, 0.5 * dof, 0.5);
  return t >= 0 ? 1.0 - tail : tail;
}

double student_t_quantile(double probability, double dof) {
  if (!(dof > 0)) throw std::invalid_argument("student_t_quantile: degrees of freedom must be > 0");
  if (!(probability > 0 && probability < 1))
    throw std::invalid_argument("student_t_quantile: probability must be in (0, 1)");
  if (probability == 0.5) return 0.0;
  if (probability < 0.5) return -student_t_quantile(1.0 - probability, dof);
  // Solve I_x(ν/2, 1/2) = 2(1 − p) for x = ν/(ν + t²) by bisection: I_x increases with x.
  const double target = 2.0 * (1.0 - probability);
  double lo = 0.0;
  double hi = 1.0;
  for (int k = 0; k < 2000; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    if (regularized_incomplete_beta(mid, 0.5 * dof, 0.5) < target)
      lo = mid;
    else
      hi = mid;
  }
  const double x = 0.5 * (lo + hi);
  return std::sqrt(dof * (1.0 - x) / x);
}

}  // namespace rheosim::rheometer
