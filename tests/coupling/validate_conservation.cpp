// Validation: in a coupled LIGGGHTS ↔ TransientSolver run with 300 particles in
// a sheared gap — some on the axis, some touching the plates and the rim, all moving and crossing
// cell faces — the particle volume carried by the grid equals the total particle volume and the
// drag on the particles equals minus the drag source given to the fluid, to round-off, at every
// coupling step, for both void-fraction schemes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "coupling_test_support.hpp"
#include "rheosim/coupling/coupler.hpp"

namespace rheosim::coupling {
namespace {

constexpr double pi = std::numbers::pi;

class Validation : public ::testing::Test {
 protected:
  testing::RunFolder folder_;
};

TEST_F(Validation, VolumeAndMomentumAreConservedEveryStep) {
  const double radius = 0.005, gap = 0.001, d = 1e-4;
  for (const char* scheme : {"centre", "divided"}) {
    fluid::TransientParams fp;
    fp.grid = {.radius = radius, .gap = gap, .radial_cells = 8, .azimuthal_cells = 8, .axial_cells = 4};
    fp.density = 1000;
    fp.rheology = testing::newtonian(1e-3);
    fp.top_angular_velocity = 2.0;
    fluid::TransientSolver fluid(fp);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<testing::BoxParticle> particles;
    for (int p = 0; p < 300; ++p) {
      // Radii up to the rim and heights from plate to plate (centres 0.55 d/2 .. inside).
      const double r = std::sqrt(u01(rng)) * (radius - 0.3 * d), t = 2 * pi * u01(rng);
      const double z = 0.3 * d + u01(rng) * (gap - 0.6 * d);
      particles.push_back({.x = r * std::cos(t),
                           .y = r * std::sin(t),
                           .z = z,
                           .diameter = d,
                           .density = 1500,
                           .vx = 2e-3 * (u01(rng) - 0.5),
                           .vy = 2e-3 * (u01(rng) - 0.5),
                           .vz = 1e-3 * (u01(rng) - 0.5)});
    }
    particles.push_back({.x = 0.0, .y = 0.0, .z = 0.5 * gap, .diameter = d, .density = 1500, .vx = 1e-3});
    dem::Engine engine({.run_directory = folder_.path() / scheme});
    testing::make_box(engine, radius, gap, 1e-5, 0.0, particles);
    CouplerSettings settings;
    settings.coupling_interval = 10;
    settings.fluid_time_step = 1e-4;
    settings.void_fraction = scheme;
    settings.void_fraction_floor = 0.05;
    Coupler coupler(settings, engine, fluid);
    double worst_volume = 0.0, worst_momentum = 0.0;
    std::size_t mapped = 0;
    for (int step = 0; step < 40; ++step) {
      const CouplingStepReport& r = coupler.step();
      worst_volume = std::max(worst_volume, r.void_fraction.relative_error);
      worst_momentum = std::max(worst_momentum, r.balance.relative_error);
      mapped = std::max(mapped, r.void_fraction.mapped_points);
      EXPECT_EQ(r.void_fraction.unplaced_volume, 0.0);
    }
    const CostSplit& c = coupler.cost();
    std::printf(
        "%s: worst relative volume error %.2e, worst relative momentum error %.2e, %zu points mapped back; "
        "cost per step DEM %.3f ms, void fraction %.3f ms, forces %.3f ms, fluid %.3f ms\n",
        scheme, worst_volume, worst_momentum, mapped, 1e3 * c.dem / c.steps, 1e3 * c.void_fraction / c.steps,
        1e3 * c.forces / c.steps, 1e3 * c.fluid / c.steps);
    EXPECT_LT(worst_volume, 1e-13) << scheme;
    EXPECT_LT(worst_momentum, 1e-13) << scheme;
    if (std::string(scheme) == "divided") {
      EXPECT_GT(mapped, 0u);
    }
    EXPECT_EQ(c.steps, 40);
  }
}

}  // namespace
}  // namespace rheosim::coupling
