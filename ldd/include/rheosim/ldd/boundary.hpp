#pragma once
// The walls of an LDD scene, for both schemes: each wall node names its boundary
// (NodeCloud::boundary), which gives the velocity its no-slip row imposes (surface_velocity) and
// the motion of the node (velocity), and keeps fluid nodes off it. A cavity's walls are planes
// (lines), its lid a plane sliding along itself; a free-surface scene adds moving moulds and the
// solids of walls.hpp.
#include <span>
#include <vector>

namespace rheosim::ldd {

// A rigid boundary as the fluid sees it, in 2D or 3D. Used to keep fluid nodes off the walls
// (the wall nodes carry the boundary conditions).
class Boundary {
 public:
  virtual ~Boundary() = default;
  // Signed distance of x from the boundary at time t [m], positive on the fluid side, and the
  // unit normal pointing into the fluid. Returns false when the boundary does not constrain x
  // (outside a mould's height range, say).
  virtual bool distance(std::span<const double> x, double t, double& distance, std::span<double> normal) const = 0;
  // Velocity of the boundary at time t [m/s] (dimension entries): how its wall nodes move.
  virtual void velocity(double t, std::span<double> v) const = 0;
  // Velocity of the wall's material at time t [m/s]: what a no-slip wall imposes on the fluid.
  // The boundary's own motion unless it slides along itself (a cavity's lid).
  virtual void surface_velocity(double t, std::span<double> v) const { velocity(t, v); }
  // Free slip: its wall nodes take the fluid's tangential velocity (a greased mould) instead of
  // the no-slip condition.
  [[nodiscard]] virtual bool slip() const { return false; }

 protected:
  Boundary() = default;
  Boundary(const Boundary&) = default;
  Boundary& operator=(const Boundary&) = default;
};

// A fixed plane (a line in 2D): the fluid is on the side its normal points to. With a sliding
// velocity (tangential, one entry per dimension) its material moves along it: a cavity's lid.
class PlaneBoundary final : public Boundary {
 public:
  PlaneBoundary(std::vector<double> point, std::vector<double> inward_normal,
                std::vector<double> sliding_velocity = {});
  bool distance(std::span<const double> x, double t, double& distance, std::span<double> normal) const override;
  void velocity(double t, std::span<double> v) const override;
  void surface_velocity(double t, std::span<double> v) const override;

 private:
  std::vector<double> point_, normal_, sliding_velocity_;
};

// The inside of a truncated cone about the z axis (3D), bottom radius at z = z0 + v t, lifted at
// speed v until the bottom reaches lift_height (then it stops): the Abrams mould (LDD §4.4), or
// with equal radii the cylinder of a cylinder slump.
// Free slip: with no slip the lifted mould carried the Bingham concrete up with it (the coarse
// slump grew to 0.41 m high); an oiled mould lets it slide.
class ConeMouldBoundary final : public Boundary {
 public:
  ConeMouldBoundary(double bottom_radius, double top_radius, double height, double z0, double lift_velocity,
                    double lift_height);
  bool distance(std::span<const double> x, double t, double& distance, std::span<double> normal) const override;
  void velocity(double t, std::span<double> v) const override;
  [[nodiscard]] bool slip() const override { return true; }
  [[nodiscard]] double bottom(double t) const;  // z of the mould's bottom edge at time t

 private:
  double bottom_radius_, top_radius_, height_, z0_, lift_velocity_, lift_height_;
};

}  // namespace rheosim::ldd
