// Free-surface LDD: the surface criterion on lattice and jittered columns (no false
// surface nodes inside or along the walls), hydrostatic pressure ρgh from a p = 0 start (LDD
// eq. 17 with p = p_atm on the surface), the volume kept by the PBD, splash nodes that fall
// ballistically without upsetting the PPE, a viscous column released by a receding slip gate at
// δt = 1e-2 without a pressure collapse, the Abrams mould geometry, and runs that stop and go on
// from their checkpoint bit for bit.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <tuple>

#include <fmt/format.h>

#include "checkpoint.hpp"  // detail::read_checkpoint, write_checkpoint (white box)
#include "rheosim/core/error.hpp"
#include "rheosim/core/log.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/free_surface.hpp"
#include "rheosim/ldd/run.hpp"
#include "rheosim/ldd/scenes.hpp"
#include "rheosim/ldd/summary.hpp"

namespace rheosim::ldd {
using ::testing::HasSubstr;
namespace {

std::shared_ptr<const core::Rheology> newtonian(double viscosity) {
  const std::string text =
      "kind: ldd\ndimension: 2\nscene: {type: column, size: [1, 1]}\n"
      "fluid: {density: 1, rheology: {model: newtonian, viscosity: " +
      std::to_string(viscosity) + "}}\ngravity: [0, -9.81]\nresolution: {spacing: 0.1}\ntime: {step: 1, end: 1}\n";
  return ldd::parse_case(text, "inline.yaml").settings.fluid.rheology;
}

SolverParams column_params(double spacing, double dt, double viscosity) {
  SolverParams p;
  p.dimension = 2;
  p.density = 1000;
  p.rheology = newtonian(viscosity);
  p.gravity = {0.0, -9.81};
  p.spacing = spacing;
  p.time_step = dt;
  return p;
}

ldd::ColumnScene column(double width, double height) {
  ldd::ColumnScene c;
  c.size = {width, height};
  return c;
}

// Highest fluid node's y.
double top_row(const FreeSurfaceSolver& s) {
  double top = -1e300;
  for (std::size_t i = 0; i < s.node_count(); ++i)
    if (s.is_fluid(i)) top = std::max(top, s.positions()[2 * i + 1]);
  return top;
}

TEST(FreeSurface, LatticeColumnHasOnlyItsTopRowOnTheSurface) {
  const double dx = 0.01;
  FreeSurfaceSolver s(column_params(dx, 1e-3, 1.0), column_scene(column(0.2, 0.3), dx).boundaries,
                      column_scene(column(0.2, 0.3), dx).cloud);
  const double top = top_row(s);
  std::size_t surface = 0, fluid = 0;
  for (std::size_t i = 0; i < s.node_count(); ++i) {
    if (!s.is_fluid(i)) continue;
    ++fluid;
    const bool in_top_row = s.positions()[2 * i + 1] > top - 0.5 * dx;
    EXPECT_EQ(s.kinds()[i] == NodeKind::surface, in_top_row)
        << "node at (" << s.positions()[2 * i] << ", " << s.positions()[2 * i + 1] << ")";
    surface += s.kinds()[i] == NodeKind::surface ? 1 : 0;
  }
  EXPECT_EQ(fluid, 20U * 30U);
  EXPECT_EQ(surface, 20U);  // the top row, corners included, and nothing along the walls
}

TEST(FreeSurface, JitteredColumnHasNoFalseSurfaceNodesInsideOrAlongWalls) {
  const double dx = 0.01;
  FreeSurfaceScene scene = column_scene(column(0.2, 0.3), dx);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.1 * dx, 0.1 * dx);
  for (std::size_t i = 0; i < scene.cloud.size(); ++i)
    if (!scene.cloud.is_wall(i))
      for (std::size_t d = 0; d < 2; ++d) scene.cloud.positions[2 * i + d] += jitter(random);
  FreeSurfaceSolver s(column_params(dx, 1e-3, 1.0), scene.boundaries, scene.cloud);
  const double top = top_row(s);
  std::size_t false_surface = 0, missed_surface = 0;
  for (std::size_t i = 0; i < s.node_count(); ++i) {
    if (!s.is_fluid(i)) continue;
    const double depth = top - s.positions()[2 * i + 1];
    if (depth > 1.5 * dx && s.kinds()[i] == NodeKind::surface) {
      ++false_surface;
      std::printf("false surface node at (%g, %g)\n", s.positions()[2 * i], s.positions()[2 * i + 1]);
    }
    if (depth < 0.3 * dx && s.kinds()[i] != NodeKind::surface) ++missed_surface;
  }
  EXPECT_EQ(false_surface, 0U);
  EXPECT_EQ(missed_surface, 0U);
}

// A strongly disordered column (±0.35 Δ jitter, as a sheared wedge beside a sloshing tank's wall
// becomes): gaps between interior nodes open empty cones and centroid offsets, which the local
// criteria take for surface; with the umbrella test (surface_detection: umbrella) those nodes stay
// interior when the void they point to is occupied Δ further on (two thirds of them here), while
// the top row, whose void is open, stays surface.
TEST(FreeSurface, UmbrellaTestKeepsGapsInADisorderedBodyInterior) {
  const double dx = 0.01;
  FreeSurfaceScene scene = column_scene(column(0.2, 0.3), dx);
  double top = -1e300;  // the lattice's top row, before the jitter
  for (std::size_t i = 0; i < scene.cloud.size(); ++i)
    if (!scene.cloud.is_wall(i)) top = std::max(top, scene.cloud.positions[2 * i + 1]);
  std::vector<char> in_top_row(scene.cloud.size(), 0), deep(scene.cloud.size(), 0);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> jitter(-0.35 * dx, 0.35 * dx);
  for (std::size_t i = 0; i < scene.cloud.size(); ++i) {
    if (scene.cloud.is_wall(i)) continue;
    in_top_row[i] = scene.cloud.positions[2 * i + 1] > top - 0.5 * dx;
    deep[i] = scene.cloud.positions[2 * i + 1] < top - 2.5 * dx;
    for (std::size_t d = 0; d < 2; ++d) scene.cloud.positions[2 * i + d] += jitter(random);
  }
  const auto count = [&](bool umbrella) {
    SolverParams p = column_params(dx, 1e-3, 1.0);
    p.surface_umbrella = umbrella;
    FreeSurfaceSolver s(p, scene.boundaries, scene.cloud);
    std::pair<std::size_t, std::size_t> false_and_missed{0, 0};
    for (std::size_t i = 0; i < s.node_count(); ++i) {
      if (deep[i] && s.kinds()[i] == NodeKind::surface) ++false_and_missed.first;
      if (in_top_row[i] && s.kinds()[i] != NodeKind::surface) ++false_and_missed.second;
    }
    return false_and_missed;
  };
  const auto local = count(false), umbrella = count(true);
  fmt::print(
      "surface nodes 2.5 Δ or more below the top row: local {}, umbrella {}; top-row nodes not surface: {}, {}\n",
      local.first, umbrella.first, local.second, umbrella.second);
  EXPECT_GE(local.first, 10U);  // the defect the test guards against is there without the umbrella
  EXPECT_LE(umbrella.first, local.first / 2);
  EXPECT_EQ(umbrella.second, local.second);  // the top row is classified as before
}

// A column at rest from p = 0: the pressure must settle to ρ g h (h measured from the surface
// row, where p = p_atm is imposed) and the velocities must die out, with the centred gradient
// on surface nodes (the default) and with eq. 14 about them (gradient: surface_anchored).
TEST(FreeSurface, RestingColumnReachesHydrostaticPressure) {
  const double dx = 0.01, height = 0.3, rho = 1000, g = 9.81;
  for (const bool anchored : {false, true}) {
    FreeSurfaceScene scene = column_scene(column(0.1, height), dx);
    SolverParams p = column_params(dx, 1e-3, 5.0);
    p.hydrostatic_start = false;
    p.anchored_surface_gradient = anchored;
    FreeSurfaceSolver s(p, scene.boundaries, scene.cloud);
    const double volume0 = s.fluid_volume();
    StepStats stats;
    for (int k = 0; k < 400; ++k) stats = s.step();
    const double top = top_row(s);
    double worst = 0, max_speed = 0;
    for (std::size_t i = 0; i < s.node_count(); ++i) {
      if (!s.is_fluid(i)) continue;
      const double depth = top - s.positions()[2 * i + 1];
      worst = std::max(worst, std::abs(s.pressure()[i] - rho * g * depth));
      max_speed = std::max(max_speed, std::hypot(s.velocity()[2 * i], s.velocity()[2 * i + 1]));
    }
    const double bottom_pressure = rho * g * (height - dx);
    std::printf(
        "[ measured ] hydrostatic column, %s surface gradient: max |p - rho g h| = %.4g Pa = %.3g %% of rho g H, "
        "max |u| = %.3g m/s, volume drift %.3g %%\n",
        anchored ? "eq. 14" : "centred", worst, 100 * worst / bottom_pressure, max_speed,
        100 * (s.fluid_volume() / volume0 - 1));
    EXPECT_LT(worst, 0.01 * bottom_pressure) << anchored;
    EXPECT_LT(max_speed, 1e-3 * std::sqrt(g * height)) << anchored;  // noise level: 0.1 % of the wave speed
    EXPECT_LT(std::abs(s.fluid_volume() / volume0 - 1), 0.01) << anchored;
    EXPECT_EQ(stats.splash_nodes, 0U) << anchored;
  }
}

// The AMG preconditioners (reused hierarchy) give the sparse-LU run's hydrostatic column to the
// solver tolerance, and repeat bit for bit. ~1 800 nodes, so the hierarchy has coarse levels.
// solver.surface_stress: normal puts the traction-free condition's normal part on the surface,
// p = 2μ n·E·n. In the extension u = (−a x, a y) the top row (n = +y) has n·E·n = a: its nodes
// away from the walls take p = 2μa after one step (the Dirichlet row of the PPE; the gradient is
// exact for this linear field); compression (a < 0) gives suction, which the no-tension clip sets to 0, and the
// default keeps p = 0.
TEST(FreeSurface, SurfaceNormalStressIsTwiceViscosityTimesNormalStrain) {
  const double dx = 0.01, viscosity = 2.0;
  const auto top_pressures = [&](double rate, bool normal_stress) {
    SolverParams p = column_params(dx, 1e-4, viscosity);
    p.gravity = {0.0, 0.0};
    p.surface_normal_stress = normal_stress;
    FreeSurfaceScene scene = column_scene(column(0.2, 0.3), dx);
    FreeSurfaceSolver solver(p, scene.boundaries, scene.cloud);
    SolverState state = solver.state();
    for (std::size_t i = 0; i < solver.node_count(); ++i) {
      state.velocity[2 * i] = -rate * state.positions[2 * i];
      state.velocity[2 * i + 1] = rate * state.positions[2 * i + 1];
    }
    state.previous_velocity = state.velocity;
    solver.restore(state);
    const double top = top_row(solver);
    solver.step();
    std::vector<double> pressures;  // top-row nodes more than 2h from the side walls
    for (std::size_t i = 0; i < solver.node_count(); ++i)
      if (solver.kinds()[i] == NodeKind::surface && std::abs(solver.positions()[2 * i] - 0.1) < 0.1 - 3.2 * dx &&
          solver.positions()[2 * i + 1] > top - 0.5 * dx)
        pressures.push_back(solver.pressure()[i]);
    return pressures;
  };
  const double rate = 0.5;
  const auto stretched = top_pressures(rate, true);
  ASSERT_GE(stretched.size(), 10U);
  // The PPE's Dirichlet rows are met to its tolerance, not exactly.
  const double tolerance = 1e-5 * 2.0 * viscosity * rate;
  for (const double p : stretched) EXPECT_NEAR(p, 2.0 * viscosity * rate, tolerance);
  for (const double p : top_pressures(-rate, true)) EXPECT_NEAR(p, 0.0, tolerance);
  for (const double p : top_pressures(rate, false)) EXPECT_NEAR(p, 0.0, tolerance);
}

// A 0.2 × 0.3 m column without gravity (Δ = 1 cm), its top row moved up by `lift` [m]
// (negative: down), and the PBD's surface treatment chosen.
FreeSurfaceSolver column_with_moved_top_row(double lift, bool tangential) {
  const double dx = 0.01;
  SolverParams p = column_params(dx, 1e-4, 1.0);
  p.gravity = {0.0, 0.0};
  p.pbd_surface_tangential = tangential;
  FreeSurfaceScene scene = column_scene(column(0.2, 0.3), dx);
  FreeSurfaceSolver solver(p, scene.boundaries, scene.cloud);
  const double top = top_row(solver);
  SolverState state = solver.state();
  for (std::size_t i = 0; i < solver.node_count(); ++i)
    if (solver.is_fluid(i) && state.positions[2 * i + 1] > top - 0.5 * dx) state.positions[2 * i + 1] += lift;
  solver.restore(state);
  return solver;
}

// A compressed top row (0.3 Δ down) is pushed apart by the PBD: with the whole shift it rises
// (outwards); with pbd_surface_tangential its nodes keep only the part along the surface, which
// on a level row away from the walls is zero by symmetry.
TEST(FreeSurface, TangentialPbdShiftKeepsCompressedSurfaceNodesOnTheirSurface) {
  const double dx = 0.01;
  const auto top_row_rise = [&](bool tangential) {
    FreeSurfaceSolver solver = column_with_moved_top_row(-0.3 * dx, tangential);
    const double top = top_row(solver);
    std::vector<std::size_t> row;  // top-row nodes more than 2h from the side walls
    for (std::size_t i = 0; i < solver.node_count(); ++i)
      if (solver.is_fluid(i) && solver.positions()[2 * i + 1] > top - 0.5 * dx &&
          std::abs(solver.positions()[2 * i] - 0.1) < 0.1 - 3.2 * dx)
        row.push_back(i);
    const std::vector<double> before(solver.positions().begin(), solver.positions().end());
    solver.step();
    EXPECT_EQ(solver.kinds()[row.front()], NodeKind::surface);
    double rise = 0;
    for (const std::size_t i : row) rise = std::max(rise, std::abs(solver.positions()[2 * i + 1] - before[2 * i + 1]));
    return std::pair{rise, row.size()};
  };
  const auto [full, count] = top_row_rise(false);
  ASSERT_GE(count, 10U);
  EXPECT_GT(full, 0.05 * dx);
  EXPECT_LT(top_row_rise(true).first, 1e-9 * dx);
}

// A column whose top row is lifted 0.3 Δ: the row under it loses part of its kernel sum to the
// gap. With the two-sided correction there the PBD pulls the surface back down, a tension the
// fluid does not have; under pbd_surface_tangential the rows within h of the surface correct only
// compression and the surface only along itself, and nothing moves.
TEST(FreeSurface, TangentialPbdDoesNotPullALiftedSurfaceBack) {
  const auto largest_shift = [](bool tangential) {  // in units of Δ
    return column_with_moved_top_row(0.003, tangential).step().max_pbd_shift;
  };
  EXPECT_GT(largest_shift(false), 0.01);
  EXPECT_LT(largest_shift(true), 1e-9);
}

// The bulk's mean kernel sum (nodes with no surface node within h): ρ₀ on the lattice column it
// was taken from, above it when the column is squeezed 5 % towards its floor (+2.6 %: with
// h = 1.6 Δ the node's own W(0) dominates the sum, which is therefore not proportional to the
// number density), whatever the truncated sums along the surface say.
TEST(FreeSurface, BulkDensityRatioSeesACompressedBody) {
  const double dx = 0.01;
  SolverParams p = column_params(dx, 1e-4, 1.0);
  FreeSurfaceScene scene = column_scene(column(0.2, 0.3), dx);
  FreeSurfaceSolver solver(p, scene.boundaries, scene.cloud);
  EXPECT_NEAR(solver.bulk_density_ratio(), 1.0, 1e-12);
  SolverState state = solver.state();
  for (std::size_t i = 0; i < solver.node_count(); ++i)
    if (solver.is_fluid(i)) state.positions[2 * i + 1] *= 0.95;  // the floor's fluid row stays above y = 0
  solver.restore(state);
  solver.classify();
  EXPECT_GT(solver.bulk_density_ratio(), 1.02);
}

// The bulk's nodes per Δ², counted in balls of 4 Δ: 1 on the lattice column, 1/0.95 when the
// column is squeezed 5 % towards its floor, and unchanged when the nodes are shuffled ±0.25 Δ
// about their places, where the kernel sums read the disorder as a compression.
TEST(FreeSurface, BulkNumberDensityCountsNodesWhateverTheirArrangement) {
  const double dx = 0.01;
  SolverParams p = column_params(dx, 1e-4, 1.0);
  p.surface_umbrella = true;  // the shuffled interior's gaps are not free surface
  FreeSurfaceScene scene = column_scene(column(0.3, 0.3), dx);
  FreeSurfaceSolver solver(p, scene.boundaries, scene.cloud);
  const std::optional<double> lattice = solver.bulk_number_density();
  ASSERT_TRUE(lattice.has_value());
  EXPECT_NEAR(*lattice, 1.0, 0.005);
  const SolverState start = solver.state();
  const auto moved = [&](const auto& move) {
    SolverState state = start;
    for (std::size_t i = 0; i < solver.node_count(); ++i)
      if (solver.is_fluid(i)) move(&state.positions[2 * i]);
    solver.restore(state);
    solver.classify();
    return std::pair{solver.bulk_number_density(), solver.bulk_density_ratio()};
  };
  const auto [squeezed, squeezed_sum] = moved([](double* x) { x[1] *= 0.95; });
  ASSERT_TRUE(squeezed.has_value());
  EXPECT_NEAR(*squeezed / *lattice, 1 / 0.95, 0.005);
  EXPECT_NEAR(squeezed_sum, 1.026, 0.005);  // the kernel sum reads it at about half
  std::mt19937 random(7);
  std::uniform_real_distribution<double> shuffle(-0.25 * dx, 0.25 * dx);
  const auto [shuffled, shuffled_sum] = moved([&](double* x) {
    if (x[0] > 2 * dx && x[0] < 0.3 - 2 * dx && x[1] > 2 * dx && x[1] < 0.3 - 2 * dx) {
      x[0] += shuffle(random);
      x[1] += shuffle(random);
    }
  });
  ASSERT_TRUE(shuffled.has_value());
  std::printf("[ measured ] lattice %.4f, squeezed %.4f (kernel sum %.4f), shuffled %.4f (kernel sum %.4f)\n", *lattice,
              *squeezed, squeezed_sum, *shuffled, shuffled_sum);
  EXPECT_NEAR(*shuffled / *lattice, 1.0, 0.005);
  EXPECT_GT(shuffled_sum, 1.02);
}

// solver.pressure_amg: auto (SolverParams::pressure_amg_switch_iterations): a pressure solve on a
// hierarchy set up in the same step that needs more iterations than the limit turns the PPE's AMG
// to plain aggregation for the rest of the run, once; the choice is part of the state, so a
// restored solver continues on plain aggregation bit for bit. A limit of 1 switches at the first
// step of a column started from p = 0; 0 never switches.
TEST(FreeSurface, AutoAggregationTurnsThePressureAmgPlainOnceAndKeepsItThroughARestore) {
  const double dx = 0.01;
  const auto params = [&](int switch_iterations) {
    SolverParams p = column_params(dx, 1e-3, 1.0);
    p.pressure_preconditioner = p.velocity_preconditioner = Preconditioner::amg;
    p.pressure_amg.reuse_steps = 4;
    p.pressure_amg_switch_iterations = switch_iterations;
    return p;
  };
  FreeSurfaceScene scene = column_scene(column(0.2, 0.3), dx);
  FreeSurfaceSolver never(params(0), scene.boundaries, scene.cloud);
  EXPECT_EQ(never.step().pressure_amg_to_plain, 0);
  ASSERT_TRUE(never.state().pressure_amg.smoothed.has_value());
  EXPECT_TRUE(*never.state().pressure_amg.smoothed);

  FreeSurfaceSolver switched(params(1), scene.boundaries, scene.cloud);
  const StepStats first = switched.step();
  EXPECT_GT(first.pressure_iterations, 1);
  EXPECT_EQ(first.pressure_amg_to_plain, first.pressure_iterations);  // no repeated solve
  EXPECT_FALSE(*switched.state().pressure_amg.smoothed);
  EXPECT_EQ(switched.step().pressure_amg_to_plain, 0);  // once
  const SolverState state = switched.state();
  FreeSurfaceSolver restored(params(1), scene.boundaries, scene.cloud);
  restored.restore(state);
  EXPECT_FALSE(*restored.state().pressure_amg.smoothed);
  for (int k = 0; k < 3; ++k) {
    const StepStats a = switched.step(), b = restored.step();
    EXPECT_EQ(a.pressure_iterations, b.pressure_iterations);
    EXPECT_EQ(b.pressure_amg_to_plain, 0);
  }
  EXPECT_TRUE(std::ranges::equal(switched.positions(), restored.positions()));
  EXPECT_TRUE(std::ranges::equal(switched.pressure(), restored.pressure()));
}

TEST(FreeSurface, AmgPreconditionersMatchTheSparseLuRun) {
  const double dx = 0.005;
  const auto run = [&](Preconditioner preconditioner) {
    FreeSurfaceScene scene = column_scene(column(0.15, 0.3), dx);
    SolverParams p = column_params(dx, 1e-3, 5.0);
    p.pressure_tolerance = 1e-9;
    p.velocity_tolerance = 1e-9;
    p.pressure_preconditioner = p.velocity_preconditioner = preconditioner;
    FreeSurfaceSolver s(p, scene.boundaries, scene.cloud);
    StepStats stats;
    for (int k = 0; k < 8; ++k) stats = s.step();
    if (preconditioner == Preconditioner::amg) {
      EXPECT_LT(stats.pressure_iterations, 30);
      EXPECT_LT(stats.velocity_iterations, 30);
    }
    return std::vector<double>(s.pressure().begin(), s.pressure().end());
  };
  const auto lu = run(Preconditioner::sparse_lu);
  const auto a = run(Preconditioner::amg), b = run(Preconditioner::amg);
  ASSERT_EQ(a.size(), lu.size());
  const double scale = 1000 * 9.81 * 0.3;  // ρ g H
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i], b[i]) << "entry " << i;
    worst = std::max(worst, std::abs(a[i] - lu[i]));
  }
  EXPECT_LT(worst, 1e-5 * scale);
}

