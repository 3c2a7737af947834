#pragma once
// Parallel-plate kinematics and the creeping-flow torque references (CD §2.2).
// In creeping flow between a plate rotating at Ω and a fixed plate a gap H below, the
// azimuthal velocity is v_θ = rΩz/H (CD eq. 6), so the shear rate is γ̇(r) = rΩ/H at every
// height, rising linearly to the rim value γ̇_R = ΩR/H. The torque on the top plate is then
//   T = 2π ∫₀ᴿ τ(γ̇_R r/R) r² dr
// for any generalized-Newtonian law τ(γ̇): closed forms below, quadrature for the rest.
#include <optional>

#include "rheosim/core/case.hpp"
#include "rheosim/core/rheology.hpp"

namespace rheosim::rheometer {

struct ParallelPlate {
  double radius = 0;  // R [m]
  double gap = 0;     // H [m]

  static ParallelPlate from(const core::PlateGeometry& g) { return {g.radius, g.gap}; }

  [[nodiscard]] double angular_velocity(double rim_shear_rate) const { return rim_shear_rate * gap / radius; }
  [[nodiscard]] double rim_shear_rate(double angular_velocity) const { return angular_velocity * radius / gap; }
  // Gap Reynolds number ρΩH²/μ: inertia (secondary flow) matters when it is O(1).
  [[nodiscard]] double gap_reynolds_number(double density, double rim_shear_rate, double viscosity) const {
    return density * angular_velocity(rim_shear_rate) * gap * gap / viscosity;
  }
};

// Closed-form creeping-flow torques [N·m] at rim shear rate γ̇_R [1/s].
[[nodiscard]] double newtonian_torque(const ParallelPlate& plate, double viscosity, double rim_shear_rate);  // CD eq. 8
[[nodiscard]] double power_law_torque(const ParallelPlate& plate, double consistency, double index,
                                      double rim_shear_rate);  // CD eq. 9
[[nodiscard]] double herschel_bulkley_torque(const ParallelPlate& plate, double consistency, double index,
                                             double yield_stress, double rim_shear_rate);
[[nodiscard]] double bingham_torque(const ParallelPlate& plate, double plastic_viscosity, double yield_stress,
                                    double rim_shear_rate);
[[nodiscard]] double casson_torque(const ParallelPlate& plate, double plastic_viscosity, double yield_stress,
                                   double rim_shear_rate);

// The closed form of the law's *unregularised* counterpart (Bingham, Casson, Herschel–Bulkley
// without Papanastasiou regularisation; power law without its low-rate plateau), or nothing
// for laws without one (Carreau–Yasuda, Cross).
[[nodiscard]] std::optional<double> closed_form_torque(const ParallelPlate& plate, const core::Rheology& rheology,
                                                       double rim_shear_rate);

// T = 2π ∫₀ᴿ τ(γ̇_R r/R) r² dr of the law exactly as implemented (regularisation included),
// by composite Gauss–Legendre quadrature to a relative tolerance.
[[nodiscard]] double creeping_torque(const ParallelPlate& plate, const core::Rheology& rheology, double rim_shear_rate,
                                     double relative_tolerance = 1e-12);

}  // namespace rheosim::rheometer
