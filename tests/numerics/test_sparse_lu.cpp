// Sparse LU of a stencil matrix (numerics/sparse_lu.hpp): both methods solve a non-symmetric
// 2D system to round-off, serve as an exact BiCGStab preconditioner, and refuse what they
// cannot factorise.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "rheosim/numerics/krylov.hpp"
#include "rheosim/numerics/neighbours.hpp"
#include "rheosim/numerics/sparse_lu.hpp"

namespace rheosim::numerics {
namespace {

// A cells × cells lattice (unit spacing), nearest-neighbour pattern: convection–diffusion rows
// 4 on the diagonal, −1 ± 0.3 to the x neighbours (not symmetric), −1 to the y neighbours;
// identity rows on the boundary.
struct Lattice {
  std::vector<double> x;
  NeighbourList nb;
  StencilMatrix a;
};

Lattice lattice(std::size_t cells) {
  Lattice l;
  for (std::size_t j = 0; j < cells; ++j)
    for (std::size_t i = 0; i < cells; ++i) l.x.insert(l.x.end(), {static_cast<double>(i), static_cast<double>(j)});
  l.nb = find_neighbours(l.x, 2, 1.5);  // the 8 lattice neighbours; diagonal ones get 0
  l.a.pattern = &l.nb;
  const std::size_t n = cells * cells;
  l.a.diagonal.assign(n, 1.0);
  l.a.off_diagonal.assign(l.nb.pair_count(), 0.0);
  for (std::size_t p = 0; p < n; ++p) {
    const std::size_t i = p % cells, j = p / cells;
    if (i == 0 || j == 0 || i + 1 == cells || j + 1 == cells) continue;
    l.a.diagonal[p] = 4.0;
    for (std::size_t k = l.nb.offsets[p]; k < l.nb.offsets[p + 1]; ++k) {
      const double dx = l.x[2 * l.nb.indices[k]] - l.x[2 * p], dy = l.x[2 * l.nb.indices[k] + 1] - l.x[2 * p + 1];
      if (dy == 0.0) l.a.off_diagonal[k] = -1.0 + 0.3 * dx;
      if (dx == 0.0) l.a.off_diagonal[k] = -1.0;
    }
  }
  return l;
}

double relative_residual(const StencilMatrix& a, const std::vector<double>& b, const std::vector<double>& x) {
  std::vector<double> ax(b.size());
  a.multiply(x, ax);
  double r = 0, bb = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    r += (b[i] - ax[i]) * (b[i] - ax[i]);
    bb += b[i] * b[i];
  }
  return std::sqrt(r / bb);
}

class SparseLuMethods : public ::testing::TestWithParam<SparseLu::Method> {};

TEST_P(SparseLuMethods, SolvesANonSymmetricLatticeSystemToRoundOff) {
  const Lattice l = lattice(40);
  std::vector<double> b(l.a.size()), x(l.a.size());
  for (std::size_t i = 0; i < b.size(); ++i) b[i] = std::sin(0.37 * static_cast<double>(i)) + 0.5;
  SparseLu lu;
  EXPECT_FALSE(lu.ready());
  ASSERT_TRUE(lu.factorise(l.a, GetParam(), l.x));
  ASSERT_TRUE(lu.ready());
  lu.solve(b, x);
  EXPECT_LT(relative_residual(l.a, b, x), 1e-12);
  // As BiCGStab's preconditioner it is exact: one iteration.
  std::vector<double> y(l.a.size(), 0.0);
  KrylovWorkspace work;
  const KrylovResult result = bicgstab(l.a, b, y, KrylovSettings{1e-10, 1e-300, 50, lu.as_preconditioner()}, work);
  EXPECT_TRUE(result.converged);
  EXPECT_LE(result.iterations, 1);
}

INSTANTIATE_TEST_SUITE_P(BothMethods, SparseLuMethods,
                         ::testing::Values(SparseLu::Method::colamd, SparseLu::Method::nested_dissection));

TEST(SparseLu, RefusesASingularMatrixAndMissingPositions) {
  Lattice l = lattice(6);
  for (std::size_t i = 0; i < 6; ++i) l.a.diagonal[i] = 0.0;  // six empty rows
  SparseLu lu;
  EXPECT_FALSE(lu.factorise(l.a, SparseLu::Method::colamd));
  EXPECT_FALSE(lu.ready());
  EXPECT_FALSE(lu.factorise(l.a, SparseLu::Method::nested_dissection, l.x));
  std::vector<double> b(l.a.size(), 1.0), x(l.a.size());
  EXPECT_THROW(lu.solve(b, x), std::logic_error);
  EXPECT_THROW((void)lu.factorise(l.a, SparseLu::Method::nested_dissection, {}), std::invalid_argument);
}

}  // namespace
}  // namespace rheosim::numerics
