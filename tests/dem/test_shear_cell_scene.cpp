// dem::ShearCellScene: the placed count matches φ, no initial overlaps (with
// periodic images), a particle pressed against a plate at the periodic edge loads the plate
// exactly once, the conveyor top plate carries a resting particle along at U, and the dry
// contact shear stress is positive and grows with the shear rate (Bagnold: ∝ γ̇²).
// CD §4 particles: d = 0.2 mm, ρ = 1000 kg/m³, E = 3 GPa, ν = 0.33, e = 0.9, μ_c = 0.3; H = 0.5 mm.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "rheosim/core/units.hpp"
#include "rheosim/dem/shear_cell_scene.hpp"

namespace rheosim::dem {
namespace {

namespace fs = std::filesystem;

constexpr double gap = 5e-4;
constexpr double diameter = 2e-4;
constexpr double cell = 2e-3;  // L_x = L_y [m]

ParticleProperties particles(double volume_fraction) {
  return {.volume_fraction = volume_fraction, .diameter = diameter, .density = 1000.0};
}

// Smallest centre distance with the minimum-image convention in x and y.
double min_pair_distance(const std::vector<double>& x, double lx, double ly) {
  const std::size_t n = x.size() / 3;
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      double dx = x[3 * i] - x[3 * j];
      double dy = x[3 * i + 1] - x[3 * j + 1];
      const double dz = x[3 * i + 2] - x[3 * j + 2];
      dx -= lx * std::round(dx / lx);
      dy -= ly * std::round(dy / ly);
      smallest = std::min(smallest, std::sqrt(dx * dx + dy * dy + dz * dz));
    }
  return smallest;
}

class ShearCellSceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("rheosim_test_cell_{}", ::getpid()) / info->name();
    fs::remove_all(dir_);
  }
  void TearDown() override {  // a failed test keeps its run folder
    if (!HasFailure()) fs::remove_all(dir_);
    std::error_code not_empty;
    fs::remove(dir_.parent_path(), not_empty);
  }
  [[nodiscard]] ShearCellScene::Params params(double volume_fraction, double shear_rate,
                                              const std::string& sub = "run") const {
    return {.gap = gap,
            .cell_length = cell,
            .cell_width = cell,
            .particles = particles(volume_fraction),
            .shear_rate = shear_rate,
            .run_directory = dir_ / sub};
  }
  fs::path dir_;
};

TEST_F(ShearCellSceneTest, PlacesTheCountOfPhiWithoutOverlaps) {
  for (const double phi : {0.1, 0.3, 0.4}) {
    ShearCellScene scene(params(phi, 100.0, fmt::format("phi{}", phi)));
    const auto expected = shear_cell_particle_count(gap, cell, cell, diameter, phi);
    EXPECT_EQ(static_cast<std::size_t>(scene.total_particle_count()), expected) << phi;
    EXPECT_NEAR(scene.volume_fraction(), phi, 0.5 * core::units::sphere_volume(diameter) / (cell * cell * gap));
    EXPECT_GE(min_pair_distance(scene.initial_positions(), cell, cell), diameter * (1.0 - 1e-9)) << phi;
    for (std::size_t i = 0; i < scene.initial_positions().size() / 3; ++i) {
      const double z = scene.initial_positions()[3 * i + 2];
      EXPECT_GE(z, 0.5 * diameter);
      EXPECT_LE(z, gap - 0.5 * diameter);
    }
    EXPECT_DOUBLE_EQ(scene.plate_velocity(), 100.0 * gap);
  }
}

TEST_F(ShearCellSceneTest, RejectsWhatItCannotPlace) {
  EXPECT_THROW(ShearCellScene(params(0.46, 10.0)), std::invalid_argument);
  auto p = params(0.1, 10.0);
  p.cell_length = 1.5 * diameter;
  EXPECT_THROW(ShearCellScene{p}, std::invalid_argument);
}

