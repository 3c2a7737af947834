// DEM throughput of the rheometer scene: particle-steps per second for the
// CD §4 rheometer (R = 15 mm, H = 0.5 mm, d = 200 µm) at φ = 0.1 and 0.3 and for a smaller
// disk, on however many ranks it is started with (bench/dem_scaling.sh runs 1 and 2), and the
// strain a dry-shear point needs to reach a steady torque on a small disk (--steady).
//
// A plain MPI program, not Google Benchmark: one LIGGGHTS run per row is the measurement, and
// all ranks must take part in it. Rank 0 prints a Markdown table.
//
// Throughput rows: the scene as the CFD-DEM runs will use it (CD §4 material, gravity on,
// δt = 0.3 t_R, γ̇_R = 100 1/s), particles placed at φ and started with a small random speed
// (1 cm/s) so that contacts form as in a settling suspension. `--warmup` steps (excluded:
// the first run sets LIGGGHTS up and builds neighbour lists), then `--steps` timed steps.
// Particle-steps/s = N · steps / wall time. The cost of one unit of strain γ = γ̇_R t at a
// rim rate γ̇_R is N / (γ̇_R δt) particle-steps, i.e. (1/(γ̇_R δt)) / (steps per second).
//
// Steady-torque row (--steady, one rank): the dry-shear scene of tests/dem/validate_dry_shear
// (R = 1 mm, H = 0.25 mm, d = 0.1 mm, φ = 0.5, γ̇_R = 16000 1/s) run to strain --strain; the
// torque is averaged in windows of 2 strain units; the steady strain γ_ss is the start of the
// first window from which on every window mean stays within ±35 % of the mean over the last
// half of the run.
//
// Usage: bench_dem [--steps=N] [--warmup=N] [--only=cd|small] [--steady] [--strain=40]
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <unistd.h>

#include "rheosim/dem/mpi_session.hpp"
#include "rheosim/dem/rheometer_scene.hpp"

