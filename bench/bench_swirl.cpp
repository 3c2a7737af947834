// Speed against error of one single-phase rheometer point (CD §2.3: R = 15 mm, H = 0.5 mm).
// Counters: rel_error = torque vs the creeping closed form (creeping runs), or vs a fine-grid
// Richardson torque (inertial runs, see inertial_reference); iterations.
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include "rheosim/core/config.hpp"
#include "rheosim/fluid/swirl.hpp"
#include "rheosim/rheometer/plate.hpp"

namespace {

using namespace rheosim;

const rheometer::ParallelPlate plate{0.015, 0.0005};

std::shared_ptr<const core::Rheology> power_law(double n) {
  const std::string yaml = "model: power_law\nconsistency: 1.0e-3\nindex: " + std::to_string(n) + "\n";
  return core::make_rheology(core::Document::from_string(yaml, "bench.yaml").root());
}

fluid::SwirlParams params(double n, bool inertia, int nr, int nz, double grading, double axial_stretching = 0) {
  fluid::SwirlParams p;
  p.grid = {plate.radius, plate.gap, nr, 1, nz, grading, axial_stretching};
  p.density = 1000;
  p.rheology = power_law(n);
  p.inertia = inertia;
  p.tolerance = 1e-8;
  return p;
}

// args: n × 10, radial cells, axial cells
void creeping_point(benchmark::State& state) {
  const double n = static_cast<double>(state.range(0)) / 10;
  const fluid::SwirlSolver solver(
      params(n, false, static_cast<int>(state.range(1)), static_cast<int>(state.range(2)), 1.0));
  const double omega = plate.angular_velocity(100);
  fluid::SwirlResult result;
  for (auto _ : state) {
    result = solver.solve(omega);
    // Input-only (const) DoNotOptimize: the "+m,r" in-out form of benchmark 1.7 corrupts
    // doubles under GCC 12 (seen here as a garbage torque).
    const double torque = result.torque;
    benchmark::DoNotOptimize(torque);
  }
  const double exact = rheometer::power_law_torque(plate, 1e-3, n, 100);
  state.counters["rel_error"] = std::abs(result.torque - exact) / exact;
  state.counters["torque"] = result.torque;
  state.counters["iterations"] = result.iterations;
}
BENCHMARK(creeping_point)
    ->Args({3, 30, 8})
    ->Args({6, 30, 8})
    ->Args({9, 30, 8})
    ->Args({10, 30, 8})
    ->Unit(benchmark::kMillisecond);

// Inertial points (grading 0.1 towards the rim). The reference torques are the Richardson
// extrapolation of 80 × 128 cells with 40 × 64 (the inertial_reference rows below, 2026-11-23);
// the grid study in tests/fluid/validate_swirl puts their uncertainty near 1e-4.
// args: n × 10, γ̇_R [1/s], radial cells, axial cells.
double reference_torque(int n10, int rate) {
  if (n10 == 3 && rate == 100) return 3.34428974e-08;
  if (n10 == 3 && rate == 50) return 2.19702548e-08;
  if (n10 == 6 && rate == 100) return 9.79217248e-08;
  return std::nan("");
}

fluid::SwirlResult inertial_solve(benchmark::State& state, double axial_stretching = 0) {
  const double n = static_cast<double>(state.range(0)) / 10;
  const fluid::SwirlSolver solver(
      params(n, true, static_cast<int>(state.range(2)), static_cast<int>(state.range(3)), 0.1, axial_stretching));
  const double omega = plate.angular_velocity(static_cast<double>(state.range(1)));
  fluid::SwirlResult result;
  for (auto _ : state) {
    result = solver.solve(omega);
    // Input-only (const) DoNotOptimize: the "+m,r" in-out form of benchmark 1.7 corrupts
    // doubles under GCC 12 (seen here as a garbage torque).
    const double torque = result.torque;
    benchmark::DoNotOptimize(torque);
  }
  state.counters["torque"] = result.torque;
  state.counters["torque_ext"] = result.extrapolated_torque;
  state.counters["est_error"] = result.extrapolation_error;  // the solver's own estimate
  state.counters["iterations"] = result.iterations;
  state.counters["converged"] = result.converged ? 1 : 0;
  return result;
}

// rel_error: this grid's torque; ext_error: the extrapolation over it and half its cells,
// which the grid-sequenced solve gives at no extra cost.
void inertial_point(benchmark::State& state) {
  const auto result = inertial_solve(state);
  const double reference = reference_torque(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  state.counters["rel_error"] = std::abs(result.torque - reference) / reference;
  state.counters["ext_error"] = std::abs(result.extrapolated_torque - reference) / reference;
}
BENCHMARK(inertial_point)
    ->ArgsProduct({{3}, {50, 100}, {20, 40}, {8, 16, 32}})
    ->Args({3, 100, 80, 64})
    ->ArgsProduct({{6}, {100}, {20, 40}, {8, 16, 32}})
    ->Unit(benchmark::kMillisecond);

// The same with the axial cells clustered towards both plates (tanh stretching β, grid.hpp),
// where the shear-thinning plate layers are thin. args: n × 10, γ̇_R, radial cells, axial
// cells, β × 10.
void inertial_point_stretched(benchmark::State& state) {
  const auto result = inertial_solve(state, static_cast<double>(state.range(4)) / 10);
  const double reference = reference_torque(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  state.counters["rel_error"] = std::abs(result.torque - reference) / reference;
  state.counters["ext_error"] = std::abs(result.extrapolated_torque - reference) / reference;
}
BENCHMARK(inertial_point_stretched)
    ->ArgsProduct({{3}, {50, 100}, {20, 40}, {8, 16}, {10, 15, 20}})
    ->ArgsProduct({{6}, {100}, {20, 40}, {8, 16}, {10, 15, 20}})
    ->Unit(benchmark::kMillisecond);

// Axial refinement at fixed N_r = 20 (the error is almost all in z): uniform and clustered.
BENCHMARK(inertial_point_stretched)
    ->Name("inertial_axial_study")
    ->ArgsProduct({{3}, {50, 100}, {20}, {8, 16, 32, 64, 128}, {0, 15, 20, 25}})
    ->ArgsProduct({{6}, {100}, {20}, {8, 16, 32, 64, 128}, {0, 15, 20, 25}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// The references: 80 × 128 cells, extrapolated with 40 × 64 (about 10 s each).
void inertial_reference(benchmark::State& state) { (void)inertial_solve(state); }
BENCHMARK(inertial_reference)
    ->Args({3, 100, 80, 128})
    ->Args({3, 50, 80, 128})
    ->Args({6, 100, 80, 128})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// An independent check of the references on plate-clustered grids (β = 1.5): 40 × 64 (with
// its 20 × 32 start) and 80 × 128 (with its 40 × 64 start) give three grids for the observed
// order and a Richardson torque. args as inertial_point_stretched.
void inertial_reference_stretched(benchmark::State& state) {
  (void)inertial_solve(state, static_cast<double>(state.range(4)) / 10);
}
BENCHMARK(inertial_reference_stretched)
    ->Args({3, 50, 40, 64, 15})
    ->Args({3, 50, 80, 128, 15})
    ->Args({3, 100, 40, 64, 15})
    ->Args({3, 100, 80, 128, 15})
    ->Args({6, 100, 40, 64, 15})
    ->Args({6, 100, 80, 128, 15})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
