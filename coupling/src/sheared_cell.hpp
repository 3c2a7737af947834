#pragma once
// The cell of the suspension box in the sheared frame (suspension_box.cpp): periodic in x and
// y, and in z either Lees–Edwards periodic (an image above is shifted by the offset the shear
// has carried it) or bounded by two plates. Positions, the minimum-image separation and the
// near-pair search live here; the box's dynamics do not.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include "rheosim/coupling/particles.hpp"

namespace rheosim::coupling {

struct ShearedCell {
  double length = 0.0;  // L, the periodic x and y extent [a]
  double height = 0.0;  // z extent: L (Lees–Edwards) or the plates' gap [a]
  bool walls = false;   // z is bounded by plates, not periodic
  double offset = 0.0;  // Lees–Edwards x shift of the image above, in [0, L)

  // Back into the cell: leaving through z = L re-enters at z = 0 shifted back by the offset.
  void wrap(Vector3& x) const {
    if (!walls && x[2] >= length) {
      x[2] -= length;
      x[0] -= offset;
    } else if (!walls && x[2] < 0.0) {
      x[2] += length;
      x[0] += offset;
    }
    for (const std::size_t d : {0UL, 1UL}) x[d] -= length * std::floor(x[d] / length);
  }

  // Minimum-image separation to − from under the Lees–Edwards offset.
  [[nodiscard]] Vector3 separation(const Vector3& from, const Vector3& to) const {
    Vector3 r{to[0] - from[0], to[1] - from[1], to[2] - from[2]};
    if (!walls) {
      const double k = std::round(r[2] / length);
      r[2] -= k * length;
      r[0] -= k * offset;
    }
    r[0] -= length * std::round(r[0] / length);
    r[1] -= length * std::round(r[1] / length);
    return r;
  }

  // visit(i, j, r, |r|) for every pair i < j closer than range (cell list in the sheared frame:
  // across the Lees–Edwards z boundary a neighbour row is searched over all x cells, which the
  // offset may shift; between plates z is not periodic). Few cells or spheres: all pairs.
  template <class Visit>
  void for_each_near_pair(std::span<const Vector3> positions, double range, Visit&& visit) const {
    const std::size_t n = positions.size();
    const auto visit_if_near = [&](std::size_t i, std::size_t j) {
      const Vector3 r = separation(positions[i], positions[j]);
      const double d = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
      if (d < range) visit(i, j, r, d);
    };
    const int cells = std::max(1, static_cast<int>(length / range));
    const int layers = std::max(1, static_cast<int>(height / range));
    if (cells < 4 || (!walls && layers < 4) || n < 64) {
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) visit_if_near(i, j);
      return;
    }
    const double cell = length / cells, layer = height / layers;
    std::vector<std::vector<std::size_t>> grid(static_cast<std::size_t>(cells * cells * layers));
    const auto id = [&](int x, int y, int z) {
      const auto m = [](int v, int k) { return ((v % k) + k) % k; };
      return static_cast<std::size_t>((m(x, cells) * cells + m(y, cells)) * layers + m(z, layers));
    };
    std::vector<std::array<int, 3>> where(n);
    for (std::size_t i = 0; i < n; ++i) {
      where[i] = {std::clamp(static_cast<int>(positions[i][0] / cell), 0, cells - 1),
                  std::clamp(static_cast<int>(positions[i][1] / cell), 0, cells - 1),
                  std::clamp(static_cast<int>(positions[i][2] / layer), 0, layers - 1)};
      grid[id(where[i][0], where[i][1], where[i][2])].push_back(i);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const auto [cx, cy, cz] = where[i];
      for (int dz = -1; dz <= 1; ++dz) {
        const bool crosses = cz + dz < 0 || cz + dz >= layers;
        if (crosses && walls) continue;
        const int x_from = crosses ? 0 : cx - 1, x_to = crosses ? cells - 1 : cx + 1;
        for (int x = x_from; x <= x_to; ++x)
          for (int dy = -1; dy <= 1; ++dy)
            for (const std::size_t j : grid[id(x, cy + dy, cz + dz)])
              if (j > i) visit_if_near(i, j);
      }
    }
  }
};

}  // namespace rheosim::coupling
