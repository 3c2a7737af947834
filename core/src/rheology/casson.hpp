#pragma once
// casson: Casson plastic with Papanastasiou regularisation (LDD eq. 9, corrected; see below).
//
//   μ(γ̇) = [√μ∞ + √(τ0/γ̇) (1 − e^(−√(mγ̇)))]²  =  [√μ∞ + √(τ0 m) g(x)]²,   x = √(mγ̇)
//   dμ/dγ̇ = 2 [√μ∞ + √(τ0 m) g(x)] · √(τ0 m) g'(x) · m/(2x)
//
// with g(x) = (1 − e^(−x))/x from bingham.hpp. The stress tends to the exact Casson stress
// τ = (√τ0 + √(μ∞γ̇))² as m → ∞; the L1 error over γ̇ is ≈ 3.5 τ0/m for large m.
//
// Deviation from the seed: LDD eq. 9 as printed has e^(−√m |γ̇|). With that exponent μ(0) = μ∞,
// i.e. the yield stress vanishes at rest, which is not a regularised Casson law. We use the
// Papanastasiou–Casson form of Mitsoulis (e^(−√(mγ̇))), for which μ(0) = (√μ∞ + √(τ0 m))².
//
// Parameters (SI):
//   plastic_viscosity  μ∞  [Pa·s]  > 0                 Casson viscosity at high shear rate
//   yield_stress       τ0  [Pa]    >= 0
//   regularization     m   [s]     > 0, default 1000
//
// YAML:
//   rheology: {model: casson, plastic_viscosity: 0.01, yield_stress: 1.0e-4, regularization: 1000}
//
// At γ̇ → 0: μ → (√μ∞ + √(τ0 m))², but dμ/dγ̇ ∝ −1/√γ̇ → −∞ (g'(0) = −1/2). So both μ and dμ/dγ̇
// are evaluated at max(γ̇, γ̇_min) with γ̇_min = 1e-12/m (i.e. x >= 1e-6): below γ̇_min μ is held
// and dμ/dγ̇ = 0. μ(0) then differs from (√μ∞ + √(τ0 m))² by a relative ≈ 1e-6 at most.
#include <algorithm>
#include <cmath>
#include <string_view>
#include <vector>

#include "bingham.hpp"
#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"

namespace rheosim::core {

class Casson final : public RheologyBase<Casson> {
 public:
  static constexpr std::string_view name = "casson";
  // x = √(mγ̇) below which μ is held constant (keeps dμ/dγ̇ finite at γ̇ = 0).
  static constexpr double min_regularized_root = 1e-6;

  struct Params {
    double plastic_viscosity = 1.0e-2;  // μ∞ [Pa·s], > 0
    double yield_stress = 1.0;          // τ0 [Pa], >= 0
    double regularization = 1000.0;     // m [s], > 0
    static Params from(const Section& section);
  };

  explicit Casson(Params params);

  [[nodiscard]] double mu(double shear_rate) const {
    const double root = sqrt_mu_inf_ + sqrt_tau0_m_ * papanastasiou::factor(x(shear_rate));
    return root * root;
  }
  [[nodiscard]] double dmu(double shear_rate) const {
    if (!(shear_rate > min_shear_rate_)) return 0.0;  // μ is held below γ̇_min
    const double xi = x(shear_rate);
    const double root = sqrt_mu_inf_ + sqrt_tau0_m_ * papanastasiou::factor(xi);
    // dx/dγ̇ = m/(2x)
    return root * sqrt_tau0_m_ * papanastasiou::factor_derivative(xi) * params_.regularization / xi;
  }

  // Shear rate below which μ is held constant [1/s].
  [[nodiscard]] double min_shear_rate() const { return min_shear_rate_; }

  [[nodiscard]] std::vector<Parameter> parameters() const override;
  [[nodiscard]] double yield_stress() const override { return params_.yield_stress; }
  [[nodiscard]] const Params& params() const { return params_; }

 private:
  [[nodiscard]] double x(double shear_rate) const {
    return std::sqrt(params_.regularization * std::max(shear_rate, min_shear_rate_));
  }

  Params params_;
  double sqrt_mu_inf_;     // √μ∞
  double sqrt_tau0_m_;     // √(τ0 m)
  double min_shear_rate_;  // γ̇_min = min_regularized_root²/m
};

}  // namespace rheosim::core
