#pragma once
// Solid walls of free-surface scenes beyond planes and the Abrams mould: axis-aligned
// boxes, capped cylinders and closed triangulated (STL) surfaces, each one Boundary (signed
// distance, normal into the fluid, wall velocity) plus the wall-node layer that carries its
// boundary conditions, selected by name from a case file's `scene.walls` through make_wall().
//
// Geometry convention (scenes.hpp): the case gives the physical wall; the Boundary and its wall
// nodes sit Δ/2 beyond it, on the solid side, and FreeSurfaceSolver keeps fluid nodes Δ/2 off the
// Boundary, i.e. on the physical wall or inside the fluid region. All three shapes are closed
// solids: the fluid is inside them (a container) or outside (an obstacle).
//
// Signed distance of the solid, s(x): negative inside, exact Euclidean distance (box and capped
// cylinder in closed form; a mesh by its nearest triangle, the sign from the angle-weighted
// pseudo-normal of the nearest feature — face, edge or vertex — after Bærentzen & Aanæs, IEEE
// TVCG 11 (2005) 243, which is correct for any closed, consistently oriented mesh).
#include <array>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rheosim/ldd/free_surface.hpp"
#include "rheosim/ldd/scene.hpp"

namespace rheosim::ldd {

// One node of a wall layer: position, unit normal into the fluid, whether walls meet there.
struct WallNode {
  std::array<double, 3> x{};
  std::array<double, 3> normal{};
  bool corner = false;
};

// A closed solid as a Boundary. distance() is the fluid-side distance to the wall layer:
// (fluid inside ? −s : s) + layer_offset, normal = ∓∇s; the wall is fixed (velocity 0).
class SolidBoundary : public Boundary {
 public:
  bool distance(std::span<const double> x, double t, double& distance, std::span<double> normal) const override;
  void velocity(double t, std::span<double> v) const override;
  // s(x) of the physical solid [m] and its outward unit normal ∇s.
  virtual double signed_distance(std::span<const double> x, std::span<double> outward) const = 0;
  // Wall nodes about `spacing` apart on the wall layer (the physical surface moved layer_offset
  // into the solid).
  [[nodiscard]] virtual std::vector<WallNode> wall_nodes(double spacing) const = 0;
  [[nodiscard]] bool fluid_inside() const { return fluid_inside_; }
  [[nodiscard]] double layer_offset() const { return layer_offset_; }
  [[nodiscard]] int dimension() const { return dimension_; }

 protected:
  SolidBoundary(int dimension, bool fluid_inside, double layer_offset);
  // The wall layer is the level set s = layer_shift(): outside the closed surface for a
  // container (the wall material is outside), inside it for an obstacle.
  [[nodiscard]] double layer_shift() const { return fluid_inside_ ? layer_offset_ : -layer_offset_; }

 private:
  int dimension_;
  bool fluid_inside_;
  double layer_offset_;
};

// Axis-aligned box [lower, upper] in 2D or 3D.
class BoxBoundary final : public SolidBoundary {
 public:
  BoxBoundary(std::vector<double> lower, std::vector<double> upper, bool fluid_inside, double layer_offset);
  double signed_distance(std::span<const double> x, std::span<double> outward) const override;
  [[nodiscard]] std::vector<WallNode> wall_nodes(double spacing) const override;

 private:
  std::vector<double> lower_, upper_;
};

// Capped cylinder (3D): bottom-cap centre `base`, unit axis, radius, height along the axis.
class CylinderBoundary final : public SolidBoundary {
 public:
  CylinderBoundary(std::array<double, 3> base, std::array<double, 3> axis, double radius, double height,
                   bool fluid_inside, double layer_offset);
  double signed_distance(std::span<const double> x, std::span<double> outward) const override;
  [[nodiscard]] std::vector<WallNode> wall_nodes(double spacing) const override;

 private:
  std::array<double, 3> base_, axis_, e1_{}, e2_{};  // e1, e2: unit vectors across the axis
  double radius_, height_;
};

// A closed triangle mesh with shared (welded) vertices; triangles wound counter-clockwise seen
// from outside (the reader reorients a mesh whose enclosed volume comes out negative).
struct TriangleMesh {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<std::size_t, 3>> triangles;
  [[nodiscard]] double volume() const;  // enclosed volume (divergence theorem), > 0 when outward
};

// Reads an STL file, ASCII ("solid … facet normal … outer loop … vertex x y z … endsolid") or
// binary (80-byte header, uint32 count, 50 bytes per triangle), scaled by `scale` [m per file
// unit]; identical vertices are merged. Throws std::invalid_argument naming the file (and the line
// for ASCII) on malformed input, and when the mesh is not closed (an edge not shared by exactly
// two triangles) — inside/outside is undefined otherwise.
[[nodiscard]] TriangleMesh read_stl(const std::filesystem::path& file, double scale = 1.0);
// Writers for tests and tools (binary: little-endian floats as the format prescribes).
void write_stl_ascii(const std::filesystem::path& file, const TriangleMesh& mesh);
void write_stl_binary(const std::filesystem::path& file, const TriangleMesh& mesh);
// Closed meshes of simple solids (tests; a cylinder with `segments` sides).
[[nodiscard]] TriangleMesh box_mesh(std::array<double, 3> lower, std::array<double, 3> upper);
[[nodiscard]] TriangleMesh cylinder_mesh(std::array<double, 3> base, double radius, double height, int segments);

// A closed triangulated surface (3D). Distance queries test every triangle (no spatial index):
// fine for the few hundred triangles of a container, slow for large scanned meshes.
class StlBoundary final : public SolidBoundary {
 public:
  StlBoundary(TriangleMesh mesh, bool fluid_inside, double layer_offset);
  double signed_distance(std::span<const double> x, std::span<double> outward) const override;
  [[nodiscard]] std::vector<WallNode> wall_nodes(double spacing) const override;
  [[nodiscard]] const TriangleMesh& mesh() const { return mesh_; }

 private:
  TriangleMesh mesh_;
  std::vector<std::array<double, 3>> face_normals_, vertex_normals_;
  std::vector<std::array<std::array<double, 3>, 3>> edge_normals_;  // per triangle, edges (0,1), (1,2), (2,0)
};

// A wall built from a case file entry: its Boundary and its wall-node layer.
struct BuiltWall {
  std::shared_ptr<const Boundary> boundary;
  std::vector<WallNode> nodes;
};

// The registry: builds `spec` by its type name (plane, box, cylinder, stl) for node spacing Δ.
// Unbounded planes get wall nodes only inside the axis-aligned box [region_lower, region_upper]
// (the scene's extent). Throws std::invalid_argument for an unknown type, or naming the STL file.
[[nodiscard]] BuiltWall make_wall(const ldd::WallSettings& spec, int dimension, double spacing,
                                  std::span<const double> region_lower, std::span<const double> region_upper);
// The names make_wall() accepts.
[[nodiscard]] std::vector<std::string> wall_types();

}  // namespace rheosim::ldd
