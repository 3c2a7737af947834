// dem::RheometerScene and dem::place_particles: the placed count matches φ,
// no initial overlaps, a dropped particle rebounds with the restitution coefficient, a particle
// on the rotating plate is carried by it (its contact point moves at Ω r), the rim is
// frictionless, and the contact torque on the top plate is right in sign and size and grows
// with Ω. Small disk: R = 2 mm, H = 0.5 mm, d = 0.1 mm, the CD §4 material (E = 3 GPa,
// ν = 0.33, e = 0.9, μ_c = 0.3, ρ = 1000 kg/m³), δt = 0.3 t_R = 4.8e-8 s.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
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

#include "disk_mesh.hpp"
#include "rheosim/core/units.hpp"
#include "rheosim/dem/contact.hpp"
#include "rheosim/dem/mpi_session.hpp"
#include "rheosim/dem/placement.hpp"
#include "rheosim/dem/rheometer_scene.hpp"

namespace rheosim::dem {
namespace {

namespace fs = std::filesystem;
using core::units::pi;
using ::testing::HasSubstr;

constexpr double plate_radius = 2e-3;  // R [m]
constexpr double gap = 5e-4;           // H [m]
constexpr double diameter = 1e-4;      // d [m]
constexpr double radius = 0.5 * diameter;

ParticleProperties particles(double volume_fraction) {
  return {.volume_fraction = volume_fraction, .diameter = diameter, .density = 1000.0};  // E, ν, e, μ_c: CD §4
}

double particle_mass() { return 1000.0 * core::units::sphere_volume(diameter); }

// Smallest pair distance, brute force (O(N²) is fine for a few thousand particles).
double min_pair_distance(const std::vector<double>& x) {
  const std::size_t n = x.size() / 3;
  double smallest = INFINITY;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double dx = x[3 * i] - x[3 * j];
      const double dy = x[3 * i + 1] - x[3 * j + 1];
      const double dz = x[3 * i + 2] - x[3 * j + 2];
      smallest = std::min(smallest, dx * dx + dy * dy + dz * dz);
    }
  return std::sqrt(smallest);
}

class RheometerSceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("rheosim_test_scene_{}", ::getpid()) / info->name();
    fs::remove_all(dir_);
  }
  // A failed test keeps its run folder (LIGGGHTS' logs, STL, data files) for inspection.
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
    std::error_code not_empty;
    fs::remove(dir_.parent_path(), not_empty);
  }

  [[nodiscard]] RheometerScene::Params params(double volume_fraction, const std::string& sub = "run") const {
    return {.geometry = {.radius = plate_radius, .gap = gap},
            .particles = particles(volume_fraction),
            .gravity = std::nullopt,
            .run_directory = dir_ / sub};
  }

  // Tests that follow one particle read its state on the rank that owns it: one rank only.
  static bool is_parallel() {
    MpiSession::ensure();
    return MpiSession::world_size() > 1;
  }

  fs::path dir_;
};

// ------------------------------------------------------------------------------- placement

// N = round(6 φ R² H / d³): 1200, 3600, 6000 particles.
TEST(Placement, CountMatchesVolumeFraction) {
  for (const double phi : {0.1, 0.3, 0.5}) {
    const auto p = place_particles(
        {.plate_radius = plate_radius, .gap = gap, .diameter = diameter, .volume_fraction = phi, .seed = 3});
    const double expected = phi * pi * plate_radius * plate_radius * gap / core::units::sphere_volume(diameter);
    EXPECT_EQ(p.count, static_cast<std::size_t>(std::llround(expected))) << "φ = " << phi;
    EXPECT_EQ(p.centres.size(), 3 * p.count);
    EXPECT_NEAR(p.volume_fraction, phi, 0.01 * phi) << "φ = " << phi;
    EXPECT_EQ(target_particle_count(plate_radius, gap, diameter, phi), p.count);
    EXPECT_GE(p.lattice_sites, p.count);
    EXPECT_GT(p.capacity_volume_fraction, 0.5);  // six hexagonal layers hold about 0.64
  }
}

