#pragma once
// herschel_bulkley: Herschel–Bulkley law, a power law plus a yield stress, with the yield term
// regularised as in bingham (Papanastasiou, LDD eq. 7) and the power-law term as in power_law
// (LDD eq. 11, held below γ̇_min).
//
//   μ(γ̇) = k · max(γ̇, γ̇_min)^(n−1) + τ0 (1 − e^(−mγ̇))/γ̇  =  k · max(γ̇, γ̇_min)^(n−1) + τ0 m g(mγ̇)
//   dμ/dγ̇ = (n−1) k γ̇^(n−2) [only for γ̇ > γ̇_min] + τ0 m² g'(mγ̇)
//
// With n = 1 it is exactly bingham with μ∞ = k; with τ0 = 0 exactly power_law.
//
// Parameters (SI):
//   consistency     k      [Pa·s^n]  > 0
//   index           n      [-]       (0, 2]
//   yield_stress    τ0     [Pa]      >= 0
//   regularization  m      [s]       > 0, default 1000
//   min_shear_rate  γ̇_min  [1/s]     > 0, default 1e-6   (power-law term only)
//
// YAML:
//   rheology: {model: herschel_bulkley, consistency: 0.5, index: 0.6, yield_stress: 2.0}
//
// At γ̇ → 0: μ(0) = k γ̇_min^(n−1) + τ0 m (finite), dμ/dγ̇(0) = −τ0 m²/2. The yield term needs
// no floor; the power-law term is held below γ̇_min exactly as in power_law.
#include <algorithm>
#include <cmath>
#include <string_view>
#include <vector>

#include "bingham.hpp"
#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"

namespace rheosim::core {

class HerschelBulkley final : public RheologyBase<HerschelBulkley> {
 public:
  static constexpr std::string_view name = "herschel_bulkley";

  struct Params {
    double consistency = 1.0;        // k [Pa·s^n], > 0
    double index = 1.0;              // n [-], (0, 2]
    double yield_stress = 1.0;       // τ0 [Pa], >= 0
    double regularization = 1000.0;  // m [s], > 0
    double min_shear_rate = 1e-6;    // γ̇_min [1/s], > 0
    static Params from(const Section& section);
  };

  explicit HerschelBulkley(Params params);

  [[nodiscard]] double mu(double shear_rate) const {
    const double m = params_.regularization;
    return power_law_part(shear_rate) + params_.yield_stress * m * papanastasiou::factor(m * shear_rate);
  }
  [[nodiscard]] double dmu(double shear_rate) const {
    const double m = params_.regularization;
    const double yield_part = params_.yield_stress * m * m * papanastasiou::factor_derivative(m * shear_rate);
    if (!(shear_rate > params_.min_shear_rate)) return yield_part;  // power-law term held
    return (params_.index - 1.0) * power_law_part(shear_rate) / shear_rate + yield_part;
  }

  [[nodiscard]] std::vector<Parameter> parameters() const override;
  [[nodiscard]] double yield_stress() const override { return params_.yield_stress; }
  [[nodiscard]] const Params& params() const { return params_; }

 private:
  [[nodiscard]] double power_law_part(double shear_rate) const {
    return params_.consistency * std::pow(std::max(shear_rate, params_.min_shear_rate), params_.index - 1.0);
  }

  Params params_;
};

}  // namespace rheosim::core
