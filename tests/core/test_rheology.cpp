// Rheology laws: closed forms, limits, regularisation convergence, analytic vs finite-difference
// derivatives, array forms, parameter validation and the registry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "rheosim/core/config.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/rheology.hpp"

// The law classes are private to core (core/src); include them by path so their Params and
// constructors can be tested directly.
#include "rheology/bingham.hpp"
#include "rheology/carreau_yasuda.hpp"
#include "rheology/casson.hpp"
#include "rheology/cross.hpp"
#include "rheology/herschel_bulkley.hpp"
#include "rheology/newtonian.hpp"
#include "rheology/power_law.hpp"

namespace {

namespace core = rheosim::core;
using LawPtr = std::shared_ptr<const core::Rheology>;

// Builds a law from the YAML text of a `rheology:` mapping, exactly as a case file would, and
// checks that the law's reader asked for every key that was given.
LawPtr law_from_yaml(const std::string& rheology_yaml) {
  const auto document = core::Document::from_string("fluid:\n  rheology: " + rheology_yaml + "\n", "test.yaml");
  const core::Section rheology =
      document.root().section({"fluid", "fluid", "-"}).section({"rheology", "rheology model", "-"});
  LawPtr law = core::make_rheology(rheology);
  document.check_all_keys_known();
  return law;
}

// The what() of the ConfigError that building this law raises, or "" (and a test failure).
std::string config_error(const std::string& rheology_yaml) {
  try {
    (void)law_from_yaml(rheology_yaml);
  } catch (const core::ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no ConfigError for " << rheology_yaml;
  return {};
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Relative difference, safe when both are zero.
double relative_difference(double a, double b) {
  const double scale = std::max(std::abs(a), std::abs(b));
  return scale == 0.0 ? 0.0 : std::abs(a - b) / scale;
}

// One law per row, with the shear rate at which its behaviour changes (1/m, 1/λ, or 1 1/s
// for laws without a scale). Derivative checks sweep 1e-4..1e4 times that scale.
struct LawCase {
  std::string label;
  std::string yaml;
  double scale;  // characteristic shear rate [1/s]
};

const std::vector<LawCase>& law_cases() {
  static const std::vector<LawCase> cases = {
      {"newtonian", "{model: newtonian, viscosity: 1.0e-3}", 1.0},
      {"power_law thinning", "{model: power_law, consistency: 0.5, index: 0.6}", 1.0},
      {"power_law thickening", "{model: power_law, consistency: 0.5, index: 1.7}", 1.0},
      {"bingham", "{model: bingham, plastic_viscosity: 0.01, yield_stress: 1.0, regularization: 1000}", 1e-3},
      {"casson", "{model: casson, plastic_viscosity: 0.01, yield_stress: 1.0, regularization: 1000}", 1e-3},
      {"herschel_bulkley",
       "{model: herschel_bulkley, consistency: 0.5, index: 0.6, yield_stress: 1.0, regularization: 1000, "
       "min_shear_rate: 1.0e-9}",
       1e-3},
      {"carreau (a = 2)",
       "{model: carreau_yasuda, zero_shear_viscosity: 1.0, infinite_shear_viscosity: 1.0e-3, time_constant: 0.5, "
       "a: 2, n: 0.4}",
       2.0},
      {"carreau_yasuda (a = 0.5)",
       "{model: carreau_yasuda, zero_shear_viscosity: 1.0, infinite_shear_viscosity: 1.0e-3, time_constant: 0.5, "
       "a: 0.5, n: 0.3}",
       2.0},
      {"cross (m = 0.7)",
       "{model: cross, zero_shear_viscosity: 1.0, infinite_shear_viscosity: 1.0e-3, time_constant: 0.5, "
       "exponent: 0.7}",
       2.0},
      {"cross (m = 1)",
       "{model: cross, zero_shear_viscosity: 1.0, infinite_shear_viscosity: 0, time_constant: 0.5, exponent: 1}", 2.0},
  };
  return cases;
}

// Shear rates from 1e-4 to 1e4 times `scale`, four per decade.
std::vector<double> shear_rate_sweep(double scale) {
  std::vector<double> rates;
  for (int quarter_decade = -16; quarter_decade <= 16; ++quarter_decade)
    rates.push_back(scale * std::pow(10.0, quarter_decade / 4.0));
  return rates;
}

// ------------------------------------------------------------------------ registry and names

TEST(RheologyRegistry, ListsExactlyTheSevenLaws) {
  const std::vector<std::string> expected = {"bingham",          "carreau_yasuda", "casson",   "cross",
                                             "herschel_bulkley", "newtonian",      "power_law"};
  EXPECT_EQ(core::builtin_rheologies().names(), expected);
}

TEST(RheologyRegistry, EachLawReportsItsYamlName) {
  for (const auto& c : law_cases()) {
    // "{model: <name>, ..."
    const std::size_t begin = c.yaml.find("model: ") + 7;
    const std::string model = c.yaml.substr(begin, c.yaml.find(',') - begin);
    EXPECT_EQ(law_from_yaml(c.yaml)->name(), model) << c.label;
  }
}

TEST(RheologyRegistry, UnknownModelErrorListsTheValidNames) {
  const std::string what = config_error("{model: bingam, plastic_viscosity: 1, yield_stress: 1}");
  EXPECT_TRUE(contains(what, "fluid.rheology.model")) << what;
  EXPECT_TRUE(contains(what, "bingam")) << what;
  for (const auto& name : core::builtin_rheologies().names()) EXPECT_TRUE(contains(what, name)) << what;
}

TEST(RheologyRegistry, RegisteringALawTwiceIsAnError) {
  core::RheologyRegistry registry = core::builtin_rheologies();
  EXPECT_THROW(core::add<core::Bingham>(registry), std::logic_error);
}

// Built by name, a law with settings is refused (its parameters come from a case file), and an
// unknown name is an error listing the valid ones; nothing is made up for either.
TEST(RheologyRegistry, ALawWithSettingsIsNotBuiltByName) {
  const core::RheologyRegistry registry = core::builtin_rheologies();
  try {
    (void)registry.make(std::string_view("bingham"));
    ADD_FAILURE() << "a Bingham law was built without its parameters";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(contains(e.what(), "has settings")) << e.what();
  }
  try {
    (void)registry.make(std::string_view("bingam"));
    ADD_FAILURE() << "an unknown law was built";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(contains(e.what(), "herschel_bulkley")) << e.what();
  }
}

// Every reported parameter is a YAML key of its law: feeding parameters() back as YAML rebuilds
// the same law (check_all_keys_known rejects any name that is not a key).
TEST(RheologyParameters, RoundTripThroughYaml) {
  for (const auto& c : law_cases()) {
    const LawPtr law = law_from_yaml(c.yaml);
    std::string yaml = fmt::format("{{model: {}", law->name());
    for (const auto& p : law->parameters()) yaml += fmt::format(", {}: {}", p.name, p.value);
    yaml += "}";
    const LawPtr rebuilt = law_from_yaml(yaml);
    ASSERT_EQ(rebuilt->parameters().size(), law->parameters().size()) << c.label;
    for (std::size_t i = 0; i < law->parameters().size(); ++i) {
      EXPECT_EQ(rebuilt->parameters()[i].name, law->parameters()[i].name);
      EXPECT_EQ(rebuilt->parameters()[i].value, law->parameters()[i].value) << c.label;
      EXPECT_FALSE(law->parameters()[i].unit.empty()) << c.label;
    }
    for (const double rate : {0.0, c.scale, 10 * c.scale})
      EXPECT_EQ(rebuilt->viscosity(rate), law->viscosity(rate)) << c.label;
  }
}

TEST(RheologyParameters, YieldStressOnlyForViscoplasticLaws) {
  EXPECT_EQ(law_from_yaml("{model: bingham, plastic_viscosity: 0.1, yield_stress: 2.5}")->yield_stress(), 2.5);
  EXPECT_EQ(law_from_yaml("{model: casson, plastic_viscosity: 0.1, yield_stress: 3.5}")->yield_stress(), 3.5);
  EXPECT_EQ(law_from_yaml("{model: herschel_bulkley, consistency: 1, index: 0.5, yield_stress: 4.5}")->yield_stress(),
            4.5);
  EXPECT_EQ(law_from_yaml("{model: power_law, consistency: 1, index: 0.5}")->yield_stress(), 0.0);
  EXPECT_EQ(law_from_yaml("{model: newtonian, viscosity: 1}")->yield_stress(), 0.0);
}

TEST(RheologyParameters, OptionalKeysHaveTheirDocumentedDefaults) {
  const auto bingham = law_from_yaml("{model: bingham, plastic_viscosity: 0.1, yield_stress: 2}");
  EXPECT_DOUBLE_EQ(bingham->viscosity(0.0), 0.1 + 2 * 1000.0);  // m = 1000
  const auto power_law = law_from_yaml("{model: power_law, consistency: 1, index: 0.5}");
  EXPECT_DOUBLE_EQ(power_law->viscosity(0.0), std::pow(1e-6, -0.5));  // γ̇_min = 1e-6
  const auto hb = law_from_yaml("{model: herschel_bulkley, consistency: 1, index: 0.5, yield_stress: 2}");
  EXPECT_DOUBLE_EQ(hb->viscosity(0.0), std::pow(1e-6, -0.5) + 2 * 1000.0);
}

// --------------------------------------------------------------------------- closed forms

void expect_viscosities(const LawPtr& law, const std::vector<std::pair<double, double>>& rate_and_mu) {
  for (const auto& [rate, mu] : rate_and_mu)
    EXPECT_LT(relative_difference(law->viscosity(rate), mu), 1e-12)
        << law->name() << " at γ̇ = " << rate << ": " << law->viscosity(rate) << " vs " << mu;
}

TEST(RheologyClosedForm, Newtonian) {
  expect_viscosities(law_from_yaml("{model: newtonian, viscosity: 2.5e-3}"),
                     {{0.0, 2.5e-3}, {1e-3, 2.5e-3}, {1.0, 2.5e-3}, {1e6, 2.5e-3}});
}

TEST(RheologyClosedForm, PowerLaw) {
  expect_viscosities(law_from_yaml("{model: power_law, consistency: 2, index: 0.5}"),
                     {{4.0, 1.0}, {100.0, 0.2}, {0.25, 4.0}, {1e-4, 200.0}});
  expect_viscosities(law_from_yaml("{model: power_law, consistency: 0.5, index: 1.5}"),
                     {{16.0, 2.0}, {2.0, 0.5 * std::sqrt(2.0)}, {0.01, 0.05}});
  // Held below γ̇_min: μ(γ̇) = k γ̇_min^(n−1).
  expect_viscosities(law_from_yaml("{model: power_law, consistency: 2, index: 0.5, min_shear_rate: 0.01}"),
                     {{0.0, 20.0}, {1e-3, 20.0}, {0.01, 20.0}, {0.04, 10.0}});
}

TEST(RheologyClosedForm, Bingham) {
  // μ∞ + τ0 (1 − e^(−mγ̇))/γ̇ with μ∞ = 0.1, τ0 = 2, m = 1000.
  expect_viscosities(law_from_yaml("{model: bingham, plastic_viscosity: 0.1, yield_stress: 2, regularization: 1000}"),
                     {{0.0, 0.1 + 2000.0},
                      {1e-5, 0.1 + 2.0 * (1.0 - std::exp(-0.01)) / 1e-5},
                      {1e-3, 0.1 + 2000.0 * (1.0 - std::exp(-1.0))},
                      {1.0, 2.1},
                      {10.0, 0.3}});
}

TEST(RheologyClosedForm, Casson) {
  // [√μ∞ + √(τ0/γ̇)(1 − e^(−√(mγ̇)))]² with μ∞ = 0.01, τ0 = 1, m = 1e4.
  const auto law = law_from_yaml("{model: casson, plastic_viscosity: 0.01, yield_stress: 1, regularization: 1e4}");
  expect_viscosities(law, {{4.0, 0.36},
                           {1e-2, std::pow(0.1 + 10.0 * (1.0 - std::exp(-10.0)), 2)},
                           {1e-4, std::pow(0.1 + 100.0 * (1.0 - std::exp(-1.0)), 2)}});
  // μ(0) = (√μ∞ + √(τ0 m))² up to the documented floor √(mγ̇_min) = 1e-6.
  EXPECT_LT(relative_difference(law->viscosity(0.0), std::pow(0.1 + 100.0, 2)), 2e-6);
}

TEST(RheologyClosedForm, HerschelBulkley) {
  // k γ̇^(n−1) + τ0 (1 − e^(−mγ̇))/γ̇ with k = 0.5, n = 0.6, τ0 = 2, m = 1000.
  const auto law =
      law_from_yaml("{model: herschel_bulkley, consistency: 0.5, index: 0.6, yield_stress: 2, regularization: 1000}");
  expect_viscosities(law, {{1.0, 2.5},
                           {32.0, 0.1875},
                           {1e-3, 0.5 * std::pow(1e-3, -0.4) + 2000.0 * (1.0 - std::exp(-1.0))},
                           {0.0, 0.5 * std::pow(1e-6, -0.4) + 2000.0}});
}

TEST(RheologyClosedForm, CarreauYasuda) {
  // μ∞ + (μ0 − μ∞)[1 + (λγ̇)^a]^((n−1)/a) with μ0 = 1, μ∞ = 0.001, λ = 0.5, a = 2, n = 0.5.
  expect_viscosities(law_from_yaml("{model: carreau_yasuda, zero_shear_viscosity: 1, infinite_shear_viscosity: "
                                   "0.001, time_constant: 0.5, a: 2, n: 0.5}"),
                     {{0.0, 1.0},
                      {2.0, 0.001 + 0.999 * std::pow(2.0, -0.25)},
                      {2e3, 0.001 + 0.999 * std::pow(1.0 + 1e6, -0.25)},
                      {0.2, 0.001 + 0.999 * std::pow(1.01, -0.25)}});
}

TEST(RheologyClosedForm, Cross) {
  // μ∞ + (μ0 − μ∞)/(1 + (λγ̇)^m) with μ0 = 1, μ∞ = 0.001, λ = 0.5, m = 0.5.
  expect_viscosities(law_from_yaml("{model: cross, zero_shear_viscosity: 1, infinite_shear_viscosity: 0.001, "
                                   "time_constant: 0.5, exponent: 0.5}"),
                     {{2.0, 0.5005}, {200.0, 0.001 + 0.999 / 11.0}, {0.02, 0.001 + 0.999 / 1.1}});
}

// ------------------------------------------------------------------- special cases agree

TEST(RheologyLimits, PowerLawWithIndexOneIsNewtonian) {
  const auto power_law = law_from_yaml("{model: power_law, consistency: 0.7, index: 1}");
  const auto newtonian = law_from_yaml("{model: newtonian, viscosity: 0.7}");
  for (const double rate : {0.0, 1e-9, 1e-3, 1.0, 1e3, 1e9}) {
    EXPECT_EQ(power_law->viscosity(rate), newtonian->viscosity(rate)) << rate;
    EXPECT_EQ(power_law->viscosity_derivative(rate), 0.0) << rate;
  }
}

TEST(RheologyLimits, BinghamWithoutYieldStressIsNewtonian) {
  const auto bingham = law_from_yaml("{model: bingham, plastic_viscosity: 0.7, yield_stress: 0}");
  const auto casson = law_from_yaml("{model: casson, plastic_viscosity: 0.7, yield_stress: 0}");
  for (const double rate : {0.0, 1e-9, 1e-3, 1.0, 1e3, 1e9}) {
    EXPECT_EQ(bingham->viscosity(rate), 0.7) << rate;
    EXPECT_EQ(bingham->viscosity_derivative(rate), 0.0) << rate;
    EXPECT_DOUBLE_EQ(casson->viscosity(rate), 0.7) << rate;
    EXPECT_EQ(casson->viscosity_derivative(rate), 0.0) << rate;
  }
}

TEST(RheologyLimits, HerschelBulkleyWithIndexOneIsBingham) {
  const auto hb =
      law_from_yaml("{model: herschel_bulkley, consistency: 0.3, index: 1, yield_stress: 2, regularization: 500}");
  const auto bingham = law_from_yaml("{model: bingham, plastic_viscosity: 0.3, yield_stress: 2, regularization: 500}");
  for (const double rate : {0.0, 1e-9, 1e-4, 2e-4, 1e-3, 1.0, 1e3}) {
    EXPECT_DOUBLE_EQ(hb->viscosity(rate), bingham->viscosity(rate)) << rate;
    EXPECT_DOUBLE_EQ(hb->viscosity_derivative(rate), bingham->viscosity_derivative(rate)) << rate;
  }
}

TEST(RheologyLimits, HerschelBulkleyWithoutYieldStressIsPowerLaw) {
  const auto hb = law_from_yaml("{model: herschel_bulkley, consistency: 0.3, index: 0.4, yield_stress: 0}");
  const auto power_law = law_from_yaml("{model: power_law, consistency: 0.3, index: 0.4}");
  for (const double rate : {0.0, 1e-9, 1e-4, 1.0, 1e3}) {
    EXPECT_DOUBLE_EQ(hb->viscosity(rate), power_law->viscosity(rate)) << rate;
    EXPECT_DOUBLE_EQ(hb->viscosity_derivative(rate), power_law->viscosity_derivative(rate)) << rate;
  }
}

TEST(RheologyLimits, CarreauYasudaAndCrossPlateaus) {
  struct Plateau {
    std::string yaml;
    double mu0, mu_inf, lambda;
    double high_rate_slope;  // μ − μ∞ ~ (μ0 − μ∞)(λγ̇)^slope at high rate
    double zero_rate_tol;    // documented relative deviation of μ(0) from μ0
  };
  const std::vector<Plateau> plateaus = {
      {"{model: carreau_yasuda, zero_shear_viscosity: 2, infinite_shear_viscosity: 0.01, time_constant: 0.5, a: 2, "
       "n: 0.4}",
       2.0, 0.01, 0.5, 0.4 - 1.0, 1e-15},
      {"{model: carreau_yasuda, zero_shear_viscosity: 2, infinite_shear_viscosity: 0.01, time_constant: 0.5, a: 0.5, "
       "n: 0.5}",
       2.0, 0.01, 0.5, 0.5 - 1.0, 4e-5},
      {"{model: cross, zero_shear_viscosity: 2, infinite_shear_viscosity: 0.01, time_constant: 0.5, exponent: 1}", 2.0,
       0.01, 0.5, -1.0, 2e-9},
      {"{model: cross, zero_shear_viscosity: 2, infinite_shear_viscosity: 0.01, time_constant: 0.5, exponent: 0.7}",
       2.0, 0.01, 0.5, -0.7, 1e-6},
  };
  for (const auto& p : plateaus) {
    const auto law = law_from_yaml(p.yaml);
    EXPECT_LT(relative_difference(law->viscosity(0.0), p.mu0), p.zero_rate_tol) << p.yaml;
    EXPECT_LE(law->viscosity(0.0), p.mu0) << p.yaml;
    // Far beyond 1/λ: approaches μ∞ along the documented power law.
    const double high_rate = 1e12 / p.lambda;
    const double excess = law->viscosity(high_rate) - p.mu_inf;
    EXPECT_GT(excess, 0.0) << p.yaml;
    EXPECT_LT(excess, 1e-3 * (p.mu0 - p.mu_inf)) << p.yaml;
    EXPECT_NEAR(excess / ((p.mu0 - p.mu_inf) * std::pow(p.lambda * high_rate, p.high_rate_slope)), 1.0, 1e-5) << p.yaml;
    // Monotonically thinning in between.
    double previous = law->viscosity(0.0);
    for (const double rate : shear_rate_sweep(1.0 / p.lambda)) {
      EXPECT_LT(law->viscosity(rate), previous) << p.yaml << " at " << rate;
      previous = law->viscosity(rate);
    }
  }
}

// ------------------------------------------------------- finite at rest, finite everywhere

TEST(RheologyAtRest, FinitePositiveViscosityAndFiniteDerivative) {
  for (const auto& c : law_cases()) {
    const auto law = law_from_yaml(c.yaml);
    for (const double rate : {0.0, 1e-300, 1e-15, 1e-6, 1.0, 1e6, 1e15}) {
      const double mu = law->viscosity(rate);
      EXPECT_TRUE(std::isfinite(mu) && mu > 0.0) << c.label << " μ(" << rate << ") = " << mu;
      EXPECT_TRUE(std::isfinite(law->viscosity_derivative(rate))) << c.label << " at " << rate;
      EXPECT_TRUE(std::isfinite(law->stress(rate))) << c.label << " at " << rate;
    }
    EXPECT_EQ(law->stress(0.0), 0.0) << c.label;
  }
}

TEST(RheologyAtRest, ExtremeParametersStayFinite) {
  for (const std::string yaml : {
           "{model: power_law, consistency: 1e3, index: 0.01}",
           "{model: power_law, consistency: 1e-6, index: 2}",
           "{model: bingham, plastic_viscosity: 1e-6, yield_stress: 1e4, regularization: 1e8}",
           "{model: casson, plastic_viscosity: 1e-6, yield_stress: 1e4, regularization: 1e8}",
           "{model: casson, plastic_viscosity: 1e-6, yield_stress: 1e-6, regularization: 1e-3}",
           "{model: herschel_bulkley, consistency: 1, index: 0.1, yield_stress: 1e4, regularization: 1e8}",
           "{model: carreau_yasuda, zero_shear_viscosity: 1e3, infinite_shear_viscosity: 0, time_constant: 1e4, "
           "a: 0.1, n: 0.05}",
           "{model: cross, zero_shear_viscosity: 1e3, infinite_shear_viscosity: 0, time_constant: 1e4, "
           "exponent: 0.05}",
       }) {
    const auto law = law_from_yaml(yaml);
    for (const double rate : {0.0, 1e-12, 1e-6, 1.0, 1e6, 1e12}) {
      EXPECT_TRUE(std::isfinite(law->viscosity(rate)) && law->viscosity(rate) > 0.0) << yaml << " at " << rate;
      EXPECT_TRUE(std::isfinite(law->viscosity_derivative(rate))) << yaml << " at " << rate;
    }
  }
}

TEST(RheologyAtRest, BinghamValueAndSlopeAtZero) {
  const auto law = law_from_yaml("{model: bingham, plastic_viscosity: 0.1, yield_stress: 2, regularization: 1000}");
  EXPECT_DOUBLE_EQ(law->viscosity(0.0), 0.1 + 2.0 * 1000.0);
  EXPECT_DOUBLE_EQ(law->viscosity_derivative(0.0), -2.0 * 1000.0 * 1000.0 / 2.0);
}

TEST(RheologyAtRest, ClampedLawsAreFlatBelowTheirFloor) {
  const auto power_law = law_from_yaml("{model: power_law, consistency: 2, index: 0.5, min_shear_rate: 0.01}");
  EXPECT_EQ(power_law->viscosity_derivative(0.005), 0.0);
  EXPECT_LT(power_law->viscosity_derivative(0.02), 0.0);
  // Continuous at the floor.
  EXPECT_LT(relative_difference(power_law->viscosity(0.01 * (1 + 1e-12)), power_law->viscosity(0.01)), 1e-11);

  const core::Casson casson({.plastic_viscosity = 0.01, .yield_stress = 1.0, .regularization = 1000.0});
  EXPECT_DOUBLE_EQ(casson.min_shear_rate(), 1e-12 / 1000.0);
  EXPECT_EQ(casson.dmu(0.5 * casson.min_shear_rate()), 0.0);
  EXPECT_EQ(casson.mu(0.0), casson.mu(casson.min_shear_rate()));
  EXPECT_LT(casson.dmu(2.0 * casson.min_shear_rate()), 0.0);

  const core::Cross cross(
      {.zero_shear_viscosity = 1, .infinite_shear_viscosity = 0, .time_constant = 0.5, .exponent = 0.5});
  EXPECT_DOUBLE_EQ(cross.min_shear_rate(), 1e-9 / 0.5);
  EXPECT_EQ(cross.dmu(0.0), 0.0);
  EXPECT_EQ(cross.mu(0.0), cross.mu(cross.min_shear_rate()));
}

// ---------------------------------------------------- regularisation converges like 1/m

// ∫ |τ_reg − τ_exact| dγ̇ over (1e-14, 1e4) 1/s: trapezoid rule on a log grid, fine enough that
// the quadrature error (~1e-6 relative) is far below the effects measured.
double stress_error_l1(const core::Rheology& law, double (*exact_stress)(double, double, double), double mu_inf,
                       double tau0) {
  constexpr int intervals = 40000;
  constexpr double lower = 1e-14, upper = 1e4;
  double sum = 0.0;
  double previous_rate = lower;
  double previous_error = std::abs(law.stress(lower) - exact_stress(lower, mu_inf, tau0));
  for (int i = 1; i <= intervals; ++i) {
    const double rate = lower * std::pow(upper / lower, static_cast<double>(i) / intervals);
    const double error = std::abs(law.stress(rate) - exact_stress(rate, mu_inf, tau0));
    sum += 0.5 * (error + previous_error) * (rate - previous_rate);
    previous_rate = rate;
    previous_error = error;
  }
  return sum;
}

double bingham_stress(double rate, double mu_inf, double tau0) { return tau0 + mu_inf * rate; }
double casson_stress(double rate, double mu_inf, double tau0) {
  return std::pow(std::sqrt(tau0) + std::sqrt(mu_inf * rate), 2);
}

TEST(RheologyRegularization, StressConvergesToIdealLawLikeOneOverM) {
  constexpr double mu_inf = 0.01, tau0 = 1.0;
  struct Law {
    std::string model;
    double (*exact)(double, double, double);
    double error_times_m_over_tau0;  // leading constant of the L1 error
  };
  for (const Law& law : {Law{"bingham", bingham_stress, 1.0}, Law{"casson", casson_stress, 3.5}}) {
    std::vector<double> errors;
    for (const double m : {1e3, 1e4, 1e5}) {
      const auto reg =
          law_from_yaml(fmt::format("{{model: {}, plastic_viscosity: {}, yield_stress: {}, "
                                    "regularization: {}}}",
                                    law.model, mu_inf, tau0, m));
      errors.push_back(stress_error_l1(*reg, law.exact, mu_inf, tau0));
      std::printf("%-8s m = %8.0e s   L1 |τ_reg − τ| = %.6e Pa/s   L1·m/τ0 = %.5f\n", law.model.c_str(), m,
                  errors.back(), errors.back() * m / tau0);
      // Bingham: exactly τ0/m. Casson: 3.5 τ0/m + O(m^-1.5).
      EXPECT_NEAR(errors.back() * m / tau0, law.error_times_m_over_tau0, 0.01 * law.error_times_m_over_tau0)
          << law.model << " m = " << m;
    }
    for (std::size_t i = 0; i + 1 < errors.size(); ++i) {
      const double observed_order = std::log10(errors[i] / errors[i + 1]);
      std::printf("%-8s observed order %.4f\n", law.model.c_str(), observed_order);
      EXPECT_NEAR(observed_order, 1.0, 0.01) << law.model;
    }
  }
}

// ------------------------------------------------------------ analytic vs numerical dμ/dγ̇

// Central difference with a relative step: truncation ~1e-8, round-off ~1e-12 relative.
double central_difference(const core::Rheology& law, double rate) {
  const double h = 1e-4 * rate;
  return (law.viscosity(rate + h) - law.viscosity(rate - h)) / (2.0 * h);
}

// Table-driven: prints analytic and numerical dμ/dγ̇ side by side at every decade and checks
// them at four points per decade over 1e-4..1e4 times each law's characteristic rate.
TEST(RheologyDerivative, AnalyticMatchesCentralDifference) {
  for (const auto& c : law_cases()) {
    const auto law = law_from_yaml(c.yaml);
    std::printf("\n%s  %s\n%14s %22s %22s %12s\n", c.label.c_str(), c.yaml.c_str(), "shear rate", "analytic dμ/dγ̇",
                "numerical dμ/dγ̇", "rel. diff");
    const auto rates = shear_rate_sweep(c.scale);
    for (std::size_t i = 0; i < rates.size(); ++i) {
      const double rate = rates[i];
      const double analytic = law->viscosity_derivative(rate);
      const double numerical = central_difference(*law, rate);
      if (i % 4 == 0)
        std::printf("%14.4e %22.12e %22.12e %12.2e\n", rate, analytic, numerical,
                    relative_difference(analytic, numerical));
      // Relative to |dμ/dγ̇|, plus a floor relative to the natural scale μ/γ̇ for where the
      // slope is nearly zero (Newtonian plateaus) and the difference quotient is round-off.
      const double tolerance = 1e-6 * std::abs(analytic) + 1e-9 * law->viscosity(rate) / rate;
      EXPECT_NEAR(analytic, numerical, tolerance) << c.label << " at γ̇ = " << rate;
    }
  }
}

TEST(RheologyDerivative, PapanastasiouFactorAccurateOnBothSidesOfTheSeriesSwitch) {
  namespace pap = core::papanastasiou;
  EXPECT_EQ(pap::factor(0.0), 1.0);
  EXPECT_EQ(pap::factor_derivative(0.0), -0.5);
  for (const double x : {1e-8, 1e-3, 0.01, 0.05, 0.0999, 0.1, 0.1001, 0.5, 1.0, 5.0, 50.0}) {
    // Reference in long double, where the cancellation in g' costs far less than a double
    // ulp for x >= 1e-3; below that, the series' leading terms are exact to double precision.
    const long double lx = x;
    const long double g = -std::expm1(-lx) / lx;
    const long double dg =
        x >= 1e-3 ? (lx * std::exp(-lx) + std::expm1(-lx)) / (lx * lx) : -0.5L + lx / 3 - lx * lx / 8;
    EXPECT_LT(relative_difference(pap::factor(x), static_cast<double>(g)), 1e-15) << x;
    EXPECT_LT(relative_difference(pap::factor_derivative(x), static_cast<double>(dg)), 2e-14) << x;
  }
  // No jump where the series hands over to the closed form.
  EXPECT_LT(relative_difference(pap::factor_derivative(std::nextafter(0.1, 0.0)), pap::factor_derivative(0.1)), 2e-14);
}

// ------------------------------------------------------------------------- array forms

TEST(RheologyArrays, ArrayFormsEqualScalarForms) {
  std::vector<double> rates = {0.0, 1e-12, 1e-9};
  for (const double r : shear_rate_sweep(1e-2)) rates.push_back(r);
  for (const auto& c : law_cases()) {
    const auto law = law_from_yaml(c.yaml);
    std::vector<double> mu(rates.size()), dmu(rates.size());
    law->viscosity(rates, mu);
    law->viscosity_derivative(rates, dmu);
    for (std::size_t i = 0; i < rates.size(); ++i) {
      EXPECT_DOUBLE_EQ(mu[i], law->viscosity(rates[i])) << c.label << " at " << rates[i];
      EXPECT_DOUBLE_EQ(dmu[i], law->viscosity_derivative(rates[i])) << c.label << " at " << rates[i];
    }
  }
}

TEST(RheologyArrays, RejectSizeMismatch) {
  const std::vector<double> rates = {0.0, 1.0, 2.0};
  std::vector<double> too_short(2), too_long(4);
  for (const auto& c : law_cases()) {
    const auto law = law_from_yaml(c.yaml);
    EXPECT_THROW(law->viscosity(rates, too_short), std::invalid_argument) << c.label;
    EXPECT_THROW(law->viscosity(rates, too_long), std::invalid_argument) << c.label;
    EXPECT_THROW(law->viscosity_derivative(rates, too_short), std::invalid_argument) << c.label;
  }
  EXPECT_NO_THROW(core::check_equal_sizes(3, 3));
  EXPECT_THROW(core::check_equal_sizes(3, 2), std::invalid_argument);
}

// ------------------------------------------------------------------ parameter validation

TEST(RheologyValidation, NegativeViscosityIsRejectedWithKeyAndRange) {
  const std::string what = config_error("{model: newtonian, viscosity: -1.0e-3}");
  EXPECT_TRUE(contains(what, "fluid.rheology.viscosity")) << what;
  EXPECT_TRUE(contains(what, core::Range::positive().str())) << what;
  EXPECT_TRUE(contains(what, "test.yaml:2:")) << what;
}

TEST(RheologyValidation, IndexOutsideZeroTwoIsRejectedWithKeyAndRange) {
  const std::string range = core::Range::open_closed(0.0, 2.0).str();
  for (const std::string yaml :
       {"{model: power_law, consistency: 1, index: 0}", "{model: power_law, consistency: 1, index: 2.5}",
        "{model: herschel_bulkley, consistency: 1, index: 2.5, yield_stress: 1}"}) {
    const std::string what = config_error(yaml);
    EXPECT_TRUE(contains(what, "fluid.rheology.index")) << what;
    EXPECT_TRUE(contains(what, range)) << what;
  }
  const std::string what = config_error(
      "{model: carreau_yasuda, zero_shear_viscosity: 1, infinite_shear_viscosity: 0, time_constant: 1, a: 2, n: 0}");
  EXPECT_TRUE(contains(what, "fluid.rheology.n")) << what;
  EXPECT_TRUE(contains(what, range)) << what;
}

TEST(RheologyValidation, InfiniteShearViscosityMustBeBelowZeroShear) {
  for (const std::string model : {"carreau_yasuda", "cross"}) {
    const std::string shape = model == "cross" ? "exponent: 0.5" : "a: 2, n: 0.5";
    for (const double mu_inf : {1.0, 3.0}) {  // equal to and above μ0 = 1
      const std::string what = config_error(
          fmt::format("{{model: {}, zero_shear_viscosity: 1, infinite_shear_viscosity: {}, time_constant: 1, {}}}",
                      model, mu_inf, shape));
      EXPECT_TRUE(contains(what, "fluid.rheology.infinite_shear_viscosity")) << what;
      EXPECT_TRUE(contains(what, "zero_shear_viscosity")) << what;
    }
  }
}

TEST(RheologyValidation, OtherRangesAreChecked) {
  struct Bad {
    std::string yaml, key, range;
  };
  const std::vector<Bad> bad = {
      {"{model: bingham, plastic_viscosity: 0, yield_stress: 1}", "plastic_viscosity", core::Range::positive().str()},
      {"{model: bingham, plastic_viscosity: 1, yield_stress: -1}", "yield_stress", core::Range::non_negative().str()},
      {"{model: casson, plastic_viscosity: 1, yield_stress: 1, regularization: 0}", "regularization",
       core::Range::positive().str()},
      {"{model: power_law, consistency: 1, index: 0.5, min_shear_rate: 0}", "min_shear_rate",
       core::Range::positive().str()},
      {"{model: carreau_yasuda, zero_shear_viscosity: 1, infinite_shear_viscosity: 0, time_constant: 1, a: 11, "
       "n: 0.5}",
       "a", core::Range::open_closed(0.0, 10.0).str()},
      {"{model: cross, zero_shear_viscosity: 1, infinite_shear_viscosity: 0, time_constant: 0, exponent: 0.5}",
       "time_constant", core::Range::positive().str()},
      {"{model: cross, zero_shear_viscosity: 1, infinite_shear_viscosity: 0, time_constant: 1, exponent: 1.5}",
       "exponent", core::Range::open_closed(0.0, 1.0).str()},
      // The plateaus' order: μ∞ below μ0, the range named with μ0's value.
      {"{model: cross, zero_shear_viscosity: 1, infinite_shear_viscosity: 2, time_constant: 1, exponent: 0.5}",
       "infinite_shear_viscosity", "[0, 1)"},
      {"{model: carreau_yasuda, zero_shear_viscosity: 1, infinite_shear_viscosity: 1, time_constant: 1, a: 2, "
       "n: 0.5}",
       "infinite_shear_viscosity", "[0, 1)"},
  };
  for (const auto& b : bad) {
    const std::string what = config_error(b.yaml);
    EXPECT_TRUE(contains(what, "fluid.rheology." + b.key)) << what;
    EXPECT_TRUE(contains(what, b.range)) << what;
  }
}

TEST(RheologyValidation, MissingRequiredKeyIsNamed) {
  const std::string what = config_error("{model: bingham, plastic_viscosity: 1}");
  EXPECT_TRUE(contains(what, "fluid.rheology")) << what;
  EXPECT_TRUE(contains(what, "'yield_stress'")) << what;
}

TEST(RheologyValidation, MisspelledOptionalKeyIsAnError) {
  const std::string what = config_error("{model: bingham, plastic_viscosity: 1, yield_stress: 1, regularisation: 10}");
  EXPECT_TRUE(contains(what, "regularisation")) << what;
}

// Constructors check the same invariants, so an invalid law cannot exist even without YAML.
TEST(RheologyValidation, ConstructorsRejectInvalidParams) {
  const auto expect_rejected = [](auto make, const std::string& key) {
    try {
      make();
      ADD_FAILURE() << "no exception for " << key;
    } catch (const std::invalid_argument& e) {
      EXPECT_TRUE(contains(e.what(), key)) << e.what();
    }
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_rejected([] { (void)core::Newtonian({.viscosity = -1}); }, "viscosity");
  expect_rejected([&] { (void)core::Newtonian({.viscosity = nan}); }, "viscosity");
  expect_rejected([] { (void)core::PowerLaw({.consistency = 1, .index = 2.5}); }, "index");
  expect_rejected([] { (void)core::PowerLaw({.consistency = 1, .index = 0}); }, "index");
  expect_rejected([] { (void)core::PowerLaw({.consistency = 1, .index = 1, .min_shear_rate = 0}); }, "min_shear_rate");
  expect_rejected([] { (void)core::Bingham({.plastic_viscosity = 1, .yield_stress = -1}); }, "yield_stress");
  expect_rejected([] { (void)core::Casson({.plastic_viscosity = 0, .yield_stress = 1}); }, "plastic_viscosity");
  expect_rejected([&] { (void)core::Casson({.plastic_viscosity = 1, .yield_stress = 1, .regularization = nan}); },
                  "regularization");
  expect_rejected(
      [] { (void)core::HerschelBulkley({.consistency = 1, .index = 0.5, .yield_stress = 1, .regularization = -5}); },
      "regularization");
  expect_rejected(
      [] { (void)core::CarreauYasuda({.zero_shear_viscosity = 1, .infinite_shear_viscosity = 1, .time_constant = 1}); },
      "infinite_shear_viscosity");
  expect_rejected([] { (void)core::CarreauYasuda({.zero_shear_viscosity = 1, .a = 0}); }, "a");
  expect_rejected([] { (void)core::Cross({.zero_shear_viscosity = 1, .infinite_shear_viscosity = 2}); },
                  "infinite_shear_viscosity");
  expect_rejected([] { (void)core::Cross({.exponent = 1.2}); }, "exponent");
  // Defaults form a valid law.
  EXPECT_NO_THROW(core::Newtonian(core::Newtonian::Params{}));
  EXPECT_NO_THROW(core::PowerLaw(core::PowerLaw::Params{}));
  EXPECT_NO_THROW(core::Bingham(core::Bingham::Params{}));
  EXPECT_NO_THROW(core::Casson(core::Casson::Params{}));
  EXPECT_NO_THROW(core::HerschelBulkley(core::HerschelBulkley::Params{}));
  EXPECT_NO_THROW(core::CarreauYasuda(core::CarreauYasuda::Params{}));
  EXPECT_NO_THROW(core::Cross(core::Cross::Params{}));
}

}  // namespace
