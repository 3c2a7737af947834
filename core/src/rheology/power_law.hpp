#pragma once
// power_law: Ostwald–de Waele power law (LDD eq. 11), held constant below a minimum shear rate.
//
//   μ(γ̇) = k · max(γ̇, γ̇_min)^(n−1)
//   dμ/dγ̇ = (n−1) μ/γ̇  for γ̇ > γ̇_min,   0 below
//
// Parameters (SI):
//   consistency     k      [Pa·s^n]  > 0              flow-consistency index
//   index           n      [-]       (0, 2]           flow-behaviour index: < 1 shear-thinning,
//                                                     1 Newtonian, > 1 shear-thickening
//   min_shear_rate  γ̇_min  [1/s]     > 0, default 1e-6
//
// YAML:
//   rheology: {model: power_law, consistency: 0.001, index: 0.6}
//
// At γ̇ → 0 the pure law gives μ → ∞ (n < 1) or μ → 0 (n > 1). Below γ̇_min the viscosity is
// held at k·γ̇_min^(n−1) (a Newtonian plateau) with dμ/dγ̇ = 0, so μ(0) is finite and positive.
// With the default γ̇_min = 1e-6 1/s and n = 0.5 the plateau is 1000 k.
#include <algorithm>
#include <cmath>
#include <string_view>
#include <vector>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"

namespace rheosim::core {

class PowerLaw final : public RheologyBase<PowerLaw> {
 public:
  static constexpr std::string_view name = "power_law";

  struct Params {
    double consistency = 1.0;      // k [Pa·s^n], > 0
    double index = 1.0;            // n [-], (0, 2]
    double min_shear_rate = 1e-6;  // γ̇_min [1/s], > 0: μ is held constant below it
    static Params from(const Section& section);
  };

  explicit PowerLaw(Params params);

  [[nodiscard]] double mu(double shear_rate) const {
    return params_.consistency * std::pow(std::max(shear_rate, params_.min_shear_rate), params_.index - 1.0);
  }
  [[nodiscard]] double dmu(double shear_rate) const {
    if (!(shear_rate > params_.min_shear_rate)) return 0.0;  // Newtonian plateau
    return (params_.index - 1.0) * mu(shear_rate) / shear_rate;
  }

  [[nodiscard]] std::vector<Parameter> parameters() const override;
  [[nodiscard]] const Params& params() const { return params_; }

 private:
  Params params_;
};

}  // namespace rheosim::core
