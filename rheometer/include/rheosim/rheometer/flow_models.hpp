#pragma once
// Flow-curve models τ(γ̇) that rheometer::fit_flow_curve (analysis.hpp) fits to measured
// (rim shear rate, rim stress) data. Each model is one small class behind FlowModel, selected by
// its name through FlowModelRegistry; add_builtin_flow_models() is the one explicit list.
// Names and parameter keys follow the rheology laws of core/ where they exist, so a
// fit can be read back as a `rheology:` section; `carreau` is carreau_yasuda with a = 2.
//
// The solver moves each parameter in its fit coordinate θ (least_squares.hpp, ParameterScale):
// scale parameters (viscosities, consistency, indices, time constants) in ln p, so they stay
// positive and their intervals are asymmetric; yield stresses and η∞ linearly with a bound at 0,
// so "no yield stress" is a reachable answer and its interval can include 0; Casson's yield
// stress as √τ_y ≥ 0 (the Casson law is smooth in √τ_y, not in τ_y at 0).
// All values SI: γ̇ in 1/s, τ in Pa, viscosities in Pa·s.
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rheosim/rheometer/least_squares.hpp"

namespace rheosim::rheometer {

struct FlowParameterInfo {
  std::string_view name;    // key as in core's rheology laws, e.g. "yield_stress"
  std::string_view symbol;  // for reports, e.g. "τ_y"
  std::string_view unit;    // SI unit, e.g. "Pa"
  ParameterScale scale;     // fit coordinate and domain
  bool is_yield_stress = false;
};

class FlowModel {
 public:
  virtual ~FlowModel() = default;

  [[nodiscard]] virtual std::string_view name() const = 0;      // e.g. "herschel_bulkley"
  [[nodiscard]] virtual std::string_view equation() const = 0;  // e.g. "τ = τ_y + k γ̇ⁿ"
  [[nodiscard]] virtual std::span<const FlowParameterInfo> parameters() const = 0;

  // τ(γ̇; p) [Pa] for physical parameter values p (size parameter_count()).
  [[nodiscard]] virtual double stress(double shear_rate, std::span<const double> values) const = 0;
  // ∂τ/∂θ_j at γ̇: the derivative with respect to each parameter's fit coordinate
  // (ParameterScale; e.g. ∂τ/∂ln k), written out per model so it stays finite on the bounds.
  virtual void stress_gradient(double shear_rate, std::span<const double> values, std::span<double> gradient) const = 0;
  // Starting points for the solver, in physical values, best first; built from the data by
  // closed-form or profiled linear least squares (each model documents how).
  [[nodiscard]] virtual std::vector<std::vector<double>> initial_guesses(std::span<const double> shear_rate,
                                                                         std::span<const double> stress) const = 0;

  [[nodiscard]] std::size_t parameter_count() const { return parameters().size(); }
  [[nodiscard]] std::optional<std::size_t> yield_stress_index() const;
  [[nodiscard]] std::optional<std::size_t> parameter_index(std::string_view name) const;
  // The flow-curve viscosity τ/γ̇ [Pa·s] (γ̇ > 0).
  [[nodiscard]] double viscosity(double shear_rate, std::span<const double> values) const {
    return stress(shear_rate, values) / shear_rate;
  }

