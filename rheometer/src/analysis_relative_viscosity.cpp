// Relative viscosity η_r(φ) against the classic correlations (rheometer/analysis.hpp §4).
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "rheosim/rheometer/analysis.hpp"

namespace rheosim::rheometer {

namespace {

void check_points(std::span<const RelativeViscosityPoint> points, std::string_view who) {
  if (points.empty()) throw std::invalid_argument(fmt::format("{}: no points", who));
  for (const auto& p : points) {
    if (!(p.volume_fraction >= 0 && p.volume_fraction < 1))
      throw std::invalid_argument(fmt::format("{}: volume fraction {} not in [0, 1)", who, p.volume_fraction));
    if (!(p.relative_viscosity > 0) || !std::isfinite(p.relative_viscosity))
      throw std::invalid_argument(fmt::format("{}: relative viscosity {} must be positive", who, p.relative_viscosity));
    if (!(p.std_error >= 0))
      throw std::invalid_argument(fmt::format("{}: std_error {} must be >= 0", who, p.std_error));
  }
}

// σ_i when every point has one, else η_r,i (relative residuals).
std::vector<double> residual_scales(std::span<const RelativeViscosityPoint> points) {
  const bool all_errors =
      std::all_of(points.begin(), points.end(), [](const RelativeViscosityPoint& p) { return p.std_error > 0; });
  std::vector<double> out;
  for (const auto& p : points) out.push_back(all_errors ? p.std_error : p.relative_viscosity);
  return out;
}

CorrelationComparison compare(std::string name, std::span<const RelativeViscosityPoint> points,
                              const std::vector<double>& predicted, int fitted_parameters) {
  const auto scales = residual_scales(points);
  CorrelationComparison c;
  c.name = std::move(name);
  c.predicted = predicted;
  for (std::size_t i = 0; i < points.size(); ++i) {
    c.residuals.push_back((predicted[i] - points[i].relative_viscosity) / scales[i]);
    c.sum_of_squares += c.residuals.back() * c.residuals.back();
  }
  const auto n = static_cast<double>(points.size());
  c.degrees_of_freedom = static_cast<int>(points.size()) - fitted_parameters;
  const double k = fitted_parameters + 1.0;
  c.aic =
      c.sum_of_squares > 0 ? n * std::log(c.sum_of_squares / n) + 2.0 * k : -std::numeric_limits<double>::infinity();
  return c;
}

// One-parameter fit of φ_m for η_r = f(φ; φ_m), kept above the largest φ of the data
// (θ = ln(φ_m − φ_max)). dlnf(φ, φ_m) is ∂ ln f/∂φ_m.
template <class F, class DLnF>
CorrelationComparison fit_max_packing(std::string name, std::span<const RelativeViscosityPoint> points,
                                      const FitOptions& options, const F& f, const DLnF& dlnf) {
  double phi_max = 0;
  for (const auto& p : points) phi_max = std::max(phi_max, p.volume_fraction);
  if (!(phi_max > 0)) {
    CorrelationComparison c = compare(std::move(name), points, std::vector<double>(points.size(), 1.0), 1);
    c.converged = false;
    c.warnings.push_back(c.name + ": no point with φ > 0: φ_m cannot be fitted");
    return c;
  }
  const auto scales = residual_scales(points);
  const ParameterScale scale = ParameterScale::positive(phi_max);
  const std::size_t n = points.size();
  const ResidualFunction residuals = [&](std::span<const double> theta, Eigen::VectorXd& r, Eigen::MatrixXd* jac) {
    const double phi_m = scale.value(theta[0]);
    r.resize(static_cast<Eigen::Index>(n));
    if (jac != nullptr) jac->resize(static_cast<Eigen::Index>(n), 1);
    for (std::size_t i = 0; i < n; ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      const double phi = points[i].volume_fraction;
      const double model = f(phi, phi_m);
      r[ii] = (model - points[i].relative_viscosity) / scales[i];
      if (jac != nullptr) (*jac)(ii, 0) = model * dlnf(phi, phi_m) * scale.derivative(theta[0]) / scales[i];
    }
  };
  // Start from the best of a scan of φ_m − φ_max over 1e-4 … 1.
  double best_theta = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  Eigen::VectorXd r;
  for (int k = 0; k <= 60; ++k) {
    const double theta = std::log(1e-4) + (std::log(1.0) - std::log(1e-4)) * k / 60.0;
    const double t[1] = {theta};
    residuals(t, r, nullptr);
    if (r.allFinite() && r.squaredNorm() < best_cost) {
      best_cost = r.squaredNorm();
      best_theta = theta;
    }
  }
  const double start[1] = {best_theta};
  const auto sol = solve_least_squares(residuals, n, start, {}, options.solver);
  const double phi_m = scale.value(sol.coordinates[0]);
  std::vector<double> predicted;
  for (const auto& p : points) predicted.push_back(f(p.volume_fraction, phi_m));
  CorrelationComparison c = compare(std::move(name), points, predicted, 1);
  c.max_packing = phi_m;
  c.converged = sol.converged;
  if (!sol.converged)
    c.warnings.push_back(fmt::format("{}: the φ_m fit did not converge ({})", c.name, sol.stop_reason));
  if (n >= 2) {
    const auto stats = parameter_statistics(sol.jacobian, sol.residuals, sol.coordinates, options.confidence);
    if (!stats.is_singular) {
      c.max_packing_std_error = scale.derivative(sol.coordinates[0]) * stats.std_errors[0];
      c.max_packing_ci95 = scale.value_interval(stats.intervals[0]);
    } else {
      c.warnings.push_back(c.name + ": the data do not depend on φ_m (singular Jacobian)");
    }
    if (c.max_packing_std_error / phi_m > options.relative_error_limit)
      c.warnings.push_back(fmt::format("{}: φ_m = {:.4g} ± {:.3g} is not identifiable from these data", c.name, phi_m,
                                       c.max_packing_std_error));
  } else {
    c.warnings.push_back(c.name + ": one point: φ_m has no interval");
  }
  return c;
}

}  // namespace

RelativeViscosityPoint relative_viscosity(double volume_fraction, double viscosity, double viscosity_std_error,
                                          double fluid_viscosity, double fluid_viscosity_std_error) {
  if (!(viscosity > 0) || !(fluid_viscosity > 0))
    throw std::invalid_argument(
        fmt::format("relative_viscosity: viscosities must be > 0 (got {} and {})", viscosity, fluid_viscosity));
  if (!(viscosity_std_error >= 0) || !(fluid_viscosity_std_error >= 0))
    throw std::invalid_argument("relative_viscosity: standard errors must be >= 0");
  const double eta_r = viscosity / fluid_viscosity;
  const double a = viscosity_std_error / viscosity;
  const double b = fluid_viscosity_std_error / fluid_viscosity;
  return {volume_fraction, eta_r, eta_r * std::sqrt(a * a + b * b)};
}

RelativeViscosityPoint relative_viscosity(double volume_fraction, const FlowPrediction& suspension,
                                          const FlowPrediction& fluid) {
  auto known = [](double se) { return std::isfinite(se) ? se : 0.0; };
  return relative_viscosity(volume_fraction, suspension.viscosity, known(suspension.viscosity_std_error),
                            fluid.viscosity, known(fluid.viscosity_std_error));
}

double einstein_relative_viscosity(double phi) { return 1.0 + 2.5 * phi; }

double batchelor_relative_viscosity(double phi) { return 1.0 + 2.5 * phi + 6.2 * phi * phi; }

double krieger_dougherty_relative_viscosity(double phi, double max_packing, double intrinsic_viscosity) {
  if (!(phi < max_packing)) return std::numeric_limits<double>::infinity();
  return std::pow(1.0 - phi / max_packing, -intrinsic_viscosity * max_packing);
}

double maron_pierce_relative_viscosity(double phi, double max_packing) {
  if (!(phi < max_packing)) return std::numeric_limits<double>::infinity();
  const double base = 1.0 - phi / max_packing;
  return 1.0 / (base * base);
}

namespace {
double boyer_viscous_number(double phi, double jamming) {
  const double root = jamming / phi - 1.0;
  return root * root;
}
}  // namespace

double boyer_friction_coefficient(double phi, double jamming) {
  if (!(phi > 0.0 && phi < jamming)) return std::numeric_limits<double>::quiet_NaN();
  const double j = boyer_viscous_number(phi, jamming);
  constexpr double mu1 = 0.32, mu2 = 0.7, i0 = 0.005;
  return mu1 + (mu2 - mu1) / (1.0 + i0 / j) + j + 2.5 * jamming * std::sqrt(j);
}

double boyer_relative_viscosity(double phi, double jamming) {
  if (phi == 0.0) return 1.0;
  if (!(phi < jamming)) return std::numeric_limits<double>::infinity();
  return boyer_friction_coefficient(phi, jamming) / boyer_viscous_number(phi, jamming);
}

double zarraga_relative_viscosity(double phi) {
  constexpr double max_packing = 0.62;
  if (!(phi < max_packing)) return std::numeric_limits<double>::infinity();
  const double base = 1.0 - phi / max_packing;
  return std::exp(-2.34 * phi) / (base * base * base);
}

CorrelationComparison fit_krieger_dougherty(std::span<const RelativeViscosityPoint> points, double intrinsic_viscosity,
                                            const FitOptions& options) {
  check_points(points, "fit_krieger_dougherty");
  if (!(intrinsic_viscosity > 0)) throw std::invalid_argument("fit_krieger_dougherty: [η] must be > 0");
  const double q = intrinsic_viscosity;
  auto c = fit_max_packing(
      "krieger_dougherty", points, options,
      [q](double phi, double phi_m) { return krieger_dougherty_relative_viscosity(phi, phi_m, q); },
      [q](double phi, double phi_m) {
        // ln η_r = −[η]φ_m ln(1 − φ/φ_m)
        const double x = phi / phi_m;
        return -q * (std::log1p(-x) + x / (1.0 - x));
      });
  c.intrinsic_viscosity = q;
  return c;
}

CorrelationComparison fit_maron_pierce(std::span<const RelativeViscosityPoint> points, const FitOptions& options) {
  check_points(points, "fit_maron_pierce");
  return fit_max_packing(
      "maron_pierce", points, options,
      [](double phi, double phi_m) { return maron_pierce_relative_viscosity(phi, phi_m); },
      [](double phi, double phi_m) {
        // ln η_r = −2 ln(1 − φ/φ_m)
        const double x = phi / phi_m;
        return -2.0 * x / (phi_m * (1.0 - x));
      });
}

RelativeViscosityAnalysis analyze_relative_viscosity(std::span<const RelativeViscosityPoint> points,
                                                     const FitOptions& options) {
  check_points(points, "analyze_relative_viscosity");
  RelativeViscosityAnalysis a;
  a.points.assign(points.begin(), points.end());
  std::vector<double> einstein, batchelor;
  for (const auto& p : points) {
    einstein.push_back(einstein_relative_viscosity(p.volume_fraction));
    batchelor.push_back(batchelor_relative_viscosity(p.volume_fraction));
  }
  a.einstein = compare("einstein", points, einstein, 0);
  a.batchelor = compare("batchelor", points, batchelor, 0);
  a.krieger_dougherty = fit_krieger_dougherty(points, 2.5, options);
  a.maron_pierce = fit_maron_pierce(points, options);
  return a;
}

}  // namespace rheosim::rheometer
