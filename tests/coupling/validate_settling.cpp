// Validation: a single sphere settling from rest in a Newtonian liquid at rest,
// coupled LIGGGHTS ↔ TransientSolver, reaches the terminal velocity the Di Felice law predicts
// (drag = buoyant weight, the buoyancy coming from the fluid's hydrostatic ∇p through CD eq. 34)
// and, at low Re, Stokes' velocity, both within 2 %.
// Container: a tall non-rotating "gap" (R = 12 mm, H = 24 mm) with cells of 4 mm ≫ d = 0.2 mm,
// so the particle's own disturbance of the fluid in its cell stays small over the run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "coupling_test_support.hpp"
#include "rheosim/coupling/coupler.hpp"

namespace rheosim::coupling {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double g = 9.81;

// Terminal velocity from the drag law: β(v) v = (ρ_p − ρ) V g, by bisection (Di Felice with ε, in the
// ε^(2−χ) form used in di_felice.hpp).
double di_felice_terminal(double d, double rho_p, double rho, double mu, double eps) {
  const double weight = (rho_p - rho) * pi / 6.0 * d * d * d * g;
  const auto drag = [&](double v) {
    const double re = eps * rho * d * v / mu;
    const double chi = 3.7 - 0.65 * std::exp(-std::pow(1.5 - std::log10(re), 2) / 2.0);
    return pi / 8.0 * mu * d * std::pow(eps, 1.0 - chi) * std::pow(4.8 + 0.63 * std::sqrt(re), 2) * v;
  };
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (drag(mid) > weight ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

struct Settling {
  double terminal_velocity, slip, void_fraction, reynolds, wall_time;
};

Settling settle(const std::filesystem::path& folder, double mu, double rho_p, double fluid_dt, int interval,
                double end_time) {
  const double radius = 0.012, gap = 0.024, d = 2e-4, rho = 1000.0;
  fluid::TransientParams fp;
  fp.grid = {.radius = radius, .gap = gap, .radial_cells = 3, .azimuthal_cells = 6, .axial_cells = 6};
  fp.density = rho;
  fp.rheology = testing::newtonian(mu);
  fp.axial_gravity = -g;
  fluid::TransientSolver fluid(fp);
  dem::Engine engine({.run_directory = folder});
  testing::make_box(
      engine, radius, gap, fluid_dt / interval, g,
      {{.x = 0.006 * std::cos(0.5), .y = 0.006 * std::sin(0.5), .z = 0.018, .diameter = d, .density = rho_p}});
  CouplerSettings settings;
  settings.coupling_interval = interval;
  settings.fluid_time_step = fluid_dt;
  settings.void_fraction = "divided";
  settings.particle_density = rho_p;
  Coupler coupler(settings, engine, fluid);
  coupler.run_until(end_time);
  const ParticleSample& s = coupler.samples().at(0);
  return {.terminal_velocity = -s.velocity[2],
          .slip = s.fluid_velocity[2] - s.velocity[2],
          .void_fraction = s.void_fraction,
          .reynolds = s.void_fraction * rho * d * std::abs(s.fluid_velocity[2] - s.velocity[2]) / mu,
          .wall_time = coupler.cost().total()};
}

class Validation : public ::testing::Test {
 protected:
  testing::RunFolder folder_;
};

// Re_p ≈ 0.04, where Di Felice's C_d is within 1.4 % of 24/Re: Stokes' law applies.
TEST_F(Validation, SettlingSphereReachesStokesVelocityAtLowReynolds) {
  const double mu = 0.01, rho_p = 2000.0, d = 2e-4;
  const Settling s = settle(folder_.path(), mu, rho_p, 2e-5, 2, 0.012);  // t_p = ρ_p d²/18μ = 0.44 ms
  const double stokes = (rho_p - 1000.0) * g * d * d / (18.0 * mu);
  const double law = di_felice_terminal(d, rho_p, 1000.0, mu, s.void_fraction);
  std::printf(
      "settling, Re_p = %.4f: v = %.6e m/s, Di Felice %.6e (error %.3f %%), Stokes %.6e (error %.3f %%), "
      "slip error %.2e, ε = %.6f, wall %.2f s\n",
      s.reynolds, s.terminal_velocity, law, 100 * (s.terminal_velocity / law - 1), stokes,
      100 * (s.terminal_velocity / stokes - 1), s.slip / law - 1, s.void_fraction, s.wall_time);
  EXPECT_NEAR(s.terminal_velocity, law, 0.02 * law);
  EXPECT_NEAR(s.terminal_velocity, stokes, 0.02 * stokes);
  EXPECT_NEAR(s.slip, law, 1e-4 * law);  // relative to the fluid it sampled, the drag law holds exactly
}

// Re_p ≈ 3: the drag law's own terminal velocity (Stokes would be 30 % off here).
TEST_F(Validation, SettlingSphereReachesDiFeliceVelocityAtModerateReynolds) {
  const double mu = 1e-3, rho_p = 2000.0, d = 2e-4;
  const Settling s = settle(folder_.path(), mu, rho_p, 1e-4, 5, 0.06);  // t_p = 4.4 ms
  const double law = di_felice_terminal(d, rho_p, 1000.0, mu, s.void_fraction);
  std::printf("settling, Re_p = %.4f: v = %.6e m/s, Di Felice %.6e (error %.3f %%), slip error %.2e, wall %.2f s\n",
              s.reynolds, s.terminal_velocity, law, 100 * (s.terminal_velocity / law - 1), s.slip / law - 1,
              s.wall_time);
  EXPECT_GT(s.reynolds, 1.0);
  EXPECT_NEAR(s.terminal_velocity, law, 0.02 * law);
  EXPECT_NEAR(s.slip, law, 1e-4 * law);
}

}  // namespace
}  // namespace rheosim::coupling