// Every pair at least d apart, every centre at least d/2 from both plates and the rim.
TEST(Placement, HasNoOverlaps) {
  for (const double phi : {0.1, 0.3, 0.5}) {
    const auto p = place_particles(
        {.plate_radius = plate_radius, .gap = gap, .diameter = diameter, .volume_fraction = phi, .seed = 11});
    EXPECT_GE(min_pair_distance(p.centres), diameter) << "φ = " << phi;
    for (std::size_t i = 0; i < p.count; ++i) {
      const double x = p.centres[3 * i];
      const double y = p.centres[3 * i + 1];
      const double z = p.centres[3 * i + 2];
      ASSERT_GE(z, radius) << "φ = " << phi << ", particle " << i;
      ASSERT_LE(z, gap - radius) << "φ = " << phi << ", particle " << i;
      ASSERT_LE(std::hypot(x, y), plate_radius - radius) << "φ = " << phi << ", particle " << i;
    }
    // Shaken, not left on the lattice: moves were accepted.
    EXPECT_GT(p.shake_acceptance, 0.1) << "φ = " << phi;
  }
}

// The CD §4 rheometer (R = 15 mm, H = 0.5 mm = 2.5 d): 42 188 particles at φ = 0.5 in three
// square layers.
TEST(Placement, ReachesHalfInTheSeedRheometer) {
  const auto p = place_particles({.plate_radius = 15e-3, .gap = 5e-4, .diameter = 2e-4, .volume_fraction = 0.5});
  EXPECT_EQ(p.count, 42188U);
  EXPECT_EQ(p.lattice, "square");
  EXPECT_EQ(p.layers, 3);
  for (std::size_t i = 0; i < p.count; ++i) {
    ASSERT_GE(p.centres[3 * i + 2], 1e-4);
    ASSERT_LE(p.centres[3 * i + 2], 4e-4);
  }
}

TEST(Placement, SameSeedSamePositions) {
  const PlacementParams params{
      .plate_radius = plate_radius, .gap = gap, .diameter = diameter, .volume_fraction = 0.2, .seed = 5};
  const auto a = place_particles(params);
  const auto b = place_particles(params);
  EXPECT_EQ(a.centres, b.centres);
  auto other = params;
  other.seed = 6;
  EXPECT_NE(place_particles(other).centres, a.centres);
}

TEST(Placement, RejectsWhatCannotBePlaced) {
  // H = 1.5 d: the best lattice (two square layers) holds φ ≈ 0.46 < 0.5.
  try {
    (void)place_particles({.plate_radius = 2e-3, .gap = 1.5e-4, .diameter = 1e-4, .volume_fraction = 0.5});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("holds only"));
  }
  EXPECT_THROW((void)place_particles({.plate_radius = 2e-3, .gap = 5e-4, .diameter = 1e-4, .volume_fraction = 0.6}),
               std::invalid_argument);
  EXPECT_THROW((void)place_particles({.plate_radius = 2e-3, .gap = 1e-4, .diameter = 1e-4, .volume_fraction = 0.1}),
               std::invalid_argument);
}

// --------------------------------------------------------------------------------- top plate

TEST(DiskMesh, CoversThePlateWithSixKSquaredTriangles) {
  for (const int rings : {1, 2, 5}) {
    const auto mesh = detail::make_disk_mesh(plate_radius, gap, rings);
    ASSERT_EQ(mesh.triangles.size(), static_cast<std::size_t>(6 * rings * rings));
    const int n = 6 * rings;  // outer polygon: regular n-gon with inscribed radius R
    const double polygon_area = n * plate_radius * plate_radius * std::tan(pi / n);
    double area = 0.0;
    for (const auto& t : mesh.triangles) {
      for (const auto& p : t) ASSERT_EQ(p[2], gap);
      const double ux = t[1][0] - t[0][0];
      const double uy = t[1][1] - t[0][1];
      const double vx = t[2][0] - t[0][0];
      const double vy = t[2][1] - t[0][1];
      const double cross = ux * vy - uy * vx;  // < 0: normal −z
      EXPECT_LT(cross, 0.0);
      area += -0.5 * cross;
    }
    EXPECT_NEAR(area, polygon_area, 1e-12 * polygon_area) << rings << " rings";
    EXPECT_NEAR(mesh.outer_radius * std::cos(pi / n), plate_radius, 1e-15);
  }
}

// ------------------------------------------------------------------------------------- scene

