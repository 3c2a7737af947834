#include "rheosim/numerics/neighbours.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string_view>
#include <utility>

#include <fmt/format.h>

namespace rheosim::numerics {
namespace {

// Cells are this much larger than h, so rounding in the cell-index arithmetic can never put
// two nodes closer than h more than one cell apart. Rounding errors are ~1e-16 × (extent/h),
// far below the margin while extent/h <= max_extent_over_h.
constexpr double cell_margin = 1e-4;
constexpr double max_extent_over_h = 1e10;
// Above this many bounding-box cells per node, cells are hashed instead of stored densely.
constexpr double dense_cells_per_node = 4.0;

using CellIndex = std::array<std::int64_t, 3>;

// splitmix64 finaliser: spreads nearby cells over the table so structured clouds do not collide.
std::uint64_t mix(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

std::uint64_t hash_cell(const CellIndex& cell) {
  const auto u = [](std::int64_t v) { return static_cast<std::uint64_t>(v); };
  return mix(u(cell[0]) * 0x9e3779b97f4a7c15ULL + u(cell[1]) * 0xc2b2ae3d27d4eb4fULL +
             u(cell[2]) * 0x165667b19e3779f9ULL);
}

std::size_t table_size_for(std::size_t node_count) {
  std::size_t size = 1;
  while (size < 2 * node_count) size *= 2;
  return size;  // power of two, so the bucket is hash & (size − 1)
}

// `caller` names the function in the messages.
void validate(std::span<const double> positions, int dimension, double support_radius, std::string_view caller) {
  if (dimension != 2 && dimension != 3)
    throw std::invalid_argument(fmt::format("{}: dimension = {} is out of range, expected 2 or 3", caller, dimension));
  if (!(std::isfinite(support_radius) && support_radius > 0.0))
    throw std::invalid_argument(
        fmt::format("{}: support_radius = {} is out of range, expected a finite value > 0", caller, support_radius));
  if (positions.size() % static_cast<std::size_t>(dimension) != 0)
    throw std::invalid_argument(fmt::format("{}: positions has {} values, not a multiple of dimension = {}", caller,
                                            positions.size(), dimension));
  for (std::size_t k = 0; k < positions.size(); ++k)
    if (!std::isfinite(positions[k]))
      throw std::invalid_argument(fmt::format("{}: position of node {} (component {}) is {}", caller,
                                              k / static_cast<std::size_t>(dimension),
                                              k % static_cast<std::size_t>(dimension), positions[k]));
}

// A run of consecutive slots in bucket order.
struct SlotRange {
  std::size_t first = 0;
  std::size_t last = 0;
};

}  // namespace

namespace detail {

// Nodes sorted by the bucket of their cell (a counting sort, so O(N + buckets)), with a copy of
// their coordinates in that order, so that scanning a bucket reads contiguous memory.
//
// Buckets are the cells themselves (lexicographic order, x fastest) when the bounding box has
// at most dense_cells_per_node cells per node: then a row of three cells is one contiguous run
// and neighbouring queries touch the same memory. Sparser clouds (nodes far apart) hash their
// cells into ~2N buckets instead, so memory stays O(N) whatever the extent.
class CellTable {
 public:
  CellTable(std::span<const double> positions, std::size_t dimension, double support_radius, std::string_view caller)
      : node_count_(positions.size() / dimension), cell_size_(support_radius * (1.0 + cell_margin)) {
    std::array<double, 3> upper{};
    for (std::size_t d = 0; d < dimension; ++d) {
      lower_[d] = std::numeric_limits<double>::infinity();
      upper[d] = -std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < node_count_; ++i) {
        lower_[d] = std::min(lower_[d], positions[i * dimension + d]);
        upper[d] = std::max(upper[d], positions[i * dimension + d]);
      }
      if (upper[d] - lower_[d] > max_extent_over_h * support_radius)
        throw std::invalid_argument(
            fmt::format("{}: the cloud spans {} m in direction {}, more than {:g} × support_radius = {} m", caller,
                        upper[d] - lower_[d], d, max_extent_over_h, support_radius));
    }

    // Coordinates padded to 3 (z = 0 in 2D: adding 0² leaves every squared distance unchanged).
    std::vector<double> padded(node_count_ * 3, 0.0);
    for (std::size_t i = 0; i < node_count_; ++i)
      for (std::size_t d = 0; d < dimension; ++d) padded[i * 3 + d] = positions[i * dimension + d];

