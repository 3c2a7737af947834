// Cell-list neighbour search: identical to brute force (same criterion d² < h², same
// arithmetic) on random and lattice clouds in 2D and 3D, including nodes exactly at distance h,
// plus the degenerate clouds: empty, single node, far apart, coincident.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rheosim/numerics/neighbours.hpp"

namespace rheosim::numerics {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

// O(N²) reference with the documented criterion, evaluated in the same order as the search.
NeighbourList brute_force(const std::vector<double>& positions, int dimension, double h) {
  const auto dim = static_cast<std::size_t>(dimension);
  const std::size_t n = positions.size() / dim;
  NeighbourList list;
  list.offsets.assign(1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      double squared = 0.0;
      for (std::size_t d = 0; d < dim; ++d) {
        const double delta = positions[j * dim + d] - positions[i * dim + d];
        squared += delta * delta;
      }
      if (squared < h * h) {
        list.indices.push_back(j);
        list.distances.push_back(std::sqrt(squared));
      }
    }
    list.offsets.push_back(list.indices.size());
  }
  return list;
}

void expect_same(const NeighbourList& actual, const NeighbourList& expected) {
  ASSERT_EQ(actual.offsets, expected.offsets);
  EXPECT_EQ(actual.indices, expected.indices);
  EXPECT_EQ(actual.distances, expected.distances);  // bitwise: same arithmetic
}

std::vector<double> random_cloud(std::size_t nodes, int dimension, double box, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coordinate(-0.3 * box, 0.7 * box);
  std::vector<double> positions(nodes * static_cast<std::size_t>(dimension));
  for (double& x : positions) x = coordinate(rng);
  return positions;
}

TEST(Neighbours, MatchesBruteForceOnRandom2DClouds) {
  // Sizes above 2048 nodes run the parallel path (several chunks).
  for (const auto& [nodes, seed] : {std::pair{1500u, 1u}, std::pair{3000u, 2u}, std::pair{6000u, 3u}}) {
    const auto positions = random_cloud(nodes, 2, 1.0, seed);
    const double h = 3.2 / std::sqrt(double(nodes));  // h/Δ = 3.2: ~30 neighbours
    const NeighbourList list = find_neighbours(positions, 2, h);
    expect_same(list, brute_force(positions, 2, h));
    EXPECT_GT(list.pair_count(), nodes * 10u);
  }
}

TEST(Neighbours, MatchesBruteForceOnRandom3DClouds) {
  for (const unsigned seed : {4u, 5u}) {
    const auto positions = random_cloud(2000, 3, 2.0e-3, seed);
    const double h = 1.6 * 2.0e-3 / std::cbrt(2000.0);
    const NeighbourList list = find_neighbours(positions, 3, h);
    expect_same(list, brute_force(positions, 3, h));
    EXPECT_GT(list.pair_count(), 2000u * 5u);
  }
}

// On a lattice of spacing 0.25 with h = 0.5 every pair at exactly h is representable, so the
// boundary case "distance == h is not a neighbour" is exercised on thousands of pairs.
// A Verlet list: candidates searched with a larger radius, then every node moved by less than
// half the skin; the pairs now within h are exactly what a fresh search finds, bit for bit.
TEST(Neighbours, FilteredCandidatesEqualAFreshSearchAfterSmallMoves) {
  for (int dimension : {2, 3}) {
    const double h = 1.0, skin = 0.4;
    std::vector<double> positions = random_cloud(dimension == 2 ? 3000 : 4000, dimension, 12.0, 7);
    const NeighbourList candidates = find_neighbours(positions, dimension, h + skin);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> step(-0.45 * skin / 2 / std::sqrt(3.0), 0.45 * skin / 2 / std::sqrt(3.0));
    for (double& x : positions) x += step(rng);
    expect_same(neighbours_within(candidates, positions, dimension, h), find_neighbours(positions, dimension, h));
  }
  // Into a used list (a solver's previous step), and never into the candidates themselves.
  std::vector<double> positions = random_cloud(2000, 3, 10.0, 5);
  NeighbourList candidates = find_neighbours(positions, 3, 1.4);
  NeighbourList used = find_neighbours(random_cloud(2500, 3, 10.0, 6), 3, 1.2);
  neighbours_within(candidates, positions, 3, 1.0, used);
  expect_same(used, find_neighbours(positions, 3, 1.0));
  EXPECT_THROW(neighbours_within(candidates, positions, 3, 1.0, candidates), std::invalid_argument);
  EXPECT_THROW((void)neighbours_within(candidates, std::vector<double>{0, 0, 1, 0, 2, 0}, 2, 1.0),
               std::invalid_argument);
}

