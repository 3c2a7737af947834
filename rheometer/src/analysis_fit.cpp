// Flow-curve fits, model ranking, predictions and yield-stress estimates
// (rheometer/analysis.hpp §2, §3).
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "rheosim/core/units.hpp"
#include "rheosim/rheometer/analysis.hpp"

namespace rheosim::rheometer {

using core::units::pi;

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();

void check_flow_data(std::span<const double> x, std::span<const double> y, std::string_view who) {
  if (x.size() != y.size())
    throw std::invalid_argument(fmt::format("{}: {} shear rates but {} stresses", who, x.size(), y.size()));
  if (x.empty()) throw std::invalid_argument(fmt::format("{}: no data", who));
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(x[i] > 0) || !std::isfinite(x[i]))
      throw std::invalid_argument(fmt::format("{}: shear rate [{}] = {} must be positive and finite", who, i, x[i]));
    if (!(y[i] > 0) || !std::isfinite(y[i]))
      throw std::invalid_argument(
          fmt::format("{}: stress [{}] = {} must be positive and finite (relative residuals)", who, i, y[i]));
  }
}

// Which of two solutions to keep: converged before not converged, then the lower Σr².
bool is_better(const LeastSquaresSolution& a, const LeastSquaresSolution& b) {
  if (a.converged != b.converged) return a.converged;
  return a.sum_of_squares < b.sum_of_squares;
}

// " Pa" for a unit, nothing for a dimensionless "-".
std::string unit_suffix(std::string_view unit) { return unit == "-" ? std::string() : fmt::format(" {}", unit); }

void warn(FitResult& fit, FitWarningKind kind, std::string parameter, std::string message) {
  fit.warnings.push_back({kind, std::move(parameter), std::move(message)});
}

}  // namespace

std::string_view to_string(FitWarningKind kind) {
  switch (kind) {
    case FitWarningKind::not_converged:
      return "not_converged";
    case FitWarningKind::no_degrees_of_freedom:
      return "no_degrees_of_freedom";
    case FitWarningKind::singular_jacobian:
      return "singular_jacobian";
    case FitWarningKind::high_correlation:
      return "high_correlation";
    case FitWarningKind::large_relative_error:
      return "large_relative_error";
    case FitWarningKind::at_bound:
      return "at_bound";
    case FitWarningKind::yield_stress_not_significant:
      return "yield_stress_not_significant";
  }
  return "unknown";
}

bool FitResult::has_warning(FitWarningKind kind) const {
  return std::any_of(warnings.begin(), warnings.end(), [&](const FitWarning& w) { return w.kind == kind; });
}

std::size_t FitResult::index(std::string_view parameter) const {
  for (std::size_t j = 0; j < parameter_names.size(); ++j)
    if (parameter_names[j] == parameter) return j;
  throw std::out_of_range(fmt::format("fit of '{}' has no parameter '{}'", model_name, parameter));
}

