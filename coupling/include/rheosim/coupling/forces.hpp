#pragma once
// Fluid → particle forces of unresolved CFD-DEM, set II / form A (CD eqs. 25, 29–35), each a
// class selected by YAML name:
//   di_felice          drag β (u_f − u_p), β from the Di Felice law in drag.hpp (CD eqs. 30–33,
//                      ε inside Re_p, μ the local apparent viscosity μ(γ̇)); any law of the drag
//                      registry is a force model under its own name
//   pressure_gradient  −V_p ∇p                                        (CD eq. 34)
//                      + ρ V_p a_c with a creeping fluid (inertia off; see below)
//   viscous            +V_p ∇·τ                                       (CD eq. 35, sign see below)
// Sign of the viscous force: the seed prints −V_p(∇·τ), following CFDEMcoupling, whose divTau
// field holds −∇·τ (OpenFOAM's divDevRhoReff convention). The force of the undisturbed stress on
// the volume V_p is V_p ∇·σ = V_p(−∇p + ∇·τ); with −V_p∇·τ a neutrally buoyant particle in a
// Poiseuille flow would not follow the fluid. rheosim uses +V_p ∇·τ.
//
// Creeping fluid (TransientParams::inertia = false): the solver drops ρ(u·∇)u, so its pressure
// lacks the centripetal ∂p/∂r = ρu_θ²/r that makes a fluid parcel, and a neutrally buoyant sphere
// with it, move on a circle; the spheres keep their inertia in the DEM and would be flung
// outward. The pressure-gradient force then adds that part back, ρ V_p a_c with a_c the
// curvature part of the fluid's acceleration at the centre, (−u_θ²/r, u_r u_θ/r, 0) of the
// interpolated u_f (CD eq. 34 with the pressure an inertial fluid would have to leading order;
// the grid-scale advective part is left out, as the ∇p filter leaves out its noise). Without it
// the spheres drift outward at ≈ ρ d² Ω² r (z/H)²/(18 μ) (0.3 mm/s at the rim of the R = 5 mm
// disk at 100 1/s); its effect on that disk's torque is below the scatter between placements
// (docs/shear-cell.md).
//
// Interpolation (FluidSampler): the fluid velocity at the particle centre is the solver's
// trilinear interpolation of the staggered components (TransientSolver::sample_velocity); ε, μ,
// ∇p and ∇·τ are the cell values weighted by the particle's volume shares (ParticleCellMap of
// the void-fraction scheme: with `centre` the value of the particle's cell, with `divided` the
// 29-point average), so the force and its reaction use the same weights. Cylindrical cell
// components are turned into Cartesian ones at the particle's own θ.
//
// Drag is kept split as β and u_f (ParticleForce::drag_coefficient): the total force on a
// particle is explicit_force + β (u_f − u_p), and the exchange to the fluid (exchange.hpp) puts β
// into the implicit coefficient K of CD eq. 29.
//
// YAML:
//   forces: [di_felice, pressure_gradient, viscous]   (coupling settings; each is {model: name})
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rheosim/core/registry.hpp"
#include "rheosim/coupling/drag.hpp"
#include "rheosim/coupling/fluid_fields.hpp"
#include "rheosim/coupling/particles.hpp"
#include "rheosim/coupling/void_fraction.hpp"
#include "rheosim/fluid/transient.hpp"

namespace rheosim::coupling {

// The fluid at one particle (Cartesian components, SI).
struct ParticleSample {
  Vector3 position{};           // [m]
  Vector3 velocity{};           // u_p [m/s]
  double diameter = 0.0;        // d [m]
  double volume = 0.0;          // V_p [m³]
  double theta = 0.0;           // azimuth of the centre [rad]
  Vector3 fluid_velocity{};     // u_f at the centre [m/s]
  double void_fraction = 1.0;   // ε [-]
  double viscosity = 0.0;       // μ(γ̇) [Pa·s]
  Vector3 pressure_gradient{};  // ∇p [Pa/m]
  Vector3 stress_divergence{};  // ∇·τ [N/m³]
  // Curvature part of the fluid's acceleration at the centre when the fluid is creeping (header
  // comment), 0 otherwise [m/s²].
  Vector3 creeping_acceleration{};
};

// Fluid properties every model may need.
struct FluidConstants {
  double density = 0.0;  // ρ [kg/m³]
};

// Force on one particle: explicit_force + drag_coefficient · (u_f − u_p).
struct ParticleForce {
  Vector3 explicit_force{};       // [N]
  double drag_coefficient = 0.0;  // β [kg/s]
  Vector3 drag{};                 // β (u_f − u_p) [N], filled by the drag model
  Vector3 pressure_gradient{};    // −V∇p (+ ρV a_c, creeping fluid) [N]
  Vector3 viscous{};              // V∇·τ [N]