TEST(Neighbours, LatticeNodesExactlyAtDistanceHAreExcluded) {
  for (const int dimension : {2, 3}) {
    const int side = dimension == 2 ? 20 : 9;
    std::vector<double> positions;
    for (int a = 0; a < side; ++a)
      for (int b = 0; b < side; ++b)
        for (int c = 0; c < (dimension == 3 ? side : 1); ++c) {
          positions.push_back(0.25 * a - 1.0);
          positions.push_back(0.25 * b);
          if (dimension == 3) positions.push_back(0.25 * c);
        }
    const NeighbourList list = find_neighbours(positions, dimension, 0.5);
    expect_same(list, brute_force(positions, dimension, 0.5));
    for (const double distance : list.distances) EXPECT_LT(distance, 0.5);
    // An interior node of the 2D lattice: 4 at 0.25, 4 at 0.354 (0.5 excluded); in 3D 6 + 12 + 8.
    const std::size_t interior = dimension == 2 ? 10 * side + 10 : (4 * side + 4) * side + 4;
    EXPECT_EQ(list.neighbours_of(interior).size(), dimension == 2 ? 8u : 26u) << dimension;
  }
}

TEST(Neighbours, TwoNodesAtExactlyHAndJustInside) {
  const std::vector<double> at_h{0.0, 0.0, 0.5, 0.0};
  EXPECT_EQ(find_neighbours(at_h, 2, 0.5).pair_count(), 0u);
  const NeighbourList inside = find_neighbours(at_h, 2, std::nextafter(0.5, 1.0));
  EXPECT_THAT(inside.neighbours_of(0), ElementsAre(1u));
  EXPECT_THAT(inside.neighbours_of(1), ElementsAre(0u));
  EXPECT_THAT(inside.distances_of(0), ElementsAre(0.5));
}

TEST(Neighbours, EmptyCloud) {
  const NeighbourList list = find_neighbours({}, 3, 1.0);
  EXPECT_EQ(list.node_count(), 0u);
  EXPECT_EQ(list.pair_count(), 0u);
  EXPECT_THAT(list.offsets, ElementsAre(0u));
}

TEST(Neighbours, SingleNodeHasNoNeighbours) {
  const std::vector<double> one{0.1, -0.2, 0.3};
  const NeighbourList list = find_neighbours(one, 3, 1.0);
  EXPECT_EQ(list.node_count(), 1u);
  EXPECT_TRUE(list.neighbours_of(0).empty());
}

TEST(Neighbours, NodesFarApart) {
  // Two close pairs a kilometre apart with h = 1 mm: 1e6 cells per direction, O(N) memory.
  const std::vector<double> positions{0.0,    0.0,    0.0,     0.0005, 0.0,    0.0,
                                      1000.0, 1000.0, -1000.0, 1000.0, 1000.0, -999.9995};
  const NeighbourList list = find_neighbours(positions, 3, 1e-3);
  EXPECT_THAT(list.neighbours_of(0), ElementsAre(1u));
  EXPECT_THAT(list.neighbours_of(1), ElementsAre(0u));
  EXPECT_THAT(list.neighbours_of(2), ElementsAre(3u));
  EXPECT_THAT(list.neighbours_of(3), ElementsAre(2u));
  expect_same(list, brute_force(positions, 3, 1e-3));
}

TEST(Neighbours, DenseClusterWithAFarOutlierMatchesBruteForce) {
  auto positions = random_cloud(800, 2, 1e-2, 9);
  positions.insert(positions.end(), {5e3, -7e3});
  const double h = 1.5e-3;
  expect_same(find_neighbours(positions, 2, h), brute_force(positions, 2, h));
}

// Clusters spread over a box ~1e3 h wide: far more bounding-box cells than nodes, so the
// search hashes its cells instead of storing them densely. Both layouts must agree with brute force.
TEST(Neighbours, MatchesBruteForceOnSparseClusteredClouds) {
  for (const int dimension : {2, 3}) {
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> centre(0.0, 3.0);
    std::normal_distribution<double> offset(0.0, 0.004);
    std::vector<double> positions;
    for (int cluster = 0; cluster < 15; ++cluster) {
      std::vector<double> c(static_cast<std::size_t>(dimension));
      for (double& x : c) x = centre(rng);
      for (int node = 0; node < 60; ++node)
        for (const double x : c) positions.push_back(x + offset(rng));
    }
    const double h = 0.003;
    const NeighbourList list = find_neighbours(positions, dimension, h);
    expect_same(list, brute_force(positions, dimension, h));
    EXPECT_GT(list.pair_count(), 900u) << dimension;
  }
}

TEST(Neighbours, CoincidentNodesAreNeighboursAtDistanceZero) {
  const std::vector<double> positions{1.0, 2.0, 1.0, 2.0, 3.0, 3.0};
  const NeighbourList list = find_neighbours(positions, 2, 0.1);
  EXPECT_THAT(list.neighbours_of(0), ElementsAre(1u));
  EXPECT_THAT(list.distances_of(0), ElementsAre(0.0));
  EXPECT_TRUE(list.neighbours_of(2).empty());
}