FitResult fit_flow_curve(std::shared_ptr<const FlowModel> model, std::span<const double> x, std::span<const double> y,
                         const FitOptions& options) {
  if (!model) throw std::invalid_argument("fit_flow_curve: no model");
  check_flow_data(x, y, "fit_flow_curve");
  if (!(options.confidence > 0 && options.confidence < 1))
    throw std::invalid_argument("fit_flow_curve: confidence must be in (0, 1)");
  const auto info = model->parameters();
  const std::size_t p = info.size();
  const std::size_t n = x.size();

  const FlowModel& law = *model;
  const ResidualFunction residuals = [&](std::span<const double> theta, Eigen::VectorXd& r, Eigen::MatrixXd* jac) {
    std::vector<double> values(p), gradient(p);
    for (std::size_t j = 0; j < p; ++j) values[j] = info[j].scale.value(theta[j]);
    r.resize(static_cast<Eigen::Index>(n));
    if (jac != nullptr) jac->resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(p));
    for (std::size_t i = 0; i < n; ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      r[ii] = (law.stress(x[i], values) - y[i]) / y[i];
      if (jac != nullptr) {
        law.stress_gradient(x[i], values, gradient);
        for (std::size_t j = 0; j < p; ++j) (*jac)(ii, static_cast<Eigen::Index>(j)) = gradient[j] / y[i];
      }
    }
  };
  std::vector<double> lower(p);
  for (std::size_t j = 0; j < p; ++j) lower[j] = info[j].scale.coordinate_lower_bound();

  LeastSquaresSolution best;
  best.sum_of_squares = inf;
  bool have = false;
  for (const auto& guess : law.initial_guesses(x, y)) {
    if (guess.size() != p)
      throw std::logic_error(fmt::format("flow model '{}': initial guess of wrong size", law.name()));
    std::vector<double> start(p);
    for (std::size_t j = 0; j < p; ++j) start[j] = info[j].scale.coordinate(guess[j]);
    auto sol = solve_least_squares(residuals, n, start, lower, options.solver);
    if (!std::isfinite(sol.sum_of_squares)) continue;
    if (!have || is_better(sol, best)) {
      best = std::move(sol);
      have = true;
    }
  }

  FitResult fit;
  fit.model = model;
  fit.model_name = std::string(law.name());
  for (const auto& pi_ : info) {
    fit.parameter_names.emplace_back(pi_.name);
    fit.units.emplace_back(pi_.unit);
  }
  fit.shear_rate.assign(x.begin(), x.end());
  fit.stress.assign(y.begin(), y.end());
  fit.points = static_cast<int>(n);
  fit.degrees_of_freedom = static_cast<int>(n) - static_cast<int>(p);
  fit.min_shear_rate = *std::min_element(x.begin(), x.end());
  fit.max_shear_rate = *std::max_element(x.begin(), x.end());
  fit.params.assign(p, nan);
  fit.std_errors.assign(p, nan);
  fit.ci95.assign(p, Interval{});
  const auto pp = static_cast<Eigen::Index>(p);
  fit.covariance = Eigen::MatrixXd::Constant(pp, pp, nan);
  fit.correlation = Eigen::MatrixXd::Constant(pp, pp, nan);
  fit.fit_covariance = Eigen::MatrixXd::Constant(pp, pp, nan);
  if (!have) {
    fit.sum_of_squares = inf;
    fit.stop_reason = "no starting point gave finite residuals";
    warn(fit, FitWarningKind::not_converged, {}, fit.model_name + ": no starting point gave finite residuals");
    return fit;
  }

  fit.converged = best.converged;
  fit.iterations = best.iterations;
  fit.stop_reason = best.stop_reason;
  fit.sum_of_squares = best.sum_of_squares;
  fit.residuals.assign(best.residuals.data(), best.residuals.data() + best.residuals.size());
  const auto stats = parameter_statistics(best.jacobian, best.residuals, best.coordinates, options.confidence);
  fit.t_quantile = stats.t_quantile;
  if (stats.degrees_of_freedom > 0) fit.residual_std = std::sqrt(stats.residual_variance);
  fit.fit_covariance = stats.covariance;
  fit.correlation = stats.correlation;
  Eigen::VectorXd dvalue(pp);
  for (std::size_t j = 0; j < p; ++j) {
    const auto jj = static_cast<Eigen::Index>(j);
    const auto& scale = info[j].scale;
    fit.params[j] = scale.value(best.coordinates[j]);
    dvalue[jj] = scale.derivative(best.coordinates[j]);
    // The delta method vanishes where dp/dθ does (√τ_y = 0): no standard error there, the
    // interval (mapped from θ) is the statement to read.
    if (dvalue[jj] != 0) fit.std_errors[j] = std::abs(dvalue[jj]) * stats.std_errors[j];
    fit.ci95[j] = scale.value_interval(stats.intervals[j]);
  }
  fit.covariance = dvalue.asDiagonal() * stats.covariance * dvalue.asDiagonal();

  // Information criteria, k = p + 1 (the parameters and the residual variance).
  const auto nd = static_cast<double>(n);
  const double k = static_cast<double>(p) + 1.0;
  fit.aic = fit.sum_of_squares > 0 ? nd * std::log(fit.sum_of_squares / nd) + 2.0 * k : -inf;
  fit.aicc = nd - k - 1.0 > 0 ? fit.aic + 2.0 * k * (k + 1.0) / (nd - k - 1.0) : inf;

  // Warnings, most fundamental first.
  const std::string& name = fit.model_name;
  if (!fit.converged)
    warn(fit, FitWarningKind::not_converged, {},
         fmt::format("{}: the solver stopped without converging ({}, {} iterations)", name, fit.stop_reason,
                     fit.iterations));
  if (fit.degrees_of_freedom < 1)
    warn(fit, FitWarningKind::no_degrees_of_freedom, {},
         fmt::format("{}: {} points for {} parameters (n − p = {}): no residual variance, no standard errors or "
                     "intervals; measure more shear rates",
                     name, n, p, fit.degrees_of_freedom));
  if (stats.is_singular)
    warn(fit, FitWarningKind::singular_jacobian, {},
         fmt::format("{}: singular Jacobian at the optimum (rank {} of {}): the data cannot separate the parameters",
                     name, stats.rank, p));
  for (std::size_t i = 0; i < p; ++i)
    for (std::size_t j = i + 1; j < p; ++j) {
      const double rho = stats.correlation(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
      if (std::abs(rho) > options.correlation_limit)
        warn(fit, FitWarningKind::high_correlation, fit.parameter_names[i] + "," + fit.parameter_names[j],
             fmt::format("{}: {} and {} are correlated (ρ = {:.4f}): only a combination of them is determined", name,
                         fit.parameter_names[i], fit.parameter_names[j], rho));
    }
  for (std::size_t j = 0; j < p; ++j) {
    if (best.at_bound[j]) {
      warn(fit, FitWarningKind::at_bound, fit.parameter_names[j],
           fmt::format("{}: {} is on its lower bound ({} = {:.4g}{}): the best fit would go lower still", name,
                       fit.parameter_names[j], info[j].symbol, fit.params[j], unit_suffix(info[j].unit)));
      continue;
    }
    const double relative = fit.std_errors[j] / std::abs(fit.params[j]);
    if (relative > options.relative_error_limit)
      warn(fit, FitWarningKind::large_relative_error, fit.parameter_names[j],
           fmt::format("{}: {} = {:.4g} ± {:.3g}{} (relative standard error {:.3g} %): not identifiable from these "
                       "data",
                       name, fit.parameter_names[j], fit.params[j], fit.std_errors[j], unit_suffix(info[j].unit),
                       100 * relative));
  }
  if (const auto iy = law.yield_stress_index()) {
    const Interval ci = fit.ci95[*iy];
    if (!(ci.lower > 0))
      warn(fit, FitWarningKind::yield_stress_not_significant, fit.parameter_names[*iy],
           fmt::format("{}: the yield stress interval [{:.4g}, {:.4g}] Pa includes 0: no yield stress is resolved",
                       name, ci.lower, ci.upper));
  }
  return fit;
}

