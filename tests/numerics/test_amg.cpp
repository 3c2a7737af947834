// Smoothed-aggregation AMG as BiCGStab's preconditioner (numerics/amg.hpp): grid-independent
// iteration counts on 2D and 3D Poisson problems, a meshless (row-normalised, not symmetric)
// Laplacian on a jittered cloud against the Jacobi-preconditioned solve, reuse of a hierarchy on a changed matrix, and
// bit-identical repeated applications.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "rheosim/numerics/amg.hpp"
#include "rheosim/numerics/krylov.hpp"
#include "rheosim/numerics/neighbours.hpp"
#include "sparse_product.hpp"  // the set-up's row-parallel product

namespace rheosim::numerics {
namespace {

// A lattice of `cells` nodes per side (unit spacing) with its nearest-neighbour pattern; the
// Poisson matrix −∇²: 2·dimension on the diagonal, −1 to each lattice neighbour, Dirichlet rows
// (identity) on the boundary.
struct Problem {
  NeighbourList nb;
  StencilMatrix a;
  std::vector<double> b;
};

Problem poisson(int dimension, std::size_t cells) {
  std::vector<double> x;
  std::vector<bool> boundary;
  const std::size_t nz = dimension == 3 ? cells : 1;
  for (std::size_t k = 0; k < nz; ++k)
    for (std::size_t j = 0; j < cells; ++j)
      for (std::size_t i = 0; i < cells; ++i) {
        x.insert(x.end(), {static_cast<double>(i), static_cast<double>(j)});
        if (dimension == 3) x.push_back(static_cast<double>(k));
        const auto edge = [&](std::size_t c) { return c == 0 || c + 1 == cells; };
        boundary.push_back(edge(i) || edge(j) || (dimension == 3 && edge(k)));
      }
  Problem p{find_neighbours(x, dimension, 1.01), {}, {}};
  const std::size_t n = boundary.size();
  p.a.pattern = &p.nb;
  p.a.diagonal.assign(n, 2.0 * dimension);
  p.a.off_diagonal.assign(p.nb.pair_count(), -1.0);
  p.b.assign(n, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!boundary[i]) continue;
    p.a.diagonal[i] = 1.0;
    p.b[i] = 0.0;
    for (std::size_t k = p.nb.offsets[i]; k < p.nb.offsets[i + 1]; ++k) p.a.off_diagonal[k] = 0.0;
  }
  return p;
}

KrylovResult solve(const StencilMatrix& a, std::span<const double> b, std::vector<double>& x, AmgPreconditioner* amg,
                   double tolerance = 1e-8, int max_iterations = 5000) {
  KrylovSettings settings{tolerance, 1e-300, max_iterations, {}};
  if (amg) settings.preconditioner = amg->as_preconditioner();
  KrylovWorkspace work;
  x.assign(a.size(), 0.0);
  return bicgstab(a, b, x, settings, work);
}

void expect_grid_independent(int dimension, std::size_t small_cells, std::size_t large_cells) {
  int iterations[2] = {0, 0};
  std::size_t index = 0;
  for (std::size_t cells : {small_cells, large_cells}) {
    const Problem p = poisson(dimension, cells);
    AmgPreconditioner amg;
    amg.setup(p.a);
    EXPECT_GE(amg.levels(), 2u);
    EXPECT_LT(amg.operator_complexity(), 3.0);
    std::vector<double> x;
    const auto result = solve(p.a, p.b, x, &amg);
    ASSERT_TRUE(result.converged) << cells << " cells: " << result.relative_residual;
    iterations[index] = result.iterations;
    if (cells == large_cells) {
      // On the large grid Jacobi-preconditioned BiCGStab is not done in 4× as many iterations
      // (its count grows ∝ cells).
      const auto plain = solve(p.a, p.b, x, nullptr, 1e-8, 4 * result.iterations);
      EXPECT_FALSE(plain.converged);
    }
    ++index;
  }
  // The multigrid count stays nearly flat while the grid grows 4× (2D: 16× the nodes).
  EXPECT_LE(iterations[1], iterations[0] + 3) << iterations[0] << " → " << iterations[1];
}

TEST(Amg, TwoDimensionalPoissonIterationsDoNotGrowWithTheGrid) { expect_grid_independent(2, 40, 160); }

TEST(Amg, ThreeDimensionalPoissonIterationsDoNotGrowWithTheGrid) { expect_grid_independent(3, 12, 30); }

// A meshless Laplacian on a jittered lattice, Dirichlet rows on the boundary: each row's kernel
// weights w = (1 − r/h)³ normalised by Σ w r² / (2 d) (Brookshaw's form, exact for quadratics on
// a symmetric stencil), so rows differ and the matrix is not symmetric, as the LDD operators.
// The AMG-preconditioned solve equals the Jacobi-preconditioned one.
struct Cloud {
  std::vector<double> x;
  std::vector<bool> boundary;
};

Cloud jittered(std::size_t cells, double jitter, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> shift(-jitter, jitter);
  Cloud c;
  for (std::size_t j = 0; j < cells; ++j)
    for (std::size_t i = 0; i < cells; ++i) {
      const bool edge = i == 0 || j == 0 || i + 1 == cells || j + 1 == cells;
      c.x.push_back(static_cast<double>(i) + (edge ? 0.0 : shift(random)));
      c.x.push_back(static_cast<double>(j) + (edge ? 0.0 : shift(random)));
      c.boundary.push_back(edge);
    }
  return c;
}

Problem meshless_laplacian(const Cloud& c) {
  const double h = 1.6;
  Problem p{find_neighbours(c.x, 2, h), {}, {}};
  std::vector<double> laplacian(p.nb.pair_count());
  for (std::size_t i = 0; i < p.nb.node_count(); ++i) {
    double normalisation = 0;
    for (std::size_t k = p.nb.offsets[i]; k < p.nb.offsets[i + 1]; ++k) {
      const double r = p.nb.distances[k];
      laplacian[k] = std::pow(1.0 - r / h, 3);
      normalisation += laplacian[k] * r * r;
    }
    for (std::size_t k = p.nb.offsets[i]; k < p.nb.offsets[i + 1]; ++k) laplacian[k] *= 4.0 / normalisation;
  }
  const std::size_t n = c.boundary.size();
  p.a.pattern = &p.nb;
  p.a.diagonal.assign(n, 1.0);
  p.a.off_diagonal.assign(p.nb.pair_count(), 0.0);
  p.b.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double xi = c.x[2 * i], yi = c.x[2 * i + 1];
    if (c.boundary[i]) {
      p.b[i] = std::sin(0.1 * xi) + 0.05 * yi;
      continue;
    }
    double sum = 0;
    for (std::size_t k = p.nb.offsets[i]; k < p.nb.offsets[i + 1]; ++k) {
      p.a.off_diagonal[k] = laplacian[k];
      sum += laplacian[k];
    }
    p.a.diagonal[i] = -sum;
    p.b[i] = std::cos(0.2 * xi) * std::sin(0.15 * yi);
  }
  return p;
}

