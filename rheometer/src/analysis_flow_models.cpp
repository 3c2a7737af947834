// Flow-curve models and their registry (rheometer/flow_models.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "rheosim/core/config.hpp"
#include "rheosim/rheometer/flow_models.hpp"

namespace rheosim::rheometer {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// Least squares with relative residuals for a law linear in two coefficients,
//   y ≈ c_b · b(x) + c_p · p(x),   minimising Σ ((c_b b_i + c_p p_i − y_i)/y_i)²,
// with c_b >= 0 (a yield stress, η∞) and c_p > 0 (a viscosity). The constrained optimum is the
// unconstrained one when feasible, else the one with c_b = 0.
struct TwoCoefficientFit {
  double bounded = 0;
  double positive = 0;
  double cost = inf;
};

TwoCoefficientFit fit_two_coefficients(std::span<const double> b, std::span<const double> p,
                                       std::span<const double> y) {
  double bb = 0, bp = 0, pp = 0, b1 = 0, p1 = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double bi = b[i] / y[i];
    const double pi = p[i] / y[i];
    bb += bi * bi;
    bp += bi * pi;
    pp += pi * pi;
    b1 += bi;
    p1 += pi;
  }
  auto cost = [&](double cb, double cp) {
    double sum = 0;
    for (std::size_t i = 0; i < y.size(); ++i) {
      const double r = (cb * b[i] + cp * p[i] - y[i]) / y[i];
      sum += r * r;
    }
    return sum;
  };
  TwoCoefficientFit best;
  const double det = bb * pp - bp * bp;
  if (det > 1e-14 * bb * pp) {
    const double cb = (b1 * pp - p1 * bp) / det;
    const double cp = (p1 * bb - b1 * bp) / det;
    if (cb >= 0 && cp > 0) best = {cb, cp, cost(cb, cp)};
  }
  if (pp > 0) {
    const double cp = p1 / pp;
    if (cp > 0) {
      const double c = cost(0.0, cp);
      if (c < best.cost) best = {0.0, cp, c};
    }
  }
  return best;
}

// (value, cost) candidates → the best `count` values, best first.
template <class T>
std::vector<T> best_of(std::vector<std::pair<double, T>> scored, std::size_t count) {
  std::stable_sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<T> out;
  for (const auto& [cost, value] : scored) {
    if (!std::isfinite(cost) || out.size() >= count) break;
    out.push_back(value);
  }
  return out;
}

double newtonian_guess(std::span<const double> x, std::span<const double> y) {
  double s1 = 0, s2 = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double q = x[i] / y[i];
    s1 += q;
    s2 += q * q;
  }
  return s1 / s2;
}

// Straight line ln τ = ln k + n ln γ̇ by ordinary least squares; n = 1 when the rates coincide.
std::pair<double, double> power_law_guess(std::span<const double> x, std::span<const double> y) {
  const auto count = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += std::log(x[i]);
    my += std::log(y[i]);
  }
  mx /= count;
  my /= count;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double dx = std::log(x[i]) - mx;
    sxx += dx * dx;
    sxy += dx * (std::log(y[i]) - my);
  }
  double n = sxx > 0 ? sxy / sxx : 1.0;
  if (!(n > 0.01)) n = 0.01;
  n = std::min(n, 10.0);
  const double k = std::exp(my - n * mx);
  return {k, n};
}

std::vector<double> log_grid(double lo, double hi, int count) {
  std::vector<double> out;
  for (int i = 0; i < count; ++i) out.push_back(lo * std::pow(hi / lo, static_cast<double>(i) / (count - 1)));
  return out;
}

// Profile guesses for the four-parameter viscosity-curve laws (Cross, Carreau): for each (λ, e)
// of a grid, `shape(λγ̇, e)` gives f in η = η∞ + (η0 − η∞) f and (η0, η∞) follow linearly.
template <class Shape>
std::vector<std::vector<double>> plateau_law_guesses(std::span<const double> x, std::span<const double> y,
                                                     std::span<const double> exponents, const Shape& shape) {
  const auto [min_it, max_it] = std::minmax_element(x.begin(), x.end());
  const double x_min = *min_it;
  const double x_max = *max_it;
  std::vector<double> b(x.size()), p(x.size());
  std::vector<std::pair<double, std::vector<double>>> scored;
  for (const double lambda : log_grid(0.01 / x_max, 100.0 / x_min, 41)) {
    for (const double e : exponents) {
      for (std::size_t i = 0; i < x.size(); ++i) {
        const double f = shape(lambda * x[i], e);
        p[i] = f * x[i];          // multiplies η0
        b[i] = (1.0 - f) * x[i];  // multiplies η∞
      }
      const auto fit = fit_two_coefficients(b, p, y);
      if (std::isfinite(fit.cost)) scored.push_back({fit.cost, {fit.positive, fit.bounded, lambda, e}});
    }
  }
  return best_of(std::move(scored), 4);
}

