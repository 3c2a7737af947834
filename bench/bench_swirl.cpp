// Speed against error of one single-phase rheometer point (CD §2.3: R = 15 mm, H = 0.5 mm).
// Counters: rel_error = torque vs the creeping closed form (creeping runs), or vs the
// Richardson-extrapolated torque of tests/fluid/validate_swirl (inertial runs); iterations.
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

fluid::SwirlParams params(double n, bool inertia, int nr, int nz, double grading) {
  fluid::SwirlParams p;
  p.grid = {plate.radius, plate.gap, nr, 1, nz, grading};
  p.density = 1000;
  p.rheology = power_law(n);
  p.inertia = inertia;
  p.tolerance = 1e-8;
  return p;
}

// args: n × 10, radial cells, axial cells
void creeping_point(benchmark::State& state) {
  const double n = static_cast<double>(state.range(0)) / 10;
  const fluid::SwirlSolver solver(params(n, false, static_cast<int>(state.range(1)), static_cast<int>(state.range(2)), 1.0));
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
BENCHMARK(creeping_point)->Args({3, 30, 8})->Args({6, 30, 8})->Args({9, 30, 8})->Args({10, 30, 8})->Unit(benchmark::kMillisecond);

// Inertial point, n = 0.3 at 100 1/s (Re ≈ 21); reference torque from the grid study.
void inertial_point(benchmark::State& state) {
  constexpr double richardson_torque = 3.376364987e-08;  // tests/fluid/validate_swirl, n = 0.3
  const fluid::SwirlSolver solver(params(0.3, true, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), 0.1));
  const double omega = plate.angular_velocity(100);
  fluid::SwirlResult result;
  for (auto _ : state) {
    result = solver.solve(omega);
    // Input-only (const) DoNotOptimize: the "+m,r" in-out form of benchmark 1.7 corrupts
    // doubles under GCC 12 (seen here as a garbage torque).
    const double torque = result.torque;
    benchmark::DoNotOptimize(torque);
  }
  state.counters["rel_error"] = std::abs(result.torque - richardson_torque) / richardson_torque;
  state.counters["iterations"] = result.iterations;
}
BENCHMARK(inertial_point)->Args({20, 4})->Args({40, 8})->Args({80, 16})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