TEST(Neighbours, ListIsSymmetricSortedAndRepeatable) {
  const auto positions = random_cloud(1000, 3, 1.0, 11);
  const NeighbourList list = find_neighbours(positions, 3, 0.15);
  for (std::size_t i = 0; i < list.node_count(); ++i) {
    const auto neighbours = list.neighbours_of(i);
    EXPECT_TRUE(std::is_sorted(neighbours.begin(), neighbours.end()));
    for (const std::size_t j : neighbours) {
      const auto back = list.neighbours_of(j);
      EXPECT_TRUE(std::binary_search(back.begin(), back.end(), i)) << i << " -> " << j;
    }
  }
  expect_same(find_neighbours(positions, 3, 0.15), list);
}

TEST(Neighbours, InvalidInputIsRejected) {
  const std::vector<double> xy{0.0, 0.0, 1.0, 1.0};
  const auto message = [](auto&& call) -> std::string {
    try {
      call();
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no exception";
  };
  EXPECT_THAT(message([&] { (void)find_neighbours(xy, 4, 1.0); }), HasSubstr("dimension"));
  EXPECT_THAT(message([&] { (void)find_neighbours(xy, 2, 0.0); }), HasSubstr("support_radius"));
  EXPECT_THAT(message([&] { (void)find_neighbours(xy, 3, 1.0); }), HasSubstr("multiple of dimension"));
  const std::vector<double> nan_cloud{0.0, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_THAT(message([&] { (void)find_neighbours(nan_cloud, 2, 1.0); }), HasSubstr("node 0"));
  const std::vector<double> huge{0.0, 0.0, 1e12, 0.0};
  EXPECT_THAT(message([&] { (void)find_neighbours(huge, 2, 1.0); }), HasSubstr("support_radius"));
}

// Brute force for a query point: the nodes j with Σ (x_j − p)² < r², ascending.
std::vector<std::size_t> brute_force_near(const std::vector<double>& positions, int dimension, double radius,
                                          const std::vector<double>& point) {
  const auto dim = static_cast<std::size_t>(dimension);
  std::vector<std::size_t> near;
  for (std::size_t j = 0; j < positions.size() / dim; ++j) {
    double squared = 0.0;
    for (std::size_t d = 0; d < dim; ++d) {
      const double delta = positions[j * dim + d] - point[d];
      squared += delta * delta;
    }
    if (squared < radius * radius) near.push_back(j);
  }
  return near;
}

// Points inside the cloud, at its edges and beyond them (up to 1.5 radii outside the bounding
// box, where the cell index is −1 or one past the last cell), in the dense and the hashed layout.
TEST(NodeLocator, MatchesBruteForceAtPointsInsideAndAroundTheCloud) {
  for (const int dimension : {2, 3}) {
    for (const bool sparse : {false, true}) {
      std::vector<double> positions = random_cloud(1500, dimension, 1.0, 21 + (sparse ? 1u : 0u));
      const double radius = sparse ? 0.004 : 0.09;  // sparse: far more cells than nodes, so hashed
      const NodeLocator locator(positions, dimension, radius);
      std::mt19937_64 rng(7);
      std::uniform_real_distribution<double> coordinate(-0.3 - 1.5 * radius, 0.7 + 1.5 * radius);
      std::vector<std::size_t> found;
      std::size_t total = 0;
      for (int query = 0; query < 400; ++query) {
        std::vector<double> point(static_cast<std::size_t>(dimension));
        for (double& x : point) x = coordinate(rng);
        if (query % 4 == 0)
          point = {positions.begin() + query * dimension, positions.begin() + (query + 1) * dimension};
        locator.nodes_near(point, found);
        EXPECT_EQ(found, brute_force_near(positions, dimension, radius, point)) << dimension << " " << query;
        total += found.size();
      }
      EXPECT_GE(total, 100u) << "the 100 queries at nodes find at least the node itself";
    }
  }
}

TEST(NodeLocator, FarPointsEmptyCloudsAndBadPoints) {
  const std::vector<double> xy{0.0, 0.0, 0.5, 0.0};
  const NodeLocator locator(xy, 2, 0.6);
  std::vector<std::size_t> found{99};
  locator.nodes_near(std::vector<double>{0.25, 0.0}, found);
  EXPECT_THAT(found, ElementsAre(0u, 1u));
  locator.nodes_near(std::vector<double>{0.5, 0.6}, found);  // exactly at the radius from node 1
  EXPECT_TRUE(found.empty());
  locator.nodes_near(std::vector<double>{1e300, -1e300}, found);  // its cell index would overflow
  EXPECT_TRUE(found.empty());
  const NodeLocator empty(std::vector<double>{}, 3, 1.0);
  empty.nodes_near(std::vector<double>{0.0, 0.0, 0.0}, found);
  EXPECT_TRUE(found.empty());
  EXPECT_THROW(locator.nodes_near(std::vector<double>{0.0, 0.0, 0.0}, found), std::invalid_argument);
  EXPECT_THROW(locator.nodes_near(std::vector<double>{0.0, std::numeric_limits<double>::infinity()}, found),
               std::invalid_argument);
  EXPECT_THROW(NodeLocator(xy, 2, -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace rheosim::numerics
