// Ghia, Ghia & Shin (1982), Tables I–II (cavity_reference.hpp).
#include "rheosim/ldd/cavity_reference.hpp"

#include <array>
#include <cmath>

namespace rheosim::ldd {

namespace {

// One tabulated point a line: line, coordinate, Re = 100, Re = 1000.
// clang-format off
constexpr std::array<GhiaPoint, 34> table{{
    {'u', 1.0000, 1.00000, 1.00000},
    {'u', 0.9766, 0.84123, 0.65928},
    {'u', 0.9688, 0.78871, 0.57492},
    {'u', 0.9609, 0.73722, 0.51117},
    {'u', 0.9531, 0.68717, 0.46604},
    {'u', 0.8516, 0.23151, 0.33304},
    {'u', 0.7344, 0.00332, 0.18719},
    {'u', 0.6172, -0.13641, 0.05702},
    {'u', 0.5000, -0.20581, -0.06080},
    {'u', 0.4531, -0.21090, -0.10648},
    {'u', 0.2813, -0.15662, -0.27805},
    {'u', 0.1719, -0.10150, -0.38289},
    {'u', 0.1016, -0.06434, -0.29730},
    {'u', 0.0703, -0.04775, -0.22220},
    {'u', 0.0625, -0.04192, -0.20196},
    {'u', 0.0547, -0.03717, -0.18109},
    {'u', 0.0000, 0.00000, 0.00000},
    {'v', 1.0000, 0.00000, 0.00000},
    {'v', 0.9688, -0.05906, -0.21388},
    {'v', 0.9609, -0.07391, -0.27669},
    {'v', 0.9531, -0.08864, -0.33714},
    {'v', 0.9453, -0.10313, -0.39188},
    {'v', 0.9063, -0.16914, -0.51550},
    {'v', 0.8594, -0.22445, -0.42665},
    {'v', 0.8047, -0.24533, -0.31966},
    {'v', 0.5000, 0.05454, 0.02526},
    {'v', 0.2344, 0.17527, 0.32235},
    {'v', 0.2266, 0.17507, 0.33075},
    {'v', 0.1563, 0.16077, 0.37095},
    {'v', 0.0938, 0.12317, 0.32627},
    {'v', 0.0781, 0.10890, 0.30353},
    {'v', 0.0703, 0.10091, 0.29012},
    {'v', 0.0625, 0.09233, 0.27485},
    {'v', 0.0000, 0.00000, 0.00000},
}};
// clang-format on

}  // namespace

std::span<const GhiaPoint> ghia_1982() { return table; }

std::optional<int> ghia_reynolds(const CavityScene& scene, const core::FluidProperties& fluid) {
  if (scene.skew_angle != 0 || scene.size[0] != scene.size[1] || !fluid.rheology ||
      fluid.rheology->name() != "newtonian")
    return std::nullopt;
  const double length = scene.size[0], speed = std::abs(scene.lid_velocity);
  const double reynolds = fluid.density * speed * length / fluid.rheology->viscosity(speed / length);
  for (const int tabulated : {100, 1000})
    if (std::abs(reynolds / tabulated - 1.0) < 5e-3) return tabulated;
  return std::nullopt;
}

}  // namespace rheosim::ldd
