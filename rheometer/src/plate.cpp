#include "rheosim/rheometer/plate.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rheosim/core/units.hpp"
#include "rheosim/numerics/quadrature.hpp"

namespace rheosim::rheometer {

using core::units::pi;

double newtonian_torque(const ParallelPlate& plate, double viscosity, double rim_shear_rate) {
  // T = π η Ω R⁴ / (2H) = π η γ̇_R R³ / 2
  return pi * viscosity * rim_shear_rate * std::pow(plate.radius, 3) / 2.0;
}

double power_law_torque(const ParallelPlate& plate, double consistency, double index, double rim_shear_rate) {
  // T = 2π k γ̇_R^n R³ / (n + 3)
  return 2.0 * pi * consistency * std::pow(rim_shear_rate, index) * std::pow(plate.radius, 3) / (index + 3.0);
}

double herschel_bulkley_torque(const ParallelPlate& plate, double consistency, double index, double yield_stress,
                               double rim_shear_rate) {
  // τ = τ₀ + k γ̇ⁿ is yielded at every r > 0, so the two parts integrate separately.
  return 2.0 * pi * std::pow(plate.radius, 3) * yield_stress / 3.0 +
         power_law_torque(plate, consistency, index, rim_shear_rate);
}

double bingham_torque(const ParallelPlate& plate, double plastic_viscosity, double yield_stress,
                      double rim_shear_rate) {
  return herschel_bulkley_torque(plate, plastic_viscosity, 1.0, yield_stress, rim_shear_rate);
}

double casson_torque(const ParallelPlate& plate, double plastic_viscosity, double yield_stress, double rim_shear_rate) {
  // τ = (√τ₀ + √(μγ̇))² = τ₀ + 2√(τ₀μγ̇) + μγ̇; ∫₀ᴿ r^{5/2} dr / √R = 2R³/7.
  const double r3 = std::pow(plate.radius, 3);
  return 2.0 * pi * r3 *
         (yield_stress / 3.0 + 4.0 / 7.0 * std::sqrt(yield_stress * plastic_viscosity * rim_shear_rate) +
          plastic_viscosity * rim_shear_rate / 4.0);
}

namespace {
double parameter(const core::Rheology& rheology, const std::string& name) {
  for (const auto& p : rheology.parameters())
    if (p.name == name) return p.value;
  throw std::logic_error("rheology '" + std::string(rheology.name()) + "' has no parameter '" + name + "'");
}
}  // namespace

std::optional<double> closed_form_torque(const ParallelPlate& plate, const core::Rheology& rheology,
                                         double rim_shear_rate) {
  const std::string name(rheology.name());
  const auto p = [&](const char* key) { return parameter(rheology, key); };
  if (name == "newtonian") return newtonian_torque(plate, p("viscosity"), rim_shear_rate);
  if (name == "power_law") return power_law_torque(plate, p("consistency"), p("index"), rim_shear_rate);
  if (name == "bingham") return bingham_torque(plate, p("plastic_viscosity"), p("yield_stress"), rim_shear_rate);
  if (name == "casson") return casson_torque(plate, p("plastic_viscosity"), p("yield_stress"), rim_shear_rate);
  if (name == "herschel_bulkley")
    return herschel_bulkley_torque(plate, p("consistency"), p("index"), p("yield_stress"), rim_shear_rate);
  return std::nullopt;
}

namespace {

// Adaptive bisection: accept a panel when splitting it changes the integral by less than tol.
template <class F>
double adaptive(const F& f, double a, double b, double whole, double tolerance, int depth) {
  const double mid = 0.5 * (a + b);
  const double left = numerics::integrate_gauss_legendre<8>(a, mid, f);
  const double right = numerics::integrate_gauss_legendre<8>(mid, b, f);
  if (depth >= 40 || std::abs(left + right - whole) <= tolerance) return left + right;
  return adaptive(f, a, mid, left, 0.5 * tolerance, depth + 1) + adaptive(f, mid, b, right, 0.5 * tolerance, depth + 1);
}

}  // namespace

double creeping_torque(const ParallelPlate& plate, const core::Rheology& rheology, double rim_shear_rate,
                       double relative_tolerance) {
  // Substitute s = r/R: T = 2π R³ ∫₀¹ τ(γ̇_R s) s² ds.
  const auto integrand = [&](double s) { return rheology.stress(rim_shear_rate * s) * s * s; };
  // The scale for the tolerance: the integrand's size at the rim.
  const double scale = std::abs(rheology.stress(rim_shear_rate)) / 3.0 + 1e-300;
  // Geometric panels towards the axis resolve regularisation layers at small s.
  double integral = 0;
  double upper = 1.0;
  for (int panel = 0; panel < 60 && upper > 1e-18; ++panel) {
    const double lower = upper / 4.0;
    integral += adaptive(integrand, lower, upper, numerics::integrate_gauss_legendre<8>(lower, upper, integrand),
                         relative_tolerance * scale, 0);
    upper = lower;
  }
  return 2.0 * pi * std::pow(plate.radius, 3) * integral;
}

}  // namespace rheosim::rheometer
