// Lubrication resistance against the analytic near-contact results:
//  - equal spheres: X^A = 1/(4ξ) + (9/40) ln(1/ξ), Y^A = (1/6) ln(1/ξ), Y^B = 1/4 ln, Y^C_11 = 1/5 ln,
//    Y^C_12 = 1/20 ln (Jeffrey & Onishi 1984; Kim & Karrila 1991 Table 11.x); the leading squeeze
//    force is the Reynolds result F = 6πμ (a₁a₂/(a₁+a₂))² V / h;
//  - sphere–plate: F = 6πμa² V/h (1 + (h/5a) ln(a/h)) (Cox & Brenner 1967), shear (8/15) ln(a/h),
//    rotation–translation (2/15)·6 = 4/5 of 4πμa² ... (Goldman, Cox & Brenner 1967);
//  - structure: the assembled resistance is symmetric and positive semi-definite, a rigid-body
//    motion of a close pair gives no singular force, forces balance (F_i = −F_j), and the
//    unequal-sphere coefficients are consistent when the roles of the spheres are exchanged.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "lubrication.hpp"
#include "rheosim/core/rheology.hpp"
#include "rheosim/coupling/near_field.hpp"

namespace rheosim::coupling {
namespace {

constexpr double pi = std::numbers::pi;

TEST(LubricationResistance, EqualSpheresMatchJeffreyOnishi) {
  for (const double xi : {1e-3, 1e-2, 0.1, 0.5}) {
    const auto r = sphere_sphere_resistance(1.0, xi);
    const double l = std::log(1.0 / xi);
    EXPECT_NEAR(r.squeeze, 0.25 / xi + 9.0 / 40.0 * l, 1e-13 * r.squeeze);
    EXPECT_NEAR(r.shear, l / 6.0, 1e-14);
    EXPECT_NEAR(r.rotation_coupling_self, l / 4.0, 1e-14);
    EXPECT_NEAR(r.rotation_coupling_other, l / 4.0, 1e-14);
    EXPECT_NEAR(r.rotation_self, l / 5.0, 1e-14);
    EXPECT_NEAR(r.rotation_other, l / 20.0, 1e-14);
  }
}

// Leading squeeze term = Reynolds lubrication between two spheres: 6πμ a_eff² V/h with
// a_eff = a₁a₂/(a₁+a₂) (ξ = 2h/(a₁+a₂)), for any size ratio.
TEST(LubricationResistance, LeadingSqueezeTermIsReynoldsForUnequalSpheres) {
  const double a1 = 1.0;
  for (const double lambda : {0.25, 0.5, 1.0, 2.0, 4.0}) {
    const double a2 = lambda * a1;
    const double h = 1e-6;
    const double xi = 2.0 * h / (a1 + a2);
    const auto r = sphere_sphere_resistance(lambda, xi);
    const double a_eff = a1 * a2 / (a1 + a2);
    const double reynolds = a_eff * a_eff / h;  // F/(6πμV)
    // The log term is O(ln(1/ξ)) against O(1/ξ): relative O(ξ ln(1/ξ)) ≈ 2e-5 at this gap.
    EXPECT_NEAR(a1 * r.squeeze / reynolds, 1.0, 5.0 * xi * std::log(1.0 / xi)) << "λ = " << lambda;
  }
}

// Exchanging the spheres: a₁ X(λ) = a₂ X(1/λ) (and the same for Y^A), the coupling of i to
// Ω_j equals the coupling of j to its own rotation (reciprocity), c_o symmetric.
TEST(LubricationResistance, UnequalSpheresAreConsistentUnderExchange) {
  const double xi = 3e-3;
  for (const double lambda : {0.2, 0.5, 3.0}) {
    const auto r12 = sphere_sphere_resistance(lambda, xi);
    const auto r21 = sphere_sphere_resistance(1.0 / lambda, xi);
    EXPECT_NEAR(r12.squeeze, lambda * r21.squeeze, 1e-12 * r12.squeeze);
    EXPECT_NEAR(r12.shear, lambda * r21.shear, 1e-12 * r12.shear);
    // 4πμa₁² b_o(λ) = 4πμa₂² b_s(1/λ)
    EXPECT_NEAR(r12.rotation_coupling_other, lambda * lambda * r21.rotation_coupling_self, 1e-12);
    // 8πμa₁³ c_o(λ) = 8πμa₂³ c_o(1/λ)
    EXPECT_NEAR(r12.rotation_other, lambda * lambda * lambda * r21.rotation_other, 1e-12);
  }
}

TEST(LubricationResistance, SpherePlateIsLimitOfUnequalSpheres) {
  const double xi_plate = 2e-3;  // h/a
  const auto plate = sphere_plate_resistance(xi_plate);
  const double l = std::log(1.0 / xi_plate);
  EXPECT_NEAR(plate.squeeze, 1.0 / xi_plate + 0.2 * l, 1e-12 * plate.squeeze);  // Cox & Brenner
  EXPECT_NEAR(plate.shear, 8.0 / 15.0 * l, 1e-14);                              // Goldman, Cox & Brenner
  EXPECT_NEAR(plate.rotation_coupling_self, 0.2 * l, 1e-14);
  EXPECT_NEAR(plate.rotation_self, 0.4 * l, 1e-14);
  // A sphere next to a much larger one (λ = 1e4) at the same h: same leading squeeze force
  // (the log terms differ by (1/5) ln((1+λ)/2), relative 3e-3 here: the two-sphere ℓ is
  // ln((a₁+a₂)/2h), the plate's ln(a/h)).
  const double lambda = 1e4;
  const double xi = 2.0 * xi_plate / (1.0 + lambda);
  const auto big = sphere_sphere_resistance(lambda, xi);
  EXPECT_NEAR(big.squeeze / plate.squeeze, 1.0, 0.2 * std::log((1.0 + lambda) / 2.0) * xi_plate * 1.01);
  EXPECT_GT(big.squeeze, plate.squeeze);
  EXPECT_NEAR(big.shear / (8.0 / 15.0 * std::log(1.0 / xi)), 1.0, 1e-3);
}

TEST(LubricationResistance, RejectsInvalidGaps) {
  EXPECT_THROW((void)sphere_sphere_resistance(1.0, 0.0), std::invalid_argument);
  EXPECT_THROW((void)sphere_sphere_resistance(-1.0, 0.1), std::invalid_argument);
  EXPECT_THROW((void)sphere_plate_resistance(-1e-3), std::invalid_argument);
}

// ---- the assembled gap -------------------------------------------------------------------

struct TwoSpheres {
  lubrication::Gap gap;
  double a1 = 1e-4, a2 = 1e-4;
};

TwoSpheres make_pair(double a1, double a2, double h, const std::array<double, 3>& direction) {
  TwoSpheres t;
  t.a1 = a1;
  t.a2 = a2;
  const double norm = std::hypot(direction[0], direction[1], direction[2]);
  t.gap.i = 0;
  t.gap.j = 1;
  t.gap.n = {direction[0] / norm, direction[1] / norm, direction[2] / norm};
  const double d = a1 + a2 + h;
  t.gap.separation = {d * t.gap.n[0], d * t.gap.n[1], d * t.gap.n[2]};
  lubrication::set_pair_coefficients(t.gap, a1, a2, h, 0.7, 1e-3);
  return t;
}

// Dense 12×12 resistance of one gap, column by column (R e_k = −F(e_k)).
std::vector<std::array<double, 12>> resistance_matrix(const lubrication::Gap& gap) {
  std::vector<std::array<double, 12>> r(12);
  for (std::size_t k = 0; k < 12; ++k) {
    std::vector<double> v(12, 0.0), out(12, 0.0);
    v[k] = 1.0;
    lubrication::add_gap_forces(gap, v, out, false);
    for (std::size_t row = 0; row < 12; ++row) r[row][k] = -out[row];
  }
  return r;
}

TEST(LubricationGap, ResistanceIsSymmetricPositiveSemiDefinite) {
  for (const double lambda : {1.0, 0.4, 2.5}) {
    const auto pair = make_pair(1e-4, lambda * 1e-4, 2e-7, {0.3, -0.5, 0.8});
    const auto r = resistance_matrix(pair.gap);
    double scale = 0.0;
    for (const auto& row : r)
      for (double x : row) scale = std::max(scale, std::abs(x));
    for (std::size_t i = 0; i < 12; ++i)
      for (std::size_t j = 0; j < 12; ++j) EXPECT_NEAR(r[i][j], r[j][i], 1e-12 * scale) << i << "," << j;
    // V·R V >= 0 for a few deterministic directions (dissipation).
    for (int trial = 0; trial < 50; ++trial) {
      std::array<double, 12> v{};
      for (std::size_t k = 0; k < 12; ++k) v[k] = std::sin(1.7 * trial + 2.3 * k) * (k % 6 < 3 ? 1.0 : 1e4);
      double power = 0.0, magnitude = 0.0;
      for (std::size_t i = 0; i < 12; ++i)
        for (std::size_t j = 0; j < 12; ++j) {
          power += v[i] * r[i][j] * v[j];
          magnitude += std::abs(v[i] * r[i][j] * v[j]);
        }
      EXPECT_GE(power, -1e-12 * magnitude) << "λ = " << lambda;
    }
  }
}

// Rigid rotation of the pair about any axis through any point, plus a translation: the
// singular parts cancel; what remains is O(h) relative to the squeeze force scale.
TEST(LubricationGap, RigidBodyMotionGivesNoSingularForce) {
  for (const double lambda : {1.0, 0.5, 3.0}) {
    const double a1 = 1e-4, a2 = lambda * a1, h = 1e-7;
    const auto pair = make_pair(a1, a2, h, {1.0, 2.0, -0.5});
    const std::array<double, 3> omega{3.0, -1.0, 2.0}, u0{0.01, 0.02, -0.03};
    const std::array<double, 3> x1{0.0, 0.0, 0.0},
        x2 = {pair.gap.separation[0], pair.gap.separation[1], pair.gap.separation[2]};
    std::vector<double> v(12, 0.0), out(12, 0.0);
    for (int s = 0; s < 2; ++s) {
      const auto& x = s == 0 ? x1 : x2;
      const std::array<double, 3> wx{omega[1] * x[2] - omega[2] * x[1], omega[2] * x[0] - omega[0] * x[2],
                                     omega[0] * x[1] - omega[1] * x[0]};
      for (std::size_t k = 0; k < 3; ++k) {
        v[6 * s + k] = u0[k] + wx[k];
        v[6 * s + 3 + k] = omega[k];
      }
    }
    lubrication::add_gap_forces(pair.gap, v, out, false);
    // Scale of a singular force at this speed: k_squeeze · |Ω| a.
    const double scale = pair.gap.k_squeeze * 3.7 * a1;
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_LT(std::abs(out[k]), 1e-3 * scale) << "λ = " << lambda;
      EXPECT_LT(std::abs(out[3 + k]), 1e-3 * scale * a1) << "λ = " << lambda;
    }
  }
}

TEST(LubricationGap, SqueezeForceOnTwoApproachingSpheresIsAnalytic) {
  const double a = 1e-4, h = 5e-7, mu = 0.7, approach = 1e-3;
  const auto pair = make_pair(a, a, h, {0.0, 0.0, 1.0});
  std::vector<double> v(12, 0.0), out(12, 0.0);
  v[2] = approach;  // sphere 0 moves up towards sphere 1
  lubrication::add_gap_forces(pair.gap, v, out, false);
  const double xi = (h + 1e-3 * a) / a;
  const double expected = 6.0 * pi * mu * a * (0.25 / xi + 9.0 / 40.0 * std::log(1.0 / xi)) * approach;
  EXPECT_NEAR(out[2], -expected, 1e-12 * expected);
  EXPECT_NEAR(out[8], expected, 1e-12 * expected);
  for (int k : {0, 1, 3, 4, 5, 6, 7, 9, 10, 11}) EXPECT_EQ(out[static_cast<std::size_t>(k)], 0.0);
}

// Equal spheres: the tangential force is −πμa ln(1/ξ) × the relative surface velocity.
TEST(LubricationGap, EqualSpheresShearOnRelativeSurfaceVelocity) {
  const double a = 1e-4, h = 1e-6, mu = 0.7;
  const auto pair = make_pair(a, a, h, {1.0, 0.0, 0.0});
  std::vector<double> v(12, 0.0), out(12, 0.0);
  v[1] = 2e-3;   // U_1y
  v[5] = 5.0;    // Ω_1z: (Ω×n)_y = Ω_z n_x = 5
  v[11] = -3.0;  // Ω_2z
  lubrication::add_gap_forces(pair.gap, v, out, false);
  const double xi = (h + 1e-3 * a) / a;
  const double slip = 2e-3 + a * (5.0 - 3.0);
  EXPECT_NEAR(out[1], -pi * mu * a * std::log(1.0 / xi) * slip, 1e-12 * std::abs(out[1]));
  EXPECT_NEAR(out[7], -out[1], 1e-18);
}

TEST(LubricationGap, PlateSqueezeMatchesCoxBrenner) {
  const double a = 1e-4, h = 2e-6, mu = 0.3, speed = -4e-3;  // moving down onto the plate
  lubrication::Gap gap;
  gap.i = 0;
  gap.n = {0.0, 0.0, -1.0};
  gap.separation = {0.0, 0.0, -(a + h)};
  lubrication::set_plate_coefficients(gap, a, h, mu, 1e-3);
  std::vector<double> v(6, 0.0), out(6, 0.0);
  v[2] = speed;
  lubrication::add_gap_forces(gap, v, out, true);
  const double h_eff = h + 1e-3 * a;
  const double expected = 6.0 * pi * mu * a * a / h_eff * (1.0 + h_eff / (5.0 * a) * std::log(a / h_eff)) * -speed;
  EXPECT_NEAR(out[2], expected, 1e-12 * expected);
  // A sphere translating with a sliding plate (and not spinning) feels nothing.
  gap.plate_velocity = {0.02, -0.01, 0.0};
  std::vector<double> w(6, 0.0), out2(6, 0.0);
  w[0] = 0.02;
  w[1] = -0.01;
  lubrication::add_gap_forces(gap, w, out2, true);
  for (double x : out2) EXPECT_NEAR(x, 0.0, 1e-20);
}

}  // namespace
}  // namespace rheosim::coupling
