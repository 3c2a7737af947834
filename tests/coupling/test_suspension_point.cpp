// Steady-state detector on synthetic torque series, and one short suspension point through
// run_point (scene + fluid + coupler).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include "coupling_test_support.hpp"
#include "rheosim/coupling/suspension_point.hpp"

namespace rheosim::coupling {
namespace {

TEST(SteadyState, NoisyConstantTorqueIsSteadyWithAnErrorBar) {
  SteadyStateDetector d({.strain_window = 1.0, .relative_tolerance = 0.02, .min_strain = 2.0, .max_strain = 50.0},
                        10.0);
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 0.05);
  double t = 0.0;
  while (!d.done()) {
    t += 1e-3;
    d.add(t, 1.0 + noise(rng));
  }
  const SteadyEstimate e = d.estimate();
  EXPECT_TRUE(e.steady);
  EXPECT_NEAR(d.strain(), 2.0, 0.02);  // decided at the first chance
  EXPECT_NEAR(e.mean, 1.0, 3 * 0.05 / std::sqrt(100.0));
  EXPECT_GT(e.standard_error, 0.0);
  EXPECT_LT(e.standard_error, 0.02);
}

TEST(SteadyState, DriftingTorqueIsNotSteadyUntilMaxStrain) {
  SteadyStateDetector d({.strain_window = 1.0, .relative_tolerance = 0.01, .min_strain = 2.0, .max_strain = 6.0}, 1.0);
  double t = 0.0;
  while (!d.done()) {
    t += 0.01;
    d.add(t, 1.0 + 0.2 * t);  // +20 % per unit strain
  }
  EXPECT_FALSE(d.estimate().steady);
  EXPECT_NEAR(d.strain(), 6.0, 0.011);
}

TEST(SteadyState, RejectsBadSettings) {
  EXPECT_THROW(SteadyStateDetector({.strain_window = 0.0}, 1.0), std::invalid_argument);
  EXPECT_THROW(SteadyStateDetector({}, 0.0), std::invalid_argument);
}

// particles.drag names the law; a force list that carries another one is refused before any work.
TEST(SuspensionPoint, ForceListMustCarryTheParticlesDragLaw) {
  testing::RunFolder folder;
  SuspensionPointSettings s;
  s.geometry = {.radius = 0.002, .gap = 0.0005};
  s.fluid = {.density = 1000, .rheology = testing::newtonian(1e-3)};
  s.particles = {.volume_fraction = 0.03, .diameter = 1e-4, .density = 1000};
  s.drag = DragLaw::schiller_naumann;
  s.rim_shear_rate = 50.0;
  s.run_directory = folder.path();
  try {
    (void)run_point(s);  // coupling.forces is still the seed's (di_felice)
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("di_felice but particles.drag is schiller_naumann"), std::string::npos)
        << e.what();
  }
}

TEST(SuspensionPoint, ShortRunReportsTorquePartsAndCost) {
  testing::RunFolder folder;
  SuspensionPointSettings s;
  s.geometry = {.radius = 0.002, .gap = 0.0005};
  s.fluid = {.density = 1000, .rheology = testing::newtonian(1e-3)};
  s.particles = {.volume_fraction = 0.03,
                 .diameter = 1e-4,
                 .density = 1000,
                 .youngs_modulus = 1e7,
                 .poisson_ratio = 0.33,
                 .restitution = 0.9,
                 .friction = 0.3};
  s.rim_shear_rate = 50.0;
  s.radial_cells = 4;
  s.azimuthal_cells = 8;
  s.axial_cells = 2;
  s.dem_time_step = 1e-6;
  s.coupling.coupling_interval = 50;
  s.steady = {.strain_window = 0.05, .relative_tolerance = 0.05, .min_strain = 0.1, .max_strain = 0.2};
  s.run_directory = folder.path();
  const SuspensionPoint p = run_point(s);
  EXPECT_DOUBLE_EQ(p.fluid_time_step, 5e-5);
  EXPECT_GE(p.strain, 0.1);
  EXPECT_LE(p.strain, 0.2 + 50.0 * 5e-5);
  EXPECT_EQ(p.series.size(), static_cast<std::size_t>(p.cost.steps));
  EXPECT_GT(p.torque_fluid, 0.0);
  EXPECT_NEAR(p.torque, p.torque_fluid + p.torque_contact, 1e-9 * std::abs(p.torque));
  EXPECT_GT(p.particles, 50);
  EXPECT_LT(p.void_fraction.relative_error, 1e-13);
  EXPECT_GT(p.cost.dem, 0.0);
  // Creeping single-phase torque π μ Ω R⁴ / (2H): the suspension is at least that (φ = 3 %).
  const double omega = 50.0 * 0.0005 / 0.002;
  const double newtonian = std::numbers::pi * 1e-3 * omega * std::pow(0.002, 4) / (2 * 0.0005);
  EXPECT_GT(p.torque_fluid, 0.9 * newtonian);
  EXPECT_LT(p.torque_fluid, 1.3 * newtonian);
}

// φ = 0: the fluid alone on the same grid and step, converging to the creeping torque here (Re small).
TEST(SuspensionPoint, ZeroVolumeFractionRunsTheFluidAlone) {
  SuspensionPointSettings s;
  s.geometry = {.radius = 0.002, .gap = 0.0005};
  s.fluid = {.density = 1000, .rheology = testing::newtonian(1e-2)};
  s.particles = {.volume_fraction = 0.0, .diameter = 1e-4, .density = 1000};
  s.rim_shear_rate = 10.0;
  s.radial_cells = 4;
  s.azimuthal_cells = 4;
  s.axial_cells = 2;
  s.dem_time_step = 1e-6;
  s.coupling.coupling_interval = 100;
  s.steady = {.strain_window = 0.05, .relative_tolerance = 1e-3, .min_strain = 0.1, .max_strain = 1.0};
  const SuspensionPoint p = run_point(s);
  const double omega = 10.0 * 0.0005 / 0.002;
  const double newtonian = std::numbers::pi * 1e-2 * omega * std::pow(0.002, 4) / (2 * 0.0005);
  EXPECT_TRUE(p.converged);
  EXPECT_EQ(p.particles, 0);
  EXPECT_DOUBLE_EQ(p.fluid_time_step, 1e-4);
  EXPECT_NEAR(p.torque, newtonian, 1e-3 * newtonian);
  EXPECT_EQ(p.torque_contact, 0.0);
}

}  // namespace
}  // namespace rheosim::coupling