FitResult fit_flow_curve(std::string_view model_name, std::span<const double> x, std::span<const double> y,
                         const FitOptions& options) {
  return fit_flow_curve(make_flow_model(model_name), x, y, options);
}

std::vector<FitResult> fit_flow_curves(std::span<const std::string> model_names, std::span<const double> x,
                                       std::span<const double> y, const FitOptions& options) {
  std::vector<std::string> names(model_names.begin(), model_names.end());
  if (names.empty()) names = builtin_flow_models().names();
  std::vector<FitResult> out;
  for (const auto& name : names) out.push_back(fit_flow_curve(name, x, y, options));
  return out;
}

std::vector<ModelRanking> rank_by_aic(std::span<const FitResult> fits) {
  // AICc when at least two models have one: a model with n − k − 1 <= 0 (infinite AICc) cannot
  // be judged from so few points and ranks last with weight 0 — plain AIC would reward it for
  // interpolating the data. With fewer, AICc would crown the one model it can judge, however
  // badly it fits; then plain AIC decides among the models with a residual degree of freedom.
  const auto with_aicc =
      std::count_if(fits.begin(), fits.end(), [](const FitResult& f) { return std::isfinite(f.aicc); });
  const bool use_aicc = with_aicc >= 2;
  std::vector<ModelRanking> out;
  double best = inf;
  for (std::size_t i = 0; i < fits.size(); ++i) {
    const double c = use_aicc ? fits[i].aicc : (fits[i].degrees_of_freedom >= 1 ? fits[i].aic : inf);
    out.push_back({fits[i].model_name, i, fits[i].aic, fits[i].aicc, c, 0});
    if (c < best) best = c;
  }
  double total = 0;
  for (auto& r : out) {
    const double c = r.delta;
    if (std::isnan(c) || c == inf) {
      r.delta = inf;
    } else if (best == -inf) {
      r.delta = c == -inf ? 0.0 : inf;
    } else {
      r.delta = c - best;
    }
    r.weight = std::exp(-0.5 * r.delta);
    total += r.weight;
  }
  for (auto& r : out) r.weight = total > 0 ? r.weight / total : 0.0;
  std::stable_sort(out.begin(), out.end(),
                   [](const ModelRanking& a, const ModelRanking& b) { return a.delta < b.delta; });
  return out;
}