void check_values(std::span<const double> values, std::size_t expected, std::string_view model) {
  if (values.size() != expected)
    throw std::invalid_argument(std::string(model) + ": expected " + std::to_string(expected) + " parameters, got " +
                                std::to_string(values.size()));
}

}  // namespace

// ---------------------------------------------------------------------------------------------

std::optional<std::size_t> FlowModel::yield_stress_index() const {
  const auto ps = parameters();
  for (std::size_t j = 0; j < ps.size(); ++j)
    if (ps[j].is_yield_stress) return j;
  return std::nullopt;
}

std::optional<std::size_t> FlowModel::parameter_index(std::string_view name) const {
  const auto ps = parameters();
  for (std::size_t j = 0; j < ps.size(); ++j)
    if (ps[j].name == name) return j;
  return std::nullopt;
}

// newtonian -----------------------------------------------------------------------------------

std::span<const FlowParameterInfo> NewtonianModel::parameters() const {
  static const std::array<FlowParameterInfo, 1> info{{{"viscosity", "η", "Pa·s", ParameterScale::positive(), false}}};
  return info;
}

double NewtonianModel::stress(double shear_rate, std::span<const double> v) const {
  check_values(v, 1, model_name);
  return v[0] * shear_rate;
}

void NewtonianModel::stress_gradient(double shear_rate, std::span<const double> v, std::span<double> g) const {
  check_values(v, 1, model_name);
  g[0] = v[0] * shear_rate;  // ∂τ/∂ln η
}

std::vector<std::vector<double>> NewtonianModel::initial_guesses(std::span<const double> x,
                                                                 std::span<const double> y) const {
  return {{newtonian_guess(x, y)}};
}

// power_law -----------------------------------------------------------------------------------

std::span<const FlowParameterInfo> PowerLawModel::parameters() const {
  static const std::array<FlowParameterInfo, 2> info{{
      {"consistency", "k", "Pa·sⁿ", ParameterScale::positive(), false},
      {"index", "n", "-", ParameterScale::positive(), false},
  }};
  return info;
}

double PowerLawModel::stress(double shear_rate, std::span<const double> v) const {
  check_values(v, 2, model_name);
  return v[0] * std::pow(shear_rate, v[1]);
}

void PowerLawModel::stress_gradient(double shear_rate, std::span<const double> v, std::span<double> g) const {
  check_values(v, 2, model_name);
  const double tau = v[0] * std::pow(shear_rate, v[1]);
  g[0] = tau;                                // ∂τ/∂ln k
  g[1] = tau * std::log(shear_rate) * v[1];  // ∂τ/∂ln n
}

std::vector<std::vector<double>> PowerLawModel::initial_guesses(std::span<const double> x,
                                                                std::span<const double> y) const {
  const auto [k, n] = power_law_guess(x, y);
  return {{k, n}, {newtonian_guess(x, y), 1.0}};
}

// bingham -------------------------------------------------------------------------------------

std::span<const FlowParameterInfo> BinghamModel::parameters() const {
  static const std::array<FlowParameterInfo, 2> info{{
      {"yield_stress", "τ_y", "Pa", ParameterScale::at_least(0.0), true},
      {"plastic_viscosity", "η_p", "Pa·s", ParameterScale::positive(), false},
  }};
  return info;
}

double BinghamModel::stress(double shear_rate, std::span<const double> v) const {
  check_values(v, 2, model_name);
  return v[0] + v[1] * shear_rate;
}

void BinghamModel::stress_gradient(double shear_rate, std::span<const double> v, std::span<double> g) const {
  check_values(v, 2, model_name);
  g[0] = 1.0;                // ∂τ/∂τ_y
  g[1] = v[1] * shear_rate;  // ∂τ/∂ln η_p
}

std::vector<std::vector<double>> BinghamModel::initial_guesses(std::span<const double> x,
                                                               std::span<const double> y) const {
  const std::vector<double> ones(x.size(), 1.0);
  std::vector<std::vector<double>> out;
  if (const auto fit = fit_two_coefficients(ones, x, y); std::isfinite(fit.cost))
    out.push_back({fit.bounded, fit.positive});
  out.push_back({0.0, newtonian_guess(x, y)});
  return out;
}

// casson --------------------------------------------------------------------------------------

std::span<const FlowParameterInfo> CassonModel::parameters() const {
  static const std::array<FlowParameterInfo, 2> info{{
      {"yield_stress", "τ_y", "Pa", ParameterScale::squared(0.0), true},
      {"plastic_viscosity", "η_p", "Pa·s", ParameterScale::positive(), false},
  }};
  return info;
}

