#pragma once
// The scenes of an LDD case (`scene:` in the case file, read by ldd::read_case): the geometry and
// driving of each, and the extra solid walls of a 3D free-surface scene. Plain values in SI units;
// domain.hpp and scenes.hpp build the node clouds from them.
#include <array>
#include <string>
#include <variant>
#include <vector>

namespace rheosim::ldd {

struct CavityScene {             // cavity | skewed_cavity
  std::array<double, 2> size{};  // width, height [m] (skewed: side length along the walls)
  double lid_velocity = 0;       // [m/s]
  double skew_angle = 0;         // [rad]; YAML gives degrees; 0 for a square cavity
};
struct DamBreakScene {
  std::array<double, 2> reservoir{};  // length, height [m]
  double channel_length = 0;          // [m], from the reservoir's outer wall
};
struct SlumpScene {
  double cone_height = 0;           // H₀ [m]
  double cone_bottom_diameter = 0;  // D₀ [m]
  double cone_top_diameter = 0;     // d₀ [m], <= D₀ (equal: a cylinder)
  double lift_velocity = 0;         // mould lift speed [m/s]
};
struct ColumnScene {             // a resting column (hydrostatics), or a sloshing one
  std::array<double, 2> size{};  // width W, mean height H [m]
  // Initial surface y = H + wave_amplitude·cos(πx/W) (the first sloshing mode) [m]; 0: flat.
  double wave_amplitude = 0;
};
using SceneSettings = std::variant<CavityScene, DamBreakScene, SlumpScene, ColumnScene>;

// scene.walls: — extra solid walls of a 3D free-surface scene, one Boundary each, built by type
// through the registry in walls.hpp. Box, cylinder and STL are closed solids; the fluid is inside
// them (a container) or outside (an obstacle).
struct WallSettings {
  std::string type;                   // plane | box | cylinder | stl
  bool fluid_inside = true;           // box, cylinder, stl
  std::vector<double> point, normal;  // plane: a point on it [m], normal pointing into the fluid
  std::vector<double> lower, upper;   // box: opposite corners [m]
  std::vector<double> base, axis;     // cylinder: centre of the bottom cap [m], axis direction
  double radius = 0, height = 0;      // cylinder [m]
  std::string file;                   // stl: path, resolved against the case file's directory
  double scale = 1;                   // stl: metres per file unit
};

}  // namespace rheosim::ldd