FlowPrediction predict(const FitResult& fit, double shear_rate) {
  if (!fit.model) throw std::invalid_argument("predict: the fit has no model");
  if (!(shear_rate > 0) || !std::isfinite(shear_rate))
    throw std::invalid_argument(fmt::format("predict: shear rate {} must be positive and finite", shear_rate));
  const auto p = fit.params.size();
  FlowPrediction out;
  out.shear_rate = shear_rate;
  out.stress = fit.model->stress(shear_rate, fit.params);
  out.viscosity = out.stress / shear_rate;
  std::vector<double> g(p);
  fit.model->stress_gradient(shear_rate, fit.params, g);
  const Eigen::Map<const Eigen::VectorXd> grad(g.data(), static_cast<Eigen::Index>(p));
  const double variance = grad.dot(fit.fit_covariance * grad);
  if (variance >= 0) {
    out.stress_std_error = std::sqrt(variance);
    out.viscosity_std_error = out.stress_std_error / shear_rate;
    out.stress_ci95 = {out.stress - fit.t_quantile * out.stress_std_error,
                       out.stress + fit.t_quantile * out.stress_std_error};
  }
  constexpr double slack = 1e-12;
  if (shear_rate < fit.min_shear_rate * (1 - slack) || shear_rate > fit.max_shear_rate * (1 + slack)) {
    out.is_extrapolated = true;
    out.warning = fmt::format(
        "{} fit evaluated at γ̇ = {:.4g} 1/s, outside the fitted range [{:.4g}, {:.4g}] 1/s: "
        "extrapolation",
        fit.model_name, shear_rate, fit.min_shear_rate, fit.max_shear_rate);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Yield stress

YieldStressEstimate yield_stress_from_fit(const FitResult& fit, std::string method) {
  if (!fit.model) throw std::invalid_argument("yield_stress_from_fit: the fit has no model");
  const auto index = fit.model->yield_stress_index();
  if (!index)
    throw std::invalid_argument(fmt::format("yield_stress_from_fit: model '{}' has no yield stress", fit.model_name));
  YieldStressEstimate e;
  e.method = std::move(method);
  e.value = fit.params[*index];
  e.std_error = fit.std_errors[*index];
  e.ci95 = fit.ci95[*index];
  e.is_significant = e.ci95.lower > 0;
  e.converged = fit.converged;
  for (const auto& w : fit.warnings) e.warnings.push_back(w.message);
  return e;
}

TorqueLineFit fit_torque_line(const ParallelPlate& plate, std::span<const double> x, std::span<const double> torque,
                              double confidence) {
  if (!(plate.radius > 0)) throw std::invalid_argument("fit_torque_line: plate radius must be > 0");
  if (x.size() != torque.size())
    throw std::invalid_argument(fmt::format("fit_torque_line: {} shear rates but {} torques", x.size(), torque.size()));
  if (x.size() < 2) throw std::invalid_argument("fit_torque_line: needs at least 2 points");
  if (!(confidence > 0 && confidence < 1)) throw std::invalid_argument("fit_torque_line: confidence must be in (0, 1)");
  const auto n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    my += torque[i];
  }
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (torque[i] - my);
  }
  if (!(sxx > 0)) throw std::invalid_argument("fit_torque_line: needs at least 2 distinct shear rates");

  TorqueLineFit f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  double ssr = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    f.residuals.push_back(torque[i] - (f.intercept + f.slope * x[i]));
    ssr += f.residuals.back() * f.residuals.back();
  }
  const double r3 = std::pow(plate.radius, 3);
  const double to_yield = 3.0 / (2.0 * pi * r3);  // τ_y = 3T₀/(2πR³)
  const double to_plastic = 2.0 / (pi * r3);      // η_p = 2b/(πR³)
  f.plastic_viscosity = to_plastic * f.slope;
  auto& e = f.yield_stress;
  e.method = "torque_intercept";
  e.value = to_yield * f.intercept;
  e.converged = true;
  if (x.size() >= 3) {
    const double s = std::sqrt(ssr / (n - 2.0));
    const double t = student_t_quantile(0.5 * (1.0 + confidence), n - 2.0);
    f.slope_std_error = s / std::sqrt(sxx);
    f.intercept_std_error = s * std::sqrt(1.0 / n + mx * mx / sxx);
    f.plastic_viscosity_ci95 = {to_plastic * (f.slope - t * f.slope_std_error),
                                to_plastic * (f.slope + t * f.slope_std_error)};
    e.std_error = to_yield * f.intercept_std_error;
    e.ci95 = {e.value - t * e.std_error, e.value + t * e.std_error};
  } else {
    e.warnings.push_back("torque_intercept: a line through 2 points has no residual variance: no interval");
  }
  e.is_significant = e.ci95.lower > 0;
  if (!e.is_significant && e.ci95.is_finite())
    e.warnings.push_back(fmt::format("torque_intercept: the yield stress interval [{:.4g}, {:.4g}] Pa includes 0",
                                     e.ci95.lower, e.ci95.upper));
  return f;
}

std::vector<YieldStressEstimate> YieldStressEstimates::all() const {
  return {bingham_intercept, casson_intercept, herschel_bulkley, torque_intercept};
}

YieldStressEstimates estimate_yield_stress(const ParallelPlate& plate, std::span<const double> rim_shear_rate,
                                           std::span<const double> torque, const FitOptions& options) {
  const auto curve = rim_stress_curve(plate, rim_shear_rate, torque);
  YieldStressEstimates out;
  out.bingham_intercept = yield_stress_from_fit(
      fit_flow_curve(make_flow_model("bingham"), curve.rim_shear_rate, curve.corrected_stress, options),
      "bingham_intercept");
  out.casson_intercept = yield_stress_from_fit(
      fit_flow_curve(make_flow_model("casson"), curve.rim_shear_rate, curve.corrected_stress, options),
      "casson_intercept");
  out.herschel_bulkley = yield_stress_from_fit(
      fit_flow_curve(make_flow_model("herschel_bulkley"), curve.rim_shear_rate, curve.corrected_stress, options),
      "herschel_bulkley");
  out.torque_intercept = fit_torque_line(plate, rim_shear_rate, torque, options.confidence).yield_stress;
  return out;
}

}  // namespace rheosim::rheometer
