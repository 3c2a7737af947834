// Unit tests of the flow-curve analysis: statistics, solver, models, plate correction, fits on
// exact data, warnings, yield-stress line, relative viscosity and validity flags.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "rheosim/core/units.hpp"
#include "rheosim/rheometer/analysis.hpp"
#include "rheosim/rheometer/plate.hpp"

namespace rheosim::rheometer {
namespace {

using core::units::pi;

const ParallelPlate cd_plate{0.015, 0.0005};  // CD §2.3

std::vector<double> log_spaced(double lo, double hi, int count) {
  std::vector<double> out;
  for (int i = 0; i < count; ++i) out.push_back(lo * std::pow(hi / lo, static_cast<double>(i) / (count - 1)));
  return out;
}

// Standard normal deviates from a fixed-seed 64-bit Mersenne Twister (Box–Muller, portable).
class Noise {
 public:
  explicit Noise(std::uint64_t seed) : rng_(seed) {}
  double normal() {
    const double u1 = (static_cast<double>(rng_() >> 11) + 0.5) * 0x1.0p-53;
    const double u2 = static_cast<double>(rng_() >> 11) * 0x1.0p-53;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * pi * u2);
  }

 private:
  std::mt19937_64 rng_;
};

std::vector<double> curve(const FlowModel& model, const std::vector<double>& values, const std::vector<double>& rates) {
  std::vector<double> out;
  for (const double r : rates) out.push_back(model.stress(r, values));
  return out;
}

// ---------------------------------------------------------------------------------------------
// Statistics

TEST(AnalysisStatistics, StudentTQuantilesMatchTables) {
  // t_{0.975, ν} from standard tables (R: qt(0.975, nu)).
  EXPECT_NEAR(student_t_quantile(0.975, 1), 12.706204736174707, 1e-10);
  EXPECT_NEAR(student_t_quantile(0.975, 2), 4.302652729749464, 1e-11);
  EXPECT_NEAR(student_t_quantile(0.975, 5), 2.570581835636314, 1e-11);
  EXPECT_NEAR(student_t_quantile(0.975, 10), 2.228138851986274, 1e-11);
  EXPECT_NEAR(student_t_quantile(0.975, 30), 2.042272456301238, 1e-11);
  EXPECT_NEAR(student_t_quantile(0.995, 4), 4.604094871415897, 1e-10);
  EXPECT_NEAR(student_t_quantile(0.975, 1e7), 1.959963984540054, 1e-5);
  EXPECT_NEAR(student_t_quantile(0.025, 10), -2.228138851986274, 1e-11);
  EXPECT_DOUBLE_EQ(student_t_quantile(0.5, 3), 0.0);
  EXPECT_NEAR(student_t_cdf(2.228138851986274, 10), 0.975, 1e-13);
  EXPECT_NEAR(student_t_cdf(-1.0, 1), 0.25, 1e-14);  // Cauchy: 1/2 + atan(t)/π
  EXPECT_THROW((void)student_t_quantile(1.0, 3), std::invalid_argument);
  EXPECT_THROW((void)student_t_quantile(0.9, 0), std::invalid_argument);
}

TEST(AnalysisStatistics, IncompleteBetaClosedForms) {
  for (double x : {0.0, 0.1, 0.37, 0.5, 0.9, 1.0}) {
    EXPECT_NEAR(regularized_incomplete_beta(x, 1, 1), x, 1e-15);
    // I_x(2, 3) = 6x² − 8x³ + 3x⁴
    EXPECT_NEAR(regularized_incomplete_beta(x, 2, 3), 6 * x * x - 8 * x * x * x + 3 * x * x * x * x, 1e-14);
  }
}

TEST(AnalysisStatistics, ParameterScalesMapValuesAndIntervals) {
  const auto log = ParameterScale::positive(0.5);
  EXPECT_NEAR(log.value(log.coordinate(0.75)), 0.75, 1e-15);
  EXPECT_NEAR(log.derivative(std::log(0.25)), 0.25, 1e-15);
  const Interval li = log.value_interval({std::log(0.1), std::log(0.2)});
  EXPECT_NEAR(li.lower, 0.6, 1e-15);
  EXPECT_NEAR(li.upper, 0.7, 1e-15);

  const auto bounded = ParameterScale::at_least(0);
  EXPECT_DOUBLE_EQ(bounded.coordinate(-3), 0.0);  // clamped into the domain
  const Interval bi = bounded.value_interval({-1, 2});
  EXPECT_DOUBLE_EQ(bi.lower, 0.0);
  EXPECT_DOUBLE_EQ(bi.upper, 2.0);

  const auto square = ParameterScale::squared();
  EXPECT_DOUBLE_EQ(square.value(3), 9.0);
  EXPECT_DOUBLE_EQ(square.coordinate(16), 4.0);
  const Interval si = square.value_interval({-1, 2});
  EXPECT_DOUBLE_EQ(si.lower, 0.0);
  EXPECT_DOUBLE_EQ(si.upper, 4.0);
  EXPECT_TRUE(si.contains(0));
}

// ---------------------------------------------------------------------------------------------
// Solver

TEST(AnalysisLeastSquares, SolvesRosenbrock) {
  // r = (10(θ₁ − θ₀²), 1 − θ₀): minimum 0 at (1, 1) along a curved valley.
  const ResidualFunction f = [](std::span<const double> t, Eigen::VectorXd& r, Eigen::MatrixXd* j) {
    r.resize(2);
    r << 10 * (t[1] - t[0] * t[0]), 1 - t[0];
    if (j) {
      j->resize(2, 2);
      *j << -20 * t[0], 10, -1, 0;
    }
  };
  const std::vector<double> start{-1.2, 1.0};
  const auto sol = solve_least_squares(f, 2, start);
  EXPECT_TRUE(sol.converged) << sol.stop_reason;
  EXPECT_NEAR(sol.coordinates[0], 1.0, 1e-10);
  EXPECT_NEAR(sol.coordinates[1], 1.0, 1e-10);
}

TEST(AnalysisLeastSquares, HoldsABoundThatTheDataPushAgainst) {
  // r = (θ₀ + 1, θ₁ − 2) with θ₀ >= 0: optimum (0, 2), θ₀ on its bound.
  const ResidualFunction f = [](std::span<const double> t, Eigen::VectorXd& r, Eigen::MatrixXd* j) {
    r.resize(2);
    r << t[0] + 1, t[1] - 2;
    if (j) *j = Eigen::MatrixXd::Identity(2, 2);
  };
  const std::vector<double> start{3, 0}, lower{0, -std::numeric_limits<double>::infinity()};
  const auto sol = solve_least_squares(f, 2, start, lower);
  EXPECT_TRUE(sol.converged) << sol.stop_reason;
  EXPECT_DOUBLE_EQ(sol.coordinates[0], 0.0);
  EXPECT_NEAR(sol.coordinates[1], 2.0, 1e-12) << sol.stop_reason << " after " << sol.iterations;
  EXPECT_TRUE(sol.at_bound[0]);
  EXPECT_FALSE(sol.at_bound[1]);
}

TEST(AnalysisLeastSquares, StatisticsOfAStraightLineMatchTheTextbook) {
  // y = a + b x by least squares: se(b) = s/√Sxx, se(a) = s √(1/n + x̄²/Sxx).
  const std::vector<double> x{1, 2, 3, 4, 5}, y{1.1, 1.9, 3.2, 3.9, 5.1};
  Eigen::MatrixXd j(5, 2);
  for (int i = 0; i < 5; ++i) j.row(i) << 1, x[static_cast<std::size_t>(i)];
  const ResidualFunction f = [&](std::span<const double> t, Eigen::VectorXd& r, Eigen::MatrixXd* jac) {
    r.resize(5);
    for (int i = 0; i < 5; ++i) r[i] = t[0] + t[1] * x[static_cast<std::size_t>(i)] - y[static_cast<std::size_t>(i)];
    if (jac) *jac = j;
  };
  const std::vector<double> start{0, 0};
  const auto sol = solve_least_squares(f, 5, start);
  const auto st = parameter_statistics(sol.jacobian, sol.residuals, sol.coordinates);
  const double sxx = 10, xbar = 3;
  const double s = std::sqrt(sol.sum_of_squares / 3);
  EXPECT_NEAR(sol.coordinates[1], 1.0, 1e-12);
  EXPECT_NEAR(st.std_errors[1], s / std::sqrt(sxx), 1e-12);
  EXPECT_NEAR(st.std_errors[0], s * std::sqrt(0.2 + xbar * xbar / sxx), 1e-12);
  EXPECT_NEAR(st.correlation(0, 1), -xbar / std::sqrt(0.2 * sxx + xbar * xbar), 1e-12);
  EXPECT_NEAR(st.t_quantile, 3.182446305284263, 1e-10);
  EXPECT_EQ(st.degrees_of_freedom, 3);
  EXPECT_FALSE(st.is_singular);
}

// ---------------------------------------------------------------------------------------------
// Models

struct ModelCase {
  std::string name;
  std::vector<double> values;
};

// Truths used by several tests: CD-like magnitudes, thinning in the middle of 0.1 … 1000 1/s.
const std::vector<ModelCase> model_cases{
    {"newtonian", {0.05}},
    {"power_law", {0.8, 0.45}},
    {"bingham", {2.0, 0.01}},
    {"casson", {1.5, 0.02}},
    {"herschel_bulkley", {3.0, 0.4, 0.6}},
    {"cross", {2.0, 0.01, 0.5, 0.8}},
    {"carreau", {2.0, 0.01, 0.8, 0.4}},
};

TEST(AnalysisModels, RegistryListsEveryModelByName) {
  const auto names = builtin_flow_models().names();
  const std::vector<std::string> expected{"bingham",          "carreau",   "casson",   "cross",
                                          "herschel_bulkley", "newtonian", "power_law"};
  EXPECT_EQ(names, expected);
  for (const auto& c : model_cases) EXPECT_EQ(make_flow_model(c.name)->name(), c.name);
  try {
    (void)make_flow_model("herschel_bulkly");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("did you mean 'herschel_bulkley'"), std::string::npos) << what;
    EXPECT_NE(what.find("power_law"), std::string::npos) << what;
  }
}

