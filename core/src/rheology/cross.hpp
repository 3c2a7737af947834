#pragma once
// cross: Cross law.
//
//   μ(γ̇) = μ∞ + (μ0 − μ∞) / (1 + (λγ̇)^m)
//   dμ/dγ̇ = −(μ0 − μ∞) m λ^m γ̇^(m−1) / (1 + (λγ̇)^m)²
//
// μ → μ0 as γ̇ → 0 and μ − μ∞ ~ (μ0 − μ∞)(λγ̇)^(−m) as γ̇ → ∞.
//
// Parameters (SI):
//   zero_shear_viscosity      μ0  [Pa·s]  > 0
//   infinite_shear_viscosity  μ∞  [Pa·s]  >= 0 and < μ0
//   time_constant             λ   [s]     > 0     1/λ is the shear rate where thinning sets in
//   exponent                  m   [-]     (0, 1]  rate of thinning
//
// YAML:
//   rheology: {model: cross, zero_shear_viscosity: 1.0, infinite_shear_viscosity: 0.001,
//              time_constant: 0.5, exponent: 0.7}
//
// At γ̇ → 0: for m < 1 the slope dμ/dγ̇ ∝ γ̇^(m−1) diverges. So μ and dμ/dγ̇ are evaluated at
// max(γ̇, γ̇_min) with λγ̇_min = 1e-9: below γ̇_min μ is held and dμ/dγ̇ = 0. Then μ(0) differs
// from μ0 by a relative (1 − μ∞/μ0)·(1e-9)^m at most (< 1e-9 for m = 1, 1e-6 for m = 2/3).
#include <algorithm>
#include <cmath>
#include <string_view>
#include <vector>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"

namespace rheosim::core {

class Cross final : public RheologyBase<Cross> {
 public:
  static constexpr std::string_view name = "cross";
  // λγ̇ below which μ is held constant (keeps dμ/dγ̇ finite at γ̇ = 0 when m < 1).
  static constexpr double min_reduced_shear_rate = 1e-9;

  struct Params {
    double zero_shear_viscosity = 1.0;      // μ0 [Pa·s], > 0
    double infinite_shear_viscosity = 0.0;  // μ∞ [Pa·s], [0, μ0)
    double time_constant = 1.0;             // λ [s], > 0
    double exponent = 1.0;                  // m [-], (0, 1]
    static Params from(const Section& section);
  };

  explicit Cross(Params params);

  [[nodiscard]] double mu(double shear_rate) const {
    const double reduced = std::pow(params_.time_constant * std::max(shear_rate, min_shear_rate_), params_.exponent);
    return params_.infinite_shear_viscosity + viscosity_drop_ / (1.0 + reduced);
  }
  [[nodiscard]] double dmu(double shear_rate) const {
    if (!(shear_rate > min_shear_rate_)) return 0.0;                                        // μ is held below γ̇_min
    const double reduced = std::pow(params_.time_constant * shear_rate, params_.exponent);  // (λγ̇)^m
    const double base = 1.0 + reduced;
    // (λγ̇)^m / γ̇ = λ^m γ̇^(m−1)
    return -viscosity_drop_ * params_.exponent * (reduced / shear_rate) / (base * base);
  }

  // Shear rate below which μ is held constant [1/s].
  [[nodiscard]] double min_shear_rate() const { return min_shear_rate_; }

  [[nodiscard]] std::vector<Parameter> parameters() const override;
  [[nodiscard]] const Params& params() const { return params_; }

 private:
  Params params_;
  double viscosity_drop_;  // μ0 − μ∞
  double min_shear_rate_;  // γ̇_min = min_reduced_shear_rate/λ
};

}  // namespace rheosim::core
