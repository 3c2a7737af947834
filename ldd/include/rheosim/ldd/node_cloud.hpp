#pragma once
// The initial node cloud of an LDD scene, for either scheme of the solver: a cavity's lattice (domain.hpp) or a
// free-surface scene's fluid and wall nodes (scenes.hpp).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace rheosim::ldd {

// What a node is, in both schemes and in the `kind` of every node frame. A cloud starts with
// interior (fluid), wall and corner nodes (a corner, where walls meet, has no unique normal);
// the free-surface solver reclassifies each step: fluid nodes on the surface (p = 0) or splashed
// (few neighbours), wall nodes with no fluid within reach idle.
enum class NodeKind : std::uint8_t { interior = 0, surface = 1, splash = 2, wall = 3, corner = 4, idle_wall = 5 };
// The kind's name in messages ("free-surface", "idle wall", …), and with its article ("an
// interior", "a wall").
[[nodiscard]] const char* kind_name(NodeKind k);
[[nodiscard]] std::string a_kind(NodeKind k);

struct NodeCloud {
  int dimension = 2;
  std::vector<double> positions;  // interleaved with stride dimension [m]
  std::vector<NodeKind> kinds;
  std::vector<double> normals;  // inward unit normal per node (0 for fluid nodes; corners: bisector)
  // Index of the wall node's boundary in the scene's list (boundary.hpp), −1 for fluid nodes.
  std::vector<int> boundary;

  [[nodiscard]] std::size_t size() const { return kinds.size(); }
  [[nodiscard]] bool is_wall(std::size_t i) const { return kinds[i] != NodeKind::interior; }
  // Appends a node of a free-surface scene (position and normal with dimension entries).
  void add(std::span<const double> x, NodeKind kind, std::span<const double> normal, int boundary_index);
};

}  // namespace rheosim::ldd
