// Matrix-free BiCGStab (numerics/krylov.hpp): a non-symmetric stencil system, the shadow-residual
// restart (a right-hand side that lives on Dirichlet rows only broke down without it), a custom
// preconditioner, and deterministic dot products.
#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <vector>

#include "blocks.hpp"  // the work split the Krylov and AMG loops share
#include "rheosim/numerics/krylov.hpp"
#include "rheosim/numerics/neighbours.hpp"
#include "rheosim/numerics/row_blocks.hpp"

namespace rheosim::numerics {
namespace {

// A 1D chain of n nodes with neighbours i ± 1: convection–diffusion rows (non-symmetric), the
// two end rows Dirichlet.
struct Chain {
  NeighbourList nb;
  StencilMatrix a;
};

Chain chain(std::size_t n) {
  std::vector<double> x;
  for (std::size_t i = 0; i < n; ++i) x.insert(x.end(), {static_cast<double>(i), 0.0});
  Chain c{find_neighbours(x, 2, 1.5), {}};
  c.a.pattern = &c.nb;
  c.a.diagonal.assign(n, 2.0);
  c.a.off_diagonal.assign(c.nb.pair_count(), 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = c.nb.offsets[i]; k < c.nb.offsets[i + 1]; ++k)
      c.a.off_diagonal[k] = (i == 0 || i + 1 == n) ? 0.0 : (c.nb.indices[k] < i ? -1.3 : -0.7);
  c.a.diagonal.front() = c.a.diagonal.back() = 1.0;
  return c;
}

TEST(FloatingGroups, FindsTheBlocksThatNoDirichletRowReaches) {
  Chain c = chain(10);  // rows 0 and 9 Dirichlet: everything anchored
  EXPECT_EQ(floating_groups(c.a).groups, 0u);
  // Cut 4–5 in both rows and couple row 9: nodes 5–9 form a Neumann block.
  for (std::size_t i = 0; i < 10; ++i)
    for (std::size_t k = c.nb.offsets[i]; k < c.nb.offsets[i + 1]; ++k) {
      const std::size_t j = c.nb.indices[k];
      if ((i == 4 && j == 5) || (i == 5 && j == 4)) c.a.off_diagonal[k] = 0.0;
      if (i == 9) c.a.off_diagonal[k] = -1.0;
    }
  const FloatingGroups f = floating_groups(c.a);
  EXPECT_EQ(f.groups, 1u);
  EXPECT_EQ(f.nodes, 5u);
  EXPECT_EQ(f.largest, 5u);
  EXPECT_GE(f.largest_member, 5u);
  // A coupling in one direction is enough to anchor: row 5 reads node 4 again.
  for (std::size_t k = c.nb.offsets[5]; k < c.nb.offsets[6]; ++k)
    if (c.nb.indices[k] == 4) c.a.off_diagonal[k] = -0.5;
  EXPECT_EQ(floating_groups(c.a).groups, 0u);
}

TEST(BiCGStab, SolvesNonSymmetricSystemWithDirichletOnlyRightHandSide) {
  const std::size_t n = 200;
  const Chain c = chain(n);
  std::vector<double> b(n, 0.0), x(n, 0.0), check(n);
  b.front() = 1.0;  // only a boundary value: r̂·r vanishes after one step without the restart
  b.back() = 2.0;
  KrylovWorkspace work;
  const auto result = bicgstab(c.a, b, x, KrylovSettings{1e-12, 1e-300, 1000, {}}, work);
  ASSERT_TRUE(result.converged) << result.relative_residual;
  c.a.multiply(x, check);
  for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(check[i], b[i], 1e-9);
}

TEST(BiCGStab, AcceptsAPreconditioner) {
  const Chain c = chain(50);
  std::vector<double> b(50, 1.0), x(50, 0.0);
  int calls = 0;
  KrylovSettings settings{1e-10, 1e-300, 500, {}};
  settings.preconditioner = [&](std::span<const double> r, std::span<double> z) {
    ++calls;
    for (std::size_t i = 0; i < r.size(); ++i) z[i] = r[i] / c.a.diagonal[i];
  };
  KrylovWorkspace work;
  EXPECT_TRUE(bicgstab(c.a, b, x, settings, work).converged);
  EXPECT_GT(calls, 0);
}

// The fused two-component solve runs each component's BiCGStab arithmetic unchanged, so it must
// match two separate Jacobi solves bit for bit, including a component that needs the restart
// and one that converges first.
TEST(BiCGStabPair, IsBitIdenticalToTwoSeparateJacobiSolves) {
  const std::size_t n = 200;
  const Chain c = chain(n);
  std::vector<double> b(2 * n, 0.0), x(2 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    b[2 * i] = 0.0;                                          // x component: Dirichlet values only
    b[2 * i + 1] = std::sin(0.05 * static_cast<double>(i));  // y component: smooth interior source
    x[2 * i + 1] = 0.1;                                      // a warm start for y
  }
  b[0] = 1.0;
  b[2 * (n - 1)] = 2.0;
  const KrylovSettings settings{1e-10, 1e-300, 1000, {}};
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    std::vector<double> pair = x;
    PairKrylovWorkspace pair_work;
    const auto results = bicgstab_jacobi_pair(c.a, b, pair, settings, pair_work);
    for (std::size_t d = 0; d < 2; ++d) {
      std::vector<double> bd(n), xd(n);
      for (std::size_t i = 0; i < n; ++i) {
        bd[i] = b[2 * i + d];
        xd[i] = x[2 * i + d];
      }
      KrylovWorkspace work;
      const auto single = bicgstab(c.a, bd, xd, settings, work);
      EXPECT_TRUE(results[d].converged);
      EXPECT_EQ(results[d].iterations, single.iterations);
      EXPECT_EQ(results[d].residual, single.residual);
      for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(pair[2 * i + d], xd[i]) << "component " << d << " node " << i;
    }
  }
  omp_set_num_threads(1);
}

TEST(ParallelDot, IsIdenticalAcrossRepeatsForAThreadCount) {
  std::vector<double> a(100003), b(100003);
  for (std::size_t i = 0; i < a.size(); ++i) {
    a[i] = std::sin(0.1 * static_cast<double>(i));
    b[i] = 1.0 / (1.0 + static_cast<double>(i));
  }
  omp_set_num_threads(2);
  const double first = parallel_dot(a, b);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(parallel_dot(a, b), first);
  omp_set_num_threads(1);
  EXPECT_NEAR(parallel_dot(a, b), first, 1e-12);
}

// A slump-like pattern: 35 000 short wall rows (8 entries) first, then 50 000 fluid rows (26).
// An even split by rows gave the second of two threads 70 % of the entries.
TEST(BalancedBlocks, SplitRowsByTheirEntriesAndCoverEveryRowOnce) {
  std::vector<std::size_t> offsets{0};
  for (std::size_t i = 0; i < 85000; ++i) offsets.push_back(offsets.back() + (i < 35000 ? 8 : 26));
  const auto work = [&](std::size_t begin, std::size_t end) {
    return static_cast<double>(end - begin + offsets[end] - offsets[begin]);
  };
  const double total = work(0, 85000);
  for (int blocks : {1, 2, 3, 7}) {
    std::size_t expected_begin = 0;
    for (int t = 0; t < blocks; ++t) {
      const auto [begin, end] = balanced_block_range<std::size_t>(offsets, t, blocks);
      EXPECT_EQ(begin, expected_begin) << blocks << " blocks, block " << t;
      expected_begin = end;
      // Within one row's work (27) of an even share.
      EXPECT_NEAR(work(begin, end), total / blocks, 27.0) << blocks << " blocks, block " << t;
    }
    EXPECT_EQ(expected_begin, 85000U) << blocks << " blocks";
  }
  // No rows, more blocks than rows: empty or single-row blocks, still covering all.
  const std::vector<std::size_t> empty{0};
  EXPECT_EQ(balanced_block_range<std::size_t>(empty, 0, 2), std::make_pair(std::size_t{0}, std::size_t{0}));
  const std::vector<std::size_t> two_rows{0, 3, 3};
  EXPECT_EQ(balanced_block_range<std::size_t>(two_rows, 0, 4).first, 0U);
  EXPECT_EQ(balanced_block_range<std::size_t>(two_rows, 3, 4).second, 2U);
}

// for_balanced_rows visits every row once, on two threads, each thread within its own block.
TEST(BalancedBlocks, ForBalancedRowsVisitsEveryRowOnceInItsThreadsBlock) {
  std::vector<std::size_t> offsets{0};
  for (std::size_t i = 0; i < 10000; ++i) offsets.push_back(offsets.back() + (i < 4000 ? 8 : 26));
  std::vector<int> visits(10000, 0), thread_of(10000, -1);
  omp_set_num_threads(2);
  for_balanced_rows(offsets, [&](std::size_t i) {
    ++visits[i];
    thread_of[i] = omp_get_thread_num();
  });
  omp_set_num_threads(1);
  for (std::size_t i = 0; i < visits.size(); ++i) ASSERT_EQ(visits[i], 1) << "row " << i;
  // The split is the balanced one, not an even split by rows (which would end at row 5000).
  const auto [begin, end] = balanced_block_range<std::size_t>(offsets, 0, 2);
  EXPECT_EQ(begin, 0U);
  EXPECT_GT(end, 5000U);
  for (std::size_t i = 0; i < visits.size(); ++i) EXPECT_EQ(thread_of[i], i < end ? 0 : 1) << "row " << i;
}

}  // namespace
}  // namespace rheosim::numerics