namespace {

namespace fs = std::filesystem;
using rheosim::dem::RheometerScene;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

struct Row {
  std::string name;
  double radius, gap, diameter, phi;
};

void throughput(const Row& row, std::int64_t warmup, std::int64_t steps, int ranks, int rank, const fs::path& dir) {
  MPI_Barrier(MPI_COMM_WORLD);
  const auto t0 = Clock::now();
  RheometerScene scene({.geometry = {.radius = row.radius, .gap = row.gap},
                        .particles = {.volume_fraction = row.phi, .diameter = row.diameter, .density = 1000.0},
                        .rim_shear_rate = 100.0,
                        .run_directory = dir,
                        .initial_speed = 0.01,
                        .torque_sample_interval = 1000});
  const double build = seconds_since(t0);
  scene.advance(warmup);
  MPI_Barrier(MPI_COMM_WORLD);
  const auto t1 = Clock::now();
  scene.advance(steps);
  MPI_Barrier(MPI_COMM_WORLD);
  const double wall = seconds_since(t1);
  const auto n = static_cast<double>(scene.total_particle_count());
  const double rate = n * static_cast<double>(steps) / wall;
  const double steps_per_strain = 1.0 / (100.0 * scene.time_step());  // at γ̇_R = 100 1/s
  if (rank == 0)
    fmt::print("| {} | {} | {:.0f} | {} | {:.2f} | {} | {:.3g} | {:.3g} | {:.3g} | {:.0f} |\n", row.name, row.phi, n,
               ranks, build, steps, wall, rate, scene.time_step(), steps_per_strain * n / rate);
}

void steady(double strain, const fs::path& dir) {
  constexpr double rate = 16000.0;
  constexpr double gap = 2.5e-4;
  RheometerScene::Params p{.geometry = {.radius = 1e-3, .gap = gap},
                           .particles = {.volume_fraction = 0.5, .diameter = 1e-4, .density = 1000.0},
                           .rim_shear_rate = rate,
                           .gravity = std::nullopt,
                           .seed = 3,
                           .run_directory = dir,
                           .initial_speed = 0.5 * rate * gap,
                           .torque_sample_interval = 65,                                 // ~20 samples per unit strain
                           .communicator_fortran_handle = MPI_Comm_c2f(MPI_COMM_SELF)};  // rank 0 alone
  RheometerScene scene(p);
  const double steps_per_strain = 1.0 / (rate * scene.time_step());
  const auto t0 = Clock::now();
  const auto steps = static_cast<std::int64_t>(std::ceil(strain * steps_per_strain));
  scene.advance(steps);
  const double wall = seconds_since(t0);
  // Window means over 2 strain units.
  std::vector<double> sums(static_cast<std::size_t>(std::ceil(strain / 2.0)), 0.0);
  std::vector<int> counts(sums.size(), 0);
  double tail = 0.0;
  int tail_count = 0;
  for (const auto& s : scene.torque_series()) {
    const double g = s.time * rate;
    const auto w = std::min(sums.size() - 1, static_cast<std::size_t>(g / 2.0));
    sums[w] += s.torque;
    ++counts[w];
    if (g > 0.5 * strain) {
      tail += s.torque;
      ++tail_count;
    }
  }
  const double final_mean = tail / std::max(1, tail_count);
  std::size_t first = sums.size();
  for (std::size_t w = sums.size(); w-- > 0;) {
    const double mean = counts[w] > 0 ? sums[w] / counts[w] : 0.0;
    if (std::abs(mean - final_mean) > 0.35 * final_mean) break;
    first = w;
  }
  const double n = static_cast<double>(scene.total_particle_count());
  fmt::print("\nsteady dry shear, R = 1 mm, H = 0.25 mm, d = 0.1 mm, φ = 0.5, γ̇_R = {} 1/s, N = {:.0f}:\n", rate, n);
  fmt::print("  window means (strain: torque N·m):");
  for (std::size_t w = 0; w < sums.size(); ++w)
    fmt::print("{} {:.0f}: {:.2e}", w % 5 == 0 ? "\n   " : ",", 2.0 * static_cast<double>(w),
               counts[w] > 0 ? sums[w] / counts[w] : 0.0);
  fmt::print("\n  mean over the last half: {:.3e} N·m\n", final_mean);
  fmt::print("  steady from strain γ_ss = {:.0f} (windows within ±35 % of that mean from there on)\n",
             2.0 * static_cast<double>(first));
  fmt::print("  {} steps ({:.1f} steps per unit strain) in {:.1f} s: {:.3g} particle-steps/s\n", steps,
             steps_per_strain, wall, n * static_cast<double>(steps) / wall);
}

int run(int argc, char** argv) {
  const rheosim::dem::MpiSession session;
  int rank = 0;
  int ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  std::int64_t steps = 2000;
  std::int64_t warmup = 500;
  std::string only;
  bool do_steady = false;
  double strain = 40.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--steps=", 0) == 0)
      steps = std::stoll(a.substr(8));
    else if (a.rfind("--warmup=", 0) == 0)
      warmup = std::stoll(a.substr(9));
    else if (a.rfind("--only=", 0) == 0)
      only = a.substr(7);
    else if (a == "--steady")
      do_steady = true;
    else if (a.rfind("--strain=", 0) == 0)
      strain = std::stod(a.substr(9));
    else {
      if (rank == 0) fmt::print(stderr, "bench_dem: unknown argument '{}'\n", a);
      return 2;
    }
  }
  long long pid = ::getpid();
  MPI_Bcast(&pid, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  const fs::path dir = fs::temp_directory_path() / fmt::format("rheosim_bench_dem_{}", pid);

  const std::vector<Row> rows{
      {"cd", 15e-3, 5e-4, 2e-4, 0.1},
      {"cd", 15e-3, 5e-4, 2e-4, 0.3},
      {"small", 5e-3, 5e-4, 2e-4, 0.1},
      {"small", 5e-3, 5e-4, 2e-4, 0.3},
  };
  if (!do_steady) {
    if (rank == 0) {
      fmt::print("cd: R = 15 mm, H = 0.5 mm, d = 0.2 mm (CD §4); small: R = 5 mm, same gap and particles\n");
      fmt::print(
          "| disk | φ | particles | ranks | build s | timed steps | wall s | particle-steps/s | δt s | "
          "wall s per unit strain at γ̇_R = 100 1/s |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
    }
    int k = 0;
    for (const auto& row : rows)
      if (only.empty() || only == row.name)
        throughput(row, warmup, steps, ranks, rank, dir / fmt::format("row{}", k++));
  } else if (rank == 0) {
    steady(strain, dir / "steady");
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) fs::remove_all(dir);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_dem: {}\n", e.what());
    rheosim::dem::MpiSession::abort_all(1);
  }
}
