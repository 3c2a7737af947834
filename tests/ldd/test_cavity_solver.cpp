// LDD solver on small cavities: the node cloud of square and skewed cavities, hydrostatic rest
// under gravity (PPE Neumann walls, LDD eq. 17), divergence detection that leaves the last good
// state, bit-identical repeated runs, and a case file run end to end through run_case.
#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>

#include <nlohmann/json.hpp>

#include "rheosim/core/output.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/cavity_solver.hpp"
#include "rheosim/ldd/domain.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd {
namespace {

std::shared_ptr<const core::Rheology> newtonian(double viscosity) {
  const std::string text =
      "kind: ldd\ndimension: 2\nscene: {type: cavity, size: [1, 1], lid_velocity: 1}\n"
      "fluid: {density: 1, rheology: {model: newtonian, viscosity: " +
      std::to_string(viscosity) + "}}\ngravity: [0, 0]\nresolution: {spacing: 0.1}\ntime: {step: 1, end: 1}\n";
  return ldd::parse_case(text, "inline.yaml").settings.fluid.rheology;
}

ldd::CavityScene square(double lid) {
  ldd::CavityScene s;
  s.size = {1.0, 1.0};
  s.lid_velocity = lid;
  return s;
}

TEST(Cavity, SquareCloudHasWallsCornersAndALid) {
  const Cavity cavity(square(2.0), 0.125);
  const NodeCloud& cloud = cavity.initial_cloud();
  ASSERT_EQ(cloud.size(), 81U);  // 9 × 9
  int walls = 0, corners = 0, lid = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.kinds[i] == NodeKind::wall) ++walls;
    if (cloud.kinds[i] == NodeKind::corner) ++corners;
    double material[2] = {0, 0};  // the velocity the node's wall imposes
    if (cloud.boundary[i] >= 0)
      cavity.walls()[static_cast<std::size_t>(cloud.boundary[i])]->surface_velocity(0.0, material);
    if (material[0] == 2.0) {
      ++lid;
      EXPECT_DOUBLE_EQ(cloud.positions[2 * i + 1], 1.0);
      EXPECT_DOUBLE_EQ(cloud.normals[2 * i + 1], -1.0);  // inward, downwards
    }
  }
  EXPECT_EQ(walls, 28);
  EXPECT_EQ(corners, 4);
  EXPECT_EQ(lid, 7);  // the lid's end points are stationary corners
}

TEST(Cavity, SkewedWallsHaveInwardUnitNormals) {
  ldd::CavityScene s = square(1.0);
  s.skew_angle = std::numbers::pi / 3;
  const Cavity cavity(s, 0.1);
  EXPECT_NEAR(cavity.area(), std::sin(std::numbers::pi / 3), 1e-12);
  const Vec2 centre = cavity.point(0.5, 0.5);
  ASSERT_EQ(cavity.walls().size(), 4u);
  for (const auto& wall : cavity.walls()) {
    double distance = 0, n[2] = {0, 0};
    ASSERT_TRUE(wall->distance(centre, 0.0, distance, n));
    EXPECT_NEAR(std::hypot(n[0], n[1]), 1.0, 1e-12);
    EXPECT_GT(distance, 0.0);
  }
  double distance = 0, n[2] = {0, 0};  // the lid (third wall) passes through the top-left corner
  ASSERT_TRUE(cavity.walls()[2]->distance(cavity.point(0, 1), 0.0, distance, n));
  EXPECT_NEAR(distance, 0.0, 1e-12);
  const Vec2 top_left = cavity.point(0, 1);
  EXPECT_NEAR(top_left[0], 0.5, 1e-12);
  EXPECT_NEAR(top_left[1], std::sqrt(3.0) / 2, 1e-12);
}

TEST(CavitySolver, StaysAtRestUnderGravity) {
  omp_set_num_threads(1);
  const Cavity cavity(square(0.0), 1.0 / 16);
  SolverParams p = SolverParams::for_cavity();
  p.rheology = newtonian(0.01);
  p.spacing = 1.0 / 16;
  p.time_step = 0.01;
  p.gravity = {0.0, -9.81};
  CavitySolver solver(p, cavity.walls(), cavity.initial_cloud());
  for (int k = 0; k < 20; ++k) solver.step();
  double max_speed = 0;
  for (std::size_t i = 0; i < solver.node_count(); ++i)
    max_speed = std::max(max_speed, std::hypot(solver.velocity()[2 * i], solver.velocity()[2 * i + 1]));
  EXPECT_LT(max_speed, 3e-3 * 9.81 * solver.time());  // spurious currents < 0.3 % of g·t
  // Hydrostatic pressure: p(bottom) − p(top) ≈ ρ g H.
  const auto p_at = [&](std::size_t i, std::size_t j) { return solver.pressure()[j * 17 + i]; };
  EXPECT_NEAR(p_at(8, 1) - p_at(8, 15), 9.81 * 14.0 / 16, 0.05 * 9.81);
}