TEST(AnalysisModels, GradientsMatchFiniteDifferencesInFitCoordinates) {
  for (const auto& c : model_cases) {
    const auto model = make_flow_model(c.name);
    const auto info = model->parameters();
    for (const double rate : {0.3, 2.0, 50.0, 700.0}) {
      std::vector<double> g(c.values.size());
      model->stress_gradient(rate, c.values, g);
      for (std::size_t j = 0; j < c.values.size(); ++j) {
        const double theta = info[j].scale.coordinate(c.values[j]);
        const double h = 1e-6 * (1 + std::abs(theta));
        auto plus = c.values, minus = c.values;
        plus[j] = info[j].scale.value(theta + h);
        minus[j] = info[j].scale.value(theta - h);
        const double fd = (model->stress(rate, plus) - model->stress(rate, minus)) / (2 * h);
        EXPECT_NEAR(g[j], fd, 1e-7 * (std::abs(fd) + model->stress(rate, c.values)))
            << c.name << " parameter " << info[j].name << " at γ̇ = " << rate;
      }
    }
  }
}

TEST(AnalysisModels, ClosedFormsAgreeWithTheirDefinitions) {
  const auto casson = make_flow_model("casson");
  const std::vector<double> v{1.5, 0.02};
  EXPECT_NEAR(std::sqrt(casson->stress(40, v)), std::sqrt(1.5) + std::sqrt(0.02 * 40), 1e-14);
  const auto cross = make_flow_model("cross");
  EXPECT_NEAR(cross->viscosity(1e-8, model_cases[5].values), 2.0, 1e-6);  // η0 plateau
  const auto carreau = make_flow_model("carreau");
  const std::vector<double> cv{2.0, 0.0, 0.8, 0.4};
  // Far above 1/λ the Carreau law is a power law: η ≈ η0 (λγ̇)^(n−1).
  EXPECT_NEAR(carreau->viscosity(1e6, cv), 2.0 * std::pow(0.8e6, -0.6), 1e-9 * 2.0 * std::pow(0.8e6, -0.6));
  EXPECT_EQ(*make_flow_model("herschel_bulkley")->yield_stress_index(), 0u);
  EXPECT_FALSE(make_flow_model("cross")->yield_stress_index().has_value());
}

