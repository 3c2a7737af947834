#pragma once
// Closed 2D domains for the LDD solver: a convex polygon of straight walls at any angle, each
// moving tangentially at its own velocity (a lid) or at rest, and the initial node cloud.
//
// Cavities (`cavity`, `skewed_cavity`; LDD §4.1–4.2) are parallelograms in their own
// coordinates (ξ, η) ∈ [0, W] × [0, S]:
//     x = ξ + η cos α,   y = η sin α
// with W the width (bottom and lid), S the side-wall length and α the angle between the bottom
// and the side walls (90° for the square cavity). The lid is the top edge, moving in +x.
// Nodes start on the (ξ, η) lattice with spacing Δ (a square lattice for α = 90°, the
// hexagonal one for α = 60°); the lattice's outer ring sits on the walls (wall nodes), its
// four corners are corner nodes (velocity of the stationary walls, see docs/ldd.md).
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "rheosim/ldd/boundary.hpp"
#include "rheosim/ldd/node_cloud.hpp"
#include "rheosim/ldd/scene.hpp"

namespace rheosim::ldd {

using Vec2 = std::array<double, 2>;

// A parallelogram cavity (square when the skew angle is 90°).
class Cavity {
 public:
  // scene.skew_angle == 0 means a square cavity (α = 90°). Throws std::invalid_argument for a
  // spacing that leaves fewer than 4 cells along a side.
  Cavity(const ldd::CavityScene& scene, double spacing);

  // The four walls as planes (lines) through their sides, normals into the cavity, counter-
  // clockwise from the bottom; the lid (the third) slides along +x. Each wall node of the cloud
  // names its wall (a corner a side wall: stationary).
  [[nodiscard]] const std::vector<std::shared_ptr<const Boundary>>& walls() const { return walls_; }
  [[nodiscard]] const NodeCloud& initial_cloud() const { return cloud_; }
  [[nodiscard]] double width() const { return width_; }
  [[nodiscard]] double side_length() const { return side_; }
  [[nodiscard]] double skew_angle() const { return angle_; }  // α [rad]
  [[nodiscard]] double lid_velocity() const { return lid_velocity_; }
  [[nodiscard]] std::array<int, 2> cells() const { return cells_; }  // lattice cells along ξ, η
  // Physical point of the cavity coordinates (ξ/W, η/S) ∈ [0, 1]².
  [[nodiscard]] Vec2 point(double xi_fraction, double eta_fraction) const;
  // Area of the cavity [m²].
  [[nodiscard]] double area() const;

 private:
  double width_, side_, angle_, lid_velocity_;
  std::array<int, 2> cells_{};
  std::vector<std::shared_ptr<const Boundary>> walls_;
  NodeCloud cloud_;
};

}  // namespace rheosim::ldd
