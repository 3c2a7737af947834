#include "rheosim/ldd/scenes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "rheosim/ldd/walls.hpp"

namespace rheosim::ldd {
namespace {

int cells_along(double length, double spacing, const char* what) {
  const auto cells = static_cast<int>(std::lround(length / spacing));
  if (cells < 4)
    throw std::invalid_argument(fmt::format(
        "LDD scene: spacing {} m leaves {} cells along the {} ({} m); need at least 4", spacing, cells, what, length));
  return cells;
}

// An open-top 2D box: floor over cells [0, cells_x) (x from x0), side walls `wall_rows` high.
// Fluid fills columns [fluid_begin, fluid_end) up to fluid_rows rows.
FreeSurfaceScene box_2d(double x0, int cells_x, int wall_rows, int fluid_begin, int fluid_end, int fluid_rows,
                        double dx) {
  FreeSurfaceScene s;
  s.cloud.dimension = 2;
  const double xl = x0 - 0.5 * dx, xr = x0 + (cells_x + 0.5) * dx, yb = -0.5 * dx;
  s.boundaries.push_back(std::make_shared<PlaneBoundary>(std::vector<double>{0.0, yb}, std::vector<double>{0.0, 1.0}));
  s.boundaries.push_back(std::make_shared<PlaneBoundary>(std::vector<double>{xl, 0.0}, std::vector<double>{1.0, 0.0}));
  s.boundaries.push_back(std::make_shared<PlaneBoundary>(std::vector<double>{xr, 0.0}, std::vector<double>{-1.0, 0.0}));
  const double diagonal = std::numbers::sqrt2 / 2;
  s.cloud.add(std::vector<double>{xl, yb}, NodeKind::corner, std::vector<double>{diagonal, diagonal}, 0);
  for (int i = 0; i < cells_x; ++i)
    s.cloud.add(std::vector<double>{x0 + (i + 0.5) * dx, yb}, NodeKind::wall, std::vector<double>{0.0, 1.0}, 0);
  s.cloud.add(std::vector<double>{xr, yb}, NodeKind::corner, std::vector<double>{-diagonal, diagonal}, 0);
  for (int j = 0; j < wall_rows; ++j) {
    s.cloud.add(std::vector<double>{xl, (j + 0.5) * dx}, NodeKind::wall, std::vector<double>{1.0, 0.0}, 1);
    s.cloud.add(std::vector<double>{xr, (j + 0.5) * dx}, NodeKind::wall, std::vector<double>{-1.0, 0.0}, 2);
  }
  const std::vector<double> none{0.0, 0.0};
  for (int j = 0; j < fluid_rows; ++j)
    for (int i = fluid_begin; i < fluid_end; ++i)
      s.cloud.add(std::vector<double>{x0 + (i + 0.5) * dx, (j + 0.5) * dx}, NodeKind::interior, none, -1);
  return s;
}

}  // namespace

std::array<double, 2> column_extent(const ldd::ColumnScene& scene, double spacing) {
  return {cells_along(scene.size[0], spacing, "column width") * spacing,
          cells_along(scene.size[1], spacing, "column height") * spacing};
}

FreeSurfaceScene column_scene(const ldd::ColumnScene& scene, double spacing) {
  const int nx = cells_along(scene.size[0], spacing, "column width");
  const int ny = cells_along(scene.size[1], spacing, "column height");
  const double amplitude = scene.wave_amplitude;
  const int crest_rows = static_cast<int>(std::ceil(amplitude / spacing));
  FreeSurfaceScene s = box_2d(0.0, nx, ny + crest_rows + 4, 0, nx, amplitude > 0 ? 0 : ny, spacing);
  if (amplitude > 0) {
    // Each column of cells (centre x) holds round(η/Δ) nodes spaced evenly from the floor to its
    // surface η = H + A cos(πx/W), the top one half a spacing below it (spacing within Δ(1 ± 1/(2·rows))).
    // Cells cut at the lattice's rows instead leave a staircase of Δ-high steps whose corner nodes,
    // unsupported, fell and seeded grid-scale ripples that grew (docs/ldd.md, sloshing).
    const double width = nx * spacing, height = ny * spacing;
    const std::vector<double> none{0.0, 0.0};
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5) * spacing, surface = height + amplitude * std::cos(std::numbers::pi * x / width);
      const int rows = static_cast<int>(std::lround(surface / spacing));
      for (int j = 0; j < rows; ++j)
        s.cloud.add(std::vector<double>{x, (j + 0.5) * surface / rows}, NodeKind::interior, none, -1);
    }
  }
  return s;
}

