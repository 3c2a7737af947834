#include "rheosim/dem/contact.hpp"

#include <cmath>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "rheosim/core/units.hpp"

namespace rheosim::dem {
namespace {

using core::units::pi;

void check_positive(std::string_view name, double value) {
  if (!(std::isfinite(value) && value > 0.0))
    throw std::invalid_argument(fmt::format("{} = {} is out of range, expected a finite value > 0", name, value));
}

void check_in(std::string_view name, double value, double lower, double upper, std::string_view range) {
  if (!(value >= lower && value <= upper))  // also rejects NaN
    throw std::invalid_argument(fmt::format("{} = {} is out of range, expected {}", name, value, range));
}

// lower < value <= upper, i.e. in (lower, upper].
void check_open_closed(std::string_view name, double value, double lower, double upper) {
  if (!(value > lower && value <= upper))
    throw std::invalid_argument(fmt::format("{} = {} is out of range, expected ({}, {}]", name, value, lower, upper));
}

}  // namespace

void check(const ElasticSphere& sphere) {
  check_positive("radius", sphere.radius);
  check_positive("density", sphere.density);
  check_positive("youngs_modulus", sphere.youngs_modulus);
  // The Rayleigh-time fit and E* > 0 need 0 <= ν <= 0.5.
  check_in("poisson_ratio", sphere.poisson_ratio, 0.0, 0.5, "[0, 0.5]");
}

double mass(const ElasticSphere& sphere) {
  check(sphere);
  return sphere.density * core::units::sphere_volume(2.0 * sphere.radius);
}

double shear_modulus(double youngs_modulus, double poisson_ratio) {
  check_positive("youngs_modulus", youngs_modulus);
  check_in("poisson_ratio", poisson_ratio, 0.0, 0.5, "[0, 0.5]");
  return youngs_modulus / (2.0 * (1.0 + poisson_ratio));
}

double effective_modulus(const ElasticSphere& a, const ElasticSphere& b) {
  check(a);
  check(b);
  const double compliance = (1.0 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                            (1.0 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus;
  return 1.0 / compliance;
}

double effective_radius(const ElasticSphere& a, const ElasticSphere& b) {
  check(a);
  check(b);
  return a.radius * b.radius / (a.radius + b.radius);
}

double effective_mass(const ElasticSphere& a, const ElasticSphere& b) {
  const double m_a = mass(a);
  const double m_b = mass(b);
  return m_a * m_b / (m_a + m_b);
}

double rayleigh_time(const ElasticSphere& sphere) {
  check(sphere);
  const double g = shear_modulus(sphere.youngs_modulus, sphere.poisson_ratio);
  return pi * sphere.radius * std::sqrt(sphere.density / g) / (0.1631 * sphere.poisson_ratio + 0.8766);
}

double rayleigh_time_step(const ElasticSphere& sphere, double fraction) {
  check_open_closed("fraction", fraction, 0.0, 1.0);
  return fraction * rayleigh_time(sphere);
}

double hertz_collision_time(const ElasticSphere& a, const ElasticSphere& b, double impact_speed) {
  check_positive("impact_speed", impact_speed);
  const double m_eff = effective_mass(a, b);
  const double r_eff = effective_radius(a, b);
  const double e_eff = effective_modulus(a, b);
  return 2.87 * std::pow(m_eff * m_eff / (r_eff * e_eff * e_eff * impact_speed), 0.2);
}

double damping_ratio_from_restitution(double restitution) {
  check_open_closed("restitution", restitution, 0.0, 1.0);
  const double log_e = std::log(restitution);
  return log_e / std::sqrt(log_e * log_e + pi * pi);
}

double hertz_normal_damping(const ElasticSphere& a, const ElasticSphere& b, double restitution, double overlap) {
  if (!(std::isfinite(overlap) && overlap >= 0.0))
    throw std::invalid_argument(fmt::format("overlap = {} is out of range, expected a finite value >= 0", overlap));
  const double beta = damping_ratio_from_restitution(restitution);
  const double stiffness = 2.0 * effective_modulus(a, b) * std::sqrt(effective_radius(a, b) * overlap);  // S_n
  return -2.0 * std::sqrt(5.0 / 6.0) * beta * std::sqrt(stiffness * effective_mass(a, b));
}

}  // namespace rheosim::dem