// The Verlet neighbour list (SolverParams::neighbour_reuse_skin) changes only the cost: a
// collapsing dam gives the same cloud bit for bit with it and with a fresh search every step,
// and it searches less often.
TEST(FreeSurface, ReusedNeighbourListGivesTheSameRunWithFewerSearches) {
  const double dx = 0.01, dt = 1e-3;
  const auto run = [&](double reuse_skin) {
    FreeSurfaceScene scene = dam_break_scene(ldd::DamBreakScene{{0.1, 0.1}, 0.3}, dx);
    SolverParams p = column_params(dx, dt, 1.0);
    p.neighbour_reuse_skin = reuse_skin;
    FreeSurfaceSolver s(p, scene.boundaries, scene.cloud);
    for (int k = 0; k < 40; ++k) (void)s.step();
    return std::make_pair(std::vector<double>(s.positions().begin(), s.positions().end()), s.neighbour_searches());
  };
  const auto [fresh, fresh_searches] = run(0.0);
  const auto [reused, reused_searches] = run(0.3);
  std::printf("[ measured ] neighbour searches in 40 steps: %zu fresh, %zu with the Verlet list\n", fresh_searches,
              reused_searches);
  EXPECT_EQ(fresh_searches, 41U);  // the constructor's and one per step
  EXPECT_LT(reused_searches, 30U);
  ASSERT_EQ(fresh.size(), reused.size());
  for (std::size_t k = 0; k < fresh.size(); ++k) ASSERT_EQ(fresh[k], reused[k]) << "coordinate " << k;
}

