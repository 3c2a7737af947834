#pragma once
// bingham: Bingham plastic with Papanastasiou regularisation (LDD eq. 7).
//
//   μ(γ̇) = μ∞ + τ0 (1 − e^(−mγ̇)) / γ̇  =  μ∞ + τ0 m g(mγ̇),     g(x) = (1 − e^(−x)) / x
//   dμ/dγ̇ = τ0 m² g'(mγ̇)
//
// The stress τ = μγ̇ tends to the exact Bingham stress μ∞γ̇ + τ0 as m → ∞; the L1 error over
// γ̇ ∈ (0, ∞) is exactly τ0/m.
//
// Parameters (SI):
//   plastic_viscosity  μ∞  [Pa·s]  > 0                 viscosity at high shear rate
//   yield_stress       τ0  [Pa]    >= 0
//   regularization     m   [s]     > 0, default 1000   larger m: closer to the ideal law,
//                                                      stiffer: μ(0) = μ∞ + τ0 m
//
// YAML:
//   rheology: {model: bingham, plastic_viscosity: 0.01, yield_stress: 1.0, regularization: 1000}
//
// At γ̇ → 0: μ(0) = μ∞ + τ0 m (finite), dμ/dγ̇(0) = −τ0 m²/2. No floor is needed: g is evaluated
// as −expm1(−x)/x and g' by its Taylor series for small x, avoiding cancellation.
#include <cmath>
#include <string_view>
#include <vector>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"

namespace rheosim::core {

// Papanastasiou factor g(x) = (1 − e^(−x))/x and its derivative, shared by bingham, casson and
// herschel_bulkley. Relative error < 1e-14 for every x >= 0.
namespace papanastasiou {

[[nodiscard]] inline double factor(double x) {
  if (x < 1e-10) return 1.0 - 0.5 * x;  // expm1(−x)/x would be 0/0 at x = 0
  return -std::expm1(-x) / x;
}

// g'(x) = (x e^(−x) + expm1(−x)) / x². Below x = 0.1 the two terms cancel, so use the series
// g'(x) = Σ_{k>=1} (−1)^k k x^(k−1)/(k+1)! = −1/2 + x/3 − x²/8 + x³/30 − …, truncated after
// the x⁹ term (relative truncation error < 1e-16 at x = 0.1).
[[nodiscard]] inline double factor_derivative(double x) {
  if (x < 0.1) {
    constexpr double c[] = {-1.0 / 2,  1.0 / 3,     -1.0 / 8,    1.0 / 30,      -1.0 / 144,
                            1.0 / 840, -1.0 / 5760, 1.0 / 45360, -1.0 / 403200, 1.0 / 3991680};
    double sum = 0.0;
    for (int k = 9; k >= 0; --k) sum = sum * x + c[k];
    return sum;
  }
  return (x * std::exp(-x) + std::expm1(-x)) / (x * x);
}

}  // namespace papanastasiou

class Bingham final : public RheologyBase<Bingham> {
 public:
  static constexpr std::string_view name = "bingham";

  struct Params {
    double plastic_viscosity = 1.0e-2;  // μ∞ [Pa·s], > 0
    double yield_stress = 1.0;          // τ0 [Pa], >= 0
    double regularization = 1000.0;     // m [s], > 0
    static Params from(const Section& section);
  };

  explicit Bingham(Params params);

  [[nodiscard]] double mu(double shear_rate) const {
    const double m = params_.regularization;
    return params_.plastic_viscosity + params_.yield_stress * m * papanastasiou::factor(m * shear_rate);
  }
  [[nodiscard]] double dmu(double shear_rate) const {
    const double m = params_.regularization;
    return params_.yield_stress * m * m * papanastasiou::factor_derivative(m * shear_rate);
  }

  [[nodiscard]] std::vector<Parameter> parameters() const override;
  [[nodiscard]] double yield_stress() const override { return params_.yield_stress; }
  [[nodiscard]] const Params& params() const { return params_; }

 private:
  Params params_;
};

}  // namespace rheosim::core