TEST(Amg, MeshlessLaplacianOnAJitteredCloudMatchesTheJacobiSolve) {
  const Problem p = meshless_laplacian(jittered(66, 0.2, 7));  // 4 356 nodes: the parallel smoother path
  AmgPreconditioner amg;
  amg.setup(p.a);
  std::vector<double> with_amg, with_jacobi;
  const auto r1 = solve(p.a, p.b, with_amg, &amg, 1e-10);
  const auto r2 = solve(p.a, p.b, with_jacobi, nullptr, 1e-10);
  ASSERT_TRUE(r1.converged) << r1.relative_residual;
  ASSERT_TRUE(r2.converged) << r2.relative_residual;
  EXPECT_LT(r1.iterations * 4, r2.iterations) << r1.iterations << " vs " << r2.iterations;
  double largest = 0, difference = 0;
  for (std::size_t i = 0; i < with_amg.size(); ++i) {
    largest = std::max(largest, std::abs(with_jacobi[i]));
    difference = std::max(difference, std::abs(with_amg[i] - with_jacobi[i]));
  }
  EXPECT_LT(difference, 1e-6 * largest) << difference << " of " << largest;
}

// A jittered(cells, ...) cloud one Lagrangian step later: every interior node moved by up to
// ±0.05 Δ more.
Cloud moved_on(Cloud c, std::size_t cells) {
  const Cloud nudge = jittered(cells, 0.05, 11);
  for (std::size_t i = 0; i < c.x.size(); ++i) c.x[i] += nudge.x[i] - std::round(nudge.x[i]);
  return c;
}