// The divergence probe only measures: the collapsing dam's cloud is the same bit for bit with it on.
// It reads two different fields: the projection removes part of the predicted velocity's mean
// divergence in the bulk, not all of it (the PPE's Laplacian is not the divergence of the
// gradient on a cloud; 0.45 → 0.24 1/s summed over these steps; the water column: docs/ldd.md).
TEST(FreeSurface, DivergenceProbeMeasuresWithoutChangingTheRun) {
  const double dx = 0.01, dt = 1e-3;
  double predicted = 0, projected = 0;
  const auto run = [&](bool probe) {
    FreeSurfaceScene scene = dam_break_scene(ldd::DamBreakScene{{0.1, 0.1}, 0.3}, dx);
    FreeSurfaceSolver s(column_params(dx, dt, 1.0), scene.boundaries, scene.cloud);
    s.set_divergence_probe(probe);
    for (int k = 0; k < 40; ++k) {
      const StepStats stats = s.step();
      if (!probe) {
        EXPECT_EQ(stats.bulk_divergence_predicted, 0.0);
        EXPECT_EQ(stats.bulk_divergence, 0.0);
      }
      predicted += std::abs(stats.bulk_divergence_predicted);
      projected += std::abs(stats.bulk_divergence);
    }
    return std::vector<double>(s.positions().begin(), s.positions().end());
  };
  const auto plain = run(false);
  const auto probed = run(true);
  std::printf(
      "[ measured ] bulk mean divergence over 40 steps, summed magnitudes: predicted %.4g 1/s, projected %.4g 1/s\n",
      predicted, projected);
  ASSERT_EQ(plain.size(), probed.size());
  for (std::size_t k = 0; k < plain.size(); ++k) ASSERT_EQ(plain[k], probed[k]) << "coordinate " << k;
  EXPECT_GT(predicted, 0.0);
  EXPECT_LT(projected, 0.75 * predicted);
}

// Criterion (4), the failure of the first coarse slump (docs/ldd.md): a node on the floor whose
// kernel support (h = 1.6 Δ) holds only floor wall nodes, while fluid nodes at 1.75 Δ — inside the
// 1.9 Δ detection radius, outside h — cover every upward direction and the floor normal removes
// their centroid offset. Criteria (1)–(3) call it interior, and as interior its pressure had no
// level of its own; with the fluid-support test it is on the surface.
TEST(FreeSurface, NodeSupportedOnlyByWallNodesIsOnTheSurface) {
  const double dx = 0.01;
  const auto build = [&](double fluid_weight_limit) {
    NodeCloud cloud;
    cloud.dimension = 2;
    const std::vector<double> up{0.0, 1.0}, none{0.0, 0.0};
    for (int i = -6; i < 6; ++i) cloud.add(std::vector<double>{(i + 0.5) * dx, -0.5 * dx}, NodeKind::wall, up, 0);
    cloud.add(std::vector<double>{0.0, 0.0}, NodeKind::interior, none, -1);  // node 12: the lone node
    for (int q = 0; q <= 6; ++q) {
      const double angle = std::numbers::pi * q / 6;
      cloud.add(std::vector<double>{1.75 * dx * std::cos(angle), 1.75 * dx * std::sin(angle)}, NodeKind::interior, none,
                -1);
    }
    SolverParams p = column_params(dx, 1e-3, 1.0);
    p.surface_fluid_weight = fluid_weight_limit;
    p.hydrostatic_start = false;
    std::vector<std::shared_ptr<const Boundary>> walls{
        std::make_shared<PlaneBoundary>(std::vector<double>{0.0, -0.5 * dx}, std::vector<double>{0.0, 1.0})};
    return FreeSurfaceSolver(p, walls, cloud);
  };
  EXPECT_EQ(build(0.0).kinds()[12], NodeKind::interior);  // criteria (1)–(3) alone
  EXPECT_EQ(build(0.1).kinds()[12], NodeKind::surface);
}

