#pragma once
// Generalized-Newtonian viscosity laws μ(γ̇), with γ̇ = √(2E:E) (LDD eq. 5) everywhere.
// Each law is one class in core/src/rheology/<name>.{hpp,cpp}, registered by its YAML name
// in add_builtin_rheologies(). All values are SI: μ in Pa·s, γ̇ in 1/s, τ in Pa.
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rheosim/core/registry.hpp"

namespace rheosim::core {

// One named model parameter, for reports and summary.json.
struct Parameter {
  std::string name;  // YAML key, e.g. "yield_stress"
  double value = 0;
  std::string unit;  // SI unit, e.g. "Pa"
};

class Rheology {
 public:
  virtual ~Rheology() = default;

  [[nodiscard]] virtual std::string_view name() const = 0;  // YAML name, e.g. "power_law"
  [[nodiscard]] virtual std::vector<Parameter> parameters() const = 0;

  // Apparent viscosity μ(γ̇) [Pa·s] for γ̇ >= 0. Finite and positive for every γ̇ >= 0,
  // including γ̇ = 0 (each law documents how it stays finite there).
  [[nodiscard]] virtual double viscosity(double shear_rate) const = 0;
  // dμ/dγ̇ [Pa·s²], consistent with viscosity() (also in its regularised/clamped parts).
  [[nodiscard]] virtual double viscosity_derivative(double shear_rate) const = 0;
  // Shear stress τ = μ(γ̇) γ̇ [Pa].
  [[nodiscard]] double stress(double shear_rate) const { return viscosity(shear_rate) * shear_rate; }
  // Yield stress of the underlying (unregularised) law [Pa]; 0 for laws without one.
  [[nodiscard]] virtual double yield_stress() const { return 0.0; }

  // Array forms for hot loops: one virtual call per array. Spans must have equal sizes.
  virtual void viscosity(std::span<const double> shear_rate, std::span<double> mu) const = 0;
  virtual void viscosity_derivative(std::span<const double> shear_rate, std::span<double> dmu) const = 0;

 protected:
  Rheology() = default;
  Rheology(const Rheology&) = default;
  Rheology& operator=(const Rheology&) = default;
};

// Implements the array forms of Rheology for a Derived law with non-virtual
// `double mu(double)` and `double dmu(double)` members, so the compiler can inline them.
template <class Derived>
class RheologyBase : public Rheology {
 public:
  [[nodiscard]] std::string_view name() const final { return Derived::name; }
  [[nodiscard]] double viscosity(double shear_rate) const final { return self().mu(shear_rate); }
  [[nodiscard]] double viscosity_derivative(double shear_rate) const final { return self().dmu(shear_rate); }
  void viscosity(std::span<const double> shear_rate, std::span<double> mu) const final {
    check_sizes(shear_rate.size(), mu.size());
    for (std::size_t i = 0; i < shear_rate.size(); ++i) mu[i] = self().mu(shear_rate[i]);
  }
  void viscosity_derivative(std::span<const double> shear_rate, std::span<double> dmu) const final {
    check_sizes(shear_rate.size(), dmu.size());
    for (std::size_t i = 0; i < shear_rate.size(); ++i) dmu[i] = self().dmu(shear_rate[i]);
  }

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
  static void check_sizes(std::size_t a, std::size_t b);
};

void check_equal_sizes(std::size_t a, std::size_t b);  // throws std::invalid_argument

template <class Derived>
void RheologyBase<Derived>::check_sizes(std::size_t a, std::size_t b) {
  check_equal_sizes(a, b);
}

using RheologyRegistry = Registry<Rheology>;

// Adds every built-in law: newtonian, power_law, bingham, casson, herschel_bulkley,
// carreau_yasuda, cross.
void add_builtin_rheologies(RheologyRegistry& registry);
// The registry of the built-in laws, built once (core::builtin_registry).
[[nodiscard]] const RheologyRegistry& builtin_rheologies();
// Builds a law from a `rheology:` section ({model: name, ...parameters}).
[[nodiscard]] std::shared_ptr<const Rheology> make_rheology(const Section& section);

}  // namespace rheosim::core
