// Hertz contact scales against hand-computed values for the CD seed §4 particles
// (r = 100 µm, ρ = 1000 kg/m³, E = 3 GPa, ν = 0.33), their scaling laws, and the DEM step
// they imply.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "rheosim/dem/contact.hpp"

namespace rheosim::dem {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double rel = 1e-12;
const ElasticSphere seed_particle{.radius = 100e-6, .density = 1000.0, .youngs_modulus = 3e9, .poisson_ratio = 0.33};

ElasticSphere scaled(ElasticSphere s, double radius_factor) {
  s.radius *= radius_factor;
  return s;
}

TEST(Contact, EffectivePropertiesOfLikeSpheres) {
  // G = 3e9/(2·1.33) = 1.12781954887e9 Pa
  EXPECT_NEAR(shear_modulus(3e9, 0.33), 1.1278195488721805e9, rel * 1.2e9);
  // E* = E/(2(1 − ν²)) = 3e9/(2·0.8911) = 1.68331275951e9 Pa
  EXPECT_NEAR(effective_modulus(seed_particle, seed_particle), 1.6833127595107172e9, rel * 1.7e9);
  EXPECT_DOUBLE_EQ(effective_radius(seed_particle, seed_particle), 50e-6);
  // m = 1000 · (4/3)π(1e-4)³ = 4.18879020479e-9 kg, m* = m/2
  EXPECT_NEAR(mass(seed_particle), 4.188790204786392e-9, rel * 4.2e-9);
  EXPECT_NEAR(effective_mass(seed_particle, seed_particle), 0.5 * 4.188790204786392e-9, rel * 4.2e-9);
}

TEST(Contact, UnlikeSpheresUseHarmonicMeans) {
  ElasticSphere stiff = seed_particle;
  stiff.youngs_modulus = 2e11;
  stiff.poisson_ratio = 0.3;
  stiff.radius = 300e-6;
  const double expected_modulus = 1.0 / ((1 - 0.33 * 0.33) / 3e9 + (1 - 0.3 * 0.3) / 2e11);
  EXPECT_NEAR(effective_modulus(seed_particle, stiff), expected_modulus, rel * expected_modulus);
  EXPECT_NEAR(effective_radius(seed_particle, stiff), 75e-6, rel * 75e-6);  // 100·300/400 µm
  // A very large partner approaches a flat wall: r* → r.
  EXPECT_NEAR(effective_radius(seed_particle, scaled(seed_particle, 1e9)), 100e-6, 2e-9 * 100e-6);
}

TEST(Contact, RayleighTimeOfSeedParticles) {
  // t_R = π·1e-4·√(1000/1.12782e9)/(0.1631·0.33 + 0.8766) = 2.95819e-7/0.930423 = 3.17943e-7 s
  const double t_r = rayleigh_time(seed_particle);
  EXPECT_NEAR(t_r, 3.179432623038359e-7, rel * 3.2e-7);
  // t_R ∝ r at fixed material.
  EXPECT_NEAR(rayleigh_time(scaled(seed_particle, 3.0)), 3.0 * t_r, rel * t_r);
}

TEST(Contact, TimeStepFromTheRayleighTime) {
  const double t_r = rayleigh_time(seed_particle);
  EXPECT_GT(t_r, 1e-7);
  EXPECT_LT(t_r, 1e-6);
  // 0.2 t_R = 6.36e-8 s: just below the seed's 1e-7 s ...
  const double dt = rayleigh_time_step(seed_particle);
  EXPECT_NEAR(dt, 6.358865246076718e-8, rel * 6.4e-8);
  EXPECT_GT(dt, 1e-8);
  EXPECT_LT(dt, 1e-7);
  // ... which is 0.31 t_R, inside the customary 0.1–0.4 t_R.
  EXPECT_NEAR(1e-7 / t_r, 0.3145, 1e-4);
  EXPECT_DOUBLE_EQ(rayleigh_time_step(seed_particle, 0.4), 0.4 * t_r);
}

TEST(Contact, HertzCollisionTimeOfSeedParticles) {
  // t_c = 2.87 (m*²/(r* E*² v))^(1/5) with m* = 2.0944e-9 kg, r* = 5e-5 m, E* = 1.68331e9 Pa, v = 1 m/s:
  //     = 2.87 · (3.09614e-32)^(0.2) = 1.43234e-6 s
  EXPECT_NEAR(hertz_collision_time(seed_particle, seed_particle, 1.0), 1.432337674268135e-6, 1e-11 * 1.4e-6);
  // Much longer than the Rayleigh time at rheometer slip speeds (γ̇ d ≈ 100/s · 200 µm = 0.02 m/s).
  EXPECT_NEAR(hertz_collision_time(seed_particle, seed_particle, 0.02), 3.132127380249799e-6, 1e-11 * 3.1e-6);
}

TEST(Contact, HertzCollisionTimeScalesAsSpeedToMinusOneFifth) {
  const double t1 = hertz_collision_time(seed_particle, seed_particle, 0.1);
  for (const double factor : {2.0, 10.0, 1000.0}) {
    const double t2 = hertz_collision_time(seed_particle, seed_particle, 0.1 * factor);
    EXPECT_NEAR(t2 / t1, std::pow(factor, -0.2), 1e-12) << factor;
  }
}

TEST(Contact, HertzCollisionTimeScalesWithRadiusAtFixedSpeed) {
  // m*² ∝ r⁶, r* ∝ r: (r⁶/r)^(1/5) = r.
  const double t1 = hertz_collision_time(seed_particle, seed_particle, 0.5);
  for (const double factor : {0.5, 2.0, 7.0}) {
    const auto big = scaled(seed_particle, factor);
    EXPECT_NEAR(hertz_collision_time(big, big, 0.5) / t1, factor, 1e-12) << factor;
  }
}

TEST(Contact, DampingRatioFromRestitution) {
  // β = ln e/√(ln²e + π²): e = 0.9 → −0.105361/3.143352 = −0.0335184; e = 0.5 → −0.215454
  EXPECT_NEAR(damping_ratio_from_restitution(0.9), -0.03351844910567637, 1e-15);
  EXPECT_NEAR(damping_ratio_from_restitution(0.5), -0.2154537619662468, 1e-15);
  EXPECT_EQ(damping_ratio_from_restitution(1.0), 0.0);  // elastic: no damping
  // Monotone: lower restitution, stronger damping; β → −1 as e → 0.
  EXPECT_LT(damping_ratio_from_restitution(0.1), damping_ratio_from_restitution(0.5));
  EXPECT_GT(damping_ratio_from_restitution(1e-300), -1.0);
}

TEST(Contact, HertzNormalDampingAsInLiggghts) {
  // δ = 1 µm, e = 0.9: S_n = 2E*√(r*δ) = 2·1.68331e9·√(5e-11) = 23805.6 N/m,
  // γ_n = −2√(5/6)·β·√(S_n m*) = 4.32108e-4 kg/s
  EXPECT_NEAR(hertz_normal_damping(seed_particle, seed_particle, 0.9, 1e-6), 4.321081938956189e-4, 1e-11 * 4.3e-4);
  EXPECT_EQ(hertz_normal_damping(seed_particle, seed_particle, 0.9, 0.0), 0.0);
  EXPECT_EQ(hertz_normal_damping(seed_particle, seed_particle, 1.0, 1e-6), 0.0);
}

std::string error_of(auto&& call) {
  try {
    call();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no exception";
}

TEST(Contact, InvalidInputsAreRejectedByName) {
  auto bad = seed_particle;
  bad.radius = 0.0;
  EXPECT_THAT(error_of([&] { (void)rayleigh_time(bad); }), AllOf(HasSubstr("radius"), HasSubstr("> 0")));
  bad = seed_particle;
  bad.density = -1.0;
  EXPECT_THAT(error_of([&] { (void)mass(bad); }), HasSubstr("density"));
  bad = seed_particle;
  bad.youngs_modulus = std::nan("");
  EXPECT_THAT(error_of([&] { (void)effective_modulus(bad, seed_particle); }), HasSubstr("youngs_modulus"));
  bad = seed_particle;
  bad.poisson_ratio = 0.6;
  EXPECT_THAT(error_of([&] { (void)rayleigh_time(bad); }), AllOf(HasSubstr("poisson_ratio"), HasSubstr("[0, 0.5]")));
  EXPECT_THAT(error_of([&] { (void)rayleigh_time_step(seed_particle, 0.0); }),
              AllOf(HasSubstr("fraction"), HasSubstr("(0, 1]")));
  EXPECT_THAT(error_of([&] { (void)hertz_collision_time(seed_particle, seed_particle, 0.0); }),
              HasSubstr("impact_speed"));
  EXPECT_THAT(error_of([&] { (void)damping_ratio_from_restitution(1.2); }),
              AllOf(HasSubstr("restitution"), HasSubstr("(0, 1]")));
  EXPECT_THAT(error_of([&] { (void)hertz_normal_damping(seed_particle, seed_particle, 0.9, -1e-9); }),
              HasSubstr("overlap"));
}

}  // namespace
}  // namespace rheosim::dem