TEST(FreeSurface, SplashNodeFallsFreelyWithoutUpsettingThePressure) {
  const double dx = 0.01, dt = 1e-3;
  FreeSurfaceScene scene = column_scene(column(0.1, 0.1), dx);
  const std::vector<double> drop{0.05, 0.25};
  scene.cloud.add(drop, NodeKind::interior, std::vector<double>{0.0, 0.0}, -1);
  FreeSurfaceSolver s(column_params(dx, dt, 1.0), scene.boundaries, scene.cloud);
  const std::size_t last = s.node_count() - 1;
  StepStats stats;
  for (int k = 0; k < 50; ++k) stats = s.step();
  EXPECT_EQ(s.kinds()[last], NodeKind::splash);
  // Ballistic: u_n = −g n δt, and eq. 20 moves it by (3/2 u_n − 1/2 u_{n−1}) δt = −g δt² (n + ½)
  // per step (the first step is Euler, −g δt²): y_N = y0 − g δt² (1 + Σ_{n=2..N} (n + ½)).
  const double t = 50 * dt;
  double drop_distance = 1.0;
  for (int step = 2; step <= 50; ++step) drop_distance += step + 0.5;
  EXPECT_NEAR(s.positions()[2 * last + 1], 0.25 - 9.81 * dt * dt * drop_distance, 1e-6);
  EXPECT_NEAR(s.velocity()[2 * last + 1], -9.81 * t, 1e-6);
  EXPECT_LT(stats.max_speed, 9.81 * t * 1.001);
  for (double v : s.pressure()) EXPECT_TRUE(std::isfinite(v));
}

// A free-slip gate (normal −x, the fluid on its left) drawn away from the fluid at speed v, like
// the rising Abrams mould's slanted wall.
class RecedingGate final : public Boundary {
 public:
  RecedingGate(double x0, double speed) : x0_(x0), speed_(speed) {}
  bool distance(std::span<const double> x, double t, double& distance, std::span<double> normal) const override {
    distance = x0_ + speed_ * t - x[0];
    normal[0] = -1.0;
    normal[1] = 0.0;
    return true;
  }
  void velocity(double /*t*/, std::span<double> v) const override {
    v[0] = speed_;
    v[1] = 0.0;
  }
  [[nodiscard]] bool slip() const override { return true; }

 private:
  double x0_, speed_;
};

// The failure of the 50 000-node slump at δt = 1e-2 (docs/ldd.md) in 2D: a viscous square
// (μ = 1000 Pa·s, viscous time ρΔ²/μ = 1e-4 s ≪ δt) at hydrostatic pressure whose right-hand gate
// recedes at 0.1 m/s. The gate may not pull the fluid after it (before: its normal velocity was
// imposed, the PPE answered with suction that the no-tension clip turned into p = 0 everywhere),
// its moved wall nodes may not keep last step's pressure (a Neumann source of ρ g v δt per node),
// and the column edge the gate uncovers turns surface without an inviscid kick δt/ρ · ρgh/Δ
// (≈ 1 m/s here); the physical speeds are ρgH²/μ ≈ 0.1 m/s.
TEST(FreeSurface, RecedingGateReleasesAViscousColumnWithoutPressureCollapse) {
  const double dx = 0.01, dt = 1e-2, rho = 1000, g = 9.81, height = 0.1;
  FreeSurfaceScene scene = dam_break_scene(ldd::DamBreakScene{{0.1, height}, 0.3}, dx);
  scene.boundaries.push_back(std::make_shared<RecedingGate>(0.5 * dx, 0.1));
  const int gate = static_cast<int>(scene.boundaries.size()) - 1;
  for (int j = 0; j < 14; ++j)
    scene.cloud.add(std::vector<double>{0.5 * dx, (j + 0.5) * dx}, NodeKind::wall, std::vector<double>{-1.0, 0.0},
                    gate);
  SolverParams p = column_params(dx, dt, 1000.0);
  p.max_courant = 10;  // measure the speeds rather than stop at the guard
  FreeSurfaceSolver s(p, scene.boundaries, scene.cloud);
  const double volume0 = s.fluid_volume();
  double slowest_bottom = 1e300, fastest = 0;
  for (int k = 0; k < 30; ++k) {
    const StepStats stats = s.step();
    fastest = std::max(fastest, stats.max_speed);
    // Bottom-row pressure away from the released edge: hydrostatic support must not vanish.
    double bottom = 0;
    for (std::size_t i = 0; i < s.node_count(); ++i)
      if (s.kinds()[i] == NodeKind::interior && s.positions()[2 * i + 1] < dx && s.positions()[2 * i] < -0.05)
        bottom = std::max(bottom, s.pressure()[i]);
    slowest_bottom = std::min(slowest_bottom, bottom);
  }
  std::printf(
      "[ measured ] receding gate: lowest bottom pressure %.4g Pa (rho g H = %.4g Pa), max |u| %.3g m/s, "
      "volume drift %.3g %%\n",
      slowest_bottom, rho * g * height, fastest, 100 * (s.fluid_volume() / volume0 - 1));
  EXPECT_GT(slowest_bottom, 0.5 * rho * g * height);
  EXPECT_LT(fastest, 0.1);  // ρgH²/μ; the unilateral gate alone: 0.2 m/s
  EXPECT_LT(std::abs(s.fluid_volume() / volume0 - 1), 0.01);
}

TEST(ConeMould, DistanceNormalAndLift) {
  const ConeMouldBoundary cone(0.1, 0.05, 0.3, 0.0, 0.1, 0.45);
  double distance = 0;
  std::vector<double> normal(3);
  const std::vector<double> on_axis{0.0, 0.0, 0.15};
  ASSERT_TRUE(cone.distance(on_axis, 0.0, distance, normal));
  const double slope = 0.05 / 0.3, cosine = 1 / std::sqrt(1 + slope * slope);
  EXPECT_NEAR(distance, 0.075 * cosine, 1e-12);  // radius 0.075 at mid-height
  EXPECT_NEAR(normal[2], -slope * cosine, 1e-12);
  EXPECT_FALSE(cone.distance(std::vector<double>{0.0, 0.0, 0.05}, 1.0, distance, normal));  // below the lifted mould
  EXPECT_NEAR(cone.bottom(1.0), 0.1, 1e-12);
  EXPECT_NEAR(cone.bottom(10.0), 0.45, 1e-12);  // stops at its lift height
  std::vector<double> v(3);
  cone.velocity(10.0, v);
  EXPECT_EQ(v[2], 0.0);
}

TEST(SlumpScene, FillsTheConeVolume) {
  ldd::SlumpScene scene;
  scene.cone_height = 0.3;
  scene.cone_bottom_diameter = 0.2;
  scene.cone_top_diameter = 0.1;
  scene.lift_velocity = 0.1;
  const double dx = 0.01;
  const FreeSurfaceScene s = slump_scene(scene, dx);
  std::size_t fluid = 0;
  for (const NodeKind k : s.cloud.kinds) fluid += k == NodeKind::interior ? 1 : 0;
  const double cone_volume = std::numbers::pi * 0.3 / 3 * (0.01 + 0.005 + 0.0025);
  EXPECT_NEAR(static_cast<double>(fluid) * dx * dx * dx / cone_volume, 1.0, 0.03);
}

// The sloshing column: surface H + A cos(πx/W), so the left wall stands A above H, the right A
// below, and the volume is the flat column's (the cosine integrates to zero over the width). No
// staircase: every column's top node lies half its row spacing below the curve.
TEST(ColumnScene, WaveAmplitudeShapesTheFirstSloshingMode) {
  ldd::ColumnScene scene;
  scene.size = {0.1, 0.05};
  scene.wave_amplitude = 0.005;
  const double dx = 0.001;
  const FreeSurfaceScene s = column_scene(scene, dx);
  std::size_t fluid = 0;
  double left = 0, right = 0;
  for (std::size_t i = 0; i < s.cloud.size(); ++i) {
    if (s.cloud.is_wall(i)) continue;
    ++fluid;
    const double x = s.cloud.positions[2 * i], y = s.cloud.positions[2 * i + 1] + 0.5 * dx;
    if (x < dx) left = std::max(left, y);
    if (x > 0.1 - dx) right = std::max(right, y);
  }
  EXPECT_NEAR(static_cast<double>(fluid) * dx * dx / (0.1 * 0.05), 1.0, 0.01);
  EXPECT_NEAR(left, 0.05 + 0.005, dx);
  EXPECT_NEAR(right, 0.05 - 0.005, dx);
  std::map<long, std::vector<double>> columns;  // heights of the fluid nodes per column of cells
  for (std::size_t i = 0; i < s.cloud.size(); ++i)
    if (!s.cloud.is_wall(i))
      columns[std::lround(s.cloud.positions[2 * i] / dx - 0.5)].push_back(s.cloud.positions[2 * i + 1]);
  ASSERT_EQ(columns.size(), 100u);
  for (auto& [column, heights] : columns) {
    std::sort(heights.begin(), heights.end());
    const double x = (static_cast<double>(column) + 0.5) * dx;
    const double surface = 0.05 + 0.005 * std::cos(std::numbers::pi * x / 0.1);
    const double row = surface / static_cast<double>(heights.size());
    EXPECT_NEAR(heights.back() + 0.5 * row, surface, 1e-12) << "column at x = " << x;
    EXPECT_NEAR(row / dx, 1.0, 0.011) << "column at x = " << x;
    for (std::size_t j = 1; j < heights.size(); ++j) EXPECT_NEAR(heights[j] - heights[j - 1], row, 1e-12);
  }
  double wall_top = 0;  // the side walls rise above the crest
  for (std::size_t i = 0; i < s.cloud.size(); ++i)
    if (s.cloud.is_wall(i)) wall_top = std::max(wall_top, s.cloud.positions[2 * i + 1]);
  EXPECT_GT(wall_top, 0.055 + 3 * dx);
}