TEST_F(RheometerSceneTest, BuildsTheCaseScene) {
  if (is_parallel()) GTEST_SKIP() << "single-rank test";
  auto p = params(0.3);
  p.rim_shear_rate = 40.0;
  RheometerScene scene(p);
  ASSERT_TRUE(scene.placement().has_value());
  const auto& placed = *scene.placement();
  EXPECT_EQ(placed.count, 3600U);
  EXPECT_EQ(scene.total_particle_count(), 3600);

  // LIGGGHTS holds the placed particles (ids follow the data file's order).
  scene.advance(0);
  const auto ids = scene.engine().ids();
  const auto x = scene.engine().positions();
  const auto r = scene.engine().radii();
  ASSERT_EQ(ids.size(), 3600U);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const auto k = static_cast<std::size_t>(ids[i] - 1);
    for (std::size_t c = 0; c < 3; ++c) ASSERT_DOUBLE_EQ(x[3 * i + c], placed.centres[3 * k + c]);
    ASSERT_DOUBLE_EQ(r[i], radius);
  }

  // δt = 0.3 t_R; Ω = γ̇_R H / R.
  const ElasticSphere sphere{.radius = radius, .density = 1000.0, .youngs_modulus = 3e9, .poisson_ratio = 0.33};
  EXPECT_DOUBLE_EQ(scene.rayleigh_time(), rayleigh_time(sphere));
  EXPECT_DOUBLE_EQ(scene.time_step(), 0.3 * rayleigh_time(sphere));
  EXPECT_DOUBLE_EQ(scene.engine().time_step(), scene.time_step());
  EXPECT_DOUBLE_EQ(scene.angular_velocity(), 40.0 * gap / plate_radius);
  scene.set_shear_rate(80.0);
  EXPECT_DOUBLE_EQ(scene.rim_shear_rate(), 80.0);
  EXPECT_DOUBLE_EQ(scene.angular_velocity(), 80.0 * gap / plate_radius);

  // Files in the run folder: mesh, data, log.
  EXPECT_TRUE(fs::exists(scene.top_plate_mesh_path()));
  EXPECT_TRUE(fs::exists(scene.particle_data_path()));
  EXPECT_TRUE(fs::exists(p.run_directory / "liggghts.log"));
  EXPECT_EQ(scene.top_plate_triangles(), 24);  // ⌈R / 10 d⌉ = 2 rings

  // Samples at every block end of 100 steps.
  scene.advance(250);
  ASSERT_EQ(scene.torque_series().size(), 2U);
  EXPECT_EQ(scene.torque_series()[0].step, 100);
  EXPECT_EQ(scene.torque_series()[1].step, 200);
  EXPECT_DOUBLE_EQ(scene.torque_series()[1].time, 200 * scene.time_step());
  scene.advance(50);
  EXPECT_EQ(scene.torque_series().size(), 3U);
  EXPECT_EQ(scene.engine().step(), 300);
}

TEST_F(RheometerSceneTest, TimeStepOverrideAndParameterChecks) {
  auto p = params(0.1);
  p.time_step = 2e-8;
  RheometerScene scene(p);
  EXPECT_DOUBLE_EQ(scene.time_step(), 2e-8);
  EXPECT_DOUBLE_EQ(scene.engine().time_step(), 2e-8);

  auto bad = params(0.1, "bad");
  bad.particles.volume_fraction = 0.55;
  EXPECT_THROW(RheometerScene{bad}, std::invalid_argument);
  bad = params(0.1, "bad");
  bad.particles.diameter = gap;
  EXPECT_THROW(RheometerScene{bad}, std::invalid_argument);
  bad = params(0.1, "bad");
  bad.positions = std::vector<double>{0.0, 0.0, 0.5 * radius};  // into the bottom plate
  EXPECT_THROW(RheometerScene{bad}, std::invalid_argument);
  bad = params(0.1, "bad dir");
  EXPECT_THROW(RheometerScene{bad}, std::invalid_argument);
  bad = params(0.1, "bad");
  bad.time_step_fraction = 0.0;
  EXPECT_THROW(RheometerScene{bad}, std::invalid_argument);
}

