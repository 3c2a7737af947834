// dem::Engine against closed forms: free fall under gravity, acceleration F/m and angular
// acceleration T/I from the external-force hook; extraction of the particle arrays; LIGGGHTS
// output in the run folder and not on stdout; LIGGGHTS errors as exceptions that leave the
// process running. Particles are the CD seed §4 ones (r = 100 µm, ρ = 1000 kg/m³, E = 3 GPa,
// ν = 0.33, e = 0.9, μ = 0.3), time step 0.2 t_R from contact.hpp.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "rheosim/dem/contact.hpp"
#include "rheosim/dem/engine.hpp"
#include "rheosim/dem/mpi_session.hpp"

namespace rheosim::dem {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

const ElasticSphere seed_particle{.radius = 100e-6, .density = 1000.0, .youngs_modulus = 3e9, .poisson_ratio = 0.33};
constexpr double gravity = 9.81;  // m/s²

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class EngineTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("rheosim_test_engine_{}", ::getpid()) / info->name();
    fs::remove_all(dir_);
  }
  // A failed test keeps its run folder (and LIGGGHTS' logs) for inspection.
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
    std::error_code not_empty;
    fs::remove(dir_.parent_path(), not_empty);
  }

  [[nodiscard]] Engine::Params params(const std::string& sub = "run") const { return {.run_directory = dir_ / sub}; }

  // A 10 mm cube with fixed walls, the seed material, Hertz contact with tangential history.
  static void make_box(Engine& engine) {
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
        "hard_particles yes",  // LIGGGHTS refuses E > 1e9 Pa in SI units without it
        "fix m1 all property/global youngsModulus peratomtype 3e9",
        "fix m2 all property/global poissonsRatio peratomtype 0.33",
        "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.9",
        "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
        "pair_style gran model hertz tangential history",
        "pair_coeff * *",
        "fix integrate all nve/sphere",
    });
    engine.command(fmt::format("timestep {:.17g}", rayleigh_time_step(seed_particle)));
  }

  static void add_particle(Engine& engine, double x, double y, double z) {
    engine.command(fmt::format("create_atoms 1 single {:.17g} {:.17g} {:.17g} units box", x, y, z));
  }

  // Seed diameter and density for every particle (sets the mass, too).
  static void set_seed_material(Engine& engine) {
    engine.command(fmt::format("set group all diameter {:.17g} density {:.17g}", 2.0 * seed_particle.radius,
                               seed_particle.density));
  }

  fs::path dir_;
};

TEST_F(EngineTest, OpensAndClosesTwiceInOneProcess) {
  for (int i = 0; i < 2; ++i) {
    Engine engine(params(fmt::format("run{}", i)));
    make_box(engine);
    add_particle(engine, 0.0, 0.0, 0.005);
    engine.run(10);
    EXPECT_EQ(engine.step(), 10);
    EXPECT_EQ(engine.particle_count(), 1U);
    EXPECT_FALSE(engine.has_failed());
  }
  EXPECT_TRUE(MpiSession::is_running());
  EXPECT_EQ(MpiSession::world_size(), 1);
}

TEST_F(EngineTest, ExtractsParticleArrays) {
  Engine engine(params());
  make_box(engine);
  add_particle(engine, -0.002, 0.001, 0.003);
  add_particle(engine, 0.002, -0.001, 0.006);
  set_seed_material(engine);
  engine.command("velocity all set 0.1 -0.2 0.3 units box");
  engine.run(0);

  ASSERT_EQ(engine.particle_count(), 2U);
  EXPECT_EQ(engine.total_particle_count(), 2);
  const auto ids = engine.ids();
  const auto x = engine.positions();
  const auto v = engine.velocities();
  const auto omega = engine.angular_velocities();
  const auto radii = engine.radii();
  ASSERT_EQ(ids.size(), 2U);
  ASSERT_EQ(x.size(), 6U);
  ASSERT_EQ(v.size(), 6U);
  ASSERT_EQ(omega.size(), 6U);
  ASSERT_EQ(radii.size(), 2U);
  for (std::size_t i = 0; i < 2; ++i) {
    const bool first = ids[i] == 1;
    EXPECT_TRUE(ids[i] == 1 || ids[i] == 2);
    EXPECT_DOUBLE_EQ(x[3 * i + 0], first ? -0.002 : 0.002);
    EXPECT_DOUBLE_EQ(x[3 * i + 1], first ? 0.001 : -0.001);
    EXPECT_DOUBLE_EQ(x[3 * i + 2], first ? 0.003 : 0.006);
    EXPECT_DOUBLE_EQ(v[3 * i + 0], 0.1);
    EXPECT_DOUBLE_EQ(v[3 * i + 1], -0.2);
    EXPECT_DOUBLE_EQ(v[3 * i + 2], 0.3);
    for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(omega[3 * i + k], 0.0);  // spin: see the torque test
    EXPECT_DOUBLE_EQ(radii[i], seed_particle.radius);
  }
  EXPECT_EQ(engine.step(), 0);
  EXPECT_DOUBLE_EQ(engine.time_step(), rayleigh_time_step(seed_particle));
  EXPECT_DOUBLE_EQ(engine.time(), 0.0);
}