// A dam-break case end to end through run_case (the `rheosim run` path): files and summary keys.
TEST(FreeSurfaceRun, DamBreakCaseWritesFrontTableAndFrames) {
  const std::string text =
      "kind: ldd\ndimension: 2\nscene: {type: dam_break, reservoir: [0.2, 0.08], channel_length: 0.5}\n"
      "fluid: {density: 1200, rheology: {model: bingham, plastic_viscosity: 25.0, yield_stress: 25.0, "
      "regularization: 1000}}\ngravity: [0, -9.81]\nresolution: {spacing: 0.02}\ntime: {step: 1.0e-3, end: 0.1}\n";
  const ldd::Case c = ldd::parse_case(text, "dam_break_small.yaml");
  const auto dir = std::filesystem::temp_directory_path() / "rheosim_ldd_dam_break_run";
  std::filesystem::remove_all(dir);
  const RunOutcome outcome = run_case(c, dir, core::Log::null());
  EXPECT_EQ(outcome.status, "end_time");
  for (const char* file : {"summary.json", "front.csv", "nodes.pvd", "frames/nodes_0000.vtk"})
    EXPECT_TRUE(std::filesystem::exists(dir / file)) << file;
  // Not LDD §4.3's 2 m × 0.1 m release: no Table 1 beside it.
  EXPECT_FALSE(std::filesystem::exists(dir / "table1.csv"));
  const auto summary = core::read_json(dir / "summary.json");
  EXPECT_EQ(summary["scene"], "dam_break");
  EXPECT_EQ(summary["fluid_nodes"], 40);  // 10 × 4 cells
  ASSERT_TRUE(summary["front"].is_array());
  EXPECT_GT(summary["front"].back()["x"].get<double>(), 0.0);  // the front left the gate
  EXPECT_LT(summary["volume_drift"].get<double>(), 0.01);
  EXPECT_FALSE(summary.contains("table1"));
  // The final shape, and the yield test: still flowing at 0.1 s, stresses well above τ₀, so not
  // arrested.
  EXPECT_DOUBLE_EQ(summary["final_spread"].get<double>(), summary["front"].back()["x"].get<double>());
  EXPECT_GT(summary["final_height"].get<double>(), 0.0);
  EXPECT_LE(summary["final_height"].get<double>(), 0.08 + 0.02);
  EXPECT_GT(summary["yielded_fraction"].get<double>(), 0.0);
  EXPECT_GT(summary["largest_stress_ratio"].get<double>(), 1.5);
  EXPECT_FALSE(summary["arrested"].get<bool>());
  // The shallow arrest of this reservoir (A = 0.016 m², 2τ₀/(ρg) = 4.247 mm): ℓ = 0.5138 m.
  const auto& arrest = summary["thin_film_arrest"];
  EXPECT_NEAR(arrest["length"].get<double>(), 0.5138, 5e-4);
  EXPECT_NEAR(arrest["front"].get<double>(), arrest["length"].get<double>() - 0.2, 1e-12);
  EXPECT_NEAR(arrest["relative_error"].get<double>(),
              (summary["front"].back()["x"].get<double>() + 0.2) / arrest["length"].get<double>() - 1.0, 1e-12);
  // The final free surface per Δ column, with the shallow arrest's height at each column.
  const core::CsvTable profile = core::read_csv(dir / "profile.csv");
  ASSERT_EQ(profile.numeric_columns().size(), 3u);
  EXPECT_EQ(profile.numeric_columns()[2].name, "thin_film_arrest");
  ASSERT_GE(profile.row_count(), 10u);  // the reservoir's 10 columns at least
  const ThinFilmArrest theory = thin_film_arrest(0.2 * 0.08, 25.0, 1200, 9.81);
  double area = 0;
  for (std::size_t i = 0; i < profile.row_count(); ++i) {
    const auto row = profile.row(i);
    if (i > 0) {
      EXPECT_NEAR(row[0] - profile.row(i - 1)[0], 0.02, 1e-9);  // adjacent columns
    }
    EXPECT_GT(row[1], 0.0);
    EXPECT_LE(row[1], 0.08 + 0.02);
    EXPECT_DOUBLE_EQ(row[2], theory.height_at(row[0] + 0.2));
    area += 0.02 * row[1];
  }
  EXPECT_NEAR(profile.row(0)[0], -0.2 + 0.01, 1e-9);  // the back wall's column
  EXPECT_NEAR(profile.row(profile.row_count() - 1)[0] + 0.01, summary["final_spread"].get<double>(), 0.02);
  EXPECT_NEAR(area / (0.2 * 0.08), 1.0, 0.1);  // the columns hold the reservoir's area
  // The final surface read as a shallow arrest: the summary's fit is profile.csv's.
  std::vector<double> distance, height;
  for (std::size_t i = 0; i < profile.row_count(); ++i) {
    distance.push_back(profile.row(i)[0] + 0.2);
    height.push_back(profile.row(i)[1]);
  }
  const auto fit = fit_thin_film_deposit(distance, height, 0.02, 1200, 9.81);
  ASSERT_TRUE(fit.has_value());
  EXPECT_NEAR(arrest["fitted_yield_stress"].get<double>(), fit->yield_stress, 1e-9 * fit->yield_stress);
  EXPECT_NEAR(arrest["fitted_length"].get<double>(), fit->length, 1e-9);
  EXPECT_NEAR(arrest["fitted_rms_height_error"].get<double>(), fit->rms_height_error, 1e-12);
  std::filesystem::remove_all(dir);
}

// The shallow arrest holds the reservoir's area and balances the yield stress at the base.
TEST(ThinFilmArrest, HoldsTheAreaAndBalancesTheYieldStress) {
  const double density = 1000, gravity = 9.81, yield_stress = 20, area = 0.1 * 0.1;
  const ThinFilmArrest a = thin_film_arrest(area, yield_stress, density, gravity);
  // Midpoint rule on a graded grid (h ~ √(ℓ − s) at the front): s = ℓ(1 − u²).
  double integral = 0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double u = (k + 0.5) / n, s = a.length * (1 - u * u);
    integral += a.height_at(s) * 2 * a.length * u / n;
  }
  EXPECT_NEAR(integral / area, 1.0, 1e-6);
  for (double s : {0.01, 0.1, 0.25, 0.35}) {  // ρ g h |dh/ds| = τ₀
    const double ds = 1e-7, slope = (a.height_at(s + ds) - a.height_at(s - ds)) / (2 * ds);
    EXPECT_NEAR(density * gravity * a.height_at(s) * std::abs(slope) / yield_stress, 1.0, 1e-6) << s;
  }
  EXPECT_NEAR(a.wall_height, a.height_at(0.0), 1e-15);
  EXPECT_EQ(a.height_at(a.length + 0.01), 0.0);
  EXPECT_THROW((void)thin_film_arrest(area, 0.0, density, gravity), std::invalid_argument);
}

// The fit reads τ and ℓ back from a shallow arrest's columns, ignoring the columns beside the back
// wall and those thinner than two spacings.
TEST(ThinFilmFit, ReadsTheYieldStressAndRunoutOfAnArrestShape) {
  const double density = 1000, gravity = 9.81, spacing = 0.0025;
  for (const double yield_stress : {20.0, 35.0}) {
    const ThinFilmArrest a = thin_film_arrest(0.1 * 0.1, yield_stress, density, gravity);
    std::vector<double> distance, height;
    for (int k = 0; (k + 0.5) * spacing < a.length; ++k) {
      const double s = (k + 0.5) * spacing;
      distance.push_back(s);
      height.push_back(a.height_at(s));
    }
    height[0] = height[1] = 0.097;  // columns held by the back wall: not fitted
    const double tip = 1.5 * spacing;
    for (std::size_t k = 0; k < height.size(); ++k)
      if (height[k] < 2 * spacing) height[k] = tip;  // a blunt tip thinner than two nodes: not fitted
    const auto fit = fit_thin_film_deposit(distance, height, spacing, density, gravity);
    ASSERT_TRUE(fit.has_value());
    EXPECT_NEAR(fit->yield_stress, yield_stress, 1e-9 * yield_stress);
    EXPECT_NEAR(fit->length, a.length, 1e-9);
    EXPECT_LT(fit->rms_height_error, 1e-12);
    EXPECT_GT(fit->columns, 100u);
    EXPECT_LT(fit->columns, distance.size() - 2);
  }
  // Heights off the profile by ±1 mm alternately: an rms height error of about 1 mm.
  {
    const ThinFilmArrest a = thin_film_arrest(0.1 * 0.1, 20.0, density, gravity);
    std::vector<double> distance, height;
    for (int k = 2; (k + 0.5) * spacing < 0.3; ++k) {
      distance.push_back((k + 0.5) * spacing);
      height.push_back(a.height_at(distance.back()) + (k % 2 == 0 ? 1e-3 : -1e-3));
    }
    const auto fit = fit_thin_film_deposit(distance, height, spacing, density, gravity);
    ASSERT_TRUE(fit.has_value());
    EXPECT_NEAR(fit->rms_height_error, 1e-3, 1e-4);
    EXPECT_NEAR(fit->yield_stress, 20.0, 0.5);
  }
  // A surface that does not fall towards the front, or too few columns: no fit.
  const std::vector<double> s{0.01, 0.02, 0.03, 0.04}, flat{0.03, 0.03, 0.03, 0.03};
  EXPECT_FALSE(fit_thin_film_deposit(s, flat, 0.0025, density, gravity).has_value());
  EXPECT_FALSE(
      fit_thin_film_deposit(std::span(s).first(2), std::span(flat).first(2), 0.0025, density, gravity).has_value());
  EXPECT_THROW((void)fit_thin_film_deposit(s, std::span(flat).first(3), 0.0025, density, gravity),
               std::invalid_argument);
}

