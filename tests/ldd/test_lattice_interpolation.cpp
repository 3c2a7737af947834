// The lattice reordering's semi-Lagrangian return (lattice_interpolation.hpp): the quadratic fit
// is exact for quadratics on square, skewed and jittered clouds; zero displacement returns the
// field unchanged (Shepard's eq. 12 smooths it); a uniform translation of a quadratic is exact;
// the midpoint departure is third order per step under rotation; the limiter removes the
// overshoot at a jump.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "rheosim/ldd/lattice_interpolation.hpp"
#include "rheosim/ldd/operators.hpp"
#include "rheosim/ldd/cavity_solver.hpp"
#include "rheosim/numerics/neighbours.hpp"

namespace rheosim::ldd {
namespace {

constexpr double spacing = 0.1;
constexpr double support = 1.6 * spacing;  // h of the solver's default smoothing ratio

struct Cloud {
  std::vector<double> positions;
  std::vector<NodeKind> kinds;  // outer ring: wall (copied), inside: fluid
  numerics::NeighbourList neighbours;
};

// (cells + 1)² nodes, lattice vectors (Δ, 0) and (Δ cos α, Δ sin α), each moved by up to
// `jitter`·Δ in x and y.
Cloud lattice(int cells, double angle, double jitter, unsigned seed = 7) {
  Cloud c;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> shake(-jitter * spacing, jitter * spacing);
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) {
      const bool edge = i == 0 || j == 0 || i == cells || j == cells;
      const double x = spacing * (i + j * std::cos(angle)), y = spacing * j * std::sin(angle);
      c.positions.insert(c.positions.end(), {x + (edge ? 0.0 : shake(random)), y + (edge ? 0.0 : shake(random))});
      c.kinds.push_back(edge ? NodeKind::wall : NodeKind::interior);
    }
  c.neighbours = numerics::find_neighbours(c.positions, 2, support + 0.2 * spacing);
  return c;
}

double quadratic(double x, double y) { return 0.3 + 1.7 * x - 0.9 * y + 2.5 * x * x - 1.3 * x * y + 0.8 * y * y; }

// Max error of the fitted derivatives of `quadratic` over the fluid nodes.
double fit_error(const Cloud& c) {
  const QuadraticFit fit(c.positions, c.neighbours, support);
  std::vector<double> f(c.kinds.size());
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = quadratic(c.positions[2 * i], c.positions[2 * i + 1]);
  double error = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (c.kinds[i] != NodeKind::interior) continue;
    const double x = c.positions[2 * i], y = c.positions[2 * i + 1];
    const auto d = fit.derivatives(c.neighbours, f, 1, 0, i);
    const double exact[5] = {1.7 + 5.0 * x - 1.3 * y, -0.9 - 1.3 * x + 1.6 * y, 5.0, -1.3, 1.6};
    for (std::size_t t = 0; t < 5; ++t) error = std::max(error, std::abs(d[t] - exact[t]));
  }
  return error;  // exact second derivatives: the fluid nodes did not fall back to a linear fit
}

TEST(QuadraticFit, ExactForQuadraticsOnSquareSkewedAndJitteredClouds) {
  EXPECT_LT(fit_error(lattice(8, std::acos(0.0), 0.0)), 1e-9);
  EXPECT_LT(fit_error(lattice(8, std::acos(0.5), 0.0)), 1e-9);  // 60°: six neighbours within h
  EXPECT_LT(fit_error(lattice(8, std::acos(0.0), 0.2)), 1e-9);
}

TEST(QuadraticFit, FallsBackToLinearWithTooFewNeighbours) {
  // Four nodes on a line and one off it: not enough for five second-order terms.
  Cloud c;
  c.positions = {0, 0, 0.1, 0, -0.1, 0, 0.0, 0.1};
  c.neighbours = numerics::find_neighbours(c.positions, 2, support);
  const QuadraticFit fit(c.positions, c.neighbours, support);
  EXPECT_EQ(fit.linear_only_count(), 4U);           // node 0 sees all three others; the rest fewer
  const std::vector<double> f{1.0, 1.2, 0.8, 1.5};  // f = 1 + 2x + 5y
  const auto d = fit.derivatives(c.neighbours, f, 1, 0, 0);
  EXPECT_NEAR(d[0], 2.0, 1e-12);
  EXPECT_NEAR(d[1], 5.0, 1e-12);
  EXPECT_EQ(d[2], 0.0);
}

// Velocity (u, v) = (g(x, y), −g(x, y)) per node.
std::vector<double> velocity_of(const Cloud& c, double (*g)(double, double)) {
  std::vector<double> u(c.positions.size());
  for (std::size_t i = 0; i < c.kinds.size(); ++i) {
    const double value = g(c.positions[2 * i], c.positions[2 * i + 1]);
    u[2 * i] = value;
    u[2 * i + 1] = -value;
  }
  return u;
}