// A particle let go at rest falls onto the fixed bottom plate under standard gravity and
// leaves it with e times its impact speed (e = 0.9; the fall from 0.3 mm gives 0.077 m/s).
TEST_F(RheometerSceneTest, DroppedParticleReboundsWithRestitution) {
  if (is_parallel()) GTEST_SKIP() << "single-rank test";
  constexpr double z0 = 3.5e-4;
  constexpr double g = core::units::standard_gravity;
  auto p = params(0.0);
  p.gravity = std::array<double, 3>{0.0, 0.0, -g};
  p.positions = std::vector<double>{0.0, 0.0, z0};
  RheometerScene scene(p);
  const double dt = scene.time_step();
  const double fall_time = std::sqrt(2.0 * (z0 - radius) / g);
  const auto before = static_cast<std::int64_t>(fall_time / dt) - 50;
  scene.advance(before);

  double impact_speed = NAN;
  double rebound_speed = NAN;
  bool touched = false;
  for (int k = 0; k < 1000 && std::isnan(rebound_speed); ++k) {
    const double z = scene.engine().positions()[2];
    const double vz = scene.engine().velocities()[2];
    if (z < radius)
      touched = true;
    else if (!touched)
      impact_speed = -vz;  // last state before the contact
    else
      rebound_speed = vz;  // first state after it
    scene.advance(1);
  }
  ASSERT_FALSE(std::isnan(rebound_speed)) << "no rebound within 1000 steps";
  EXPECT_NEAR(impact_speed, std::sqrt(2.0 * g * (z0 - radius)), 1e-3 * impact_speed);
  const double ratio = rebound_speed / impact_speed;
  RecordProperty("restitution_ratio", fmt::format("{:.5f}", ratio));
  EXPECT_NEAR(ratio, 0.9, 0.01);
}

// A sphere pressed against the rotating plate (here by an acceleration of 1000 m/s² towards it)
// first slides, with Coulomb friction μ_c m a, then rolls on it: its contact point moves with
// the plate at Ω r, the plate's surface speed there. A free sphere that rolls without slipping
// on a turntable is not carried along rigidly: its centre circles the axis at (2/7) Ω (the
// classic turntable result: friction changes the centre velocity and the spin together, and
// with I = (2/5) m r² the rolling constraint gives dv/dt = (2/7) Ω ẑ × v). Slip phase: the
// torque on the plate is the sliding friction's moment, μ_c m a r0, and then drops to ~0.
TEST_F(RheometerSceneTest, ParticleOnRotatingPlateIsCarriedAtItsContactPoint) {
  if (is_parallel()) GTEST_SKIP() << "single-rank test";
  constexpr double r0 = 5e-4;
  constexpr double omega = 400.0;  // rad/s: plate speed Ω r0 = 0.2 m/s under the particle
  constexpr double press = 1000.0;
  auto p = params(0.0);
  p.rim_shear_rate = omega * plate_radius / gap;
  p.gravity = std::array<double, 3>{0.0, 0.0, press};
  p.positions = std::vector<double>{r0, 0.0, gap - radius};
  p.torque_sample_interval = 500;
  RheometerScene scene(p);
  ASSERT_DOUBLE_EQ(scene.angular_velocity(), omega);

  // Slip phase: lasts Ω r0 / (3.5 μ_c a) = 0.19 ms = 4000 steps.
  scene.advance(2000);
  const double sliding_torque = 0.3 * particle_mass() * press * r0;
  ASSERT_EQ(scene.torque_series().size(), 4U);
  for (std::size_t k = 1; k < 4; ++k)  // the first block includes the first touch
    EXPECT_NEAR(scene.torque_series()[k].torque, sliding_torque, 0.02 * sliding_torque) << "block " << k;

  scene.advance(18000);  // 0.95 ms in all
  const auto x = scene.engine().positions();
  const auto v = scene.engine().velocities();
  const auto w = scene.engine().angular_velocities();
  const double r = std::hypot(x[0], x[1]);
  // Contact point above the centre: v + ω × (a ẑ); the plate there moves at Ω ẑ × x.
  const double slip_x = v[0] + w[1] * radius + omega * x[1];
  const double slip_y = v[1] - w[0] * radius - omega * x[0];
  const double slip = std::hypot(slip_x, slip_y);
  const double azimuthal = (x[0] * v[1] - x[1] * v[0]) / r;
  RecordProperty("contact_slip_over_omega_r", fmt::format("{:.3g}", slip / (omega * r)));
  RecordProperty("centre_speed_over_omega_r", fmt::format("{:.5f}", azimuthal / (omega * r)));
  EXPECT_LT(slip, 1e-3 * omega * r);                                                // contact point carried at Ω r
  EXPECT_NEAR(azimuthal, 2.0 / 7.0 * omega * r, 1e-3 * omega * r);                  // centre: (2/7) Ω r
  EXPECT_NEAR(r, r0, 1e-3 * r0);                                                    // circling the axis
  EXPECT_NEAR(x[2], gap - radius, 1e-3 * radius);                                   // pressed against the plate
  EXPECT_LT(std::abs(scene.torque_series().back().torque), 1e-3 * sliding_torque);  // rolling: no friction moment

  // Doubling the rate mid-run: slip again, then roll at the new plate speed; the centre gains
  // (2/7) of the change of the plate speed. No new run setup is needed for that.
  scene.set_shear_rate(2.0 * p.rim_shear_rate);
  ASSERT_DOUBLE_EQ(scene.angular_velocity(), 2.0 * omega);
  scene.advance(20000);
  const auto x2 = scene.engine().positions();
  const auto v2 = scene.engine().velocities();
  const auto w2 = scene.engine().angular_velocities();
  const double r2 = std::hypot(x2[0], x2[1]);
  const double slip2 =
      std::hypot(v2[0] + w2[1] * radius + 2.0 * omega * x2[1], v2[1] - w2[0] * radius - 2.0 * omega * x2[0]);
  EXPECT_LT(slip2, 1e-3 * 2.0 * omega * r2);
  EXPECT_NEAR((x2[0] * v2[1] - x2[1] * v2[0]) / r2, 2.0 / 7.0 * 2.0 * omega * r2, 2e-3 * omega * r2);
  std::ifstream log(p.run_directory / "liggghts.log");
  std::stringstream text;
  text << log.rdbuf();
  const std::string s = text.str();
  std::size_t setups = 0;
  for (std::size_t at = s.find("Setting up run"); at != std::string::npos; at = s.find("Setting up run", at + 1))
    ++setups;
  EXPECT_EQ(setups, 1U);
}

