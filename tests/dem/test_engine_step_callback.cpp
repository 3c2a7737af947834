// dem::Engine::set_step_force_callback: the callback runs on every DEM step, sees
// LIGGGHTS' current arrays, and the force and torque it returns act on that step. Checked
// against closed forms: a constant callback force gives x = x0 + F t²/(2m) (velocity Verlet is
// exact for constant acceleration), a callback torque gives ω = T t / I with I = (2/5) m r², a
// callback force adds to set_external_forces(), and a linear damping force F = −c v applied
// through the callback decays the velocity like the discrete map of the scheme.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "rheosim/dem/contact.hpp"
#include "rheosim/dem/engine.hpp"

namespace rheosim::dem {
namespace {

namespace fs = std::filesystem;

const ElasticSphere seed_particle{.radius = 100e-6, .density = 1000.0, .youngs_modulus = 3e9, .poisson_ratio = 0.33};

double seed_mass() { return 4.0 / 3.0 * std::numbers::pi * std::pow(seed_particle.radius, 3) * seed_particle.density; }

class EngineStepCallbackTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("rheosim_test_engine_step_{}", ::getpid()) / info->name();
    fs::remove_all(dir_);
  }
  void TearDown() override {  // a failed test keeps its run folder
    if (!HasFailure()) fs::remove_all(dir_);
    std::error_code not_empty;
    fs::remove(dir_.parent_path(), not_empty);
  }

  // A 10 mm box, seed material, no gravity, particles far from each other and the walls.
  void make_box(Engine& engine, const std::vector<std::array<double, 3>>& positions) const {
    engine.commands({
        "atom_style granular",
        "atom_modify map array",
        "boundary f f f",
        "newton off",
        "communicate single vel yes",
        "units si",
        "region box block -0.005 0.005 -0.005 0.005 0.0 0.01 units box",
        "create_box 1 box",
        "neighbor 2e-5 bin",
        "neigh_modify delay 0",
        "hard_particles yes",
        "fix m1 all property/global youngsModulus peratomtype 3e9",
        "fix m2 all property/global poissonsRatio peratomtype 0.33",
        "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.9",
        "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
        "pair_style gran model hertz tangential history",
        "pair_coeff * *",
        "fix integrate all nve/sphere",
    });
    engine.command(fmt::format("timestep {:.17g}", rayleigh_time_step(seed_particle)));
    for (const auto& x : positions)
      engine.command(fmt::format("create_atoms 1 single {:.17g} {:.17g} {:.17g} units box", x[0], x[1], x[2]));
    engine.command(fmt::format("set group all diameter {:.17g} density {:.17g}", 2.0 * seed_particle.radius,
                               seed_particle.density));
  }

  fs::path dir_;
};

TEST_F(EngineStepCallbackTest, ConstantForceMovesParticleAsFOverM) {
  Engine engine({.run_directory = dir_});
  make_box(engine, {{0.0, 0.0, 0.005}});
  const std::array<double, 3> force{2e-6, -1e-6, 3e-6};    // N
  const std::array<double, 3> torque{1e-14, 0.0, -2e-14};  // N·m
  int calls = 0;
  engine.set_step_force_callback([&](const StepState& s, std::span<double> f, std::span<double> t) {
    ++calls;
    ASSERT_EQ(s.size(), 1U);
    EXPECT_DOUBLE_EQ(s.masses[0], seed_mass());
    EXPECT_DOUBLE_EQ(s.radii[0], seed_particle.radius);
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(f[k], 0.0);  // zeroed before each call
      f[k] = force[k];
      t[k] = torque[k];
    }
  });
  constexpr int steps = 2000;
  engine.run(steps / 2);
  engine.run(steps / 2);  // the second run skips setup
  // One call per step, plus one in the setup of the first run.
  EXPECT_EQ(calls, steps + 1);

  const double m = seed_mass();
  const double inertia = 0.4 * m * seed_particle.radius * seed_particle.radius;
  const double t = steps * rayleigh_time_step(seed_particle);
  const auto x = engine.positions();
  const auto v = engine.velocities();
  const auto omega = engine.angular_velocities();
  const std::array<double, 3> x0{0.0, 0.0, 0.005};
  for (std::size_t k = 0; k < 3; ++k) {
    const double a = force[k] / m;
    EXPECT_NEAR(x[k], x0[k] + 0.5 * a * t * t, 1e-9 * std::abs(0.5 * a * t * t) + 1e-15);
    EXPECT_NEAR(v[k], a * t, 1e-9 * std::abs(a * t));
    EXPECT_NEAR(omega[k], torque[k] / inertia * t, 1e-9 * std::abs(torque[k] / inertia * t) + 1e-12);
  }
}