// Pashias et al.'s cylinder slump: the top 2τ₀/(ρg) of the cylinder stays unyielded, the rest
// ends at the height where the weight above balances the yield stress, H_f = z₀(1 + ln(H/z₀)).
TEST(SlumpReferences, PashiasSlumpIsTheHeightAtWhichTheYieldStressHolds) {
  const double density = 1000, gravity = 9.81, height = 0.1;
  for (const double ratio : {0.02, 0.05, 0.1, 0.2, 0.3, 0.45}) {
    const double z0 = 2 * ratio * density * gravity * height / (density * gravity);
    const double final_height = z0 * (1 + std::log(height / z0));
    EXPECT_NEAR(pashias_slump(ratio), 1 - final_height / height, 1e-12) << ratio;
  }
  EXPECT_NEAR(pashias_slump(0.1), 0.478112, 1e-6);
  EXPECT_NEAR(pashias_slump(0.5 - 1e-9), 0.0, 1e-8);  // continuous where the whole cylinder holds
  EXPECT_EQ(pashias_slump(0.6), 0.0);
  EXPECT_THROW((void)pashias_slump(0.0), std::invalid_argument);
}

// The tensor laws' yield criterion: uniaxial compression E = ε̇ diag(−1, ½, ½) has γ̇ = √(2E:E) =
// √3 ε̇ (LDD eq. 5) and axial stress difference 2μ·(3/2)ε̇ = √3 μγ̇, which is √3 τ₀ at yield; the
// unyielded top is √3 τ₀/(ρg) high and the slump follows as in Pashias' balance.
TEST(SlumpReferences, VonMisesSlumpHoldsATopOfRootThreeYieldStressOverWeight) {
  const double rate = 0.7, e2 = rate * rate * (1.0 + 0.25 + 0.25);  // E:E
  const double shear_rate = std::sqrt(2 * e2), yield_stress = 50.0;
  const double viscosity = yield_stress / shear_rate;  // at yield, μγ̇ = τ₀
  EXPECT_NEAR(2 * viscosity * 1.5 * rate, std::sqrt(3.0) * yield_stress, 1e-12);
  const double density = 1000, gravity = 9.81, height = 0.1;
  for (const double ratio : {0.02, 0.05, 0.1, 0.2, 0.3, 0.5}) {
    const double z0 = std::sqrt(3.0) * ratio * density * gravity * height / (density * gravity);
    EXPECT_NEAR(von_mises_cylinder_slump(ratio), 1 - z0 * (1 + std::log(height / z0)) / height, 1e-12) << ratio;
    EXPECT_GT(von_mises_cylinder_slump(ratio), pashias_slump(ratio)) << ratio;  // a weaker column slumps more
  }
  EXPECT_NEAR(von_mises_cylinder_slump(0.3), 0.140210, 1e-6);
  EXPECT_EQ(von_mises_cylinder_slump(0.6), 0.0);
  EXPECT_THROW((void)von_mises_cylinder_slump(-1.0), std::invalid_argument);
}

// Roussel & Coussot's pancake h(r) = √(2τ₀(R − r)/(ρg)) holds the volume it was given.
// The first sloshing mode's period between its limits: deep water (tanh kH → 1) 2π/√(gk), shallow
// water (kH → 0) 2W/√(gH), the long wave crossing the tank and back.
TEST(SloshingReference, LinearPeriodReachesItsDeepAndShallowLimits) {
  const double g = 9.81, width = 0.1, k = std::numbers::pi / width;
  EXPECT_NEAR(linear_sloshing(width, 10 * width, 0.001, 1000, g).period, 2 * std::numbers::pi / std::sqrt(g * k),
              1e-12);
  const double depth = 1e-4 * width;
  EXPECT_NEAR(linear_sloshing(width, depth, 0.0, 1000, g).period * std::sqrt(g * depth) / (2 * width), 1.0, 1e-6);
  EXPECT_DOUBLE_EQ(linear_sloshing(width, 0.05, 0.002, 1000, g).wave_energy, 1000 * g * 0.002 * 0.002 * width / 4);
  EXPECT_THROW((void)linear_sloshing(width, 0.0, 0.001, 1000, g), std::invalid_argument);
  EXPECT_THROW((void)linear_sloshing(width, 0.05, -0.001, 1000, g), std::invalid_argument);
}

// Crossings of a sampled cosine fall on its zeros (here samples, each counted once) and stop at
// `until`; sampled off its zeros, to the chord's error.
TEST(SloshingReference, LevelCrossingsInterpolateBetweenSamples) {
  std::vector<double> t, h;
  for (int i = 0; i <= 1000; ++i) {
    t.push_back(1e-3 * i);
    h.push_back(2.0 + std::cos(2 * std::numbers::pi * t.back() / 0.4));
  }
  const std::vector<double> all = level_crossings(t, h, 2.0, t.size());
  ASSERT_EQ(all.size(), 5u);  // 0.1, 0.3, 0.5, 0.7, 0.9
  for (std::size_t q = 0; q < all.size(); ++q) EXPECT_NEAR(all[q], 0.1 + 0.2 * static_cast<double>(q), 1e-6);
  EXPECT_EQ(level_crossings(t, h, 2.0, 400).size(), 2u);  // samples before t = 0.4 s
  for (double& v : t) v += 3e-4;                          // h sampled off its zeros
  for (std::size_t i = 0; i < t.size(); ++i) h[i] = 2.0 + std::cos(2 * std::numbers::pi * t[i] / 0.4);
  const std::vector<double> off = level_crossings(t, h, 2.0, t.size());
  ASSERT_EQ(off.size(), 5u);
  for (std::size_t q = 0; q < off.size(); ++q) EXPECT_NEAR(off[q], 0.1 + 0.2 * static_cast<double>(q), 1e-6);
}

TEST(SlumpReferences, RousselCoussotPancakeHoldsTheVolume) {
  const double density = 2200, gravity = 9.81, yield_stress = 32;
  const double volume = std::numbers::pi * 0.3 * (0.1 * 0.1 + 0.1 * 0.05 + 0.05 * 0.05) / 3;  // the Abrams cone
  const double radius = 0.5 * roussel_coussot_spread(volume, yield_stress, density, gravity);
  double integral = 0;  // midpoint rule in u with r = R(1 − u²) (h ~ √(R − r) at the edge)
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double u = (k + 0.5) / n, r = radius * (1 - u * u);
    integral += 2 * std::numbers::pi * r * std::sqrt(2 * yield_stress * (radius - r) / (density * gravity)) * 2 *
                radius * u / n;
  }
  EXPECT_NEAR(integral / volume, 1.0, 1e-6);
  EXPECT_NEAR(2 * radius, 0.65, 0.005);  // docs/ldd.md: 0.65 m for LDD §4.4's concrete
  EXPECT_THROW((void)roussel_coussot_spread(volume, 0.0, density, gravity), std::invalid_argument);
  // A spread test reads τ₀ back from the spread; 1 % more spread reads 5 % less yield stress.
  EXPECT_NEAR(roussel_coussot_yield_stress(volume, 2 * radius, density, gravity), yield_stress, 1e-9);
  EXPECT_NEAR(roussel_coussot_yield_stress(volume, 2.02 * radius, density, gravity), yield_stress / std::pow(1.01, 5),
              1e-9);
  EXPECT_THROW((void)roussel_coussot_yield_stress(volume, 0.0, density, gravity), std::invalid_argument);
}

// A slump test reads τ′ back from a slump by Pashias' formula, over its whole range.
TEST(SlumpReferences, PashiasFormulaReadsTheYieldStressRatioBackFromASlump) {
  for (const double ratio : {0.001, 0.05, 0.1, 0.2, 0.3, 0.45, 0.499}) {
    const auto read = pashias_yield_stress_ratio(pashias_slump(ratio));
    ASSERT_TRUE(read.has_value()) << ratio;
    EXPECT_NEAR(*read, ratio, 1e-12) << ratio;
  }
  EXPECT_NEAR(*pashias_yield_stress_ratio(0.478), 0.1, 2e-4);  // docs/ldd.md: s′ = 0.478 at τ′ = 0.1
  EXPECT_FALSE(pashias_yield_stress_ratio(0.0).has_value());   // no slump: any τ′ ≥ 1/2
  EXPECT_FALSE(pashias_yield_stress_ratio(1.0).has_value());
  EXPECT_FALSE(pashias_yield_stress_ratio(-0.1).has_value());
}

