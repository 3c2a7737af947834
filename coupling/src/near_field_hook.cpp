// NearFieldStepHook: a NearFieldModel on every DEM step of a dem::Engine (near_field.hpp).
#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <utility>

#include "rheosim/coupling/near_field.hpp"

namespace rheosim::coupling {

NearFieldStepHook::NearFieldStepHook(dem::Engine& engine, std::shared_ptr<const NearFieldModel> model,
                                     NearFieldScene scene, AmbientFlow ambient)
    : engine_(engine), model_(std::move(model)), scene_(std::move(scene)), ambient_(std::move(ambient)) {
  if (!model_) throw std::invalid_argument("NearFieldStepHook: no model");
  sums_.plate_forces.assign(scene_.plates.size(), Vector3{});
  sums_.plate_moments.assign(scene_.plates.size(), Vector3{});
  engine_.set_step_force_callback([this](const dem::StepState& state, std::span<double> forces,
                                         std::span<double> torques) { on_step(state, forces, torques); });
}

NearFieldStepHook::~NearFieldStepHook() {
  try {
    if (!engine_.has_failed()) engine_.set_step_force_callback({});
  } catch (...) {
    // The engine is unusable; nothing will call the callback again.
  }
}

void NearFieldStepHook::set_ambient(AmbientFlow ambient) { ambient_ = std::move(ambient); }

void NearFieldStepHook::on_step(const dem::StepState& state, std::span<double> forces, std::span<double> torques) {
  const auto start = std::chrono::steady_clock::now();
  const ParticleSnapshot snapshot{.positions = state.positions,
                                  .velocities = state.velocities,
                                  .angular_velocities = state.angular_velocities,
                                  .radii = state.radii,
                                  .masses = state.masses,
                                  .other_forces = state.forces,
                                  .other_torques = state.torques,
                                  .time_step = state.time_step};
  last_.reset(state.size(), scene_.plates.size());
  model_->evaluate(snapshot, scene_, ambient_, last_);
  for (std::size_t k = 0; k < forces.size(); ++k) {
    forces[k] += last_.forces[k];
    torques[k] += last_.torques[k];
  }
  ++sums_.steps;
  for (std::size_t c = 0; c < 6; ++c) {
    sums_.particle_stress[c] += last_.particle_stress[c];
    sums_.lubrication_virial[c] += last_.lubrication_virial[c];
    sums_.plate_virial[c] += last_.plate_virial[c];
    sums_.stresslet_sum[c] += last_.stresslet_sum[c];
  }
  sums_.stresslet_axial_moment += last_.stresslet_axial_moment;
  sums_.rotation_torque_radial_moment += last_.rotation_torque_radial_moment;
  for (std::size_t k = 0; k < 3; ++k) sums_.rotation_torque_sum[k] += last_.rotation_torque_sum[k];
  for (std::size_t k = 0; k < 9; ++k) sums_.lubrication_virial_full[k] += last_.lubrication_virial_full[k];
  for (std::size_t w = 0; w < scene_.plates.size(); ++w)
    for (std::size_t k = 0; k < 3; ++k) {
      sums_.plate_forces[w][k] += last_.plate_forces[w][k];
      sums_.plate_moments[w][k] += last_.plate_moments[w][k];
    }
  pair_sum_ += static_cast<double>(last_.lubricated_pairs);
  sums_.max_solver_iterations = std::max(sums_.max_solver_iterations, last_.solver_iterations);
  sums_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

NearFieldStepHook::Means NearFieldStepHook::take_means() {
  Means out = sums_;
  if (out.steps > 0) {
    const double inv = 1.0 / static_cast<double>(out.steps);
    for (std::size_t c = 0; c < 6; ++c) {
      out.particle_stress[c] *= inv;
      out.lubrication_virial[c] *= inv;
      out.plate_virial[c] *= inv;
      out.stresslet_sum[c] *= inv;
    }
    out.stresslet_axial_moment *= inv;
    out.rotation_torque_radial_moment *= inv;
    for (double& x : out.rotation_torque_sum) x *= inv;
    for (double& x : out.lubrication_virial_full) x *= inv;
    for (auto& f : out.plate_forces)
      for (double& x : f) x *= inv;
    for (auto& m : out.plate_moments)
      for (double& x : m) x *= inv;
    out.mean_lubricated_pairs = pair_sum_ * inv;
  }
  sums_ = Means{};
  sums_.plate_forces.assign(scene_.plates.size(), Vector3{});
  sums_.plate_moments.assign(scene_.plates.size(), Vector3{});
  pair_sum_ = 0.0;
  return out;
}

}  // namespace rheosim::coupling
