// Two-sphere and sphere–plate squeeze in LIGGGHTS with the near-field hook:
// spheres pressed together (or onto a plate) by a constant force F in a quiescent liquid close
// the gap along the quasi-static trajectory dh/dt = −F / (6πμa X^A(ξ)) with the analytic
// near-contact resistance (Jeffrey & Onishi 1984 for two equal spheres, X^A = 1/(4ξ) + (9/40)
// ln(1/ξ); Cox & Brenner 1967 for a plate, X^A = 1/ξ + (1/5) ln(1/ξ)), ξ = (h + δ)/a. The DEM
// step is 10–40 × the explicit stability limit of the squeeze at the final gap, so this also
// checks the implicit update inside LIGGGHTS' velocity Verlet (dem::Engine's step callback).
// The gap is sampled along the run and compared with an RK4 solution of the ODE.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <vector>

#include "coupling_test_support.hpp"
#include "near_field_test_support.hpp"
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/dem/engine.hpp"

namespace rheosim::coupling {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double a = 1e-4, rho = 1000.0, mu = 1.0, force = 1e-5, roughness = 1e-3;

double rk4_gap(double h0, double t_end, const std::function<double(double)>& closing_speed) {
  double h = h0;
  const int steps = 100000;
  const double dt = t_end / steps;
  for (int i = 0; i < steps; ++i) {
    const double k1 = -closing_speed(h), k2 = -closing_speed(h + 0.5 * dt * k1);
    const double k3 = -closing_speed(h + 0.5 * dt * k2), k4 = -closing_speed(h + dt * k3);
    h += dt / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return h;
}

TEST(ValidateLubricationSqueeze, TwoEqualSpheresFollowJeffreyOnishi) {
  testing::RunFolder folder;
  dem::Engine engine({.run_directory = folder.path()});
  const double h0 = 0.2 * a, dt = 2e-6;
  testing::make_sphere_box(engine, {.low = {-1e-3, -1e-3, -1e-3}, .high = {1e-3, 1e-3, 1e-3}, .time_step = dt},
                           {{.x = -(a + h0 / 2), .y = 0, .z = 0, .radius = a, .density = rho},
                            {.x = a + h0 / 2, .y = 0, .z = 0, .radius = a, .density = rho}});
  engine.run(0);
  // Force +F on the left sphere (id 1), −F on the right one.
  const std::vector<dem::ParticleId> ids{1, 2};
  engine.set_external_forces(ids, std::vector<double>{force, 0, 0, -force, 0, 0});
  NearFieldSettings settings;
  settings.terms = {.lubrication = true};
  NearFieldStepHook hook(engine, make_near_field_model(settings, testing::newtonian(mu)), {}, {});

  const auto closing_speed = [](double h) {
    const double xi = (h + roughness * a) / a;
    // F = k (U₁ − U₂)·n with k = 6πμa X^A: the gap closes at F/k.
    return force / (6.0 * pi * mu * a * (0.25 / xi + 9.0 / 40.0 * std::log(1.0 / xi)));
  };
  const auto gap_now = [&] {
    const auto x = engine.positions();
    return std::abs(x[3] - x[0]) - 2.0 * a;
  };
  const int block = 1000;
  double worst = 0.0, final_gap = 0.0;
  for (int b = 1; b <= 8; ++b) {
    engine.run(block);
    const double h = gap_now();
    const double reference = rk4_gap(h0, b * block * dt, closing_speed);
    worst = std::max(worst, std::abs(h / reference - 1.0));
    final_gap = h;
    RecordProperty(fmt::format("gap_{}", b), fmt::format("{:.6e} (reference {:.6e})", h, reference));
  }
  std::printf("two spheres: final h/a = %.4e, worst |h/h_ref − 1| = %.3e\n", final_gap / a, worst);
  EXPECT_LT(final_gap, 0.02 * a);  // reached the stiff regime
  EXPECT_LT(worst, 0.01);
  // δt against the explicit limit at the final gap.
  const auto limit = make_near_field_model(settings, testing::newtonian(mu))
                         ->stable_time_step({.positions = engine.positions(),
                                             .velocities = engine.velocities(),
                                             .angular_velocities = engine.angular_velocities(),
                                             .radii = engine.radii()},
                                            rho);
  std::printf("two spheres: δt / explicit limit = %.1f\n", dt / limit);
  EXPECT_GT(dt / limit, 5.0);
}

TEST(ValidateLubricationSqueeze, SphereOntoPlateFollowsCoxBrenner) {
  testing::RunFolder folder;
  dem::Engine engine({.run_directory = folder.path()});
  const double h0 = 0.2 * a, dt = 5e-6;
  testing::make_sphere_box(engine, {.low = {-1e-3, -1e-3, -1e-4}, .high = {1e-3, 1e-3, 1e-3}, .time_step = dt},
                           {{.x = 0, .y = 0, .z = a + h0, .radius = a, .density = rho}});
  engine.run(0);
  engine.set_external_forces(std::vector<double>{0, 0, -force});
  NearFieldSettings settings;
  settings.terms = {.lubrication = true};
  NearFieldScene scene;
  scene.plates.push_back({.z = 0.0, .faces_up = true, .velocity_at = {}});
  NearFieldStepHook hook(engine, make_near_field_model(settings, testing::newtonian(mu)), scene, {});
  const auto closing_speed = [](double h) {
    const double xi = (h + roughness * a) / a;
    return force / (6.0 * pi * mu * a * (1.0 / xi + 0.2 * std::log(1.0 / xi)));
  };
  const int block = 1000;
  double worst = 0.0, h = h0;
  for (int b = 1; b <= 10; ++b) {
    engine.run(block);
    h = engine.positions()[2] - a;
    const double reference = rk4_gap(h0, b * block * dt, closing_speed);
    worst = std::max(worst, std::abs(h / reference - 1.0));
  }
  const auto means = hook.take_means();
  std::printf("sphere–plate: final h/a = %.4e, worst |h/h_ref − 1| = %.3e\n", h / a, worst);
  EXPECT_LT(h, 0.02 * a);
  EXPECT_LT(worst, 0.01);
  // The plate carries the load: mean plate force ≈ F downwards once quasi-static.
  EXPECT_NEAR(hook.last().plate_forces[0][2], -force, 0.02 * force);
  EXPECT_EQ(means.steps, 10 * block + 1);
}

}  // namespace
}  // namespace rheosim::coupling