double CassonModel::stress(double shear_rate, std::span<const double> v) const {
  check_values(v, 2, model_name);
  const double root = std::sqrt(std::max(v[0], 0.0)) + std::sqrt(v[1] * shear_rate);
  return root * root;
}

void CassonModel::stress_gradient(double shear_rate, std::span<const double> v, std::span<double> g) const {
  check_values(v, 2, model_name);
  const double a = std::sqrt(std::max(v[0], 0.0));
  const double c = std::sqrt(v[1] * shear_rate);
  g[0] = 2.0 * (a + c);  // ∂τ/∂√τ_y
  g[1] = (a + c) * c;    // ∂τ/∂ln η_p
}

std::vector<std::vector<double>> CassonModel::initial_guesses(std::span<const double> x,
                                                              std::span<const double> y) const {
  // The Casson plot: √τ = √τ_y + √η_p √γ̇, relative residuals in √τ (half those in τ).
  std::vector<double> ones(x.size(), 1.0), sx(x.size()), sy(y.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx[i] = std::sqrt(x[i]);
    sy[i] = std::sqrt(y[i]);
  }
  std::vector<std::vector<double>> out;
  if (const auto fit = fit_two_coefficients(ones, sx, sy); std::isfinite(fit.cost))
    out.push_back({fit.bounded * fit.bounded, fit.positive * fit.positive});
  out.push_back({0.0, newtonian_guess(x, y)});
  return out;
}

// herschel_bulkley ----------------------------------------------------------------------------

std::span<const FlowParameterInfo> HerschelBulkleyModel::parameters() const {
  static const std::array<FlowParameterInfo, 3> info{{
      {"yield_stress", "τ_y", "Pa", ParameterScale::at_least(0.0), true},
      {"consistency", "k", "Pa·sⁿ", ParameterScale::positive(), false},
      {"index", "n", "-", ParameterScale::positive(), false},
  }};
  return info;
}

double HerschelBulkleyModel::stress(double shear_rate, std::span<const double> v) const {
  check_values(v, 3, model_name);
  return v[0] + v[1] * std::pow(shear_rate, v[2]);
}

void HerschelBulkleyModel::stress_gradient(double shear_rate, std::span<const double> v, std::span<double> g) const {
  check_values(v, 3, model_name);
  const double flow = v[1] * std::pow(shear_rate, v[2]);
  g[0] = 1.0;                                 // ∂τ/∂τ_y
  g[1] = flow;                                // ∂τ/∂ln k
  g[2] = flow * std::log(shear_rate) * v[2];  // ∂τ/∂ln n
}

std::vector<std::vector<double>> HerschelBulkleyModel::initial_guesses(std::span<const double> x,
                                                                       std::span<const double> y) const {
  const std::vector<double> ones(x.size(), 1.0);
  std::vector<double> p(x.size());
  std::vector<std::pair<double, std::vector<double>>> scored;
  for (int step = 0; step <= 38; ++step) {
    const double n = 0.1 + 0.05 * step;  // 0.1 … 2.0
    for (std::size_t i = 0; i < x.size(); ++i) p[i] = std::pow(x[i], n);
    const auto fit = fit_two_coefficients(ones, p, y);
    if (std::isfinite(fit.cost)) scored.push_back({fit.cost, {fit.bounded, fit.positive, n}});
  }
  auto out = best_of(std::move(scored), 2);
  const auto [k, n] = power_law_guess(x, y);
  out.push_back({0.0, k, n});
  return out;
}

// cross ---------------------------------------------------------------------------------------

std::span<const FlowParameterInfo> CrossModel::parameters() const {
  static const std::array<FlowParameterInfo, 4> info{{
      {"zero_shear_viscosity", "η0", "Pa·s", ParameterScale::positive(), false},
      {"infinite_shear_viscosity", "η∞", "Pa·s", ParameterScale::at_least(0.0), false},
      {"time_constant", "λ", "s", ParameterScale::positive(), false},
      {"exponent", "m", "-", ParameterScale::positive(), false},
  }};
  return info;
}

double CrossModel::stress(double shear_rate, std::span<const double> v) const {
  check_values(v, 4, model_name);
  const double s = 1.0 / (1.0 + std::pow(v[2] * shear_rate, v[3]));  // 1/(1 + u)
  return shear_rate * (v[1] + (v[0] - v[1]) * s);
}

void CrossModel::stress_gradient(double shear_rate, std::span<const double> v, std::span<double> g) const {
  check_values(v, 4, model_name);
  const double u = std::pow(v[2] * shear_rate, v[3]);
  const double s = 1.0 / (1.0 + u);  // 1/(1+u); u/(1+u) = 1 − s; u/(1+u)² = s(1 − s): finite for u → ∞
  const double drop = (v[0] - v[1]) * shear_rate;
  g[0] = v[0] * shear_rate * s;                                       // ∂τ/∂ln η0
  g[1] = shear_rate * (1.0 - s);                                      // ∂τ/∂η∞
  g[2] = -drop * v[3] * s * (1.0 - s);                                // ∂τ/∂ln λ
  g[3] = -drop * v[3] * std::log(v[2] * shear_rate) * s * (1.0 - s);  // ∂τ/∂ln m
}