// The meshless Laplacians of a 60² jittered cloud and of the same cloud one step later.
struct CloudStep {
  Problem before = meshless_laplacian(jittered(60, 0.2, 3));
  Problem after = meshless_laplacian(moved_on(jittered(60, 0.2, 3), 60));
};

// A hierarchy built on one cloud still preconditions the matrix of the cloud moved a little
// (what the free-surface solver relies on between set-ups), and prepare() rebuilds when due.
TEST(Amg, ReusedHierarchyPreconditionsAMovedCloud) {
  const CloudStep cloud;
  const Problem& before = cloud.before;
  const Problem& after = cloud.after;

  AmgSettings settings;
  settings.reuse_steps = 2;
  AmgPreconditioner amg(settings);
  EXPECT_TRUE(amg.prepare(before.a));
  std::vector<double> x;
  const auto fresh = solve(before.a, before.b, x, &amg);
  amg.record_iterations(fresh.iterations);
  EXPECT_FALSE(amg.prepare(after.a));  // reused: the finest level is the new matrix
  const auto reused = solve(after.a, after.b, x, &amg);
  ASSERT_TRUE(reused.converged) << reused.relative_residual;
  EXPECT_LE(reused.iterations, 2 * fresh.iterations + 2) << fresh.iterations << " → " << reused.iterations;
  amg.record_iterations(reused.iterations);
  EXPECT_TRUE(amg.prepare(after.a));  // reuse_steps reached
  EXPECT_EQ(amg.setups(), 2u);
}

TEST(Amg, RepeatedApplicationsAreBitIdentical) {
  const Problem p = meshless_laplacian(jittered(70, 0.2, 5));
  AmgPreconditioner amg;
  amg.setup(p.a);
  std::vector<double> z1(p.b.size()), z2(p.b.size());
  amg.apply(p.b, z1);
  amg.apply(p.b, z2);
  EXPECT_EQ(z1, z2);
  double norm = 0;
  for (double v : z1) norm += v * v;
  EXPECT_GT(norm, 0.0);
}

// A kept hierarchy survives state() → restore() into a fresh preconditioner (a checkpoint): on
// the moved cloud the restored one, reusing its coarse levels like the original, preconditions
// bit for bit the same, and its reuse counters carry on (the next prepare() is a set-up in both).
TEST(Amg, RestoredStateRebuildsTheKeptHierarchy) {
  const CloudStep cloud;
  const Problem& before = cloud.before;
  const Problem& after = cloud.after;
  AmgSettings settings;
  settings.reuse_steps = 3;
  AmgPreconditioner original(settings);
  EXPECT_TRUE(original.prepare(before.a));
  original.record_iterations(7);
  const AmgState state = original.state();
  ASSERT_FALSE(state.empty());
  AmgPreconditioner restored(settings);
  restored.restore(state);
  EXPECT_FALSE(original.prepare(after.a));
  EXPECT_FALSE(restored.prepare(after.a));  // reused, as the original
  std::vector<double> z1(after.b.size()), z2(after.b.size());
  original.apply(after.b, z1);
  restored.apply(after.b, z2);
  EXPECT_EQ(z1, z2);
  EXPECT_FALSE(original.prepare(after.a));
  EXPECT_FALSE(restored.prepare(after.a));
  EXPECT_TRUE(original.prepare(after.a));  // reuse_steps reached in both
  EXPECT_TRUE(restored.prepare(after.a));
  // Nothing kept when every call is a set-up.
  AmgPreconditioner fresh;  // reuse_steps 50 by default: keeps
  AmgSettings every_step;
  every_step.reuse_steps = 1;
  AmgPreconditioner no_reuse(every_step);
  no_reuse.setup(before.a);
  EXPECT_TRUE(no_reuse.state().empty());
  EXPECT_TRUE(fresh.state().empty());  // nothing set up yet
}

