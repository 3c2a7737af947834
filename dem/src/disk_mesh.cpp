#include "disk_mesh.hpp"

#include <cmath>
#include <ostream>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "rheosim/core/units.hpp"

namespace rheosim::dem::detail {

DiskMesh make_disk_mesh(double radius, double height, int rings) {
  if (!(std::isfinite(radius) && radius > 0.0))
    throw std::invalid_argument(fmt::format("disk radius = {} is out of range, expected a finite value > 0", radius));
  if (rings < 1) throw std::invalid_argument(fmt::format("disk rings = {} is out of range, expected >= 1", rings));
  using core::units::pi;
  DiskMesh mesh;
  mesh.outer_radius = radius / std::cos(pi / (6.0 * rings));
  const auto node = [&](int ring, int j) -> std::array<double, 3> {
    if (ring == 0) return {0.0, 0.0, height};
    const int n = 6 * ring;
    const double r = mesh.outer_radius * ring / rings;
    const double phi = 2.0 * pi * (j % n) / n;
    return {r * std::cos(phi), r * std::sin(phi), height};
  };
  // Corners in counter-clockwise order seen from +z give a +z normal; store them clockwise.
  const auto add = [&](const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c) {
    mesh.triangles.push_back({a, c, b});
  };
  for (int k = 1; k <= rings; ++k) {
    const int n_out = 6 * k;
    if (k == 1) {
      for (int j = 0; j < n_out; ++j) add(node(0, 0), node(1, j), node(1, j + 1));
      continue;
    }
    const int n_in = 6 * (k - 1);
    int i = 0;
    int j = 0;
    // Walk both rings counter-clockwise: advance on the ring whose next node comes first.
    while (i < n_in || j < n_out) {
      const bool advance_outer =
          j < n_out && (i >= n_in || static_cast<long>(j + 1) * n_in <= static_cast<long>(i + 1) * n_out);
      if (advance_outer) {
        add(node(k - 1, i), node(k, j), node(k, j + 1));
        ++j;
      } else {
        add(node(k - 1, i), node(k, j), node(k - 1, i + 1));
        ++i;
      }
    }
  }
  return mesh;
}

void write_ascii_stl(std::ostream& out, const DiskMesh& mesh, std::string_view name) {
  fmt::print(out, "solid {}\n", name);
  for (const auto& t : mesh.triangles) {
    fmt::print(out, "  facet normal 0 0 -1\n    outer loop\n");
    for (const auto& p : t) fmt::print(out, "      vertex {:.17g} {:.17g} {:.17g}\n", p[0], p[1], p[2]);
    fmt::print(out, "    endloop\n  endfacet\n");
  }
  fmt::print(out, "endsolid {}\n", name);
}

}  // namespace rheosim::dem::detail