 protected:
  FlowModel() = default;
  FlowModel(const FlowModel&) = default;
  FlowModel& operator=(const FlowModel&) = default;
};

// newtonian: τ = η γ̇.                                    viscosity η [Pa·s] > 0
class NewtonianModel final : public FlowModel {
 public:
  static constexpr std::string_view model_name = "newtonian";
  [[nodiscard]] std::string_view name() const override { return model_name; }
  [[nodiscard]] std::string_view equation() const override { return "τ = η γ̇"; }
  [[nodiscard]] std::span<const FlowParameterInfo> parameters() const override;
  [[nodiscard]] double stress(double shear_rate, std::span<const double> values) const override;
  void stress_gradient(double shear_rate, std::span<const double> values, std::span<double> gradient) const override;
  // The relative-weighted optimum in closed form: η = Σ(γ̇/τ) / Σ(γ̇/τ)².
  [[nodiscard]] std::vector<std::vector<double>> initial_guesses(std::span<const double> shear_rate,
                                                                 std::span<const double> stress) const override;
};

// power_law: τ = k γ̇ⁿ.                consistency k [Pa·sⁿ] > 0, index n [-] > 0
class PowerLawModel final : public FlowModel {
 public:
  static constexpr std::string_view model_name = "power_law";
  [[nodiscard]] std::string_view name() const override { return model_name; }
  [[nodiscard]] std::string_view equation() const override { return "τ = k γ̇ⁿ"; }
  [[nodiscard]] std::span<const FlowParameterInfo> parameters() const override;
  [[nodiscard]] double stress(double shear_rate, std::span<const double> values) const override;
  void stress_gradient(double shear_rate, std::span<const double> values, std::span<double> gradient) const override;
  // Straight line through (ln γ̇, ln τ).
  [[nodiscard]] std::vector<std::vector<double>> initial_guesses(std::span<const double> shear_rate,
                                                                 std::span<const double> stress) const override;
};

// bingham: τ = τ_y + η_p γ̇.       yield_stress τ_y [Pa] >= 0, plastic_viscosity η_p [Pa·s] > 0
class BinghamModel final : public FlowModel {
 public:
  static constexpr std::string_view model_name = "bingham";
  [[nodiscard]] std::string_view name() const override { return model_name; }
  [[nodiscard]] std::string_view equation() const override { return "τ = τ_y + η_p γ̇"; }
  [[nodiscard]] std::span<const FlowParameterInfo> parameters() const override;
  [[nodiscard]] double stress(double shear_rate, std::span<const double> values) const override;
  void stress_gradient(double shear_rate, std::span<const double> values, std::span<double> gradient) const override;
  // Relative-weighted straight line τ(γ̇) with τ_y >= 0.
  [[nodiscard]] std::vector<std::vector<double>> initial_guesses(std::span<const double> shear_rate,
                                                                 std::span<const double> stress) const override;
};

// casson: √τ = √τ_y + √(η_p γ̇).  yield_stress τ_y [Pa] >= 0 (fitted as √τ_y), plastic_viscosity η_p [Pa·s] > 0
class CassonModel final : public FlowModel {
 public:
  static constexpr std::string_view model_name = "casson";
  [[nodiscard]] std::string_view name() const override { return model_name; }
  [[nodiscard]] std::string_view equation() const override { return "√τ = √τ_y + √(η_p γ̇)"; }
  [[nodiscard]] std::span<const FlowParameterInfo> parameters() const override;
  [[nodiscard]] double stress(double shear_rate, std::span<const double> values) const override;
  void stress_gradient(double shear_rate, std::span<const double> values, std::span<double> gradient) const override;
  // Weighted straight line √τ(√γ̇) (the Casson plot) with √τ_y >= 0.
  [[nodiscard]] std::vector<std::vector<double>> initial_guesses(std::span<const double> shear_rate,
                                                                 std::span<const double> stress) const override;
};

// herschel_bulkley: τ = τ_y + k γ̇ⁿ.
//   yield_stress τ_y [Pa] >= 0, consistency k [Pa·sⁿ] > 0, index n [-] > 0
class HerschelBulkleyModel final : public FlowModel {
 public:
  static constexpr std::string_view model_name = "herschel_bulkley";
  [[nodiscard]] std::string_view name() const override { return model_name; }
  [[nodiscard]] std::string_view equation() const override { return "τ = τ_y + k γ̇ⁿ"; }
  [[nodiscard]] std::span<const FlowParameterInfo> parameters() const override;
  [[nodiscard]] double stress(double shear_rate, std::span<const double> values) const override;
  void stress_gradient(double shear_rate, std::span<const double> values, std::span<double> gradient) const override;
  // Profile over n (linear least squares for τ_y >= 0 and k at each n of a grid); best n first.
  [[nodiscard]] std::vector<std::vector<double>> initial_guesses(std::span<const double> shear_rate,
                                                                 std::span<const double> stress) const override;
};

// cross: τ = γ̇ [η∞ + (η0 − η∞) / (1 + (λγ̇)^m)].
//   zero_shear_viscosity η0 [Pa·s] > 0, infinite_shear_viscosity η∞ [Pa·s] >= 0,
//   time_constant λ [s] > 0, exponent m [-] > 0
class CrossModel final : public FlowModel {
 public:
  static constexpr std::string_view model_name = "cross";
  [[nodiscard]] std::string_view name() const override { return model_name; }
  [[nodiscard]] std::string_view equation() const override { return "η = η∞ + (η0 − η∞)/(1 + (λγ̇)^m)"; }
  [[nodiscard]] std::span<const FlowParameterInfo> parameters() const override;
  [[nodiscard]] double stress(double shear_rate, std::span<const double> values) const override;
  void stress_gradient(double shear_rate, std::span<const double> values, std::span<double> gradient) const override;
  // Profile over a (λ, m) grid: for fixed λ, m the law is linear in (η0, η∞ >= 0).
  [[nodiscard]] std::vector<std::vector<double>> initial_guesses(std::span<const double> shear_rate,
                                                                 std::span<const double> stress) const override;
};

// carreau (Carreau–Yasuda with a = 2): τ = γ̇ [η∞ + (η0 − η∞) (1 + (λγ̇)²)^((n−1)/2)].
//   zero_shear_viscosity η0 [Pa·s] > 0, infinite_shear_viscosity η∞ [Pa·s] >= 0,
//   time_constant λ [s] > 0, index n [-] > 0
class CarreauModel final : public FlowModel {
 public:
  static constexpr std::string_view model_name = "carreau";
  [[nodiscard]] std::string_view name() const override { return model_name; }
  [[nodiscard]] std::string_view equation() const override { return "η = η∞ + (η0 − η∞)(1 + (λγ̇)²)^((n−1)/2)"; }
  [[nodiscard]] std::span<const FlowParameterInfo> parameters() const override;
  [[nodiscard]] double stress(double shear_rate, std::span<const double> values) const override;
  void stress_gradient(double shear_rate, std::span<const double> values, std::span<double> gradient) const override;
  // Profile over a (λ, n) grid: for fixed λ, n the law is linear in (η0, η∞ >= 0).
  [[nodiscard]] std::vector<std::vector<double>> initial_guesses(std::span<const double> shear_rate,
                                                                 std::span<const double> stress) const override;
};

// Name → model. Unknown names throw std::invalid_argument listing the valid names (and the
// nearest one); a config reader can check names up front with names() and Section::choice.
class FlowModelRegistry {
 public:
  using Maker = std::function<std::shared_ptr<const FlowModel>()>;
  void add(std::string name, Maker make);
  template <class Model>
  void add() {
    add(std::string(Model::model_name), [] { return std::make_shared<const Model>(); });
  }
  [[nodiscard]] std::shared_ptr<const FlowModel> make(std::string_view name) const;
  [[nodiscard]] bool contains(std::string_view name) const;
  [[nodiscard]] std::vector<std::string> names() const;  // sorted

 private:
  std::map<std::string, Maker, std::less<>> makers_;
};

// newtonian, power_law, bingham, casson, herschel_bulkley, cross, carreau.
void add_builtin_flow_models(FlowModelRegistry& registry);
[[nodiscard]] const FlowModelRegistry& builtin_flow_models();
[[nodiscard]] std::shared_ptr<const FlowModel> make_flow_model(std::string_view name);

}  // namespace rheosim::rheometer