// A particle pushed against the top plate by a body force (gravity along +z) gives the plate its
// weight, once, whether it sits mid-cell or straddles the periodic edge x = 0.
TEST_F(ShearCellSceneTest, PlateContactAtThePeriodicEdgeCountsOnce) {
  const double r = 0.5 * diameter;
  const double g = 9.81;
  const double weight = 1000.0 * core::units::sphere_volume(diameter) * g;
  for (const double x : {0.5 * cell, 0.01 * r, cell - 0.01 * r}) {
    auto p = params(0.0, 0.0, fmt::format("edge{}", x));
    p.positions = std::vector<double>{x, 0.37 * cell, gap - r};  // just touching
    p.gravity = std::array<double, 3>{0.0, 0.0, g};
    p.start_in_shear_profile = false;
    p.stress_sample_interval = 1000;
    ShearCellScene scene(p);
    scene.advance(20000);  // contact damping (e = 0.9) settles the Hertz oscillation
    const auto& last = scene.stress_series().back();
    EXPECT_NEAR(last.top_normal * scene.plate_area(), weight, 1e-3 * weight) << "x = " << x;
    EXPECT_NEAR(last.bottom_normal, 0.0, 1e-12);
  }
}

// A particle pressed against the conveyor top plate (body force W along +z, friction μ_c = 0.3)
// first slides: the plate feels the Coulomb force μ_c W against its motion; then it rolls
// without slip. For a uniform sphere, v̇ = μ_c g and ω̇ r = (5/2) μ_c g, so sliding ends when
// v + ω r = U, at v = 2U/7 — after which nothing drives it any more.
TEST_F(ShearCellSceneTest, ConveyorTopPlateDragsAParticleIntoRolling) {
  const double r = 0.5 * diameter;
  const double g = 9.81;
  const double weight = 1000.0 * core::units::sphere_volume(diameter) * g;
  auto p = params(0.0, 100.0);
  p.positions = std::vector<double>{0.5 * cell, 0.5 * cell, gap - r};
  p.gravity = std::array<double, 3>{0.0, 0.0, g};
  p.start_in_shear_profile = false;
  ShearCellScene scene(p);
  const double u = scene.plate_velocity();
  const double sliding_time = u / (3.5 * 0.3 * g);  // 4.9 ms
  const auto sliding_steps = static_cast<std::int64_t>(sliding_time / scene.time_step());
  scene.advance(sliding_steps / 2);
  double drag = 0.0;  // mean plate shear force over the second quarter of the sliding phase
  const auto series = scene.stress_series();
  const std::size_t from = series.size() / 2;
  for (std::size_t i = from; i < series.size(); ++i) drag += series[i].top_shear * scene.plate_area();
  drag /= static_cast<double>(series.size() - from);
  EXPECT_NEAR(drag, 0.3 * weight, 0.02 * 0.3 * weight);
  scene.advance(sliding_steps);
  const double vx = scene.engine().velocities()[0];
  const double spin_y = scene.engine().angular_velocities()[1];
  EXPECT_NEAR(vx, 2.0 * u / 7.0, 0.02 * u);
  EXPECT_NEAR(vx + spin_y * r, u, 0.02 * u);  // the top of the sphere moves with the plate
}

// Dry shear at φ = 0.3: the mean contact shear stress on the top plate is positive and rises
// with the rate (Bagnold scaling τ ∝ γ̇² for rate-independent contacts; accept a ratio > 2 for
// a doubled rate), and top and bottom plates agree in the mean (momentum balance of the layer).
TEST_F(ShearCellSceneTest, DryShearStressIsPositiveAndGrowsWithRate) {
  std::vector<double> stress;
  for (const double rate : {2000.0, 4000.0}) {
    auto p = params(0.3, rate, fmt::format("rate{}", rate));
    p.initial_speed = 0.1 * rate * gap;
    ShearCellScene scene(p);
    const auto steps_per_strain = static_cast<std::int64_t>(1.0 / (rate * scene.time_step()));
    scene.advance(3 * steps_per_strain);  // start-up
    const std::size_t before = scene.stress_series().size();
    scene.advance(6 * steps_per_strain);
    const auto series = scene.stress_series().subspan(before);
    double top = 0.0, bottom = 0.0;
    for (const auto& s : series) {
      top += s.top_shear;
      bottom += s.bottom_shear;
    }
    top /= static_cast<double>(series.size());
    bottom /= static_cast<double>(series.size());
    EXPECT_GT(top, 0.0) << rate;
    EXPECT_NEAR(bottom, top, 0.15 * top) << rate;
    stress.push_back(top);
    std::printf("dry shear, rate %g 1/s: tau_top %.4g Pa, tau_bottom %.4g Pa\n", rate, top, bottom);
  }
  EXPECT_GT(stress[1], 2.0 * stress[0]);
}

}  // namespace
}  // namespace rheosim::dem
