// Preconditioned conjugate gradients (numerics/conjugate_gradient.hpp) on the 1D Dirichlet
// Laplacian, whose solution and CG convergence are known: with n unknowns plain CG is exact
// (to round-off) after n iterations, an exact preconditioner after one.
#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <vector>

#include "rheosim/numerics/conjugate_gradient.hpp"

namespace rheosim::numerics {
namespace {

// (A x)_i = 2 x_i − x_{i−1} − x_{i+1}, x_0 = x_{n+1} = 0.
void laplacian(std::span<const double> x, std::span<double> out) {
  const std::size_t n = x.size();
  for (std::size_t i = 0; i < n; ++i) out[i] = 2.0 * x[i] - (i > 0 ? x[i - 1] : 0.0) - (i + 1 < n ? x[i + 1] : 0.0);
}
void jacobi(std::span<const double> r, std::span<double> z) {
  for (std::size_t i = 0; i < r.size(); ++i) z[i] = 0.5 * r[i];
}

TEST(ConjugateGradient, SolvesTheLaplacianInAtMostNIterations) {
  const std::size_t n = 40;
  std::vector<double> expected(n), b(n), x(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    expected[i] = std::sin(0.3 * static_cast<double>(i)) + 0.01 * static_cast<double>(i);
  laplacian(expected, b);
  ConjugateGradientSettings settings;
  settings.relative_tolerance = 1e-12;
  ConjugateGradientWorkspace work;
  const KrylovResult result = conjugate_gradient(laplacian, jacobi, b, x, settings, work);
  ASSERT_TRUE(result.converged) << result.relative_residual;
  EXPECT_LE(result.iterations, static_cast<int>(n) + 1);
  EXPECT_GT(result.iterations, 10);  // not solved by accident
  for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(x[i], expected[i], 1e-9);
  // A warm start at the solution needs no iteration.
  const KrylovResult again = conjugate_gradient(laplacian, jacobi, b, x, settings, work);
  EXPECT_TRUE(again.converged);
  EXPECT_EQ(again.iterations, 0);
  // min_iterations forces a step from a start inside the tolerance, but not from an exact one.
  settings.relative_tolerance = 1e-3;
  settings.min_iterations = 1;
  std::vector<double> close = expected;
  close[0] += 1e-6;
  const KrylovResult forced = conjugate_gradient(laplacian, jacobi, b, close, settings, work);
  EXPECT_TRUE(forced.converged);
  EXPECT_EQ(forced.iterations, 1);
  const KrylovResult exact = conjugate_gradient(laplacian, jacobi, b, x, settings, work);
  EXPECT_TRUE(exact.converged);
  EXPECT_LE(exact.iterations, 1);
}

TEST(ConjugateGradient, AnExactPreconditionerConvergesInOneIteration) {
  const std::size_t n = 12;
  // A⁻¹ of the 1D Laplacian: (A⁻¹)_ij = min(i, j)(n + 1 − max(i, j)) / (n + 1), 1-based.
  const auto inverse = [n](std::span<const double> r, std::span<double> z) {
    for (std::size_t i = 0; i < n; ++i) {
      z[i] = 0.0;
      for (std::size_t j = 0; j < n; ++j)
        z[i] += static_cast<double>(std::min(i, j) + 1) * static_cast<double>(n - std::max(i, j)) /
                static_cast<double>(n + 1) * r[j];
    }
  };
  std::vector<double> b(n, 1.0), x(n, 0.0);
  ConjugateGradientWorkspace work;
  const KrylovResult result = conjugate_gradient(laplacian, inverse, b, x, ConjugateGradientSettings{}, work);
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.iterations, 1);
  EXPECT_NEAR(x[0], 0.5 * n, 1e-10);  // x_i = i (n + 1 − i) / 2
}

TEST(ConjugateGradient, StopsAtTheReferenceNormAndOnZeroRightHandSide) {
  std::vector<double> b(10, 1e-14), x(10, 3.0);
  ConjugateGradientWorkspace work;
  ConjugateGradientSettings settings;
  settings.relative_tolerance = 1e-6;
  // Relative to ‖b‖ the start x = 0 is far off (no iteration allowed: unconverged) ...
  settings.max_iterations = 0;
  std::fill(x.begin(), x.end(), 0.0);
  EXPECT_FALSE(conjugate_gradient(laplacian, jacobi, b, x, settings, work).converged);
  // ... relative to a reference norm 1e12 × ‖b‖ it is converged.
  settings.max_iterations = 100;
  settings.reference_norm = 1e12 * std::sqrt(10.0) * 1e-14;
  std::fill(x.begin(), x.end(), 0.0);
  const KrylovResult loose = conjugate_gradient(laplacian, jacobi, b, x, settings, work);
  EXPECT_TRUE(loose.converged);
  EXPECT_EQ(loose.iterations, 0);
  std::vector<double> zero(10, 0.0), y(10, 5.0);
  const KrylovResult none = conjugate_gradient(laplacian, jacobi, zero, y, settings, work);
  EXPECT_TRUE(none.converged);
  EXPECT_EQ(y, zero);
}

TEST(ConjugateGradient, ReportsABreakdownOnAnIndefiniteMatrix) {
  const auto indefinite = [](std::span<const double> x, std::span<double> out) {
    for (std::size_t i = 0; i < x.size(); ++i) out[i] = (i % 2 == 0 ? 1.0 : -1.0) * x[i];
  };
  const auto identity = [](std::span<const double> r, std::span<double> z) {
    std::copy(r.begin(), r.end(), z.begin());
  };
  std::vector<double> b(4, 1.0), x(4, 0.0);  // pᵀA p = 0 on the first direction
  ConjugateGradientWorkspace work;
  const KrylovResult result = conjugate_gradient(indefinite, identity, b, x, ConjugateGradientSettings{}, work);
  EXPECT_FALSE(result.converged);
  EXPECT_EQ(result.iterations, 0);
}

}  // namespace
}  // namespace rheosim::numerics