TEST_F(EngineTest, EmptyBoxHasEmptyViews) {
  Engine engine(params());
  make_box(engine);
  EXPECT_EQ(engine.particle_count(), 0U);
  EXPECT_TRUE(engine.positions().empty());
  EXPECT_TRUE(engine.radii().empty());
  EXPECT_TRUE(engine.ids().empty());
}

// Velocity Verlet is exact for a constant acceleration, so x(t) = x0 − g t²/2 holds to
// round-off; the tolerance (1e-12 m, about 2e-6 of the fall) only absorbs that round-off.
TEST_F(EngineTest, FreeFallFollowsClosedForm) {
  Engine engine(params());
  make_box(engine);
  constexpr double z0 = 0.005;
  add_particle(engine, 0.0, 0.0, z0);
  set_seed_material(engine);
  engine.command("fix gravity all gravity 9.81 vector 0.0 0.0 -1.0");

  constexpr int steps = 5000;
  engine.run(steps / 2);
  engine.run(steps / 2);  // second run skips LIGGGHTS' setup (pre no post no)
  const double dt = rayleigh_time_step(seed_particle);
  const double t = steps * dt;
  EXPECT_EQ(engine.step(), steps);
  EXPECT_NEAR(engine.time(), t, 1e-15 * t);

  const auto x = engine.positions();
  const auto v = engine.velocities();
  ASSERT_EQ(x.size(), 3U);
  EXPECT_NEAR(x[2], z0 - 0.5 * gravity * t * t, 1e-12);  // fall ≈ 4.96e-7 m
  EXPECT_NEAR(v[2], -gravity * t, 1e-12 * gravity * t);
  EXPECT_DOUBLE_EQ(x[0], 0.0);
  EXPECT_DOUBLE_EQ(x[1], 0.0);
  EXPECT_DOUBLE_EQ(v[0], 0.0);
  EXPECT_DOUBLE_EQ(v[1], 0.0);
}