FreeSurfaceScene dam_break_scene(const ldd::DamBreakScene& scene, double spacing) {
  const int reservoir = cells_along(scene.reservoir[0], spacing, "reservoir length");
  const int rows = cells_along(scene.reservoir[1], spacing, "reservoir height");
  const int channel = cells_along(scene.channel_length, spacing, "channel length");
  const double x0 = -reservoir * spacing;  // the gate is at x = 0
  return box_2d(x0, channel, rows + 4, 0, reservoir, rows, spacing);
}

FreeSurfaceScene slump_scene(const ldd::SlumpScene& scene, double spacing, std::span<const ldd::WallSettings> walls) {
  const double dx = spacing, height = scene.cone_height;
  const double rb = 0.5 * scene.cone_bottom_diameter, rt = 0.5 * scene.cone_top_diameter;
  cells_along(scene.cone_top_diameter, spacing, "cone top diameter");
  FreeSurfaceScene s;
  s.cloud.dimension = 3;
  // Floor z = 0 (wall nodes at z = −Δ/2) and the mould: its wall nodes lie Δ/2 outside the
  // physical cone, so that the fluid nodes (kept Δ/2 inside it) fill the cone's own volume.
  const double slope = (rb - rt) / height;
  const double offset = 0.5 * dx * std::sqrt(1.0 + slope * slope);  // radial offset for a Δ/2 normal offset
  s.boundaries.push_back(
      std::make_shared<PlaneBoundary>(std::vector<double>{0.0, 0.0, -0.5 * dx}, std::vector<double>{0.0, 0.0, 1.0}));
  s.boundaries.push_back(
      std::make_shared<ConeMouldBoundary>(rb + offset, rt + offset, height, 0.0, scene.lift_velocity, 1.5 * height));
  const double floor_radius = rb + 1.2 * height;
  const int m = static_cast<int>(std::ceil(floor_radius / dx));
  for (int i = -m; i < m; ++i)
    for (int j = -m; j < m; ++j) {
      const double x = (i + 0.5) * dx, y = (j + 0.5) * dx;
      if (std::hypot(x, y) <= floor_radius)
        s.cloud.add(std::vector<double>{x, y, -0.5 * dx}, NodeKind::wall, std::vector<double>{0.0, 0.0, 1.0}, 0);
    }
  // Mould rings every Δ from Δ/2 to H₀ + Δ, each with nodes about Δ apart.
  const double cosine = 1.0 / std::sqrt(1.0 + slope * slope);
  for (int k = 0; (k + 0.5) * dx <= height + dx; ++k) {
    const double z = (k + 0.5) * dx;
    const double r = rb + offset - slope * z;
    const int count = std::max(6, static_cast<int>(std::lround(2 * std::numbers::pi * r / dx)));
    for (int q = 0; q < count; ++q) {
      const double angle = 2 * std::numbers::pi * (q + 0.5 * (k % 2)) / count;
      const double c = std::cos(angle), sn = std::sin(angle);
      s.cloud.add(std::vector<double>{r * c, r * sn, z}, NodeKind::wall,
                  std::vector<double>{-c * cosine, -sn * cosine, -slope * cosine}, 1);
    }
  }
  const int mr = static_cast<int>(std::ceil(rb / dx));
  const std::vector<double> none{0.0, 0.0, 0.0};
  for (int k = 0; (k + 0.5) * dx < height; ++k)
    for (int i = -mr; i < mr; ++i)
      for (int j = -mr; j < mr; ++j) {
        const double x = (i + 0.5) * dx, y = (j + 0.5) * dx, z = (k + 0.5) * dx;
        if (std::hypot(x, y) <= rb - slope * z) s.cloud.add(std::vector<double>{x, y, z}, NodeKind::interior, none, -1);
      }
  if (!walls.empty()) {
    const std::vector<double> lower{-floor_radius, -floor_radius, -dx}, upper{floor_radius, floor_radius, 2 * height};
    add_walls(s, walls, dx, {0}, lower, upper);  // the floor (boundary 0) is fixed; the mould moves
  }
  return s;
}

