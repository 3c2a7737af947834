#pragma once
// Fixed-radius neighbour search for 2D and 3D point clouds by a cell list: the support of the
// LDD weight W(r, h) = (1 − r/h)³, zero for r >= h (LDD §3.1), and of the operators built on it
// (LDD eqs. 12–16).
//
// Definition: node j is a neighbour of node i iff j ≠ i and
//   Σ_d (x_j,d − x_i,d)² < h²          (evaluated in double precision)
// A node exactly at distance h is not a neighbour (W = 0 there, so it would contribute nothing),
// and the relation is symmetric. Coincident distinct nodes (distance 0) are neighbours.
//
// Method: a cell list with cells slightly larger than h. Nodes are counting-sorted by cell,
// with a copy of their coordinates in that order, and each node scans the 3^D cells around its
// own. When the bounding box holds more than 4 cells per node (nodes far apart, clusters), the
// cells are hashed into ~2N buckets instead (spatial hashing, Teschner et al., VMV 2003), so
// memory stays O(N) whatever the extent. Build and search are O(N) for clouds of bounded
// density; the per-node work runs in parallel with OpenMP. The result is deterministic: each
// node's neighbours are sorted by index and nothing depends on the thread count.
//
// Positions are interleaved, stride = dimension: {x0, y0, x1, y1, ...} or {x0, y0, z0, ...}.
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

namespace rheosim::numerics {

namespace detail {
class CellTable;
}

// Neighbours of every node in compressed sparse row form: the neighbours of node i are
// indices[offsets[i] .. offsets[i+1]), ascending, with their distances [m] alongside.
struct NeighbourList {
  std::vector<std::size_t> offsets{0};  // size node_count() + 1
  std::vector<std::size_t> indices;
  std::vector<double> distances;

  [[nodiscard]] std::size_t node_count() const { return offsets.size() - 1; }
  [[nodiscard]] std::size_t pair_count() const { return indices.size(); }  // ordered pairs (i, j)
  [[nodiscard]] std::span<const std::size_t> neighbours_of(std::size_t node) const {
    return std::span(indices).subspan(offsets[node], offsets[node + 1] - offsets[node]);
  }
  [[nodiscard]] std::span<const double> distances_of(std::size_t node) const {
    return std::span(distances).subspan(offsets[node], offsets[node + 1] - offsets[node]);
  }
};

// All neighbours within support_radius h [m] > 0. dimension is 2 or 3 and must divide
// positions.size(); positions must be finite. Throws std::invalid_argument otherwise, and when
// the cloud's extent exceeds 1e10·h (beyond that the cell arithmetic loses its margin).
[[nodiscard]] NeighbourList find_neighbours(std::span<const double> positions, int dimension, double support_radius);

// The pairs of `candidates` (a list found with a larger radius) that are now closer than
// `radius`, in the same order and with the same distances find_neighbours(positions, dimension,
// radius) would give — identical to it as long as no pair has closed in from beyond the
// candidates' radius (a Verlet list: FreeSurfaceSolver re-searches once nodes have moved half the
// skin).
[[nodiscard]] NeighbourList neighbours_within(const NeighbourList& candidates, std::span<const double> positions,
                                              int dimension, double radius);
// The same into `out`, reusing its storage (out must not be `candidates`).
void neighbours_within(const NeighbourList& candidates, std::span<const double> positions, int dimension, double radius,
                       NeighbourList& out);

// Nodes near any point, not only near a node: the same cell list, kept for repeated queries
// (FreeSurfaceSolver counts nodes in balls centred on a grid). A node j is near the point p iff
// Σ_d (x_j,d − p_d)² < radius², the criterion find_neighbours uses. The positions are copied, so
// the locator answers for the cloud as it was when built.
class NodeLocator {
 public:
  // Same requirements and errors as find_neighbours (radius in the role of support_radius).
  NodeLocator(std::span<const double> positions, int dimension, double radius);
  ~NodeLocator();
  NodeLocator(NodeLocator&&) noexcept;
  NodeLocator& operator=(NodeLocator&&) noexcept;
  NodeLocator(const NodeLocator&) = delete;
  NodeLocator& operator=(const NodeLocator&) = delete;

  // The nodes near `point` (dimension finite coordinates, anywhere: inside the cloud's bounding
  // box or far outside it), ascending, into `found`, which is cleared first and keeps its storage.
  // Throws std::invalid_argument for a point of the wrong size or with a coordinate not finite.
  void nodes_near(std::span<const double> point, std::vector<std::size_t>& found) const;

 private:
  std::unique_ptr<const detail::CellTable> table_;  // null for an empty cloud
  int dimension_;
  double radius_;
};

}  // namespace rheosim::numerics