// use_plain_aggregation() makes the next prepare() a set-up with plain aggregation (the hierarchy
// of a fresh plain preconditioner, bit for bit), and the choice travels with state().
TEST(Amg, PlainAggregationFromTheNextSetUpTravelsWithTheState) {
  const CloudStep cloud;
  AmgSettings settings;
  settings.reuse_steps = 3;
  AmgPreconditioner switched(settings);
  EXPECT_TRUE(switched.prepare(cloud.before.a));
  EXPECT_TRUE(switched.smoothed());
  EXPECT_TRUE(switched.state().smoothed.value_or(false));
  switched.use_plain_aggregation();
  EXPECT_FALSE(switched.smoothed());
  EXPECT_TRUE(switched.prepare(cloud.after.a));  // due at once, not after reuse_steps
  AmgSettings plain_settings = settings;
  plain_settings.smoothed = false;
  AmgPreconditioner plain(plain_settings);
  plain.setup(cloud.after.a);
  std::vector<double> z_switched(cloud.after.b.size()), z_plain(cloud.after.b.size()), z_smoothed(cloud.after.b.size());
  switched.apply(cloud.after.b, z_switched);
  plain.apply(cloud.after.b, z_plain);
  EXPECT_EQ(z_switched, z_plain);
  AmgPreconditioner smoothed(settings);
  smoothed.setup(cloud.after.a);
  smoothed.apply(cloud.after.b, z_smoothed);
  EXPECT_NE(z_switched, z_smoothed);  // the two aggregations differ on this matrix
  const AmgState state = switched.state();
  ASSERT_TRUE(state.smoothed.has_value());
  EXPECT_FALSE(*state.smoothed);
  AmgPreconditioner restored(settings);  // configured smoothed, restored plain
  restored.restore(state);
  EXPECT_FALSE(restored.smoothed());
  std::vector<double> z_restored(cloud.after.b.size());
  restored.apply(cloud.after.b, z_restored);
  EXPECT_EQ(z_restored, z_plain);
}

// Strong connections are symmetrised whether or not the pattern is: a matrix whose zero entries
// (i, i+1) are explicit (structurally symmetric: the parallel reverse-entry lookup) and the same
// matrix with those entries left out (a strong (i+1, i) without its reverse: the serial scatter)
// must give the same hierarchy, so the same preconditioned solve bit for bit. 6 400 rows: the
// set-up's parallel loops run.
TEST(Amg, OneSidedPatternGivesTheSameHierarchyAsItsSymmetricCompletion) {
  Problem full = poisson(2, 80);
  const std::size_t n = full.b.size();
  const auto dropped = [&](std::size_t i, std::size_t j) { return j == i + 1 && i % 3 == 0; };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = full.nb.offsets[i]; k < full.nb.offsets[i + 1]; ++k)
      if (dropped(i, full.nb.indices[k])) full.a.off_diagonal[k] = 0.0;
  NeighbourList one_sided;
  StencilMatrix a{&one_sided, full.a.diagonal, {}};
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = full.nb.offsets[i]; k < full.nb.offsets[i + 1]; ++k) {
      if (dropped(i, full.nb.indices[k])) continue;
      one_sided.indices.push_back(full.nb.indices[k]);
      one_sided.distances.push_back(full.nb.distances[k]);
      a.off_diagonal.push_back(full.a.off_diagonal[k]);
    }
    one_sided.offsets.push_back(one_sided.indices.size());
  }
  ASSERT_LT(one_sided.pair_count(), full.nb.pair_count());
  omp_set_num_threads(2);
  AmgPreconditioner symmetric_pattern, one_sided_pattern;
  symmetric_pattern.setup(full.a);
  one_sided_pattern.setup(a);
  EXPECT_EQ(symmetric_pattern.levels(), one_sided_pattern.levels());
  EXPECT_GE(symmetric_pattern.levels(), 2U);
  for (std::size_t l = 0; l < symmetric_pattern.levels(); ++l)
    EXPECT_EQ(symmetric_pattern.rows(l), one_sided_pattern.rows(l)) << "level " << l;
  // Coarse nonzeros alike (the complexity's denominator counts the explicit zeros).
  const auto coarse_nonzeros = [&](const AmgPreconditioner& amg, const NeighbourList& pattern) {
    return (amg.operator_complexity() - 1.0) * static_cast<double>(n + pattern.pair_count());
  };
  EXPECT_NEAR(coarse_nonzeros(symmetric_pattern, full.nb), coarse_nonzeros(one_sided_pattern, one_sided), 1e-6);
  std::vector<double> x1, x2;
  const auto r1 = solve(full.a, full.b, x1, &symmetric_pattern);
  const auto r2 = solve(a, full.b, x2, &one_sided_pattern);
  omp_set_num_threads(1);
  ASSERT_TRUE(r1.converged);
  EXPECT_EQ(r1.iterations, r2.iterations);
  EXPECT_EQ(x1, x2);
}