  [[nodiscard]] Vector3 total(const ParticleSample& at) const {
    return {explicit_force[0] + drag_coefficient * (at.fluid_velocity[0] - at.velocity[0]),
            explicit_force[1] + drag_coefficient * (at.fluid_velocity[1] - at.velocity[1]),
            explicit_force[2] + drag_coefficient * (at.fluid_velocity[2] - at.velocity[2])};
  }
};

class ForceModel {
 public:
  virtual ~ForceModel() = default;
  [[nodiscard]] virtual std::string_view name() const = 0;
  // Adds this model's contribution to every particle's force (spans of equal size).
  virtual void add(const FluidConstants& fluid, std::span<const ParticleSample> particles,
                   std::span<ParticleForce> forces) const = 0;

 protected:
  ForceModel() = default;
  ForceModel(const ForceModel&) = default;
  ForceModel& operator=(const ForceModel&) = default;
};

// Drag through any DragModel.
class DragForce final : public ForceModel {
 public:
  explicit DragForce(std::unique_ptr<const DragModel> law);
  [[nodiscard]] std::string_view name() const override;
  void add(const FluidConstants& fluid, std::span<const ParticleSample> particles,
           std::span<ParticleForce> forces) const override;

 private:
  std::unique_ptr<const DragModel> law_;
  mutable std::vector<DragInput> inputs_;
  mutable std::vector<double> beta_;
};

class PressureGradientForce final : public ForceModel {  // CD eq. 34
 public:
  static constexpr std::string_view model_name = "pressure_gradient";
  [[nodiscard]] std::string_view name() const override { return model_name; }
  void add(const FluidConstants& fluid, std::span<const ParticleSample> particles,
           std::span<ParticleForce> forces) const override;
};

class ViscousForce final : public ForceModel {  // CD eq. 35 (sign: see the header)
 public:
  static constexpr std::string_view model_name = "viscous";
  [[nodiscard]] std::string_view name() const override { return model_name; }
  void add(const FluidConstants& fluid, std::span<const ParticleSample> particles,
           std::span<ParticleForce> forces) const override;
};

using ForceRegistry = core::Registry<ForceModel>;
// pressure_gradient, viscous, and every drag law by its name (di_felice).
void add_builtin_force_models(ForceRegistry& registry);
[[nodiscard]] const ForceRegistry& builtin_force_models();
[[nodiscard]] std::unique_ptr<const ForceModel> make_force_model(const core::Section& section);
[[nodiscard]] std::unique_ptr<const ForceModel> make_force_model(std::string_view name);
// The seed's set (CD §4): di_felice, pressure_gradient, viscous.
[[nodiscard]] std::vector<std::string> seed_force_models();
// The seed's set with the drag law `drag` in place of di_felice.
[[nodiscard]] std::vector<std::string> force_models(DragLaw drag);

// Interpolates the fluid to every particle (see the header). The particle's cell shares come
// from the void-fraction map of the same step (same particle order).
class FluidSampler {
 public:
  explicit FluidSampler(const fluid::CylindricalGrid& grid);
  // Updates the cell fields from the solver and fills samples (resized to the particle count).
  void sample(const fluid::TransientSolver& solver, const VoidFractionField& void_fraction,
              const ParticleView& particles, std::vector<ParticleSample>& samples);
  [[nodiscard]] const FluidCellFields& cell_fields() const { return fields_; }
  // Time constant [s] of the ∇p filter (FluidCellFields::set_pressure_gradient_filter).
  void set_pressure_gradient_filter(double time_constant) { fields_.set_pressure_gradient_filter(time_constant); }

 private:
  FluidCellFields fields_;
  std::vector<fluid::CylindricalPoint> points_;
};

// Sums all models' contributions (forces resized and zeroed first).
void compute_forces(std::span<const std::unique_ptr<const ForceModel>> models, const FluidConstants& fluid,
                    std::span<const ParticleSample> particles, std::vector<ParticleForce>& forces);

}  // namespace rheosim::coupling