// a = F/m and dω/dt = T/I with I = (2/5) m r² for a solid sphere.
TEST_F(EngineTest, ExternalForceAndTorqueAccelerateAsFOverM) {
  Engine engine(params());
  make_box(engine);
  constexpr std::array<double, 3> x0{0.0, 0.0, 0.005};
  add_particle(engine, x0[0], x0[1], x0[2]);
  set_seed_material(engine);

  const std::array<double, 3> force{1e-6, -2e-6, 3e-6};    // N
  const std::array<double, 3> torque{0.0, 2e-14, -1e-14};  // N·m
  engine.set_external_forces(force, torque);

  constexpr int steps = 1000;
  engine.run(steps / 2);
  engine.run(steps / 2);
  const double t = steps * rayleigh_time_step(seed_particle);
  const double m = mass(seed_particle);
  const double inertia = 0.4 * m * seed_particle.radius * seed_particle.radius;

  const auto x = engine.positions();
  const auto v = engine.velocities();
  const auto omega = engine.angular_velocities();
  for (std::size_t k = 0; k < 3; ++k) {
    const double a = force[k] / m;  // up to 716 m/s²
    EXPECT_NEAR(v[k], a * t, 1e-9 * std::abs(a) * t) << "component " << k;
    EXPECT_NEAR(x[k], x0[k] + 0.5 * a * t * t, 1e-12) << "component " << k;
    EXPECT_NEAR(omega[k], torque[k] / inertia * t, 1e-9 * 2e-14 / inertia * t) << "component " << k;
  }

  // Cleared: no more acceleration, the particle keeps its velocity.
  const std::vector<double> v_before(v.begin(), v.end());
  engine.clear_external_forces();
  engine.run(100);
  const auto v_after = engine.velocities();
  for (std::size_t k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(v_after[k], v_before[k]);
}

// A force changed between two runs acts from the change on, also when the second run skips
// LIGGGHTS' setup: v = a t1 + 2a t2 exactly (velocity Verlet, piecewise-constant force).
TEST_F(EngineTest, ChangedForceActsFromTheChangeOn) {
  Engine engine(params());
  make_box(engine);
  add_particle(engine, 0.0, 0.0, 0.005);
  set_seed_material(engine);
  const std::array<double, 3> force{0.0, 0.0, 1e-6};
  const std::array<double, 3> doubled{0.0, 0.0, 2e-6};
  constexpr int steps1 = 300;
  constexpr int steps2 = 200;
  engine.set_external_forces(force);
  engine.run(steps1);
  engine.set_external_forces(doubled);
  engine.run(steps2);
  const double dt = rayleigh_time_step(seed_particle);
  const double a = force[2] / mass(seed_particle);
  const double expected = a * steps1 * dt + 2.0 * a * steps2 * dt;
  EXPECT_NEAR(engine.velocities()[2], expected, 1e-9 * expected);
}

TEST_F(EngineTest, ExternalForceByIdReachesOnlyThatParticle) {
  Engine engine(params());
  make_box(engine);
  add_particle(engine, -0.002, 0.0, 0.005);
  add_particle(engine, 0.002, 0.0, 0.005);
  set_seed_material(engine);

  const std::array<ParticleId, 1> target{2};
  const std::array<double, 3> force{0.0, 0.0, 5e-6};
  engine.set_external_forces(target, force);
  constexpr int steps = 500;
  engine.run(steps);
  const double t = steps * rayleigh_time_step(seed_particle);

  const auto ids = engine.ids();
  const auto v = engine.velocities();
  ASSERT_EQ(ids.size(), 2U);
  for (std::size_t i = 0; i < 2; ++i) {
    const double expected = ids[i] == 2 ? force[2] / mass(seed_particle) * t : 0.0;
    EXPECT_NEAR(v[3 * i + 2], expected, 1e-9 * force[2] / mass(seed_particle) * t) << "id " << ids[i];
  }

  const std::array<ParticleId, 1> missing{7};
  EXPECT_THROW(engine.set_external_forces(missing, force), std::invalid_argument);
  const std::array<double, 2> wrong_size{1.0, 2.0};
  EXPECT_THROW(engine.set_external_forces(wrong_size), std::invalid_argument);
  const std::array<double, 6> not_finite{0.0, 0.0, NAN, 0.0, 0.0, 0.0};
  EXPECT_THROW(engine.set_external_forces(not_finite), std::invalid_argument);
  EXPECT_FALSE(engine.has_failed());
}

// Also nothing on stderr, and nothing in the working directory (LIGGGHTS' defaults would be
// log.liggghts and log.cite there).
TEST_F(EngineTest, WritesLogIntoRunFolderAndNothingToStdout) {
  const fs::path cwd = dir_ / "cwd";
  fs::create_directories(cwd);
  const fs::path previous_cwd = fs::current_path();
  fs::current_path(cwd);
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  fs::path log;
  {
    Engine engine(params("quiet"));
    log = engine.log_path();
    make_box(engine);
    add_particle(engine, 0.0, 0.0, 0.005);
    engine.command("thermo 100");
    engine.run(200);
  }
  {
    Engine second(params("quiet2"));  // later instances used to print style collisions to stderr
    make_box(second);
  }
  const std::string out = ::testing::internal::GetCapturedStdout();
  const std::string err = ::testing::internal::GetCapturedStderr();
  fs::current_path(previous_cwd);
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");
  EXPECT_TRUE(fs::is_empty(cwd));
  EXPECT_EQ(log, dir_ / "quiet" / "liggghts.log");
  ASSERT_TRUE(fs::exists(log));
  const std::string text = slurp(log);
  EXPECT_THAT(text, HasSubstr("LIGGGHTS ("));
  EXPECT_THAT(text, HasSubstr("pair_style gran model hertz tangential history"));  // echoed
  EXPECT_THAT(text, HasSubstr("Loop time"));
}

TEST_F(EngineTest, BadCommandThrowsAndTheProcessGoesOn) {
  const std::string bad = "fix 1 all nonexistent_style";
  fs::path log;
  {
    Engine engine(params("bad"));
    log = engine.log_path();
    make_box(engine);
    try {
      engine.command(bad);
      FAIL() << "expected EngineError";
    } catch (const EngineError& e) {
      EXPECT_THAT(e.what(), AllOf(HasSubstr(bad), HasSubstr("Invalid fix style")));
      EXPECT_EQ(e.command(), bad);
      EXPECT_THAT(e.liggghts_message(), HasSubstr("Invalid fix style"));
      EXPECT_TRUE(e.is_collective());
    }
    EXPECT_TRUE(engine.has_failed());
    ASSERT_TRUE(engine.failure().has_value());
    EXPECT_EQ(engine.failure()->command(), bad);

    // Every later call says why the engine is unusable.
    try {
      engine.run(1);
      FAIL() << "expected EngineError";
    } catch (const EngineError& e) {
      EXPECT_THAT(e.what(), AllOf(HasSubstr("failed earlier"), HasSubstr(bad), HasSubstr("new Engine")));
    }
    EXPECT_THROW(engine.command("run 1"), EngineError);
    EXPECT_THROW((void)engine.positions(), EngineError);
    EXPECT_THROW((void)engine.particle_count(), EngineError);
    EXPECT_THROW(engine.clear_external_forces(), EngineError);
  }  // closing a failed engine must not crash

  const std::string text = slurp(log);
  EXPECT_THAT(text, HasSubstr("ERROR: Invalid fix style"));
  EXPECT_THAT(text, HasSubstr("abandoned"));

  // The process, MPI and LIGGGHTS keep working: a new engine runs normally.
  Engine next(params("next"));
  make_box(next);
  add_particle(next, 0.0, 0.0, 0.005);
  next.run(10);
  EXPECT_EQ(next.step(), 10);
}

TEST_F(EngineTest, ErrorInsideRunThrows) {
  Engine engine(params());
  make_box(engine);
  add_particle(engine, 0.0, 0.0, 0.0099);
  set_seed_material(engine);
  engine.command("velocity all set 0.0 0.0 100.0 units box");  // leaves the fixed box at once
  engine.commands({"thermo 1", "thermo_modify lost error"});   // LIGGGHTS ignores lost particles by default
  try {
    engine.run(100);
    FAIL() << "expected EngineError";
  } catch (const EngineError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("run 100"), HasSubstr("Lost atoms")));
  }
  EXPECT_TRUE(engine.has_failed());
}

