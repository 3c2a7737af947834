#pragma once
// carreau_yasuda: Carreau–Yasuda law; a = 2 is the Carreau law.
//
//   μ(γ̇) = μ∞ + (μ0 − μ∞) [1 + (λγ̇)^a]^((n−1)/a)
//   dμ/dγ̇ = (μ0 − μ∞) (n−1) λ^a γ̇^(a−1) [1 + (λγ̇)^a]^((n−1)/a − 1)
//
// μ → μ0 as γ̇ → 0 and μ − μ∞ ~ (μ0 − μ∞)(λγ̇)^(n−1) as γ̇ → ∞ (μ → μ∞ for n < 1).
//
// Parameters (SI):
//   zero_shear_viscosity      μ0  [Pa·s]  > 0
//   infinite_shear_viscosity  μ∞  [Pa·s]  >= 0 and < μ0
//   time_constant             λ   [s]     > 0     1/λ is the shear rate where thinning sets in
//   a                         a   [-]     (0, 10] width of the transition (Yasuda exponent)
//   n                         n   [-]     (0, 2]  power-law index at high shear rate
//
// YAML:
//   rheology: {model: carreau_yasuda, zero_shear_viscosity: 1.0, infinite_shear_viscosity: 0.001,
//              time_constant: 0.5, a: 2, n: 0.4}
//
// At γ̇ → 0: for a < 1 the slope dμ/dγ̇ ∝ γ̇^(a−1) diverges. So μ and dμ/dγ̇ are evaluated at
// max(γ̇, γ̇_min) with λγ̇_min = 1e-9: below γ̇_min μ is held and dμ/dγ̇ = 0. Then μ(0) differs
// from μ0 by a relative ≈ (|n−1|/a)·(1e-9)^a: < 1e-9 for a >= 1, 3e-5 for a = 0.5 and n = 0.5,
// which is how slowly the law itself approaches μ0 when a is small.
#include <algorithm>
#include <cmath>
#include <string_view>
#include <vector>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"

namespace rheosim::core {

class CarreauYasuda final : public RheologyBase<CarreauYasuda> {
 public:
  static constexpr std::string_view name = "carreau_yasuda";
  // λγ̇ below which μ is held constant (keeps dμ/dγ̇ finite at γ̇ = 0 when a < 1).
  static constexpr double min_reduced_shear_rate = 1e-9;

  struct Params {
    double zero_shear_viscosity = 1.0;      // μ0 [Pa·s], > 0
    double infinite_shear_viscosity = 0.0;  // μ∞ [Pa·s], [0, μ0)
    double time_constant = 1.0;             // λ [s], > 0
    double a = 2.0;                         // [-], (0, 10]
    double n = 0.5;                         // [-], (0, 2]
    static Params from(const Section& section);
  };

  explicit CarreauYasuda(Params params);

  [[nodiscard]] double mu(double shear_rate) const {
    const double reduced = std::pow(params_.time_constant * std::max(shear_rate, min_shear_rate_), params_.a);
    return params_.infinite_shear_viscosity + viscosity_drop_ * std::pow(1.0 + reduced, exponent_);
  }
  [[nodiscard]] double dmu(double shear_rate) const {
    if (!(shear_rate > min_shear_rate_)) return 0.0;                                 // μ is held below γ̇_min
    const double reduced = std::pow(params_.time_constant * shear_rate, params_.a);  // (λγ̇)^a
    const double base = 1.0 + reduced;
    // (λγ̇)^a / γ̇ = λ^a γ̇^(a−1)
    return viscosity_drop_ * (params_.n - 1.0) * (reduced / shear_rate) * std::pow(base, exponent_) / base;
  }

  // Shear rate below which μ is held constant [1/s].
  [[nodiscard]] double min_shear_rate() const { return min_shear_rate_; }

  [[nodiscard]] std::vector<Parameter> parameters() const override;
  [[nodiscard]] const Params& params() const { return params_; }

 private:
  Params params_;
  double viscosity_drop_;  // μ0 − μ∞
  double exponent_;        // (n − 1)/a
  double min_shear_rate_;  // γ̇_min = min_reduced_shear_rate/λ
};

}  // namespace rheosim::core
