#pragma once
// Fluid–particle drag laws for unresolved CFD-DEM (CD eqs. 29–33). A law gives the
// momentum-exchange coefficient β of one particle, so that the drag force on it is
//   F = β (u_f − u_p)                                            [N]
// which the fluid side can treat implicitly (CD eq. 29: −Σ F / ΔV as a source, with β in the
// matrix). Each law is one class in coupling/src/drag/<name>.{hpp,cpp}, registered by its YAML
// name in add_builtin_drag_models(). SI throughout.
//
// YAML:
//   drag: {model: di_felice}
#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <string_view>

#include "rheosim/core/config.hpp"
#include "rheosim/core/registry.hpp"

namespace rheosim::coupling {

// particles.drag: the law of a suspension point. YAML `drag: {model: auto | di_felice |
// schiller_naumann}`. auto, the default, is di_felice (the seed's, CD eqs. 30–33) for
// drag-only suspensions and schiller_naumann (the isolated sphere) when the near field has
// lubrication: the pair terms then carry the crowding that Di Felice's voidage function would
// add a second time (docs/hydrodynamics.md, "Which drag goes with the near field").
enum class DragLaw { di_felice, schiller_naumann };
// Its YAML name, the registry name in builtin_drag_models().
[[nodiscard]] constexpr const char* name_of(DragLaw d) {
  return d == DragLaw::schiller_naumann ? "schiller_naumann" : "di_felice";
}

using Vector3 = std::array<double, 3>;

// Local conditions at one particle, as the coupling sees them.
struct DragInput {
  Vector3 fluid_velocity{};      // u_f interpolated to the particle centre [m/s]
  Vector3 particle_velocity{};   // u_p [m/s]
  double void_fraction = 1.0;    // ε [-], in (0, 1]
  double diameter = 0.0;         // d [m], > 0
  double fluid_density = 0.0;    // ρ [kg/m³], > 0
  double fluid_viscosity = 0.0;  // η [Pa·s], > 0: the apparent viscosity μ(γ̇) for non-Newtonian fluids
};

// Throws std::invalid_argument naming the field and its valid range (velocities must be finite).
void check(const DragInput& particle);
// |u_f − u_p| [m/s]
[[nodiscard]] double slip_speed(const DragInput& particle);
// Re_p = ε ρ d |u_f − u_p| / η [-] (CD eq. 32: the void fraction is inside Re_p).
[[nodiscard]] double particle_reynolds_number(const DragInput& particle);

class DragModel {
 public:
  virtual ~DragModel() = default;

  [[nodiscard]] virtual std::string_view name() const = 0;  // YAML name, e.g. "di_felice"

  // β [kg/s] >= 0, finite for every valid input including zero slip (each law documents its
  // limit there). Throws std::invalid_argument for invalid input.
  [[nodiscard]] virtual double exchange_coefficient(const DragInput& particle) const = 0;
  // Array form for hot loops: one virtual call per array. Spans must have equal sizes.
  virtual void exchange_coefficients(std::span<const DragInput> particles, std::span<double> beta) const = 0;

  // F = β (u_f − u_p) [N], the drag force on the particle.
  [[nodiscard]] Vector3 force(const DragInput& particle) const;

 protected:
  DragModel() = default;
  DragModel(const DragModel&) = default;
  DragModel& operator=(const DragModel&) = default;
};

void check_equal_sizes(std::size_t particles, std::size_t coefficients);  // throws std::invalid_argument

// Implements the DragModel interface for a Derived law with a non-virtual
// `double beta(const DragInput&) const` that may assume checked input.
template <class Derived>
class DragModelBase : public DragModel {
 public:
  [[nodiscard]] std::string_view name() const final { return Derived::name; }
  [[nodiscard]] double exchange_coefficient(const DragInput& particle) const final {
    check(particle);
    return self().beta(particle);
  }
  void exchange_coefficients(std::span<const DragInput> particles, std::span<double> beta) const final {
    check_equal_sizes(particles.size(), beta.size());
    for (const DragInput& particle : particles) check(particle);
    for (std::size_t p = 0; p < particles.size(); ++p) beta[p] = self().beta(particles[p]);
  }

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
};

using DragRegistry = core::Registry<DragModel>;

// Adds every built-in law: di_felice, schiller_naumann.
void add_builtin_drag_models(DragRegistry& registry);
// The registry of the built-in laws, built once (core::builtin_registry).
[[nodiscard]] const DragRegistry& builtin_drag_models();
// Builds a law from a `drag:` section ({model: name, ...parameters}).
[[nodiscard]] std::unique_ptr<const DragModel> make_drag_model(const core::Section& section);
// The law a case's particles.drag names (no parameters).
[[nodiscard]] std::unique_ptr<const DragModel> make_drag_model(DragLaw law);

}  // namespace rheosim::coupling