// Pressed against the rim and sliding along it, a particle never starts to spin: the rim takes
// no tangential force (friction 0 for particle–rim contacts). The particle starts 1 nm off the
// rim: a contact that already exists when a run sets up gets one step of tangential damping
// (see rheometer_scene.hpp, "Rim").
TEST_F(RheometerSceneTest, RimIsFrictionless) {
  if (is_parallel()) GTEST_SKIP() << "single-rank test";
  auto p = params(0.0);
  p.gravity = std::array<double, 3>{1000.0, 0.0, 0.0};  // towards the rim at +x
  p.positions = std::vector<double>{plate_radius - radius - 1e-9, 0.0, 0.5 * gap};
  RheometerScene scene(p);
  scene.engine().command("velocity all set 0.0 0.2 0.0 units box");
  scene.advance(20000);
  const auto x = scene.engine().positions();
  const auto w = scene.engine().angular_velocities();
  EXPECT_GT(x[1], 1e-4) << "the particle should have slid along the rim";
  EXPECT_NEAR(std::hypot(x[0], x[1]), plate_radius - radius, 1e-3 * radius);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(w[k], 0.0) << "component " << k;
}

// Start-up of dry granular shear at φ = 0.3 (3600 particles, no gravity): a quick check of
// the sign and of the plate's momentum transfer, not a steady rheometer point (that is
// validate_dry_shear.cpp: steady torque over a strain window after the transient, ∝ Ω²).
// Early on, an agitated gas cools (e = 0.9) and particles touching a plate end up rolling on
// it (see the carried-particle test), so the torque decays. The test starts a granular gas
// (every particle at 1 m/s, random directions, the same state for every rate) and averages
// the torque over its first 5000 steps (0.24 ms). Plate speeds Ω R = 0.2 and 0.5 m/s are below the
// particle speed, where a plate collision is not friction-limited and the transmitted
// tangential momentum, hence the torque, grows with Ω. Ω = 0 gives the noise level.
TEST_F(RheometerSceneTest, DryShearStartUpTorqueIsPositiveAndGrowsWithOmega) {
  const auto mean_torque = [&](double rate, const std::string& sub) {
    auto p = params(0.3, sub);
    p.rim_shear_rate = rate;
    p.initial_speed = 1.0;
    p.torque_sample_interval = 5000;
    RheometerScene scene(p);
    scene.advance(5000);
    const auto series = scene.torque_series();
    if (series.empty()) throw std::logic_error("no torque sample");
    return series[0].torque;
  };
  const double at_rest = mean_torque(0.0, "rest");
  const double slow = mean_torque(400.0, "slow");   // Ω = 100 rad/s
  const double fast = mean_torque(1000.0, "fast");  // Ω = 250 rad/s
  RecordProperty("torque_at_rest", fmt::format("{:.3e}", at_rest));
  RecordProperty("torque_slow", fmt::format("{:.3e}", slow));
  RecordProperty("torque_fast", fmt::format("{:.3e}", fast));
  EXPECT_GT(slow, 0.0);
  EXPECT_GT(slow, 3.0 * std::abs(at_rest));
  EXPECT_GT(fast, 1.5 * slow);
}

}  // namespace
}  // namespace rheosim::dem