// ---------------------------------------------------------------------------------------------
// Plate correction

TEST(AnalysisPlate, ApparentStressIsTheNewtonianRimStress) {
  // For a Newtonian fluid T = πηγ̇_R R³/2, so 2T/(πR³) = ηγ̇_R and n′ = 1.
  const auto rates = log_spaced(1, 100, 7);
  std::vector<double> torque;
  for (const double r : rates) torque.push_back(newtonian_torque(cd_plate, 0.02, r));
  const auto c = rim_stress_curve(cd_plate, rates, torque);
  for (std::size_t i = 0; i < rates.size(); ++i) {
    EXPECT_NEAR(c.apparent_stress[i], 0.02 * rates[i], 1e-13 * 0.02 * rates[i]);
    EXPECT_NEAR(c.log_slope[i], 1.0, 1e-12);
    EXPECT_NEAR(c.corrected_stress[i], c.apparent_stress[i], 1e-12 * c.apparent_stress[i]);
  }
}

TEST(AnalysisPlate, CorrectionInvertsPowerLawTorqueExactly) {
  for (const double n : {0.3, 0.6, 1.0, 1.4}) {
    // Unsorted rates, as a sweep may deliver them.
    const std::vector<double> rates{50, 1, 300, 7, 0.5, 20, 120, 3};
    std::vector<double> torque;
    for (const double r : rates) torque.push_back(power_law_torque(cd_plate, 0.8, n, r));
    const auto c = rim_stress_curve(cd_plate, rates, torque);
    for (std::size_t i = 0; i < rates.size(); ++i) {
      const double exact = 0.8 * std::pow(rates[i], n);
      EXPECT_NEAR(c.log_slope[i], n, 1e-12) << "n = " << n << ", γ̇ = " << rates[i];
      EXPECT_NEAR(c.corrected_stress[i], exact, 1e-12 * exact) << "n = " << n << ", γ̇ = " << rates[i];
      EXPECT_NEAR(c.corrected_viscosity[i], exact / rates[i], 1e-12 * exact / rates[i]);
    }
  }
}

