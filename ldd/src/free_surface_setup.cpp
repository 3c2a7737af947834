// The free-surface scene's boundaries and its initial cloud (free_surface.hpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "rheosim/ldd/free_surface.hpp"

namespace rheosim::ldd {

// ------------------------------------------------------------------------------ boundaries

PlaneBoundary::PlaneBoundary(std::vector<double> point, std::vector<double> inward_normal,
                             std::vector<double> sliding_velocity)
    : point_(std::move(point)), normal_(std::move(inward_normal)), sliding_velocity_(std::move(sliding_velocity)) {
  if (point_.size() != normal_.size() || (point_.size() != 2 && point_.size() != 3))
    throw std::invalid_argument("PlaneBoundary: point and normal need 2 or 3 equal-sized entries");
  if (sliding_velocity_.empty()) sliding_velocity_.assign(point_.size(), 0.0);
  if (sliding_velocity_.size() != point_.size())
    throw std::invalid_argument("PlaneBoundary: the sliding velocity needs one entry per dimension");
  double length = 0;
  for (double v : normal_) length += v * v;
  length = std::sqrt(length);
  if (!(length > 0)) throw std::invalid_argument("PlaneBoundary: zero normal");
  for (double& v : normal_) v /= length;
  double normal_part = 0;
  for (std::size_t d = 0; d < normal_.size(); ++d) normal_part += normal_[d] * sliding_velocity_[d];
  if (std::abs(normal_part) > 1e-12 * (1.0 + std::abs(normal_part)))
    throw std::invalid_argument("PlaneBoundary: the sliding velocity must be tangential");
}

bool PlaneBoundary::distance(std::span<const double> x, double /*t*/, double& distance,
                             std::span<double> normal) const {
  distance = 0;
  for (std::size_t d = 0; d < point_.size(); ++d) {
    distance += normal_[d] * (x[d] - point_[d]);
    normal[d] = normal_[d];
  }
  return true;
}

void PlaneBoundary::velocity(double /*t*/, std::span<double> v) const { std::fill(v.begin(), v.end(), 0.0); }

void PlaneBoundary::surface_velocity(double /*t*/, std::span<double> v) const {
  std::copy(sliding_velocity_.begin(), sliding_velocity_.end(), v.begin());
}

ConeMouldBoundary::ConeMouldBoundary(double bottom_radius, double top_radius, double height, double z0,
                                     double lift_velocity, double lift_height)
    : bottom_radius_(bottom_radius),
      top_radius_(top_radius),
      height_(height),
      z0_(z0),
      lift_velocity_(lift_velocity),
      lift_height_(lift_height) {
  if (!(top_radius > 0 && bottom_radius >= top_radius && height > 0 && lift_velocity >= 0))
    throw std::invalid_argument(
        "ConeMouldBoundary: needs 0 < top radius <= bottom radius, height > 0, lift velocity >= 0");
}

double ConeMouldBoundary::bottom(double t) const { return z0_ + std::min(lift_velocity_ * t, lift_height_); }

bool ConeMouldBoundary::distance(std::span<const double> x, double t, double& distance,
                                 std::span<double> normal) const {
  const double zb = bottom(t);
  if (x[2] < zb || x[2] > zb + height_) return false;
  const double slope = (bottom_radius_ - top_radius_) / height_;  // dr/dz, radius shrinks upwards
  const double radius = bottom_radius_ - slope * (x[2] - zb);
  const double rho = std::hypot(x[0], x[1]);
  const double cosine = 1.0 / std::sqrt(1.0 + slope * slope);
  distance = (radius - rho) * cosine;  // perpendicular distance to the slanted wall
  // Inward normal: towards the axis and down the slope, −(r̂, slope)/√(1 + slope²).
  const double rx = rho > 0 ? x[0] / rho : 1.0, ry = rho > 0 ? x[1] / rho : 0.0;
  normal[0] = -rx * cosine;
  normal[1] = -ry * cosine;
  normal[2] = -slope * cosine;
  return true;
}

void ConeMouldBoundary::velocity(double t, std::span<double> v) const {
  std::fill(v.begin(), v.end(), 0.0);
  if (lift_velocity_ * t < lift_height_) v[2] = lift_velocity_;
}

void NodeCloud::add(std::span<const double> x, NodeKind kind, std::span<const double> normal, int boundary_index) {
  positions.insert(positions.end(), x.begin(), x.end());
  normals.insert(normals.end(), normal.begin(), normal.end());
  kinds.push_back(kind);
  boundary.push_back(boundary_index);
}

}  // namespace rheosim::ldd
