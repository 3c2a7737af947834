#include "rheosim/coupling/forces.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "rheosim/core/config.hpp"

namespace rheosim::coupling {
namespace {

Vector3 cartesian(double radial, double azimuthal, double axial, double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  return {radial * c - azimuthal * s, radial * s + azimuthal * c, axial};
}

}  // namespace

DragForce::DragForce(std::unique_ptr<const DragModel> law) : law_(std::move(law)) {
  if (!law_) throw std::invalid_argument("DragForce: the drag law must not be null");
}

std::string_view DragForce::name() const { return law_->name(); }

void DragForce::add(const FluidConstants& fluid, std::span<const ParticleSample> particles,
                    std::span<ParticleForce> forces) const {
  inputs_.resize(particles.size());
  beta_.resize(particles.size());
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const ParticleSample& s = particles[p];
    DragInput& in = inputs_[p];
    in.fluid_velocity = s.fluid_velocity;
    in.particle_velocity = s.velocity;
    in.void_fraction = s.void_fraction;
    in.diameter = s.diameter;
    in.fluid_density = fluid.density;
    in.fluid_viscosity = s.viscosity;  // μ(γ̇) of the cells: enters Re_p (CD eq. 32)
  }
  law_->exchange_coefficients(inputs_, beta_);
  for (std::size_t p = 0; p < particles.size(); ++p) {
    forces[p].drag_coefficient += beta_[p];
    for (std::size_t d = 0; d < 3; ++d)
      forces[p].drag[d] += beta_[p] * (particles[p].fluid_velocity[d] - particles[p].velocity[d]);
  }
}

void PressureGradientForce::add(const FluidConstants& fluid, std::span<const ParticleSample> particles,
                                std::span<ParticleForce> forces) const {
  for (std::size_t p = 0; p < particles.size(); ++p)
    for (std::size_t d = 0; d < 3; ++d) {
      const ParticleSample& s = particles[p];
      // CD eq. 34, with the creeping fluid's missing centripetal pressure (header comment).
      const double f = -s.volume * (s.pressure_gradient[d] - fluid.density * s.creeping_acceleration[d]);
      forces[p].explicit_force[d] += f;
      forces[p].pressure_gradient[d] += f;
    }
}

void ViscousForce::add(const FluidConstants& /*fluid*/, std::span<const ParticleSample> particles,
                       std::span<ParticleForce> forces) const {
  for (std::size_t p = 0; p < particles.size(); ++p)
    for (std::size_t d = 0; d < 3; ++d) {
      const double f = particles[p].volume * particles[p].stress_divergence[d];  // CD eq. 35, +V∇·τ
      forces[p].explicit_force[d] += f;
      forces[p].viscous[d] += f;
    }
}

namespace {
// A force without settings, from a section (which holds only `model`) or by name.
template <class Force>
void add_force_without_settings(ForceRegistry& registry) {
  const auto make = []() -> std::unique_ptr<ForceModel> { return std::make_unique<Force>(); };
  registry.add(
      std::string(Force::model_name), [make](const core::Section&) { return make(); }, make);
}
}  // namespace

void add_builtin_force_models(ForceRegistry& registry) {
  for (const std::string& law : builtin_drag_models().names())
    registry.add(
        law,
        [](const core::Section& section) -> std::unique_ptr<ForceModel> {
          return std::make_unique<DragForce>(make_drag_model(section));
        },
        [law]() -> std::unique_ptr<ForceModel> {
          return std::make_unique<DragForce>(builtin_drag_models().make(law));
        });
  add_force_without_settings<PressureGradientForce>(registry);
  add_force_without_settings<ViscousForce>(registry);
}

const ForceRegistry& builtin_force_models() { return core::builtin_registry<ForceModel, add_builtin_force_models>(); }

std::unique_ptr<const ForceModel> make_force_model(const core::Section& section) {
  return builtin_force_models().make(section);
}

std::unique_ptr<const ForceModel> make_force_model(std::string_view name) { return builtin_force_models().make(name); }

std::vector<std::string> seed_force_models() { return force_models(DragLaw::di_felice); }

std::vector<std::string> force_models(DragLaw drag) { return {name_of(drag), "pressure_gradient", "viscous"}; }

FluidSampler::FluidSampler(const fluid::CylindricalGrid& grid) : fields_(grid) {}

void FluidSampler::sample(const fluid::TransientSolver& solver, const VoidFractionField& void_fraction,
                          const ParticleView& particles, std::vector<ParticleSample>& samples) {
  fields_.update(solver);
  const fluid::CylindricalGrid& grid = solver.grid();
  const double radius = grid.params().radius, gap = grid.params().gap;
  const std::size_t n = particles.size();
  samples.resize(n);
  points_.resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    const Vector3 x = particles.position(p);
    ParticleSample& s = samples[p];
    s.position = x;
    s.velocity = particles.velocity(p);
    s.diameter = 2.0 * particles.radii[p];
    s.volume = sphere_volume_from_radius(particles.radii[p]);
    s.theta = std::atan2(x[1], x[0]);
    points_[p] = {std::min(std::hypot(x[0], x[1]), radius), s.theta, std::clamp(x[2], 0.0, gap)};
  }
  const std::vector<fluid::CylindricalVelocity> u = solver.sample_velocity(points_);
  const ParticleCellMap& map = void_fraction.map();
  if (map.particle_count() != n)
    throw std::invalid_argument(
        fmt::format("FluidSampler: the void-fraction map has {} particles, expected {}", map.particle_count(), n));
  const auto eps = void_fraction.void_fraction();
  const auto mu = fields_.viscosity();
  const CellVectorField& gp = fields_.pressure_gradient();
  const CellVectorField& dt = fields_.stress_divergence();
  const bool creeping = !solver.params().inertia;
  for (std::size_t p = 0; p < n; ++p) {
    ParticleSample& s = samples[p];
    s.fluid_velocity = cartesian(u[p].radial, u[p].azimuthal, u[p].axial, s.theta);
    const double r = points_[p].r;
    s.creeping_acceleration = creeping && r > 0.0 ? cartesian(-u[p].azimuthal * u[p].azimuthal / r,
                                                              u[p].radial * u[p].azimuthal / r, 0.0, s.theta)
                                                  : Vector3{};
    double e = 0.0, m = 0.0, total = 0.0;
    std::array<double, 3> g{}, t{};
    for (const VolumeShare& share : map.of(p)) {
      const double w = share.volume;
      total += w;
      e += w * eps[share.cell];
      m += w * mu[share.cell];
      g[0] += w * gp.radial[share.cell];
      g[1] += w * gp.azimuthal[share.cell];
      g[2] += w * gp.axial[share.cell];
      t[0] += w * dt.radial[share.cell];
      t[1] += w * dt.azimuthal[share.cell];
      t[2] += w * dt.axial[share.cell];
    }
    s.void_fraction = std::min(e / total, 1.0);
    s.viscosity = m / total;
    s.pressure_gradient = cartesian(g[0] / total, g[1] / total, g[2] / total, s.theta);
    s.stress_divergence = cartesian(t[0] / total, t[1] / total, t[2] / total, s.theta);
  }
}

void compute_forces(std::span<const std::unique_ptr<const ForceModel>> models, const FluidConstants& fluid,
                    std::span<const ParticleSample> particles, std::vector<ParticleForce>& forces) {
  forces.assign(particles.size(), ParticleForce{});
  for (const auto& model : models) model->add(fluid, particles, forces);
}

}  // namespace rheosim::coupling
