#include "rheosim/coupling/drag.hpp"

#include <cmath>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "drag/di_felice.hpp"
#include "drag/schiller_naumann.hpp"
#include "rheosim/core/config.hpp"

namespace rheosim::coupling {
namespace {

void check_positive(std::string_view name, double value) {
  if (!(std::isfinite(value) && value > 0.0))
    throw std::invalid_argument(fmt::format("drag: {} = {} is out of range, expected a finite value > 0", name, value));
}

void check_finite(std::string_view name, const Vector3& v) {
  if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])))
    throw std::invalid_argument(fmt::format("drag: {} = ({}, {}, {}) is not finite", name, v[0], v[1], v[2]));
}

}  // namespace

void check(const DragInput& particle) {
  check_finite("fluid_velocity", particle.fluid_velocity);
  check_finite("particle_velocity", particle.particle_velocity);
  if (!(particle.void_fraction > 0.0 && particle.void_fraction <= 1.0))
    throw std::invalid_argument(
        fmt::format("drag: void_fraction = {} is out of range, expected (0, 1]", particle.void_fraction));
  check_positive("diameter", particle.diameter);
  check_positive("fluid_density", particle.fluid_density);
  check_positive("fluid_viscosity", particle.fluid_viscosity);
}

double slip_speed(const DragInput& particle) {
  return std::hypot(particle.fluid_velocity[0] - particle.particle_velocity[0],
                    particle.fluid_velocity[1] - particle.particle_velocity[1],
                    particle.fluid_velocity[2] - particle.particle_velocity[2]);
}

double particle_reynolds_number(const DragInput& particle) {
  return particle.void_fraction * particle.fluid_density * particle.diameter * slip_speed(particle) /
         particle.fluid_viscosity;
}

Vector3 DragModel::force(const DragInput& particle) const {
  const double beta = exchange_coefficient(particle);
  return {beta * (particle.fluid_velocity[0] - particle.particle_velocity[0]),
          beta * (particle.fluid_velocity[1] - particle.particle_velocity[1]),
          beta * (particle.fluid_velocity[2] - particle.particle_velocity[2])};
}

void check_equal_sizes(std::size_t particles, std::size_t coefficients) {
  if (particles != coefficients)
    throw std::invalid_argument(
        fmt::format("drag array form: {} particles but an output array of size {}", particles, coefficients));
}

// The one list of built-in laws; a new law is added here and nowhere else.
void add_builtin_drag_models(DragRegistry& registry) {
  core::add<DiFelice>(registry);
  core::add<SchillerNaumann>(registry);
}

const DragRegistry& builtin_drag_models() { return core::builtin_registry<DragModel, add_builtin_drag_models>(); }

std::unique_ptr<const DragModel> make_drag_model(const core::Section& section) {
  return builtin_drag_models().make(section);
}

std::unique_ptr<const DragModel> make_drag_model(DragLaw law) { return builtin_drag_models().make(name_of(law)); }

}  // namespace rheosim::coupling