    double dense_cell_count = 1.0;
    for (std::size_t d = 0; d < dimension; ++d) {
      cells_per_direction_[d] = static_cast<std::int64_t>(std::floor((upper[d] - lower_[d]) / cell_size_)) + 1;
      dense_cell_count *= static_cast<double>(cells_per_direction_[d]);
    }
    is_dense_ = dense_cell_count <= dense_cells_per_node * static_cast<double>(node_count_) + 64.0;
    const std::size_t bucket_count =
        is_dense_ ? static_cast<std::size_t>(dense_cell_count) : table_size_for(node_count_);
    if (!is_dense_) hash_mask_ = bucket_count - 1;  // bucket_count is then a power of two

    std::vector<std::size_t> bucket_of(node_count_);
    bucket_start_.assign(bucket_count + 1, 0);
    for (std::size_t i = 0; i < node_count_; ++i) {
      bucket_of[i] = bucket(cell_of(&padded[i * 3]));
      ++bucket_start_[bucket_of[i] + 1];
    }
    for (std::size_t b = 0; b < bucket_count; ++b) bucket_start_[b + 1] += bucket_start_[b];
    nodes_.resize(node_count_);
    std::vector<std::size_t> fill(bucket_start_.begin(), bucket_start_.end() - 1);
    for (std::size_t i = 0; i < node_count_; ++i) nodes_[fill[bucket_of[i]]++] = i;  // stable: ascending i
    sorted_coordinates_.resize(node_count_ * 3);
    for (std::size_t slot = 0; slot < node_count_; ++slot)
      std::copy_n(&padded[nodes_[slot] * 3], 3, &sorted_coordinates_[slot * 3]);
  }

  [[nodiscard]] std::size_t node_count() const { return node_count_; }
  // The node stored at a slot. Querying slots in order keeps consecutive queries in cache.
  [[nodiscard]] std::size_t node_at(std::size_t slot) const { return nodes_[slot]; }

  // Calls visit(j, squared_distance) for every neighbour j of the node at `slot`, in no
  // particular order.
  template <class Visit>
  void for_each_neighbour(std::size_t slot, double radius_squared, Visit&& visit) const {
    scan_near(&sorted_coordinates_[slot * 3], radius_squared, slot, std::forward<Visit>(visit));
  }

  // Calls visit(j, squared_distance) for every node j closer than sqrt(radius_squared) <= the
  // cell size to the point x (three coordinates, z = 0 in 2D), in no particular order. A point
  // more than a cell outside the bounding box has no node near it (and its cell index could
  // overflow), so it is answered before any cell arithmetic.
  template <class Visit>
  void for_each_near(const double* x, double radius_squared, Visit&& visit) const {
    for (std::size_t d = 0; d < 3; ++d) {
      const double cell = std::floor((x[d] - lower_[d]) / cell_size_);
      if (!(cell >= -1.0 && cell <= static_cast<double>(cells_per_direction_[d]))) return;
    }
    scan_near(x, radius_squared, node_count_, std::forward<Visit>(visit));
  }

 private:
  // As above, leaving out the node at `skip_slot` (node_count_ skips none).
  template <class Visit>
  void scan_near(const double* x, double radius_squared, std::size_t skip_slot, Visit&& visit) const {
    std::array<SlotRange, 27> ranges{};
    const std::size_t range_count = is_dense_ ? dense_ranges(cell_of(x), ranges) : hashed_ranges(cell_of(x), ranges);
    for (std::size_t r = 0; r < range_count; ++r) {
      for (std::size_t other = ranges[r].first; other < ranges[r].last; ++other) {
        const double* y = &sorted_coordinates_[other * 3];
        const double dx = y[0] - x[0], dy = y[1] - x[1], dz = y[2] - x[2];
        const double squared = dx * dx + dy * dy + dz * dz;
        if (squared < radius_squared && other != skip_slot) visit(nodes_[other], squared);
      }
    }
  }

  [[nodiscard]] CellIndex cell_of(const double* x) const {
    CellIndex cell{0, 0, 0};
    for (std::size_t d = 0; d < 3; ++d)
      cell[d] = static_cast<std::int64_t>(std::floor((x[d] - lower_[d]) / cell_size_));
    return cell;
  }

  [[nodiscard]] std::size_t bucket(const CellIndex& cell) const {
    if (is_dense_) return linear_index(cell);
    return static_cast<std::size_t>(hash_cell(cell) & hash_mask_);
  }

  [[nodiscard]] std::size_t linear_index(const CellIndex& cell) const {
    return static_cast<std::size_t>(cell[0] + cells_per_direction_[0] * (cell[1] + cells_per_direction_[1] * cell[2]));
  }