// The set-up's row-parallel product (Galerkin operator, prolongator): a random sparse B and
// random terms against the dense sum, and bit for bit the same on 1 and 3 blocks.
TEST(SparseProduct, CombinedRowsMatchTheDenseSumOnAnyBlockCount) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::uniform_int_distribution<std::size_t> column(0, 39);
  detail::CompressedRows b;
  b.column_count = 40;
  for (std::size_t r = 0; r < 50; ++r) {
    std::vector<std::size_t> columns;
    for (int e = 0; e < 4; ++e) columns.push_back(column(random));
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    for (std::size_t c : columns) {
      b.columns.push_back(c);
      b.values.push_back(value(random));
    }
    b.offsets.push_back(b.columns.size());
  }
  std::vector<std::vector<std::pair<double, std::size_t>>> terms(30);
  std::uniform_int_distribution<std::size_t> row(0, 49);
  for (auto& t : terms)
    for (int e = 0; e < 5; ++e) t.emplace_back(value(random), row(random));
  const auto product = [&](int blocks) {
    return detail::combine_rows(terms.size(), b, blocks, [&](std::size_t i, auto&& emit) {
      for (const auto& [coefficient, r] : terms[i]) emit(coefficient, r);
    });
  };
  omp_set_num_threads(3);
  const detail::CompressedRows one = product(1), three = product(3);
  omp_set_num_threads(1);
  EXPECT_EQ(one.offsets, three.offsets);
  EXPECT_EQ(one.columns, three.columns);
  EXPECT_EQ(one.values, three.values);
  for (std::size_t i = 0; i < terms.size(); ++i) {
    std::vector<double> dense(40, 0.0);
    std::vector<bool> present(40, false);
    for (const auto& [coefficient, r] : terms[i])
      for (std::size_t k = b.offsets[r]; k < b.offsets[r + 1]; ++k) {
        dense[b.columns[k]] += coefficient * b.values[k];
        present[b.columns[k]] = true;
      }
    std::size_t expected_entries = 0;
    for (std::size_t c = 0; c < 40; ++c) expected_entries += present[c] ? 1 : 0;
    ASSERT_EQ(one.offsets[i + 1] - one.offsets[i], expected_entries) << "row " << i;
    for (std::size_t k = one.offsets[i]; k < one.offsets[i + 1]; ++k) {
      if (k > one.offsets[i]) {
        EXPECT_LT(one.columns[k - 1], one.columns[k]);  // ascending
      }
      EXPECT_NEAR(one.values[k], dense[one.columns[k]], 1e-14) << "row " << i << " column " << one.columns[k];
    }
  }
}

TEST(Amg, RejectsBadSettings) {
  AmgSettings s;
  s.pre_sweeps = 0;
  s.post_sweeps = 0;
  EXPECT_THROW(AmgPreconditioner{s}, std::invalid_argument);
  AmgSettings t;
  t.reuse_growth = 0.5;
  EXPECT_THROW(AmgPreconditioner{t}, std::invalid_argument);
}

}  // namespace
}  // namespace rheosim::numerics
