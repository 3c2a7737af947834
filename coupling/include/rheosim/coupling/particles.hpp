#pragma once
// Particle data as the coupling sees it: Cartesian (x, y, z) in the rheometer frame (axis along
// z through x = y = 0, bottom plate z = 0), the frame of dem::RheometerScene and of the fluid's
// CylindricalGrid. Arrays are interleaved like dem::Engine's views: [x0 y0 z0 x1 y1 z1 ...].
#include <array>
#include <cstddef>
#include <numbers>
#include <span>

namespace rheosim::coupling {

using Vector3 = std::array<double, 3>;

// Non-owning view of n particles (spans from dem::Engine or from a test).
struct ParticleView {
  std::span<const double> positions;   // [m], 3n
  std::span<const double> velocities;  // [m/s], 3n (may be empty where only positions matter)
  std::span<const double> radii;       // [m], n

  [[nodiscard]] std::size_t size() const { return radii.size(); }
  [[nodiscard]] Vector3 position(std::size_t p) const {
    return {positions[3 * p], positions[3 * p + 1], positions[3 * p + 2]};
  }
  [[nodiscard]] Vector3 velocity(std::size_t p) const {
    return {velocities[3 * p], velocities[3 * p + 1], velocities[3 * p + 2]};
  }
};

// Throws std::invalid_argument if the sizes disagree or a value is not finite / a radius not > 0.
void check(const ParticleView& particles, bool need_velocities);

[[nodiscard]] inline double sphere_volume_from_radius(double radius) {
  return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}

}  // namespace rheosim::coupling
