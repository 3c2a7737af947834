#pragma once
// Initial clouds and boundaries of the free-surface scenes (`dam_break`, `slump`, `column`
// in docs/case-files.md; LDD §4.3–4.4).
//
// Conventions. Fluid nodes start at the centres of Δ-cells filling the fluid region; walls are one
// layer of wall nodes Δ/2 outside the fluid region (so the first fluid layer is a lattice step
// from them) and a Boundary through that layer, which keeps fluid nodes at least Δ/2 inside —
// i.e. inside the physical region. Extents are reported from node positions ± Δ/2.
//
//   column     2D, open-top box of the given width, filled to the given height (hydrostatics).
//   dam_break  2D: reservoir [length L, height H] from x = −L to the gate at x = 0, removed at
//              t = 0; channel floor to x = channel_length − L, closed by walls at both ends.
//   slump      3D: the Abrams cone (bottom diameter D₀ on the floor z = 0, top d₀ at H₀) filled,
//              the mould lifted at lift_velocity from t = 0; floor disc radius D₀/2 + 1.2 H₀;
//              optional extra walls (a cylindrical container, an STL surface; walls.hpp).
#include <array>
#include <memory>
#include <span>
#include <vector>

#include "rheosim/ldd/free_surface.hpp"
#include "rheosim/ldd/scene.hpp"

namespace rheosim::ldd {

struct FreeSurfaceScene {
  NodeCloud cloud;
  std::vector<std::shared_ptr<const Boundary>> boundaries;
};

// The column's fluid region as built: whole cells of the spacing, width round(W/Δ)·Δ and mean
// depth round(H/Δ)·Δ [m]. Throws std::invalid_argument when fewer than 4 cells fit either way.
[[nodiscard]] std::array<double, 2> column_extent(const ldd::ColumnScene& scene, double spacing);
// Throws std::invalid_argument when the spacing leaves fewer than 4 cells across the fluid.
[[nodiscard]] FreeSurfaceScene column_scene(const ldd::ColumnScene& scene, double spacing);
[[nodiscard]] FreeSurfaceScene dam_break_scene(const ldd::DamBreakScene& scene, double spacing);
// `walls` (scene.walls of the case): extra walls built through make_wall() (walls.hpp); floor
// nodes behind them are removed, and the cone must lie on their fluid side.
[[nodiscard]] FreeSurfaceScene slump_scene(const ldd::SlumpScene& scene, double spacing,
                                           std::span<const ldd::WallSettings> walls = {});
// Adds walls to a scene: each wall's Boundary, and its wall nodes except those within Δ/2 of a
// node already there or more than Δ/2 behind one of `fixed` boundaries (indices into
// scene.boundaries); existing wall nodes of `fixed` boundaries more than Δ/2 behind a new wall
// are removed. Throws std::invalid_argument when a fluid node lies behind a new wall.
void add_walls(FreeSurfaceScene& scene, std::span<const ldd::WallSettings> walls, double spacing,
               std::vector<std::size_t> fixed, std::span<const double> region_lower,
               std::span<const double> region_upper);

}  // namespace rheosim::ldd