TEST(CavitySolver, DivergenceStopsWithTheLastGoodStateKept) {
  omp_set_num_threads(1);
  const Cavity cavity(square(1.0), 1.0 / 16);
  SolverParams p = SolverParams::for_cavity();
  p.rheology = newtonian(0.01);
  p.spacing = 1.0 / 16;
  p.time_step = 0.5;  // Courant number 8 at the lid
  CavitySolver solver(p, cavity.walls(), cavity.initial_cloud());
  try {
    solver.step();
    FAIL() << "no DivergenceError";
  } catch (const DivergenceError& e) {
    EXPECT_NE(std::string(e.what()).find("Courant number"), std::string::npos) << e.what();
  }
  EXPECT_EQ(solver.steps(), 0U);
  EXPECT_EQ(solver.time(), 0.0);
  for (std::size_t i = 0; i < solver.node_count(); ++i) {
    if (solver.kinds()[i] == NodeKind::interior) {
      EXPECT_EQ(solver.velocity()[2 * i], 0.0);
    }
  }
}

TEST(CavitySolver, RepeatedRunsAreBitIdentical) {
  omp_set_num_threads(2);
  const auto run = [] {
    const Cavity cavity(square(1.0), 1.0 / 12);
    SolverParams p = SolverParams::for_cavity();
    p.rheology = newtonian(0.01);
    p.spacing = 1.0 / 12;
    p.time_step = 0.01;
    CavitySolver solver(p, cavity.walls(), cavity.initial_cloud());
    for (int k = 0; k < 2; ++k) solver.step();
    return std::vector<double>(solver.velocity().begin(), solver.velocity().end());
  };
  const auto a = run(), b = run();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << "entry " << i;
}

// AMG preconditioners (amg.hpp) for both systems: the same velocities as the default LU / Jacobi
// solves to within the solver tolerances, and bit-identical repeated runs on two threads (5 041
// nodes, above the AMG's parallel threshold).
TEST(CavitySolver, AmgPreconditionersMatchTheDefaultSolvesAndRepeatExactly) {
  omp_set_num_threads(2);
  const auto run = [](Preconditioner pressure, Preconditioner velocity) {
    const Cavity cavity(square(1.0), 1.0 / 70);
    SolverParams p = SolverParams::for_cavity();
    p.rheology = newtonian(0.01);
    p.spacing = 1.0 / 70;
    p.time_step = 2e-3;
    p.pressure_tolerance = 1e-10;
    p.velocity_tolerance = 1e-10;
    p.pressure_preconditioner = pressure;
    p.velocity_preconditioner = velocity;
    CavitySolver solver(p, cavity.walls(), cavity.initial_cloud());
    StepStats stats;
    for (int k = 0; k < 3; ++k) stats = solver.step();
    if (velocity == Preconditioner::amg) {
      EXPECT_LT(stats.velocity_iterations, 20);
    }
    return std::vector<double>(solver.velocity().begin(), solver.velocity().end());
  };
  const auto reference = run(Preconditioner::sparse_lu, Preconditioner::jacobi);
  const auto a = run(Preconditioner::amg, Preconditioner::amg), b = run(Preconditioner::amg, Preconditioner::amg);
  ASSERT_EQ(a.size(), reference.size());
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i], b[i]) << "entry " << i;
    worst = std::max(worst, std::abs(a[i] - reference[i]));
  }
  EXPECT_LT(worst, 1e-6);  // lid speed 1 m/s
  EXPECT_GT(worst, 0.0);   // a different solve path, not the same code
}