std::vector<std::vector<double>> CrossModel::initial_guesses(std::span<const double> x,
                                                             std::span<const double> y) const {
  static constexpr std::array<double, 8> exponents{0.25, 0.4, 0.55, 0.7, 0.85, 1.0, 1.2, 1.5};
  return plateau_law_guesses(x, y, exponents, [](double lx, double m) { return 1.0 / (1.0 + std::pow(lx, m)); });
}

// carreau -------------------------------------------------------------------------------------

std::span<const FlowParameterInfo> CarreauModel::parameters() const {
  static const std::array<FlowParameterInfo, 4> info{{
      {"zero_shear_viscosity", "η0", "Pa·s", ParameterScale::positive(), false},
      {"infinite_shear_viscosity", "η∞", "Pa·s", ParameterScale::at_least(0.0), false},
      {"time_constant", "λ", "s", ParameterScale::positive(), false},
      {"index", "n", "-", ParameterScale::positive(), false},
  }};
  return info;
}

double CarreauModel::stress(double shear_rate, std::span<const double> v) const {
  check_values(v, 4, model_name);
  const double lx = v[2] * shear_rate;
  const double f = std::exp(0.5 * (v[3] - 1.0) * std::log1p(lx * lx));  // (1 + (λγ̇)²)^((n−1)/2)
  return shear_rate * (v[1] + (v[0] - v[1]) * f);
}

void CarreauModel::stress_gradient(double shear_rate, std::span<const double> v, std::span<double> g) const {
  check_values(v, 4, model_name);
  const double lx = v[2] * shear_rate;
  const double log_b = std::log1p(lx * lx);  // ln B, B = 1 + (λγ̇)²
  const double f = std::exp(0.5 * (v[3] - 1.0) * log_b);
  const double w = lx * lx / (1.0 + lx * lx);  // (λγ̇)²/B, finite for λγ̇ → ∞
  const double drop = (v[0] - v[1]) * shear_rate;
  g[0] = v[0] * shear_rate * f;          // ∂τ/∂ln η0
  g[1] = shear_rate * (1.0 - f);         // ∂τ/∂η∞
  g[2] = drop * (v[3] - 1.0) * f * w;    // ∂τ/∂ln λ = (η0−η∞)γ̇ · 2·((n−1)/2)·f·w
  g[3] = drop * f * log_b * 0.5 * v[3];  // ∂τ/∂ln n
}

std::vector<std::vector<double>> CarreauModel::initial_guesses(std::span<const double> x,
                                                               std::span<const double> y) const {
  static constexpr std::array<double, 10> indices{0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  return plateau_law_guesses(x, y, indices,
                             [](double lx, double n) { return std::exp(0.5 * (n - 1.0) * std::log1p(lx * lx)); });
}

// registry ------------------------------------------------------------------------------------

void FlowModelRegistry::add(std::string name, Maker make) {
  if (!makers_.try_emplace(name, std::move(make)).second)
    throw std::logic_error("flow model registered twice: " + name);
}

std::shared_ptr<const FlowModel> FlowModelRegistry::make(std::string_view name) const {
  if (const auto it = makers_.find(name); it != makers_.end()) return it->second();
  std::string message = "unknown flow model '" + std::string(name) + "'";
  const auto valid = names();
  if (const auto suggestion = core::nearest(name, valid)) message += " (did you mean '" + *suggestion + "'?)";
  message += "; valid models:";
  for (const auto& n : valid) message += " " + n;
  throw std::invalid_argument(message);
}

bool FlowModelRegistry::contains(std::string_view name) const { return makers_.find(name) != makers_.end(); }

std::vector<std::string> FlowModelRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, maker] : makers_) out.push_back(name);
  return out;
}

void add_builtin_flow_models(FlowModelRegistry& registry) {
  registry.add<NewtonianModel>();
  registry.add<PowerLawModel>();
  registry.add<BinghamModel>();
  registry.add<CassonModel>();
  registry.add<HerschelBulkleyModel>();
  registry.add<CrossModel>();
  registry.add<CarreauModel>();
}

const FlowModelRegistry& builtin_flow_models() {
  static const FlowModelRegistry registry = [] {
    FlowModelRegistry r;
    add_builtin_flow_models(r);
    return r;
  }();
  return registry;
}

std::shared_ptr<const FlowModel> make_flow_model(std::string_view name) { return builtin_flow_models().make(name); }

}  // namespace rheosim::rheometer