TEST_F(EngineStepCallbackTest, CallbackSeesCurrentPositionsAndStepNumbers) {
  Engine engine({.run_directory = dir_});
  make_box(engine, {{-0.002, 0.0, 0.005}, {0.002, 0.0, 0.005}});
  engine.command("velocity all set 0.5 0.0 -0.25 units box");
  std::vector<std::int64_t> steps_seen;
  std::vector<double> last_positions;
  engine.set_step_force_callback([&](const StepState& s, std::span<double>, std::span<double>) {
    steps_seen.push_back(s.step);
    last_positions.assign(s.positions.begin(), s.positions.end());
    EXPECT_DOUBLE_EQ(s.time_step, rayleigh_time_step(seed_particle));
    EXPECT_NEAR(s.time, static_cast<double>(s.step) * s.time_step, 1e-12 * s.time_step * (1.0 + s.step));
  });
  engine.run(50);
  ASSERT_EQ(steps_seen.size(), 51U);
  for (std::size_t i = 0; i < steps_seen.size(); ++i) EXPECT_EQ(steps_seen[i], static_cast<std::int64_t>(i));
  // In the last call the positions were already those at the end of the run.
  const auto x = engine.positions();
  ASSERT_EQ(last_positions.size(), x.size());
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_DOUBLE_EQ(last_positions[i], x[i]);
  const double dx = 0.5 * 50 * rayleigh_time_step(seed_particle);
  EXPECT_NEAR(x[0], x[0] > 0 ? 0.002 + dx : -0.002 + dx, 1e-15);
}

TEST_F(EngineStepCallbackTest, AddsToStoredExternalForceWhichItSees) {
  Engine engine({.run_directory = dir_});
  make_box(engine, {{0.0, 0.0, 0.005}});
  const std::array<double, 3> stored{1e-6, 0.0, 0.0};
  const std::array<double, 3> added{0.0, 0.0, -2e-6};
  engine.set_external_forces(stored);
  engine.set_step_force_callback([&](const StepState& s, std::span<double> f, std::span<double>) {
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_DOUBLE_EQ(s.forces[k], stored[k]);  // no contacts, no gravity: the known force is the stored one
      f[k] = added[k];
    }
  });
  constexpr int steps = 1000;
  engine.run(steps);
  const double t = steps * rayleigh_time_step(seed_particle);
  const auto v = engine.velocities();
  for (std::size_t k = 0; k < 3; ++k) {
    const double a = (stored[k] + added[k]) / seed_mass();
    EXPECT_NEAR(v[k], a * t, 1e-9 * std::abs(a * t) + 1e-15);
  }
}

// Linear damping F = −c v^(n+1/2) in post_force gives the leapfrog map on half-step velocities
// v^(n+3/2) = (1 − c δt/m) v^(n+1/2); after N steps from v0 (the setup call sees v0 and the
// first half-kick uses it) the velocity is known in closed form.
TEST_F(EngineStepCallbackTest, DampingCallbackFollowsDiscreteDecay) {
  Engine engine({.run_directory = dir_});
  make_box(engine, {{0.0, 0.0, 0.005}});
  constexpr double v0 = 0.01;
  engine.command(fmt::format("velocity all set {} 0 0 units box", v0));
  const double m = seed_mass();
  const double dt = rayleigh_time_step(seed_particle);
  const double c = 0.05 * m / dt;  // 5 % per step
  engine.set_step_force_callback([&](const StepState& s, std::span<double> f, std::span<double>) {
    for (std::size_t k = 0; k < 3; ++k) f[k] = -c * s.velocities[k];
  });
  engine.run(1);  // setup: F = −c v0, then one step
  // After the setup call and one step: v^(1/2) = v0 (1 − cδt/(2m)); at the end of step 1 the
  // callback sees v^(1/2) and the full-step v^1 = v^(1/2) (1 − cδt/(2m)).
  const double r = c * dt / m;
  EXPECT_NEAR(engine.velocities()[0], v0 * (1 - 0.5 * r) * (1 - 0.5 * r), 1e-15);
  engine.run(99);
  // v^(n+1/2) = v0 (1 − r/2)(1 − r)^n, and the full step adds one more half-kick.
  const double expected = v0 * (1 - 0.5 * r) * std::pow(1 - r, 99) * (1 - 0.5 * r);
  EXPECT_NEAR(engine.velocities()[0], expected, 1e-12 * v0);
}

TEST_F(EngineStepCallbackTest, ExceptionInCallbackFailsTheEngine) {
  Engine engine({.run_directory = dir_});
  make_box(engine, {{0.0, 0.0, 0.005}});
  engine.set_step_force_callback(
      [](const StepState&, std::span<double>, std::span<double>) { throw std::runtime_error("model refused"); });
  EXPECT_THROW(engine.run(5), EngineError);
  EXPECT_TRUE(engine.has_failed());
}

TEST_F(EngineStepCallbackTest, EmptyCallbackRemovesTheHook) {
  Engine engine({.run_directory = dir_});
  make_box(engine, {{0.0, 0.0, 0.005}});
  int calls = 0;
  engine.set_step_force_callback([&](const StepState&, std::span<double> f, std::span<double>) {
    ++calls;
    f[2] = 1e-6;
  });
  engine.run(10);
  EXPECT_EQ(calls, 11);
  engine.set_step_force_callback({});
  engine.run(10);
  EXPECT_EQ(calls, 11);
}

}  // namespace
}  // namespace rheosim::dem