TEST(AnalysisPlate, LocalSlopeIsExactForQuadraticsAndUsesAWindow) {
  // ln y = 0.3 + 0.7u − 0.05u², u = ln x: the quadratic fit recovers dy/du = 0.7 − 0.1u exactly.
  const auto x = log_spaced(0.1, 1000, 12);
  std::vector<double> y;
  for (const double xi : x) {
    const double u = std::log(xi);
    y.push_back(std::exp(0.3 + 0.7 * u - 0.05 * u * u));
  }
  const auto s = local_log_slopes(x, y);
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_NEAR(s.slope[i], 0.7 - 0.1 * std::log(x[i]), 1e-12);
    EXPECT_NEAR(s.std_error[i], 0.0, 1e-10);  // exact fit: no scatter
  }
  // Two points: the line through them.
  const std::vector<double> x2{1, 10}, y2{2, 20 * std::sqrt(10.0)};
  EXPECT_NEAR(local_log_slopes(x2, y2).slope[0], 1.5, 1e-14);
  EXPECT_TRUE(std::isnan(local_log_slopes(x2, y2).std_error[0]));
  // Bad input.
  const std::vector<double> dup{1, 1, 2}, y3{1, 2, 3};
  EXPECT_THROW((void)local_log_slopes(dup, y3), std::invalid_argument);
  const std::vector<double> one{1}, y1{1};
  EXPECT_THROW((void)local_log_slopes(one, y1), std::invalid_argument);
  const std::vector<double> x3{1, 2, 3}, neg{1, -2, 3};
  EXPECT_THROW((void)rim_stress_curve(cd_plate, x3, neg), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Fits on exact data

TEST(AnalysisFit, NoiseFreeDataRecoverEveryModelsParameters) {
  const auto rates = log_spaced(0.1, 1000, 25);
  for (const auto& c : model_cases) {
    const auto model = make_flow_model(c.name);
    const auto fit = fit_flow_curve(model, rates, curve(*model, c.values, rates));
    EXPECT_TRUE(fit.converged) << c.name << ": " << fit.stop_reason;
    ASSERT_EQ(fit.params.size(), c.values.size());
    for (std::size_t j = 0; j < c.values.size(); ++j)
      EXPECT_NEAR(fit.params[j], c.values[j], 1e-8 * std::abs(c.values[j])) << c.name << " " << fit.parameter_names[j];
    EXPECT_LT(fit.sum_of_squares, 1e-20) << c.name;
    EXPECT_EQ(fit.degrees_of_freedom, 25 - static_cast<int>(c.values.size()));
    EXPECT_TRUE(fit.ci95[0].contains(c.values[0]) || fit.ci95[0].width() < 1e-12) << c.name;
  }
}

TEST(AnalysisFit, ResultCarriesNamesUnitsResidualsAndCriteria) {
  const auto rates = log_spaced(1, 100, 10);
  Noise noise(7);
  const auto model = make_flow_model("herschel_bulkley");
  auto stress = curve(*model, {3.0, 0.4, 0.6}, rates);
  for (auto& s : stress) s *= 1 + 0.01 * noise.normal();
  const auto fit = fit_flow_curve("herschel_bulkley", rates, stress);
  EXPECT_EQ(fit.model_name, "herschel_bulkley");
  EXPECT_EQ(fit.parameter_names, (std::vector<std::string>{"yield_stress", "consistency", "index"}));
  EXPECT_EQ(fit.units, (std::vector<std::string>{"Pa", "Pa·sⁿ", "-"}));
  ASSERT_EQ(fit.residuals.size(), rates.size());
  double ss = 0;
  for (std::size_t i = 0; i < rates.size(); ++i) {
    const double rel = (model->stress(rates[i], fit.params) - stress[i]) / stress[i];
    EXPECT_NEAR(fit.residuals[i], rel, 1e-14);
    ss += rel * rel;
  }
  EXPECT_NEAR(fit.sum_of_squares, ss, 1e-15);
  EXPECT_NEAR(fit.aic, 10 * std::log(ss / 10) + 2 * 4, 1e-10);
  EXPECT_NEAR(fit.aicc, fit.aic + 2.0 * 4 * 5 / (10 - 4 - 1), 1e-10);
  EXPECT_NEAR(fit.t_quantile, student_t_quantile(0.975, 7), 1e-14);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(fit.correlation(i, i), 1.0, 1e-12);
  EXPECT_NEAR(fit.std_errors[1], std::sqrt(fit.covariance(1, 1)), 1e-15);
  EXPECT_DOUBLE_EQ(fit.value("index"), fit.params[2]);
  EXPECT_THROW((void)fit.value("viscosity"), std::out_of_range);
}

TEST(AnalysisFit, RejectsBadData) {
  const std::vector<double> x{1, 2, 3}, y{1, 0, 3}, y2{1, 2};
  EXPECT_THROW((void)fit_flow_curve("newtonian", x, y), std::invalid_argument);
  EXPECT_THROW((void)fit_flow_curve("newtonian", x, y2), std::invalid_argument);
  EXPECT_THROW((void)fit_flow_curve("maxwell", x, x), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Warnings for unidentifiable parameters

TEST(AnalysisWarnings, HerschelBulkleyOnNewtonianDataHasNoSignificantYieldStress) {
  const auto rates = log_spaced(1, 500, 15);
  for (std::uint64_t seed : {1u, 2u, 3u, 4u, 5u}) {
    Noise noise(seed);
    std::vector<double> stress;
    for (const double r : rates) stress.push_back(0.05 * r * (1 + 0.015 * noise.normal()));
    const auto fit = fit_flow_curve("herschel_bulkley", rates, stress);
    const Interval yield = fit.ci95[0];
    EXPECT_TRUE(yield.contains(0.0)) << "seed " << seed << ": [" << yield.lower << ", " << yield.upper << "]";
    EXPECT_TRUE(fit.has_warning(FitWarningKind::yield_stress_not_significant)) << "seed " << seed;
    EXPECT_NEAR(fit.value("index"), 1.0, 0.05);
    const auto estimate = yield_stress_from_fit(fit, "herschel_bulkley");
    EXPECT_FALSE(estimate.is_significant);
    EXPECT_FALSE(estimate.warnings.empty());
  }
}

TEST(AnalysisWarnings, CrossWithTooFewPointsHasNoDegreesOfFreedom) {
  const auto model = make_flow_model("cross");
  const std::vector<double> rates{0.1, 1, 10, 100};
  const auto fit = fit_flow_curve(model, rates, curve(*model, model_cases[5].values, rates));
  EXPECT_EQ(fit.degrees_of_freedom, 0);
  EXPECT_TRUE(fit.has_warning(FitWarningKind::no_degrees_of_freedom));
  for (const double se : fit.std_errors) EXPECT_TRUE(std::isnan(se));
  for (const auto& ci : fit.ci95) EXPECT_FALSE(ci.is_finite());
  EXPECT_FALSE(std::isfinite(fit.aicc));
}

TEST(AnalysisWarnings, CrossOnThePlateauOnlyIsNotIdentifiable) {
  // All rates well below 1/λ = 2 1/s: the data see η0 and hardly anything else.
  const auto model = make_flow_model("cross");
  const auto rates = log_spaced(0.001, 0.05, 12);
  Noise noise(11);
  auto stress = curve(*model, model_cases[5].values, rates);
  for (auto& s : stress) s *= 1 + 0.01 * noise.normal();
  const auto fit = fit_flow_curve(model, rates, stress);
  const bool flagged = fit.has_warning(FitWarningKind::large_relative_error) ||
                       fit.has_warning(FitWarningKind::high_correlation) ||
                       fit.has_warning(FitWarningKind::singular_jacobian) || fit.has_warning(FitWarningKind::at_bound);
  EXPECT_TRUE(flagged);
  for (const auto& w : fit.warnings) EXPECT_FALSE(w.message.empty());
}

TEST(AnalysisWarnings, PowerLawAtOneShearRateIsSingular) {
  // Three measurements at one rate cannot separate k from n.
  const std::vector<double> rates{10, 10, 10}, stress{5.0, 5.1, 4.9};
  const auto fit = fit_flow_curve("power_law", rates, stress);
  EXPECT_TRUE(fit.has_warning(FitWarningKind::singular_jacobian));
  EXPECT_TRUE(std::isnan(fit.std_errors[0]));
}

// ---------------------------------------------------------------------------------------------
// Predictions, ranking

TEST(AnalysisPredict, FlagsExtrapolationAndGivesABand) {
  const auto rates = log_spaced(1, 100, 12);
  Noise noise(3);
  std::vector<double> stress;
  for (const double r : rates) stress.push_back(0.8 * std::pow(r, 0.45) * (1 + 0.01 * noise.normal()));
  const auto fit = fit_flow_curve("power_law", rates, stress);
  const auto inside = predict(fit, 10);
  EXPECT_FALSE(inside.is_extrapolated);
  EXPECT_TRUE(inside.warning.empty());
  EXPECT_NEAR(inside.stress, 0.8 * std::pow(10, 0.45), 0.02 * 0.8 * std::pow(10, 0.45));
  EXPECT_GT(inside.stress_std_error, 0);
  EXPECT_TRUE(inside.stress_ci95.contains(inside.stress));
  EXPECT_NEAR(inside.viscosity, inside.stress / 10, 1e-15);
  EXPECT_FALSE(predict(fit, 1).is_extrapolated);
  EXPECT_FALSE(predict(fit, 100).is_extrapolated);
  const auto below = predict(fit, 0.1);
  EXPECT_TRUE(below.is_extrapolated);
  EXPECT_NE(below.warning.find("outside the fitted range"), std::string::npos);
  EXPECT_TRUE(predict(fit, 1000).is_extrapolated);
  // The band widens away from the data.
  EXPECT_GT(predict(fit, 1000).stress_std_error / predict(fit, 1000).stress, inside.stress_std_error / inside.stress);
  EXPECT_THROW((void)predict(fit, 0), std::invalid_argument);
}

TEST(AnalysisRanking, WeightsSumToOneAndBestIsFirst) {
  const auto rates = log_spaced(0.5, 500, 20);
  Noise noise(5);
  std::vector<double> stress;
  for (const double r : rates) stress.push_back((2.0 + 0.01 * r) * (1 + 0.01 * noise.normal()));
  const std::vector<std::string> names{"newtonian", "power_law", "bingham"};
  const auto fits = fit_flow_curves(names, rates, stress);
  const auto ranking = rank_by_aic(fits);
  ASSERT_EQ(ranking.size(), 3u);
  EXPECT_EQ(ranking[0].model_name, "bingham");
  EXPECT_DOUBLE_EQ(ranking[0].delta, 0.0);
  double total = 0;
  for (const auto& r : ranking) total += r.weight;
  EXPECT_NEAR(total, 1.0, 1e-14);
  EXPECT_EQ(fits[ranking[0].fit_index].model_name, "bingham");
  EXPECT_EQ(fit_flow_curves({}, rates, stress).size(), 7u);
}

TEST(AnalysisRanking, ModelsWithoutAFiniteAiccRankLastNotFirst) {
  // Five points of a nearly Newtonian curve: Cross and Carreau (4 parameters, k = 5) have
  // n − k − 1 < 0, so AICc is infinite. Plain AIC would crown them for interpolating the data.
  const std::vector<double> rates{10, 25, 50, 75, 100};
  std::vector<double> stress;
  for (const double r : rates) stress.push_back(1e-3 * r * (1 + 1e-5 * r));
  const auto fits = fit_flow_curves({}, rates, stress);
  const auto ranking = rank_by_aic(fits);
  ASSERT_EQ(ranking.size(), 7u);
  // Herschel–Bulkley (k = 4) has n − k − 1 = 0: infinite too.
  const auto judged = static_cast<std::size_t>(
      std::count_if(fits.begin(), fits.end(), [](const FitResult& f) { return std::isfinite(f.aicc); }));
  EXPECT_EQ(judged, 4u);
  for (std::size_t i = 0; i < ranking.size(); ++i) {
    const bool too_few_points = !std::isfinite(fits[ranking[i].fit_index].aicc);
    if (too_few_points) {
      EXPECT_GE(i, judged) << ranking[i].model_name << " ranked " << i;
      EXPECT_EQ(ranking[i].weight, 0.0);
    }
  }
  EXPECT_TRUE(std::isfinite(fits[ranking[0].fit_index].aicc));
}

// ---------------------------------------------------------------------------------------------
// Yield stress: the seed's torque line

TEST(AnalysisYieldStress, TorqueLineIsExactForBinghamTorque) {
  // T = 2πR³(τ_y/3 + η_p γ̇_R/4): the straight line's intercept gives τ_y = 3T₀/(2πR³).
  const auto rates = log_spaced(1, 200, 8);
  std::vector<double> torque;
  for (const double r : rates) torque.push_back(bingham_torque(cd_plate, 0.01, 2.0, r));
  const auto line = fit_torque_line(cd_plate, rates, torque);
  EXPECT_NEAR(line.yield_stress.value, 2.0, 1e-10);
  EXPECT_NEAR(line.plastic_viscosity, 0.01, 1e-12);
  EXPECT_NEAR(line.intercept, 2 * pi * std::pow(0.015, 3) * 2.0 / 3, 1e-16);
  EXPECT_EQ(line.yield_stress.method, "torque_intercept");
  EXPECT_TRUE(line.yield_stress.is_significant);
  EXPECT_LT(line.yield_stress.ci95.width(), 1e-8);
}

TEST(AnalysisYieldStress, TorqueLineOfNewtonianTorqueHasNoYieldStress) {
  const auto rates = log_spaced(1, 200, 8);
  Noise noise(9);
  std::vector<double> torque;
  for (const double r : rates) torque.push_back(newtonian_torque(cd_plate, 0.01, r) * (1 + 0.01 * noise.normal()));
  const auto e = fit_torque_line(cd_plate, rates, torque).yield_stress;
  EXPECT_TRUE(e.ci95.contains(0.0)) << e.ci95.lower << " " << e.ci95.upper;
  EXPECT_FALSE(e.is_significant);
  EXPECT_FALSE(e.warnings.empty());
}

// ---------------------------------------------------------------------------------------------
// Relative viscosity

TEST(AnalysisRelativeViscosity, CorrelationsAndErrorPropagation) {
  EXPECT_DOUBLE_EQ(einstein_relative_viscosity(0.1), 1.25);
  EXPECT_NEAR(batchelor_relative_viscosity(0.1), 1.312, 1e-15);
  // Krieger–Dougherty reduces to Einstein at small φ: (1 − φ/φ_m)^(−2.5φ_m) ≈ 1 + 2.5φ.
  EXPECT_NEAR(krieger_dougherty_relative_viscosity(1e-5, 0.64), 1 + 2.5e-5, 1e-9);
  EXPECT_NEAR(krieger_dougherty_relative_viscosity(0.32, 0.64), std::pow(0.5, -1.6), 1e-12);
  EXPECT_NEAR(maron_pierce_relative_viscosity(0.315), 4.0, 1e-12);
  EXPECT_TRUE(std::isinf(maron_pierce_relative_viscosity(0.7)));

  const auto p = relative_viscosity(0.2, 0.003, 0.00006, 0.001, 0.00001);
  EXPECT_DOUBLE_EQ(p.volume_fraction, 0.2);
  EXPECT_NEAR(p.relative_viscosity, 3.0, 1e-15);
  EXPECT_NEAR(p.std_error, 3.0 * std::sqrt(0.02 * 0.02 + 0.01 * 0.01), 1e-15);
  EXPECT_THROW((void)relative_viscosity(0.2, 0, 0, 1), std::invalid_argument);
}

TEST(AnalysisRelativeViscosity, ErrorBarsFromFittedViscosities) {
  // Newtonian fits of a liquid and a suspension: η_r = η/η_f with the fits' standard errors.
  const auto rates = log_spaced(1, 100, 10);
  Noise noise(21);
  std::vector<double> liquid, suspension;
  for (const double r : rates) {
    liquid.push_back(0.01 * r * (1 + 0.01 * noise.normal()));
    suspension.push_back(0.03 * r * (1 + 0.01 * noise.normal()));
  }
  const auto fl = fit_flow_curve("newtonian", rates, liquid);
  const auto fs = fit_flow_curve("newtonian", rates, suspension);
  const auto p = relative_viscosity(0.3, predict(fs, 10), predict(fl, 10));
  EXPECT_NEAR(p.relative_viscosity, fs.params[0] / fl.params[0], 1e-12);
  const double a = fs.std_errors[0] / fs.params[0], b = fl.std_errors[0] / fl.params[0];
  EXPECT_NEAR(p.std_error, p.relative_viscosity * std::sqrt(a * a + b * b), 1e-12);
  EXPECT_GT(p.std_error, 0);
}

TEST(AnalysisRelativeViscosity, ExactKriegerDoughertyDataGiveTheirMaximumPacking) {
  std::vector<RelativeViscosityPoint> points;
  for (const double phi : {0.0, 0.1, 0.2, 0.3, 0.4, 0.5})
    points.push_back({phi, krieger_dougherty_relative_viscosity(phi, 0.6), 0});
  const auto kd = fit_krieger_dougherty(points);
  EXPECT_TRUE(kd.converged);
  EXPECT_NEAR(kd.max_packing, 0.6, 1e-9);
  EXPECT_NEAR(kd.sum_of_squares, 0, 1e-20);
  EXPECT_DOUBLE_EQ(kd.intrinsic_viscosity, 2.5);
  const auto all = analyze_relative_viscosity(points);
  EXPECT_EQ(all.einstein.name, "einstein");
  EXPECT_GT(all.einstein.sum_of_squares, all.batchelor.sum_of_squares);  // both too low at φ = 0.5
  EXPECT_GT(all.maron_pierce.max_packing, 0.5);
  EXPECT_TRUE(std::isnan(all.einstein.max_packing));
}

// ---------------------------------------------------------------------------------------------
// Validity flags

TEST(AnalysisValidity, NumbersFollowTheirDefinitions) {
  PointConditions p;
  p.rim_shear_rate = 100;
  p.density = 1000;
  p.viscosity = 1e-3;  // water: Re_gap = 1000 · (100·H/R) · H² / 1e-3 = 0.8333
  p.particle_diameter = 2e-4;
  p.particle_density = 2500;
  const auto v = check_validity(cd_plate, p);
  EXPECT_NEAR(v.gap_reynolds, 1000 * (100 * 0.0005 / 0.015) * 0.0005 * 0.0005 / 1e-3, 1e-12);
  EXPECT_NEAR(v.particle_reynolds, 1000 * 100 * 4e-8 / 1e-3, 1e-12);  // 4
  EXPECT_NEAR(v.stokes, 2500 * 100 * 4e-8 / 1e-3, 1e-12);             // 10
  EXPECT_NEAR(v.gap_to_diameter, 2.5, 1e-15);
  EXPECT_TRUE(v.gap_reynolds_ok);
  EXPECT_FALSE(v.particle_reynolds_ok);
  EXPECT_FALSE(v.stokes_ok);
  EXPECT_FALSE(v.gap_to_diameter_ok);
  EXPECT_FALSE(v.is_valid());
  EXPECT_EQ(v.messages.size(), 3u);

  // A viscous suspending liquid with fine particles passes everything.
  p.viscosity = 10;
  p.fluid_viscosity = 1;
  p.particle_diameter = 2e-5;
  const auto ok = check_validity(cd_plate, p);
  EXPECT_TRUE(ok.is_valid()) << (ok.messages.empty() ? "" : ok.messages[0]);
  EXPECT_NEAR(ok.particle_reynolds, 1000 * 100 * 4e-10 / 1, 1e-15);  // uses η_f, not η
  EXPECT_NEAR(ok.gap_to_diameter, 25, 1e-12);

  // Single phase: only the gap Reynolds number is checked.
  PointConditions fluid{.rim_shear_rate = 100, .density = 1000, .viscosity = 1e-4};
  const auto thin = check_validity(cd_plate, fluid);
  EXPECT_FALSE(thin.gap_reynolds_ok);
  EXPECT_TRUE(thin.gap_to_diameter_ok);
  EXPECT_NE(thin.messages.at(0).find("gap Reynolds"), std::string::npos);
}

}  // namespace
}  // namespace rheosim::rheometer
