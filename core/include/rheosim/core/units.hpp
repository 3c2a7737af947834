#pragma once
// SI throughout. The only non-SI quantities a user may write (degrees, rpm) are converted
// here, at the edge, and physical constants used across modules live here once.
#include <numbers>

namespace rheosim::core::units {

inline constexpr double pi = std::numbers::pi;
inline constexpr double standard_gravity = 9.80665;  // [m/s²], CGPM 1901

[[nodiscard]] constexpr double radians_from_degrees(double degrees) { return degrees * pi / 180.0; }
[[nodiscard]] constexpr double degrees_from_radians(double radians) { return radians * 180.0 / pi; }
// Angular velocity [rad/s] from revolutions per minute, as rheometers display it.
[[nodiscard]] constexpr double angular_velocity_from_rpm(double rpm) { return rpm * 2.0 * pi / 60.0; }
[[nodiscard]] constexpr double rpm_from_angular_velocity(double omega) { return omega * 60.0 / (2.0 * pi); }

// Volume of a sphere of diameter d [m³].
[[nodiscard]] constexpr double sphere_volume(double diameter) { return pi * diameter * diameter * diameter / 6.0; }

}  // namespace rheosim::core::units