// Error::one (a single rank's error) and `quit` (which would exit the process) throw, too.
TEST_F(EngineTest, RankLocalErrorAndQuitThrow) {
  {
    Engine engine(params("one"));
    try {
      engine.command("log /nonexistent-rheosim-dir/x.log");
      FAIL() << "expected EngineError";
    } catch (const EngineError& e) {
      EXPECT_THAT(e.liggghts_message(), HasSubstr("Cannot open logfile"));
      EXPECT_FALSE(e.is_collective());
    }
  }
  {
    Engine engine(params("quit"));
    EXPECT_THROW(engine.command("quit"), EngineError);
    EXPECT_TRUE(engine.has_failed());
  }
}

// Global fix outputs (f_ID, f_ID[i]) and equal-style variables changed between runs.
TEST_F(EngineTest, ReadsFixOutputsAndSetsVariables) {
  Engine engine(params());
  make_box(engine);
  add_particle(engine, 0.0, 0.0, 0.005);
  engine.set_equal_variable("rheosim_a", 2.5);
  engine.command("fix avg all ave/time 1 1 1 v_rheosim_a");
  engine.run(1);
  EXPECT_DOUBLE_EQ(engine.fix_scalar("avg"), 2.5);
  engine.set_equal_variable("rheosim_a", -4.0);  // redefined; the run continues without setup
  engine.run(1);
  EXPECT_DOUBLE_EQ(engine.fix_scalar("avg"), -4.0);
  EXPECT_EQ(engine.step(), 2);

  EXPECT_THROW((void)engine.fix_scalar("no_such_fix"), std::invalid_argument);
  EXPECT_THROW((void)engine.fix_vector("avg", 0), std::invalid_argument);  // a scalar-only fix
  EXPECT_THROW((void)engine.fix_vector("avg", -1), std::invalid_argument);
  EXPECT_THROW(engine.set_equal_variable("bad name", 1.0), std::invalid_argument);
  EXPECT_THROW(engine.set_equal_variable("a", NAN), std::invalid_argument);
  EXPECT_FALSE(engine.has_failed());
}

TEST_F(EngineTest, RejectsBadParamsAndMultiLineCommands) {
  EXPECT_THROW(Engine({}), std::invalid_argument);
  EXPECT_THROW(Engine({.run_directory = dir_, .log_file_name = "sub/liggghts.log"}), std::invalid_argument);
  Engine engine(params());
  EXPECT_THROW(engine.command("units si\nboundary f f f"), std::invalid_argument);
  EXPECT_THROW(engine.run(-1), std::invalid_argument);
  EXPECT_FALSE(engine.has_failed());
}

}  // namespace
}  // namespace rheosim::dem