TEST(FreeSurfaceRun, AMaterialThatNeverYieldsIsArrested) {
  // τ₀ = 10 kPa against a weight of ρgH ≈ 940 Pa: no node reaches the yield stress, so the run
  // reports the material arrested by the yield criterion; a Newtonian liquid never is.
  const std::string base =
      "kind: ldd\ndimension: 2\nscene: {type: dam_break, reservoir: [0.2, 0.08], channel_length: 0.5}\n"
      "gravity: [0, -9.81]\nresolution: {spacing: 0.02}\ntime: {step: 1.0e-3, end: 0.05}\n";
  const auto run = [&](const std::string& fluid, const char* name) {
    const ldd::Case c = ldd::parse_case(base + fluid, std::string(name) + ".yaml");
    const auto dir = std::filesystem::temp_directory_path() / (std::string("rheosim_ldd_") + name);
    std::filesystem::remove_all(dir);
    EXPECT_EQ(run_case(c, dir, core::Log::null()).status, "end_time");
    auto summary = core::read_json(dir / "summary.json");
    std::filesystem::remove_all(dir);
    return summary;
  };
  const auto stiff =
      run("fluid: {density: 1200, rheology: {model: bingham, plastic_viscosity: 25.0, yield_stress: "
          "1.0e4, regularization: 1000}}\n",
          "never_yields");
  EXPECT_EQ(stiff["yielded_fraction"].get<double>(), 0.0);
  EXPECT_LT(stiff["largest_stress_ratio"].get<double>(), 1.0);
  EXPECT_TRUE(stiff["arrested"].get<bool>());
  const auto liquid = run("fluid: {density: 1000, rheology: {model: newtonian, viscosity: 1.0}}\n", "newtonian_liquid");
  EXPECT_TRUE(liquid["yielded_fraction"].is_null());
  EXPECT_TRUE(liquid["largest_stress_ratio"].is_null());
  EXPECT_FALSE(liquid["arrested"].get<bool>());
}

// A tilted gravity makes the dam-break scene a layer on an incline (bench/ldd_bingham_incline.sh):
// the horizontal floor's references (the shallow arrest, Table 1, Martin & Moyce) are left out
// and the summary is still read.
TEST(FreeSurfaceRun, TiltedGravityHasNoHorizontalFloorReferences) {
  const std::string text =
      "kind: ldd\ndimension: 2\nscene: {type: dam_break, reservoir: [0.2, 0.08], channel_length: 0.5}\n"
      "fluid: {density: 1200, rheology: {model: bingham, plastic_viscosity: 25.0, yield_stress: 25.0, "
      "regularization: 1000}}\ngravity: [2.0, -9.6]\nresolution: {spacing: 0.02}\ntime: {step: 1.0e-3, end: 0.02}\n";
  const auto dir = std::filesystem::temp_directory_path() / "rheosim_ldd_tilted_gravity";
  std::filesystem::remove_all(dir);
  EXPECT_EQ(run_case(ldd::parse_case(text, "incline.yaml"), dir, core::Log::null()).status, "end_time");
  const auto summary = core::read_json(dir / "summary.json");
  EXPECT_FALSE(summary.contains("thin_film_arrest"));
  EXPECT_TRUE(summary["largest_stress_ratio"].is_number());
  EXPECT_EQ(core::read_csv(dir / "profile.csv").numeric_columns().size(), 2u);  // no shallow arrest beside it
  const RunSummary read = read_run_summary(dir / "summary.json");
  EXPECT_FALSE(read.thin_film_arrest.has_value());
  std::filesystem::remove_all(dir);
}

// time.stop_at_arrest ends a run once the yield test has held over the given time after the
// material yielded: τ₀ = 150 Pa yields at the release (ρgH = 942 Pa) and stops within 1.2 s; a
// material that never yields (τ₀ = 300 Pa here) is not stopped for it: its unyielded start is not
// an arrest.
TEST(FreeSurfaceRun, StopAtArrestEndsTheRunOnceTheYieldTestHasHeldAfterYielding) {
  const auto run = [](double yield_stress, const char* name) {
    const std::string text = fmt::format(
        "kind: ldd\ndimension: 2\nscene: {{type: dam_break, reservoir: [0.2, 0.08], channel_length: 0.5}}\n"
        "fluid: {{density: 1200, rheology: {{model: bingham, plastic_viscosity: 25.0, yield_stress: {}, "
        "regularization: 1000}}}}\ngravity: [0, -9.81]\nresolution: {{spacing: 0.02}}\n"
        "time: {{step: 1.0e-3, end: 3.0, stop_at_arrest: 0.1}}\n",
        yield_stress);
    const ldd::Case c = ldd::parse_case(text, std::string(name) + ".yaml");
    const auto dir = std::filesystem::temp_directory_path() / (std::string("rheosim_ldd_") + name);
    std::filesystem::remove_all(dir);
    const RunOutcome outcome = run_case(c, dir, core::Log::null());
    const auto summary = core::read_json(dir / "summary.json");
    const core::CsvTable probes = core::read_csv(dir / "front.csv");
    std::filesystem::remove_all(dir);
    return std::tuple{outcome, summary, probes};
  };
  const auto [stopped, summary, probes] = run(150.0, "stop_at_arrest");
  EXPECT_EQ(stopped.status, "arrested");
  EXPECT_THAT(stopped.message, HasSubstr("time.stop_at_arrest 0.1 s"));
  EXPECT_EQ(summary["status"], "arrested");
  EXPECT_TRUE(summary["arrested"].get<bool>());
  EXPECT_LT(summary["time"].get<double>(), 1.5);
  // The probes' last column: yielded (above 1.1 τ₀) after the release, then 0.1 s within it.
  ASSERT_EQ(probes.numeric_columns().back().name, "largest_stress_ratio");
  const std::vector<double> time = probes.column("time"), ratio = probes.column("largest_stress_ratio");
  EXPECT_GT(*std::max_element(ratio.begin(), ratio.end()), 1.5);
  std::size_t first_within = ratio.size();
  while (first_within > 0 && ratio[first_within - 1] <= 1.1) --first_within;
  ASSERT_GT(first_within, 0u);
  ASSERT_LT(first_within, ratio.size());
  EXPECT_GE(time.back() - time[first_within], 0.1 - 1e-9);
  EXPECT_LT(time.back() - time[first_within], 0.1 + 0.02);  // stopped at the first probe that could
  const auto [unyielded, stiff, stiff_probes] = run(300.0, "stop_at_arrest_unyielded");
  EXPECT_EQ(unyielded.status, "end_time");
  EXPECT_TRUE(stiff["arrested"].get<bool>());  // the end state's test: every node below τ₀
  const std::vector<double> stiff_ratio = stiff_probes.column("largest_stress_ratio");
  EXPECT_LT(*std::max_element(stiff_ratio.begin(), stiff_ratio.end()), 1.0);
}

// A resting water column (μ = 1e-3 Pa·s, nothing to damp a spurious force) stays exactly at rest
// when the fluid leaves the dry wall nodes above its surface out of its gradients, or when they
// carry the fluid's extrapolated (negative) pressure: the hydrostatic field is then a discrete
// equilibrium. With them in at p = 0, the contact-line nodes lose part of the support that
// balances gravity; the column starts to move there and collapses.
TEST(FreeSurfaceRun, RestingWaterColumnStaysAtRestWithoutTheDryWallsInItsGradients) {
  const auto peak_energy = [](const char* dry_walls) {
    const std::string text = fmt::format(
        "kind: ldd\ndimension: 2\nscene: {{type: column, size: [0.1, 0.05]}}\n"
        "fluid: {{density: 1000, rheology: {{model: newtonian, viscosity: 1.0e-3}}}}\ngravity: [0, -9.81]\n"
        "resolution: {{spacing: 0.002}}\ntime: {{step: 1.0e-3, end: 0.3}}\n"
        "solver: {{threads: 1, velocity_tolerance: 1.0e-6, dry_walls: {}}}\n",
        dry_walls);
    const ldd::Case c = ldd::parse_case(text, std::string("resting_water_") + dry_walls + ".yaml");
    const auto dir = std::filesystem::temp_directory_path() / (std::string("rheosim_resting_water_") + dry_walls);
    std::filesystem::remove_all(dir);
    run_case(c, dir, core::Log::null());
    const double peak = core::read_json(dir / "summary.json")["kinetic_energy_peak"].get<double>();
    std::filesystem::remove_all(dir);
    return peak;
  };
  EXPECT_LT(peak_energy("exclude"), 1e-12);  // J/m, against the column's 1.2 J/m of potential energy
  EXPECT_LT(peak_energy("extrapolate"), 1e-12);
  EXPECT_GT(peak_energy("include"), 1e-4);
}

