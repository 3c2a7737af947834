#include "rheosim/ldd/domain.hpp"

#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace rheosim::ldd {

namespace {

// The unit normal into the cavity of its side from `start` to `end` (counter-clockwise: the fluid
// is on the left).
Vec2 inward_normal(const Vec2& start, const Vec2& end) {
  const double tx = end[0] - start[0], ty = end[1] - start[1];
  const double length = std::hypot(tx, ty);
  return {-ty / length, tx / length};  // left of start → end
}

}  // namespace

Cavity::Cavity(const ldd::CavityScene& scene, double spacing)
    : width_(scene.size[0]),
      side_(scene.size[1]),
      angle_(scene.skew_angle > 0 ? scene.skew_angle : std::numbers::pi / 2),
      lid_velocity_(scene.lid_velocity) {
  if (!(spacing > 0)) throw std::invalid_argument(fmt::format("cavity: spacing {} m is not > 0", spacing));
  cells_ = {static_cast<int>(std::lround(width_ / spacing)), static_cast<int>(std::lround(side_ / spacing))};
  if (cells_[0] < 4 || cells_[1] < 4)
    throw std::invalid_argument(fmt::format("cavity: spacing {} m leaves {} × {} cells; at least 4 per side are needed",
                                            spacing, cells_[0], cells_[1]));
  const Vec2 a = point(0, 0), b = point(1, 0), c = point(1, 1), d = point(0, 1);
  const std::array<Vec2, 4> normals{inward_normal(a, b), inward_normal(b, c), inward_normal(c, d), inward_normal(d, a)};
  // Counter-clockwise from the bottom; the lid (the third) slides along +x.
  const std::array<Vec2, 4> starts{a, b, c, d};
  for (std::size_t w = 0; w < 4; ++w) {
    const Vec2& start = starts[w];
    walls_.push_back(std::make_shared<PlaneBoundary>(
        std::vector<double>{start[0], start[1]}, std::vector<double>{normals[w][0], normals[w][1]},
        w == 2 ? std::vector<double>{lid_velocity_, 0.0} : std::vector<double>{0.0, 0.0}));
  }

  const int nx = cells_[0], ny = cells_[1];
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const Vec2 p = point(static_cast<double>(i) / nx, static_cast<double>(j) / ny);
      cloud_.positions.insert(cloud_.positions.end(), {p[0], p[1]});
      const bool left = i == 0, right = i == nx, bottom = j == 0, top = j == ny;
      Vec2 normal{0, 0};
      NodeKind kind = NodeKind::interior;
      int boundary = -1;
      const auto add_normal = [&](const Vec2& n) {
        normal[0] += n[0];
        normal[1] += n[1];
      };
      if (bottom) add_normal(normals[0]);
      if (right) add_normal(normals[1]);
      if (top) add_normal(normals[2]);
      if (left) add_normal(normals[3]);
      const int sides = int{bottom} + int{right} + int{top} + int{left};
      if (sides == 1) {
        kind = NodeKind::wall;
        boundary = bottom ? 0 : right ? 1 : top ? 2 : 3;  // the lid's end points are corners
      } else if (sides == 2) {
        kind = NodeKind::corner;
        boundary = right ? 1 : 3;  // stationary: the lid's ends belong to the side walls
      }
      if (sides > 0) {
        const double length = std::hypot(normal[0], normal[1]);
        normal = {normal[0] / length, normal[1] / length};
      }
      cloud_.kinds.push_back(kind);
      cloud_.normals.insert(cloud_.normals.end(), {normal[0], normal[1]});
      cloud_.boundary.push_back(boundary);
    }
}

Vec2 Cavity::point(double xi_fraction, double eta_fraction) const {
  const double xi = xi_fraction * width_, eta = eta_fraction * side_;
  return {xi + eta * std::cos(angle_), eta * std::sin(angle_)};
}

double Cavity::area() const { return width_ * side_ * std::sin(angle_); }

}  // namespace rheosim::ldd