  // Dense: each of the 3^(D−1) rows of neighbouring cells is one contiguous run.
  std::size_t dense_ranges(const CellIndex& home, std::array<SlotRange, 27>& ranges) const {
    std::size_t count = 0;
    const std::int64_t x_first = std::max<std::int64_t>(home[0] - 1, 0);
    const std::int64_t x_last = std::min<std::int64_t>(home[0] + 1, cells_per_direction_[0] - 1);
    for (std::int64_t z = home[2] - 1; z <= home[2] + 1; ++z) {
      if (z < 0 || z >= cells_per_direction_[2]) continue;
      for (std::int64_t y = home[1] - 1; y <= home[1] + 1; ++y) {
        if (y < 0 || y >= cells_per_direction_[1]) continue;
        ranges[count++] = {bucket_start_[linear_index({x_first, y, z})],
                           bucket_start_[linear_index({x_last, y, z}) + 1]};
      }
    }
    return count;
  }

  // Hashed: one run per distinct bucket of the 3^D neighbouring cells (two cells may share a
  // bucket; scanning it once keeps every neighbour from being reported twice).
  std::size_t hashed_ranges(const CellIndex& home, std::array<SlotRange, 27>& ranges) const {
    std::array<std::size_t, 27> buckets{};
    std::size_t count = 0;
    for (std::int64_t dz = -1; dz <= 1; ++dz) {
      if (cells_per_direction_[2] == 1 && dz != 0) continue;  // 2D
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dx = -1; dx <= 1; ++dx) buckets[count++] = bucket({home[0] + dx, home[1] + dy, home[2] + dz});
    }
    std::sort(buckets.begin(), buckets.begin() + static_cast<std::ptrdiff_t>(count));
    const auto end = std::unique(buckets.begin(), buckets.begin() + static_cast<std::ptrdiff_t>(count));
    std::size_t range_count = 0;
    for (auto b = buckets.begin(); b != end; ++b) ranges[range_count++] = {bucket_start_[*b], bucket_start_[*b + 1]};
    return range_count;
  }

  std::size_t node_count_;
  double cell_size_;
  std::array<double, 3> lower_{0.0, 0.0, 0.0};
  std::array<std::int64_t, 3> cells_per_direction_{1, 1, 1};
  bool is_dense_ = true;
  std::uint64_t hash_mask_ = 0;
  std::vector<std::size_t> bucket_start_;   // nodes of bucket b are at slots [bucket_start_[b], bucket_start_[b+1])
  std::vector<std::size_t> nodes_;          // node index at each slot
  std::vector<double> sorted_coordinates_;  // x, y, z of the node at each slot, at 3·slot
};

}  // namespace detail

NeighbourList find_neighbours(std::span<const double> positions, int dimension, double support_radius) {
  validate(positions, dimension, support_radius, "find_neighbours");
  NeighbourList list;
  if (positions.empty()) return list;

  const detail::CellTable table(positions, static_cast<std::size_t>(dimension), support_radius, "find_neighbours");
  const std::size_t node_count = table.node_count();
  const double radius_squared = support_radius * support_radius;

  // One scan per node: chunks of consecutive slots (bucket order) collect their nodes' sorted
  // neighbours in private buffers, then are copied into place once the offsets are known.
  // Chunks, not threads, own the buffers, so the result does not depend on the thread count.
  // A single chunk runs serially: waking a thread team costs more than a small search.
  constexpr std::size_t chunk_size = 2048;
  const std::size_t chunk_count = (node_count + chunk_size - 1) / chunk_size;
  struct ChunkResult {
    std::vector<std::size_t> indices;
    std::vector<double> distances;
  };
  std::vector<ChunkResult> chunks(chunk_count);
  list.offsets.assign(node_count + 1, 0);

#pragma omp parallel if (chunk_count > 1)
  {
    std::vector<std::pair<std::size_t, double>> found;
#pragma omp for schedule(dynamic)
    for (std::ptrdiff_t c = 0; c < static_cast<std::ptrdiff_t>(chunk_count); ++c) {
      ChunkResult& chunk = chunks[static_cast<std::size_t>(c)];
      const std::size_t first = static_cast<std::size_t>(c) * chunk_size;
      const std::size_t last = std::min(first + chunk_size, node_count);
      for (std::size_t slot = first; slot < last; ++slot) {
        const std::size_t i = table.node_at(slot);
        found.clear();
        table.for_each_neighbour(slot, radius_squared,
                                 [&](std::size_t j, double squared) { found.emplace_back(j, squared); });
        std::sort(found.begin(), found.end());
        list.offsets[i + 1] = found.size();
        for (const auto& [j, squared] : found) {
          chunk.indices.push_back(j);
          chunk.distances.push_back(std::sqrt(squared));
        }
      }
    }
  }

  for (std::size_t i = 0; i < node_count; ++i) list.offsets[i + 1] += list.offsets[i];
  list.indices.resize(list.offsets.back());
  list.distances.resize(list.offsets.back());

#pragma omp parallel for schedule(dynamic) if (chunk_count > 1)
  for (std::ptrdiff_t c = 0; c < static_cast<std::ptrdiff_t>(chunk_count); ++c) {
    ChunkResult& chunk = chunks[static_cast<std::size_t>(c)];
    const std::size_t first = static_cast<std::size_t>(c) * chunk_size;
    const std::size_t last = std::min(first + chunk_size, node_count);
    std::size_t from = 0;
    for (std::size_t slot = first; slot < last; ++slot) {
      const std::size_t i = table.node_at(slot);
      const std::size_t count = list.offsets[i + 1] - list.offsets[i];
      std::copy_n(chunk.indices.begin() + static_cast<std::ptrdiff_t>(from), count,
                  list.indices.begin() + static_cast<std::ptrdiff_t>(list.offsets[i]));
      std::copy_n(chunk.distances.begin() + static_cast<std::ptrdiff_t>(from), count,
                  list.distances.begin() + static_cast<std::ptrdiff_t>(list.offsets[i]));
      from += count;
    }
    chunk = {};  // release as we go
  }
  return list;
}