TEST(RunCase, WritesSummaryCenterlinesFramesAndResiduals) {
  const std::string text =
      "kind: ldd\ndimension: 2\nscene: {type: skewed_cavity, size: [1, 1], lid_velocity: 1, skew_angle: 60}\n"
      "fluid: {density: 1, rheology: {model: power_law, consistency: 0.002, index: 1.5}}\ngravity: [0, 0]\n"
      "resolution: {spacing: 0.0625}\ntime: {step: 0.01, end: 0.5}\nsolver: {threads: 1}\n";
  const ldd::Case c = ldd::parse_case(text, "skewed.yaml");
  const auto dir = std::filesystem::temp_directory_path() / "rheosim_test_ldd_run";
  std::filesystem::remove_all(dir);
  const RunOutcome outcome = run_case(c, dir, core::Log::null());
  EXPECT_EQ(outcome.status, "end_time");
  EXPECT_EQ(outcome.steps, 50U);
  const auto summary = core::read_json(dir / "summary.json");
  EXPECT_EQ(summary["nodes"].get<int>(), 17 * 17);
  EXPECT_EQ(summary["input_sha256"].get<std::string>(), c.sha256);
  EXPECT_EQ(summary["centerlines"]["vertical"].size(), 101U);
  EXPECT_NEAR(summary["centerlines"]["vertical"].back()["u"].get<double>(), 1.0, 0.05);  // the lid
  for (const char* f :
       {"centerline_vertical.csv", "centerline_horizontal.csv", "residual.csv", "field.vtk", "frames/nodes.vtk.series",
        "frames/field.vtk.series", "frames/field_0001.vtk", "nodes.pvd", "centerlines.gp"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  std::filesystem::remove_all(dir);
}

// A cavity run stopped part-way (step limit: status interrupted, checkpoint.h5 written) and run
// again into the same folder ends with the numbers of the run that was never stopped, bit for
// bit: the residual history, the centre lines, the summary, the state and the last frames. The
// stop falls between probes (every 5 steps) and frames (every 20), so the residual's last sample
// and the momentum solves' initial-guess increments come from the checkpoint. With AMG
// preconditioners the kept PPE hierarchy is restored too.
void expect_resumed_cavity_matches_the_straight_one(const std::string& solver, const std::string& name) {
  const std::string text =
      "kind: ldd\ndimension: 2\nscene: {type: cavity, size: [1, 1], lid_velocity: 1}\n"
      "fluid: {density: 1, rheology: {model: casson, plastic_viscosity: 0.01, yield_stress: 0.01, "
      "regularization: 100}}\ngravity: [0, 0]\nresolution: {spacing: 0.0625}\ntime: {step: 0.01, end: 0.6}\n"
      "output: {probe_interval: 0.05, frame_interval: 0.2}\nsolver: {threads: 1" +
      solver + "}\n";
  const ldd::Case c = ldd::parse_case(text, name + ".yaml");
  const auto straight = std::filesystem::temp_directory_path() / ("rheosim_" + name + "_straight");
  const auto resumed = std::filesystem::temp_directory_path() / ("rheosim_" + name + "_twice");
  std::filesystem::remove_all(straight);
  std::filesystem::remove_all(resumed);
  EXPECT_EQ(run_case(c, straight, core::Log::null()).status, "end_time");
  RunControl stop;
  stop.step_limit = 27;
  const RunOutcome first = run_case(c, resumed, core::Log::null(), stop);
  EXPECT_EQ(first.status, "interrupted");
  EXPECT_EQ(first.steps, 27U);
  ASSERT_TRUE(std::filesystem::exists(resumed / "checkpoint.h5"));
  const RunOutcome second = run_case(c, resumed, core::Log::null());
  EXPECT_EQ(second.status, "end_time");
  EXPECT_EQ(second.steps, 60U);

  for (const char* table : {"residual.csv", "centerline_vertical.csv", "centerline_horizontal.csv"})
    EXPECT_EQ(core::read_csv(straight / table), core::read_csv(resumed / table)) << table;
  auto a = core::read_json(straight / "summary.json"), b = core::read_json(resumed / "summary.json");
  EXPECT_EQ(b["resumed_at_steps"], nlohmann::json::array({27}));
  for (const char* timing : {"ms_per_step", "phase_seconds", "wall_time", "resumed_at_steps", "git_revision"}) {
    a.erase(timing);
    b.erase(timing);
  }
  EXPECT_EQ(a, b);
  for (const char* state : {"state/velocity", "state/previous_velocity", "state/pressure", "state/viscosity"})
    EXPECT_EQ(core::read_hdf5_dataset(straight / "checkpoint.h5", state).data,
              core::read_hdf5_dataset(resumed / "checkpoint.h5", state).data)
        << state;
  const auto bytes = [](const std::filesystem::path& f) {
    std::ifstream in(f, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  for (const char* frame : {"frames/nodes_0003.vtk", "frames/field_0003.vtk", "nodes.pvd", "field.vtk"}) {
    ASSERT_TRUE(std::filesystem::exists(straight / frame)) << frame;
    EXPECT_TRUE(bytes(straight / frame) == bytes(resumed / frame)) << frame;
  }
  std::filesystem::remove_all(straight);
  std::filesystem::remove_all(resumed);
}

TEST(RunCase, InterruptedCavityGoesOnBitForBitFromItsCheckpoint) {
  expect_resumed_cavity_matches_the_straight_one("", "ldd_resume_cavity");
}

TEST(RunCase, InterruptedCavityWithAmgGoesOnBitForBit) {
  expect_resumed_cavity_matches_the_straight_one(", pressure_preconditioner: amg, velocity_preconditioner: amg",
                                                 "ldd_resume_cavity_amg");
}

}  // namespace
}  // namespace rheosim::ldd