void add_walls(FreeSurfaceScene& s, std::span<const ldd::WallSettings> walls, double spacing,
               std::vector<std::size_t> fixed, std::span<const double> region_lower,
               std::span<const double> region_upper) {
  const int dimension = s.cloud.dimension;
  const auto dim = static_cast<std::size_t>(dimension);
  const auto distance_to = [&](const Boundary& b, std::span<const double> x) {
    double d = 0, normal[3] = {0, 0, 0};
    return b.distance(x, 0.0, d, std::span<double>(normal, dim)) ? d : std::numeric_limits<double>::infinity();
  };
  for (std::size_t w = 0; w < walls.size(); ++w) {
    BuiltWall built = make_wall(walls[w], dimension, spacing, region_lower, region_upper);
    const Boundary& boundary = *built.boundary;
    NodeCloud kept;
    kept.dimension = dimension;
    for (std::size_t i = 0; i < s.cloud.size(); ++i) {
      const std::span<const double> x(&s.cloud.positions[dim * i], dim);
      if (!s.cloud.is_wall(i) && distance_to(boundary, x) < 0)
        throw std::invalid_argument(
            fmt::format("LDD scene: fluid node at ({:.4g}, {:.4g}{}) lies behind wall {} ({}); the fluid must start on "
                        "the walls' fluid side",
                        x[0], x[1], dim == 3 ? fmt::format(", {:.4g}", x[2]) : std::string(), w + 1, walls[w].type));
      const int owner = s.cloud.boundary[i];
      const bool fixed_wall = s.cloud.is_wall(i) && owner >= 0 &&
                              std::find(fixed.begin(), fixed.end(), static_cast<std::size_t>(owner)) != fixed.end();
      if (fixed_wall && distance_to(boundary, x) < -0.5 * spacing) continue;  // behind the new wall
      kept.add(x, s.cloud.kinds[i], std::span<const double>(&s.cloud.normals[dim * i], dim), owner);
    }
    s.cloud = std::move(kept);
    const int index = static_cast<int>(s.boundaries.size());
    // New nodes: not within Δ/2 of an existing wall node, not behind a fixed boundary. The
    // proximity search scans the existing wall nodes sorted by x within a ±Δ/2 window.
    std::vector<std::pair<double, std::size_t>> by_x;
    for (std::size_t i = 0; i < s.cloud.size(); ++i)
      if (s.cloud.is_wall(i)) by_x.emplace_back(s.cloud.positions[dim * i], i);
    std::sort(by_x.begin(), by_x.end());
    const double min_distance = 0.5 * spacing;
    for (const WallNode& node : built.nodes) {
      const std::span<const double> x(node.x.data(), dim);
      bool behind = false;
      for (std::size_t f : fixed) behind = behind || distance_to(*s.boundaries[f], x) < -0.5 * spacing;
      if (behind) continue;
      bool near = false;
      const auto first =
          std::lower_bound(by_x.begin(), by_x.end(), std::make_pair(x[0] - min_distance, std::size_t{0}));
      for (auto it = first; it != by_x.end() && it->first <= x[0] + min_distance && !near; ++it) {
        double r2 = 0;
        for (std::size_t d = 0; d < dim; ++d) {
          const double delta = s.cloud.positions[dim * it->second + d] - x[d];
          r2 += delta * delta;
        }
        near = r2 < min_distance * min_distance;
      }
      if (near) continue;
      s.cloud.add(x, node.corner ? NodeKind::corner : NodeKind::wall, std::span<const double>(node.normal.data(), dim),
                  index);
    }
    s.boundaries.push_back(std::move(built.boundary));
    fixed.push_back(static_cast<std::size_t>(index));
  }
}

}  // namespace rheosim::ldd