NeighbourList neighbours_within(const NeighbourList& candidates, std::span<const double> positions, int dimension,
                                double radius) {
  NeighbourList list;
  neighbours_within(candidates, positions, dimension, radius, list);
  return list;
}

void neighbours_within(const NeighbourList& candidates, std::span<const double> positions, int dimension, double radius,
                       NeighbourList& list) {
  if (&list == &candidates) throw std::invalid_argument("neighbours_within: the output is the candidate list");
  validate(positions, dimension, radius, "neighbours_within");
  const auto dim = static_cast<std::size_t>(dimension);
  const std::size_t n = candidates.node_count();
  if (positions.size() != n * dim)
    throw std::invalid_argument(
        fmt::format("neighbours_within: {} coordinates for {} candidate nodes in {}D", positions.size(), n, dimension));
  const double radius_squared = radius * radius;
  // As find_neighbours: Σ (x_j − x_i)² over three components (z = 0 in 2D adds nothing).
  const auto squared = [&](std::size_t i, std::size_t j) {
    double sum = 0;
    for (std::size_t d = 0; d < dim; ++d) {
      const double delta = positions[j * dim + d] - positions[i * dim + d];
      sum += delta * delta;
    }
    return sum;
  };
  list.offsets.resize(n + 1);  // every entry written below
  list.offsets[0] = 0;
  const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    std::size_t kept = 0;
    for (std::size_t k = candidates.offsets[i]; k < candidates.offsets[i + 1]; ++k)
      kept += squared(i, candidates.indices[k]) < radius_squared ? 1 : 0;
    list.offsets[i + 1] = kept;
  }
  for (std::size_t i = 0; i < n; ++i) list.offsets[i + 1] += list.offsets[i];
  list.indices.resize(list.offsets.back());
  list.distances.resize(list.offsets.back());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    std::size_t next = list.offsets[i];
    for (std::size_t k = candidates.offsets[i]; k < candidates.offsets[i + 1]; ++k) {
      const std::size_t j = candidates.indices[k];
      const double r2 = squared(i, j);
      if (!(r2 < radius_squared)) continue;
      list.indices[next] = j;
      list.distances[next] = std::sqrt(r2);
      ++next;
    }
  }
}

NodeLocator::NodeLocator(std::span<const double> positions, int dimension, double radius)
    : dimension_(dimension), radius_(radius) {
  validate(positions, dimension, radius, "NodeLocator");
  if (!positions.empty())
    table_ = std::make_unique<const detail::CellTable>(positions, static_cast<std::size_t>(dimension), radius,
                                                       "NodeLocator");
}

NodeLocator::~NodeLocator() = default;
NodeLocator::NodeLocator(NodeLocator&&) noexcept = default;
NodeLocator& NodeLocator::operator=(NodeLocator&&) noexcept = default;

void NodeLocator::nodes_near(std::span<const double> point, std::vector<std::size_t>& found) const {
  found.clear();
  if (point.size() != static_cast<std::size_t>(dimension_))
    throw std::invalid_argument(
        fmt::format("NodeLocator::nodes_near: the point has {} coordinates, expected {}", point.size(), dimension_));
  if (!std::ranges::all_of(point, [](double x) { return std::isfinite(x); }))
    throw std::invalid_argument("NodeLocator::nodes_near: the point has a coordinate that is not finite");
  if (!table_) return;
  std::array<double, 3> padded{0.0, 0.0, 0.0};
  std::copy(point.begin(), point.end(), padded.begin());
  table_->for_each_near(padded.data(), radius_ * radius_, [&](std::size_t j, double) { found.push_back(j); });
  std::sort(found.begin(), found.end());
}

}  // namespace rheosim::numerics
