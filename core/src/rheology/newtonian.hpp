#pragma once
// newtonian: constant viscosity.
//
//   μ(γ̇) = μ                                                   dμ/dγ̇ = 0
//
// Parameters (SI):
//   viscosity  μ  [Pa·s]  > 0   dynamic viscosity
//
// YAML:
//   rheology: {model: newtonian, viscosity: 1.0e-3}
//
// At γ̇ → 0: μ(0) = μ; nothing needs regularising.
#include <string_view>
#include <vector>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"

namespace rheosim::core {

class Newtonian final : public RheologyBase<Newtonian> {
 public:
  static constexpr std::string_view name = "newtonian";

  struct Params {
    double viscosity = 1.0e-3;  // μ [Pa·s], > 0 (default: water at 20 °C)
    static Params from(const Section& section);
  };

  explicit Newtonian(Params params);

  [[nodiscard]] double mu(double /*shear_rate*/) const { return params_.viscosity; }
  [[nodiscard]] double dmu(double /*shear_rate*/) const { return 0.0; }

  [[nodiscard]] std::vector<Parameter> parameters() const override;
  [[nodiscard]] const Params& params() const { return params_; }

 private:
  Params params_;
};

}  // namespace rheosim::core