// Runs `text` once straight through and once stopped after `stop_at` steps and run again into
// the same folder; the two must end with the same numbers, bit for bit: the probe history, the
// summary, the final state and the last frame (index last_frame). Returns the stopped run's
// checkpoint (as written when it stopped) for further checks.
void expect_resumed_run_matches_the_straight_one(const std::string& text, const std::string& name, std::size_t stop_at,
                                                 std::size_t steps, int last_frame) {
  const ldd::Case c = ldd::parse_case(text, name + ".yaml");
  const auto straight = std::filesystem::temp_directory_path() / ("rheosim_" + name + "_straight");
  const auto resumed = std::filesystem::temp_directory_path() / ("rheosim_" + name + "_twice");
  std::filesystem::remove_all(straight);
  std::filesystem::remove_all(resumed);
  EXPECT_NE(run_case(c, straight, core::Log::null()).status, "interrupted");
  RunControl stop;
  stop.step_limit = stop_at;
  const RunOutcome first = run_case(c, resumed, core::Log::null(), stop);
  EXPECT_EQ(first.status, "interrupted");
  EXPECT_EQ(first.steps, stop_at);
  ASSERT_TRUE(std::filesystem::exists(resumed / "checkpoint.h5"));
  EXPECT_EQ(core::read_json(resumed / "summary.json")["status"], "interrupted");
  // The stopped run kept a coarse PPE hierarchy from an earlier step: the test covers its restore.
  EXPECT_FALSE(core::read_hdf5_dataset(resumed / "checkpoint.h5", "state/amg/pressure/diagonal").data.empty());
  const RunOutcome second = run_case(c, resumed, core::Log::null());
  EXPECT_NE(second.status, "interrupted");
  EXPECT_EQ(second.steps, steps);

  const std::string probes = std::filesystem::exists(straight / "front.csv") ? "front.csv" : "spread.csv";
  EXPECT_EQ(core::read_csv(straight / probes), core::read_csv(resumed / probes));
  auto a = core::read_json(straight / "summary.json"), b = core::read_json(resumed / "summary.json");
  EXPECT_EQ(b["resumed_at_steps"], nlohmann::json::array({stop_at}));
  // Costs and provenance of each process, not results.
  for (const char* timing :
       {"ms_per_step", "phase_seconds", "wall_time", "resumed_at_steps", "git_revision", "neighbour_searches"}) {
    a.erase(timing);
    b.erase(timing);
  }
  EXPECT_EQ(a, b);  // front / spread, table 1, volume drift, iterations, status, ...
  for (const char* state : {"state/positions", "state/velocity", "state/previous_velocity", "state/pressure"})
    EXPECT_EQ(core::read_hdf5_dataset(straight / "checkpoint.h5", state).data,
              core::read_hdf5_dataset(resumed / "checkpoint.h5", state).data)
        << state;
  const auto bytes = [](const std::filesystem::path& f) {
    std::ifstream in(f, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const auto frame = std::filesystem::path("frames") / fmt::format("nodes_{:04d}.vtk", last_frame);
  ASSERT_TRUE(std::filesystem::exists(straight / frame));
  EXPECT_TRUE(bytes(straight / frame) == bytes(resumed / frame));
  std::filesystem::remove_all(straight);
  std::filesystem::remove_all(resumed);
}

// A 2D Bingham dam break of 100 steps at Δ = 5 mm, probed every 5 steps: the resume tests' deck.
constexpr const char* bingham_dam_break_to_resume =
    "kind: ldd\ndimension: 2\nscene: {type: dam_break, reservoir: [0.2, 0.08], channel_length: 0.5}\n"
    "fluid: {density: 1200, rheology: {model: bingham, plastic_viscosity: 25.0, yield_stress: 25.0, "
    "regularization: 1000}}\ngravity: [0, -9.81]\nresolution: {spacing: 0.005}\ntime: {step: 1.0e-3, end: 0.1}\n"
    "output: {probe_interval: 0.005, frame_interval: 0.03}\n";

// A run stopped part-way (the `--stop-after` path: status interrupted, checkpoint.h5 written) and
// run again into the same folder continues from its checkpoint and ends with the numbers of the
// run that was never stopped, bit for bit. The stop falls between frames (step 46; frames every
// 30 steps), so the second process starts from the checkpoint written when the first stopped,
// with the PPE's AMG hierarchy of an earlier step kept (2D keeps it for 4 steps).
TEST(FreeSurfaceRun, InterruptedRunGoesOnBitForBitFromItsCheckpoint) {
  expect_resumed_run_matches_the_straight_one(bingham_dam_break_to_resume, "ldd_resume_dam_break", 46, 100,
                                              4);  // frame 4: t = 0.1 s
}

// A checkpoint written before the bulk's node count existed holds no first count: the run resumed
// from it counts from its first probe after the resume, and its summary says from when. The run
// that was stopped, which counted from t = 0, says nothing of the kind.
TEST(FreeSurfaceRun, ResumedRunWithoutAFirstCountSaysWhenItsCountBegan) {
  const ldd::Case c = ldd::parse_case(bingham_dam_break_to_resume, "ldd_resume_count.yaml");
  const auto dir = std::filesystem::temp_directory_path() / "rheosim_ldd_resume_count";
  std::filesystem::remove_all(dir);
  RunControl stop;
  stop.step_limit = 46;
  ASSERT_EQ(run_case(c, dir, core::Log::null(), stop).status, "interrupted");
  const auto counted_from = [](const nlohmann::json& summary) {
    for (const auto& warning : summary["warnings"])
      if (warning.get<std::string>().find("bulk_number_compression counts from") != std::string::npos)
        return warning.get<std::string>();
    return std::string();
  };
  const nlohmann::json first = core::read_json(dir / "summary.json");
  ASSERT_TRUE(first["bulk_number_compression"].is_number());
  EXPECT_EQ(counted_from(first), "");

  // The checkpoint as an earlier rheosim wrote it: no count among its numbers.
  const auto checkpoint = dir / "checkpoint.h5";
  core::CsvTable history(core::read_csv(dir / "front.csv").numeric_columns());
  detail::StoredCheckpoint stored = detail::read_checkpoint(checkpoint, c, history);
  for (const char* name : {"number_density0", "number_density0_time", "max_number_compression"})
    ASSERT_EQ(stored.record.numbers.erase(name), 1U) << name;
  detail::write_checkpoint(checkpoint, c, std::move(stored.state), stored.record, history);

  EXPECT_EQ(run_case(c, dir, core::Log::null()).status, "end_time");
  const nlohmann::json resumed = core::read_json(dir / "summary.json");
  EXPECT_TRUE(resumed["bulk_number_compression"].is_number());
  EXPECT_THAT(counted_from(resumed), HasSubstr("counts from t = 0.05 s"));  // the first probe after step 46
  std::filesystem::remove_all(dir);
}

// The same in 3D, where both hierarchies are kept for up to 50 steps: a coarse slump stopped at
// step 23 of 40.
TEST(FreeSurfaceRun, InterruptedSlumpGoesOnBitForBitFromItsCheckpoint) {
  const std::string text =
      "kind: ldd\ndimension: 3\nscene: {type: slump, cone: {height: 0.3, bottom_diameter: 0.2, top_diameter: 0.1}, "
      "lift_velocity: 0.1}\nfluid: {density: 2200, rheology: {model: bingham, plastic_viscosity: 255.0, "
      "yield_stress: 32.0, regularization: 1.0}}\ngravity: [0, 0, -9.81]\nresolution: {spacing: 0.025}\n"
      "time: {step: 1.0e-2, end: 0.4}\noutput: {probe_interval: 0.05, frame_interval: 0.2}\n";
  expect_resumed_run_matches_the_straight_one(text, "ldd_resume_slump", 23, 40, 2);  // frame 2: t = 0.4 s
}

// A folder holding another deck's checkpoint is refused (exit code 2 from `rheosim run`) and its
// checkpoint is left as it was.
TEST(FreeSurfaceRun, CheckpointOfAnotherDeckIsRefused) {
  const std::string text =
      "kind: ldd\ndimension: 2\nscene: {type: dam_break, reservoir: [0.2, 0.08], channel_length: 0.5}\n"
      "fluid: {density: 1200, rheology: {model: newtonian, viscosity: 25.0}}\ngravity: [0, -9.81]\n"
      "resolution: {spacing: 0.02}\ntime: {step: 1.0e-3, end: 0.1}\n";
  const auto dir = std::filesystem::temp_directory_path() / "rheosim_ldd_resume_other_deck";
  std::filesystem::remove_all(dir);
  RunControl stop;
  stop.step_limit = 5;
  EXPECT_EQ(run_case(ldd::parse_case(text, "a.yaml"), dir, core::Log::null(), stop).status, "interrupted");
  const auto before = std::filesystem::last_write_time(dir / "checkpoint.h5");
  std::string other = text;
  other.replace(other.find("end: 0.1"), 8, "end: 0.2");
  try {
    (void)run_case(ldd::parse_case(other, "b.yaml"), dir, core::Log::null());
    ADD_FAILURE() << "another deck's checkpoint was taken";
  } catch (const core::ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "input_sha256");
    EXPECT_NE(e.details().where.file.find("checkpoint.h5"), std::string::npos);
  }
  EXPECT_EQ(std::filesystem::last_write_time(dir / "checkpoint.h5"), before);
  std::filesystem::remove_all(dir);
}

// restore() takes only states of the same cloud: a state whose wall node became fluid (another
// scene) or whose arrays are of another size is refused before anything is changed.
TEST(FreeSurface, RestoreRefusesAStateOfAnotherCloud) {
  FreeSurfaceScene scene = column_scene(column(0.1, 0.1), 0.01);
  FreeSurfaceSolver solver(column_params(0.01, 1e-3, 5.0), scene.boundaries, scene.cloud);
  (void)solver.step();
  SolverState good = solver.state();
  SolverState wall_turned_fluid = good;
  const auto wall = std::find_if(wall_turned_fluid.kinds.begin(), wall_turned_fluid.kinds.end(),
                                 [](NodeKind k) { return k == NodeKind::wall; });
  ASSERT_NE(wall, wall_turned_fluid.kinds.end());
  *wall = NodeKind::interior;
  EXPECT_THROW(solver.restore(wall_turned_fluid), std::invalid_argument);
  SolverState shorter = good;
  shorter.pressure.pop_back();
  EXPECT_THROW(solver.restore(shorter), std::invalid_argument);
  SolverState bad_list = good;
  bad_list.neighbours.indices.front() = solver.node_count();
  EXPECT_THROW(solver.restore(bad_list), std::invalid_argument);
  EXPECT_EQ(solver.steps(), 1U);  // untouched
  solver.restore(good);
  EXPECT_EQ(solver.steps(), 1U);
  EXPECT_NO_THROW((void)solver.step());
}

}  // namespace
}  // namespace rheosim::ldd
