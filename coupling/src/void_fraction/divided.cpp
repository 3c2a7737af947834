#include "void_fraction/divided.hpp"

#include <algorithm>
#include <cmath>

namespace rheosim::coupling {

DividedVoidFraction::Params DividedVoidFraction::Params::from(const core::Section& /*section*/) { return {}; }

DividedVoidFraction::DividedVoidFraction(Params /*params*/) : offsets_(unit_offsets()) {}

std::array<double, 2> DividedVoidFraction::shell_radii() {
  // Core | inner shell | outer shell hold 1, 14 and 14 of 29 equal volumes.
  const double core = std::cbrt(1.0 / 29.0);
  const double middle = std::cbrt(15.0 / 29.0);
  const auto centroid = [](double a, double b) {
    return 0.75 * (b * b * b * b - a * a * a * a) / (b * b * b - a * a * a);  // volume-weighted mean radius
  };
  return {centroid(core, middle), centroid(middle, 1.0)};
}

std::array<Vector3, DividedVoidFraction::sub_points> DividedVoidFraction::unit_offsets() {
  std::array<Vector3, 14> directions{};
  std::size_t n = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {-1.0, 1.0}) {
      Vector3 d{0.0, 0.0, 0.0};
      d[static_cast<std::size_t>(axis)] = sign;
      directions[n++] = d;
    }
  const double c = 1.0 / std::sqrt(3.0);
  for (const double sx : {-c, c})
    for (const double sy : {-c, c})
      for (const double sz : {-c, c}) directions[n++] = {sx, sy, sz};
  std::array<Vector3, sub_points> out{};
  out[0] = {0.0, 0.0, 0.0};
  const std::array<double, 2> radii = shell_radii();
  std::size_t m = 1;
  for (const double radius : radii)
    for (const Vector3& d : directions) out[m++] = {radius * d[0], radius * d[1], radius * d[2]};
  return out;
}

void DividedVoidFraction::split(const CellLocator& locator, const ParticleView& particles, ParticleCellMap& out) const {
  out.clear();
  out.offsets.reserve(particles.size() + 1);
  out.shares.reserve(particles.size() * 4);
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const Vector3 centre = particles.position(p);
    const double radius = particles.radii[p];
    const double volume = sphere_volume_from_radius(radius);
    const double part = volume / sub_points;
    const std::size_t first = out.shares.size();
    double placed = 0.0;
    const CellLocator::Location centre_at = locator.locate(centre);
    for (std::size_t s = 0; s < offsets_.size(); ++s) {
      const Vector3 point{centre[0] + radius * offsets_[s][0], centre[1] + radius * offsets_[s][1],
                          centre[2] + radius * offsets_[s][2]};
      const CellLocator::Location at = s == 0 ? centre_at : locator.locate_near(point, centre_at.azimuthal);
      out.mapped_points += at.mapped ? 1 : 0;
      // The last part closes the balance, so the shares add up to V_p to round-off.
      const double share = s + 1 == offsets_.size() ? volume - placed : part;
      placed += share;
      const auto begin = out.shares.begin() + static_cast<std::ptrdiff_t>(first);
      const auto same = std::find_if(begin, out.shares.end(), [&](const VolumeShare& v) { return v.cell == at.cell; });
      if (same != out.shares.end())
        same->volume += share;
      else
        out.shares.push_back({at.cell, share});
    }
    out.offsets.push_back(out.shares.size());
  }
}

}  // namespace rheosim::coupling