TEST(ReturnToLattice, ZeroDisplacementLeavesAnyFieldUnchanged) {
  const Cloud c = lattice(10, std::acos(0.0), 0.0);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  std::vector<double> u(c.positions.size()), still(c.positions.size(), 0.0), out;
  for (double& value : u) value = noise(random);
  const QuadraticFit fit(c.positions, c.neighbours, support);
  return_to_lattice(c.positions, c.kinds, c.neighbours, fit, u, still, 0.01, true, out);
  EXPECT_EQ(out, u);
  // Shepard's eq. 12 on the same cloud is a smoothing filter: it changes the field by O(1).
  double shepard_change = 0;
  for (std::size_t i = 0; i < c.kinds.size(); ++i) {
    double wsum = weight(0.0, support), sum = wsum * u[2 * i];
    for (std::size_t k = c.neighbours.offsets[i]; k < c.neighbours.offsets[i + 1]; ++k) {
      const double w = weight(c.neighbours.distances[k], support);
      wsum += w;
      sum += w * u[2 * c.neighbours.indices[k]];
    }
    shepard_change = std::max(shepard_change, std::abs(sum / wsum - u[2 * i]));
  }
  EXPECT_GT(shepard_change, 0.1);  // measured 0.25 for noise in [−1, 1]
}

TEST(ReturnToLattice, UniformTranslationOfAQuadraticIsExact) {
  const Cloud c = lattice(10, std::acos(0.0), 0.15);
  const QuadraticFit fit(c.positions, c.neighbours, support);
  const std::vector<double> u = velocity_of(c, quadratic);
  std::vector<double> advection(c.positions.size()), out;
  for (std::size_t i = 0; i < c.kinds.size(); ++i) advection[2 * i] = 3.0, advection[2 * i + 1] = -2.0;
  const double dt = 0.02;  // displacement (0.06, −0.04): 0.6 Δ and 0.4 Δ
  for (const bool limit : {false, true}) {
    return_to_lattice(c.positions, c.kinds, c.neighbours, fit, u, advection, dt, limit, out);
    double error = 0;
    for (std::size_t i = 0; i < c.kinds.size(); ++i) {
      if (c.kinds[i] != NodeKind::interior) continue;
      const double exact = quadratic(c.positions[2 * i] - 3.0 * dt, c.positions[2 * i + 1] + 2.0 * dt);
      error = std::max({error, std::abs(out[2 * i] - exact), std::abs(out[2 * i + 1] + exact)});
    }
    // The limited result may clip at the extremum of the quadratic only; this one has none inside.
    EXPECT_LT(error, 1e-12) << "limit " << limit;
  }
}

TEST(ReturnToLattice, MidpointDepartureIsThirdOrderPerStepUnderRotation) {
  // Solid-body rotation a = ω(−y, x) about the cloud's centre; u = x carried back from the
  // departure point must equal the x of the exactly rotated point, X rotated by −ωδt.
  const Cloud c = lattice(12, std::acos(0.0), 0.0);
  const QuadraticFit fit(c.positions, c.neighbours, support);
  const double omega = 2.0, centre = 0.6;
  std::vector<double> u(c.positions.size()), advection(c.positions.size()), out;
  for (std::size_t i = 0; i < c.kinds.size(); ++i) {
    const double x = c.positions[2 * i] - centre, y = c.positions[2 * i + 1] - centre;
    u[2 * i] = x;
    u[2 * i + 1] = y;
    advection[2 * i] = -omega * y;
    advection[2 * i + 1] = omega * x;
  }
  const auto error_for = [&](double dt) {
    return_to_lattice(c.positions, c.kinds, c.neighbours, fit, u, advection, dt, false, out);
    double error = 0;
    for (std::size_t i = 0; i < c.kinds.size(); ++i) {
      if (c.kinds[i] != NodeKind::interior) continue;
      const double x = c.positions[2 * i] - centre, y = c.positions[2 * i + 1] - centre, angle = -omega * dt;
      error = std::max(error, std::abs(out[2 * i] - (x * std::cos(angle) - y * std::sin(angle))));
    }
    return error;
  };
  const double coarse = error_for(0.02), fine = error_for(0.01);
  EXPECT_GT(coarse, 0.0);
  EXPECT_NEAR(std::log2(coarse / fine), 3.0, 0.2);
}

double step_profile(double x, double) { return x < 0.45 ? 0.0 : 1.0; }

TEST(ReturnToLattice, LimiterRemovesTheOvershootAtAJump) {
  const Cloud c = lattice(10, std::acos(0.0), 0.0);
  const QuadraticFit fit(c.positions, c.neighbours, support);
  const std::vector<double> u = velocity_of(c, step_profile);
  std::vector<double> advection(c.positions.size()), unlimited, limited;
  for (std::size_t i = 0; i < c.kinds.size(); ++i) advection[2 * i] = 1.0;
  return_to_lattice(c.positions, c.kinds, c.neighbours, fit, u, advection, 0.05, false, unlimited);
  return_to_lattice(c.positions, c.kinds, c.neighbours, fit, u, advection, 0.05, true, limited);
  const auto [low, high] = std::minmax_element(unlimited.begin(), unlimited.end());
  EXPECT_TRUE(*low < -1e-3 || *high > 1.0 + 1e-3);  // the quadratic overshoots at the jump
  for (std::size_t i = 0; i < c.kinds.size(); ++i) {
    EXPECT_GE(limited[2 * i], 0.0);
    EXPECT_LE(limited[2 * i], 1.0);
  }
}

}  // namespace
}  // namespace rheosim::ldd
