// Anderson mixing and GMRES (numerics/anderson.hpp, numerics/gmres.hpp) on small dense systems
// whose solutions are known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "rheosim/numerics/anderson.hpp"
#include "rheosim/numerics/gmres.hpp"

namespace rheosim::numerics {
namespace {

// A non-symmetric, well-conditioned n×n matrix: the identity plus a scaled random part.
Eigen::MatrixXd test_matrix(Eigen::Index n, double scale, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  Eigen::MatrixXd m(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) m(i, j) = scale * entry(random) / std::sqrt(static_cast<double>(n));
  return Eigen::MatrixXd::Identity(n, n) + m;
}

TEST(Gmres, SolvesANonSymmetricSystemToItsTolerance) {
  const Eigen::MatrixXd a = test_matrix(30, 0.5, 1);
  const Eigen::VectorXd expected = Eigen::VectorXd::LinSpaced(30, -1.0, 2.0);
  const Eigen::VectorXd b = a * expected;
  const auto apply = [&](const auto& v) -> Eigen::VectorXd { return a * v; };
  const Eigen::VectorXd x = gmres(apply, b, 1e-12, 30);
  EXPECT_LT((a * x - b).norm(), 1e-11 * b.norm());
  EXPECT_LT((x - expected).norm(), 1e-10 * expected.norm());
  // A loose tolerance stops early, with a residual at (not far below) that tolerance.
  const Eigen::VectorXd rough = gmres(apply, b, 1e-2, 30);
  const double relative = (a * rough - b).norm() / b.norm();
  EXPECT_LE(relative, 1e-2);
  EXPECT_GT(relative, 1e-9);
}

TEST(Gmres, ZeroRightHandSideGivesZero) {
  const Eigen::MatrixXd a = test_matrix(5, 0.5, 2);
  const auto apply = [&](const auto& v) -> Eigen::VectorXd { return a * v; };
  EXPECT_EQ(gmres(apply, Eigen::VectorXd::Zero(5), 1e-8, 5), Eigen::VectorXd::Zero(5));
}

// The linear map G(y) = M y + c with spectral radius ~0.95, fixed point y* = (I − M)⁻¹ c.
// Anderson mixing of depth ≥ n is GMRES on (I − M) y = c, so it reaches y* in about n + 1
// steps; plain Picard contracts by ~0.95 a step.
int iterations_to_fixed_point(int depth, double relaxation, Eigen::Index n, double& error) {
  Eigen::MatrixXd m = test_matrix(n, 0.3, 3) - Eigen::MatrixXd::Identity(n, n);
  m *= 0.95 / m.eigenvalues().cwiseAbs().maxCoeff();
  const Eigen::VectorXd c = Eigen::VectorXd::Ones(n);
  const Eigen::VectorXd fixed_point = (Eigen::MatrixXd::Identity(n, n) - m).partialPivLu().solve(c);
  AndersonMixer mixer(depth);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(n);
  for (int k = 1; k <= 2000; ++k) {
    y = mixer.next(y, m * y + c, relaxation);
    error = (y - fixed_point).norm() / fixed_point.norm();
    if (error < 1e-10) return k;
  }
  return -1;
}

TEST(AndersonMixer, ReachesALinearFixedPointInAboutDimensionSteps) {
  double error = 0;
  const int mixed = iterations_to_fixed_point(6, 1.0, 6, error);
  ASSERT_GT(mixed, 0) << error;
  EXPECT_LE(mixed, 9);
  const int picard = iterations_to_fixed_point(0, 1.0, 6, error);
  ASSERT_GT(picard, 0) << error;
  EXPECT_GT(picard, 200);  // 0.95^k < 1e-10 needs k ≈ 450
}

TEST(AndersonMixer, DepthZeroIsRelaxedPicardAndResetForgetsTheHistory) {
  AndersonMixer picard(0);
  const Eigen::VectorXd y = Eigen::VectorXd::Constant(3, 1.0), g = Eigen::VectorXd::Constant(3, 3.0);
  EXPECT_TRUE(picard.next(y, g, 0.5).isApprox(Eigen::VectorXd::Constant(3, 2.0)));
  AndersonMixer mixer(2);
  (void)mixer.next(y, g, 1.0);
  mixer.reset();
  EXPECT_TRUE(mixer.next(y, g, 0.25).isApprox(Eigen::VectorXd::Constant(3, 1.5)));  // no history: Picard
  EXPECT_THROW(AndersonMixer(-1), std::invalid_argument);
}

}  // namespace
}  // namespace rheosim::numerics
