// LDD cavity benchmark (scripted; prints a table): milliseconds per time step for the seed's
// cavities at 100² and 200² nodes on 1 and 2 threads, with the time per phase, next to the
// seed's GPU figures (LDD §4.1: 12 ms/step square Casson cavity; §4.2: 26 ms/step skewed
// power-law cavity), and (full mode) `accuracy` for the Newtonian Re = 100 cavity at 25²–200²
// on 2 threads: error against Ghia et al. (1982) and against the finest resolution.
//
//   build-ldd/bin/bench_ldd            # full table (several minutes)
//   build-ldd/bin/bench_ldd --quick    # timings only, fewer steps
//   build-ldd/bin/bench_ldd --quick --pressure amg --velocity amg   # preconditioners of the
//                                       # PPE / eq. 19 solves (jacobi | lu | amg; default lu / jacobi)
//   build-ldd/bin/bench_ldd --quick --threads 1 --cells 200        # one thread count / resolution
//   build-ldd/bin/bench_ldd --quick --steps 200 --dump DIR          # timed steps per row; write each
//                                       # row's final u, v, p per node and the 2 × 101 centre-line
//                                       # velocities to DIR (compare_ldd_dumps.py compares two DIRs)
//   build-ldd/bin/bench_ldd bandwidth   # memory bandwidth: triad and the stencil product, 1 and 2
//                                       # threads (the floor of the free-surface step)
//   build-ldd/bin/bench_ldd floor RUN_DIR...  # the linear solves' floor of measured free-surface runs
//                                       # (bench_ldd run folders, two threads): product, V-cycle and
//                                       # AMG set-up times on their initial clouds, the floor per step
//                                       # at their iteration counts, and measured / floor
//                                       # (bench/ldd_floor.sh runs the three the docs tabulate)
//   build-ldd/bin/bench_ldd run CASE.yaml OUT_DIR [--stability-probe N] [--divergence-probe]
//                                       # one LDD case through ldd::run_case (the same code path as
//                                       # `rheosim run`, without the other modules); with N > 0 the
//                                       # probe file gains the step map's growth, with
//                                       # --divergence-probe the bulk's mean divergence before and
//                                       # after the projection (RunControl)
//   build-ldd/bin/bench_ldd accuracy [--re 100|1000] [--interpolation quadratic|shepard|gradient_corrected]
//                          [--dt S] [--end S] [--threads N] CELLS...
//                                       # Newtonian cavity at each resolution to steady state: max
//                                       # error against Ghia et al. (1982), differences between
//                                       # resolutions and against the finest, wall and CPU ms/step
//
// Timings exclude the first step (which builds the operators and factorises the pressure matrix;
// reported separately as "setup").
#include <omp.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <variant>
#include <vector>

#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rheosim/core/log.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/cavity_solver.hpp"
#include "rheosim/ldd/domain.hpp"
#include "rheosim/ldd/free_surface.hpp"
#include "rheosim/ldd/operators.hpp"
#include "rheosim/ldd/run.hpp"
#include "rheosim/ldd/scenes.hpp"
#include "rheosim/numerics/amg.hpp"
#include "rheosim/numerics/krylov.hpp"
#include "rheosim/numerics/neighbours.hpp"

namespace {

using namespace rheosim;

std::shared_ptr<const core::Rheology> rheology(const std::string& yaml) {
  const std::string text =
      "kind: ldd\ndimension: 2\nscene: {type: cavity, size: [1, 1], lid_velocity: 1}\n"
      "fluid: {density: 1, rheology: " +
      yaml + "}\ngravity: [0, 0]\nresolution: {spacing: 0.1}\ntime: {step: 1, end: 1}\n";
  return ldd::parse_case(text, "bench.yaml").settings.fluid.rheology;
}

struct Scenario {
  const char* name;
  double skew_angle;  // 0: square
  const char* rheology;
  double gpu_ms;  // seed's GPU ms/step
};

struct Preconditioners {
  ldd::Preconditioner pressure = ldd::SolverParams::for_cavity().pressure_preconditioner;
  ldd::Preconditioner velocity = ldd::SolverParams::for_cavity().velocity_preconditioner;
  numerics::AmgSettings amg;  // both systems
};

// Process CPU time [s]: under load from other jobs the wall clock overstates the work.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The state after the timed steps, for comparing builds: every node's u, v, p, then u on the
// vertical and v on the horizontal centre line of the cavity (101 points each, cavity fractions).
void dump_state(const std::string& path, const ldd::Cavity& cavity, const ldd::CavitySolver& solver) {
  std::vector<double> probes;
  for (int k = 0; k <= 100; ++k) {
    const auto a = cavity.point(0.5, k / 100.0);
    probes.insert(probes.end(), {a[0], a[1]});
  }
  for (int k = 0; k <= 100; ++k) {
    const auto a = cavity.point(k / 100.0, 0.5);
    probes.insert(probes.end(), {a[0], a[1]});
  }
  const auto sampled = solver.sample_velocity(probes);
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    return;
  }
  const auto u = solver.velocity();
  const auto p = solver.pressure();
  for (std::size_t i = 0; i < solver.node_count(); ++i)
    std::fprintf(f, "node %.17g %.17g %.17g\n", u[2 * i], u[2 * i + 1], p[i]);
  for (std::size_t k = 0; k < 202; ++k) std::fprintf(f, "line %.17g\n", sampled[2 * k + (k < 101 ? 0 : 1)]);
  std::fclose(f);
}

void time_steps(const Scenario& s, int cells, int threads, int steps, const Preconditioners& preconditioners,
                const std::string& dump_dir) {
  omp_set_num_threads(threads);
  ldd::CavityScene scene;
  scene.size = {1.0, 1.0};
  scene.lid_velocity = 1.0;
  scene.skew_angle = s.skew_angle;
  ldd::SolverParams p = ldd::SolverParams::for_cavity();
  p.rheology = rheology(s.rheology);
  p.spacing = 1.0 / cells;
  p.time_step = 1e-3;
  p.pressure_preconditioner = preconditioners.pressure;
  p.velocity_preconditioner = preconditioners.velocity;
  p.pressure_amg = p.velocity_amg = preconditioners.amg;
  const ldd::Cavity cavity(scene, p.spacing);
  ldd::CavitySolver solver(p, cavity.walls(), cavity.initial_cloud());
  const auto t0 = std::chrono::steady_clock::now();
  solver.step();
  const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const ldd::PhaseTimes before = solver.phase_times();
  const auto t1 = std::chrono::steady_clock::now();
  const double cpu_start = cpu_seconds();
  int pressure_iterations = 0, velocity_iterations = 0;
  for (int k = 0; k < steps; ++k) {
    const auto stats = solver.step();
    pressure_iterations += stats.pressure_iterations;
    velocity_iterations += stats.velocity_iterations;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  const double cpu = cpu_seconds() - cpu_start;
  const ldd::PhaseTimes& a = solver.phase_times();
  const double per = 1e3 / steps;
  std::printf(
      "| %s | %d² (%zu nodes) | %s / %s | %d | %.1f | %.1f | %.0f | %.2f s | %.1f / %.1f / %.1f / %.1f | %.1f / %.1f "
      "|\n",
      s.name, cells, solver.node_count(), ldd::name_of(preconditioners.pressure).data(),
      ldd::name_of(preconditioners.velocity).data(), threads, 1e3 * seconds / steps, 1e3 * cpu / steps, s.gpu_ms, setup,
      per * (a.rheology - before.rheology), per * (a.pressure - before.pressure), per * (a.momentum - before.momentum),
      per * (a.advection - before.advection), static_cast<double>(pressure_iterations) / steps,
      static_cast<double>(velocity_iterations) / steps);
  std::fflush(stdout);
  if (!dump_dir.empty())
    dump_state(dump_dir + "/" + (s.skew_angle == 0 ? "square" : "skewed") + "_" + std::to_string(cells) + "_t" +
                   std::to_string(threads) + ".txt",
               cavity, solver);
}

struct AccuracyOptions {
  int reynolds = 100;
  ldd::LatticeInterpolation interpolation = ldd::LatticeInterpolation::quadratic;
  double dt = 5e-3, end = 80.0;
  int threads = 1;
  std::vector<int> resolutions;
};

// u on the vertical centre line, then v on the horizontal one, from a cavity run's summary.json.
std::vector<double> centre_line_profile(const nlohmann::json& summary) {
  std::vector<double> profile;
  for (const auto& p : summary["centerlines"]["vertical"])
    profile.push_back(p["u"].is_number() ? p["u"].get<double>() : NAN);
  for (const auto& p : summary["centerlines"]["horizontal"])
    profile.push_back(p["v"].is_number() ? p["v"].get<double>() : NAN);
  return profile;
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0;
  for (std::size_t k = 0; k < a.size(); ++k) d = std::max(d, std::abs(a[k] - b[k]));
  return d;
}

// Each resolution is a `rheosim run` of the unit cavity (ldd::run_case into a temporary folder),
// stopped at steady state (residual sampled every 0.25 L/U); the Ghia comparison is the run's own.
void accuracy(const AccuracyOptions& o) {
  std::printf(
      "\nNewtonian cavity Re %d, interpolation %s, δt %g s, %d thread(s), steady residual 1e-4\n\n"
      "| cells | steps | t [s] | status | wall ms/step | CPU ms/step (whole run) | advection+interpolation ms/step | "
      "u(0.5, 0.5) | v(0.5, 0.5) | max error vs Ghia | worst point |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n",
      o.reynolds, ldd::name_of(o.interpolation).data(), o.dt, o.threads);
  std::vector<std::vector<double>> profiles;
  for (int cells : o.resolutions) {
    const std::string deck = fmt::format(
        "kind: ldd\nname: accuracy_{0}\ndimension: 2\nscene: {{type: cavity, size: [1, 1], lid_velocity: 1}}\n"
        "fluid: {{density: 1, rheology: {{model: newtonian, viscosity: {1}}}}}\ngravity: [0, 0]\n"
        "resolution: {{spacing: {2:.17g}}}\ntime: {{step: {3}, end: {4}, steady_tolerance: 1.0e-4}}\n"
        "output: {{frame_interval: {4}, probe_interval: 0.25}}\nsolver: {{threads: {5}, interpolation: {6}}}\n",
        cells, 1.0 / o.reynolds, 1.0 / cells, o.dt, o.end, o.threads, ldd::name_of(o.interpolation));
    const auto dir = std::filesystem::temp_directory_path() / fmt::format("rheosim_bench_accuracy_{}", cells);
    std::filesystem::remove_all(dir);
    const std::clock_t cpu0 = std::clock();
    (void)ldd::run_case(ldd::parse_case(deck, "accuracy.yaml"), dir, core::Log::null());
    const double cpu_seconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    const auto summary = core::read_json(dir / "summary.json");
    std::filesystem::remove_all(dir);
    const double steps = std::max(1.0, summary["steps"].get<double>());
    double worst = 0;
    std::string where = "–";
    if (summary.contains("ghia"))
      for (const auto& g : summary["ghia"]["points"]) {
        const double computed = g["computed"].get<double>(), reference = g["reference"].get<double>();
        if (std::abs(computed - reference) <= worst) continue;
        worst = std::abs(computed - reference);
        const std::string line = g["line"].get<std::string>();
        where = fmt::format("{} at {} = {:.4f} ({:.4f} vs {:.4f})", line, line == "u" ? "y" : "x",
                            g["coordinate"].get<double>(), computed, reference);
      }
    const auto profile = centre_line_profile(summary);
    std::printf("| %d² | %.0f | %.2f | %s (residual %.1e) | %.2f | %.2f | %.2f | %.4f | %.4f | %.4f | %s |\n", cells,
                steps, summary["time"].get<double>(),
                summary["status"] == "diverged" ? summary.value("message", "diverged").c_str()
                                                : summary["status"].get<std::string>().c_str(),
                summary["final_residual"].get<double>(), summary["ms_per_step"].get<double>(),
                1e3 * cpu_seconds / steps, 1e3 * summary["phase_seconds"]["advection"].get<double>() / steps,
                profile[50], profile[101 + 50], worst, where.c_str());
    std::fflush(stdout);
    profiles.push_back(profile);
  }
  if (profiles.size() < 2) return;
  std::printf("\n| cells | max |Δu|, |Δv| vs %d² (202 centre-line points) | vs the next finer |\n| --- | --- | --- |\n",
              o.resolutions.back());
  for (std::size_t r = 0; r + 1 < profiles.size(); ++r)
    std::printf("| %d² | %.4f | %.4f |\n", o.resolutions[r], max_difference(profiles[r], profiles.back()),
                max_difference(profiles[r], profiles[r + 1]));
}

// Wall seconds of the fastest of `repetitions` calls of body.
double best_seconds(int repetitions, const auto& body) {
  double best = 1e300;
  for (int r = 0; r < repetitions; ++r) {
    const auto start = std::chrono::steady_clock::now();
    body();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

// What memory bandwidth allows (docs/performance.md, "LDD free surfaces: where the floor is"):
// a STREAM-like triad over 3 × 160 MB and the free-surface solver's sparse product,
// StencilMatrix::multiply, on a 50 000-node 2D lattice with the free-surface neighbour radius
// (h + skin = 1.9 Δ), on 1 and 2 threads, best of several repetitions.
void bandwidth() {
  const std::size_t n = 20'000'000;
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  std::vector<double> x;
  for (int j = 0; j < 200; ++j)
    for (int i = 0; i < 250; ++i) x.insert(x.end(), {static_cast<double>(i), static_cast<double>(j)});
  const numerics::NeighbourList nb = numerics::find_neighbours(x, 2, 1.9);
  numerics::StencilMatrix m{&nb, std::vector<double>(nb.node_count(), 4.0), std::vector<double>(nb.pair_count(), -0.3)};
  std::vector<double> u(nb.node_count(), 1.0), out(nb.node_count());
  // Bytes a product streams: per pair an index and a value, per node a diagonal, an offset, the
  // result and (from cache, mostly) x.
  const double product_bytes =
      16.0 * static_cast<double>(nb.pair_count()) + 32.0 * static_cast<double>(nb.node_count());
  std::printf(
      "memory bandwidth: triad a = b + s c over %zu doubles; numerics::StencilMatrix::multiply on %zu nodes, %zu pairs "
      "(%.1f per node), %.1f MB per product\n",
      n, nb.node_count(), nb.pair_count(), static_cast<double>(nb.pair_count()) / static_cast<double>(nb.node_count()),
      product_bytes / 1e6);
  std::printf("%8s %14s %18s %16s\n", "threads", "triad GB/s", "product ms", "product GB/s");
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    const double triad = best_seconds(5, [&] {
      const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t i = 0; i < count; ++i)
        a[static_cast<std::size_t>(i)] = b[static_cast<std::size_t>(i)] + 3.0 * c[static_cast<std::size_t>(i)];
    });
    const double product = best_seconds(50, [&] { m.multiply(u, out); });
    std::printf("%8d %14.1f %18.3f %16.1f\n", threads, 24.0 * static_cast<double>(n) / triad / 1e9, 1e3 * product,
                product_bytes / product / 1e9);
  }
  std::printf("(check: a[7] = %g, out[7] = %g)\n", a[7], out[7]);
}

// The Krylov floor of a free-surface step (docs/performance.md, "The floor of the linear
// solves"): what the linear solves alone cost at this machine's speed, whatever else the step
// does. For each measured run (a `bench_ldd run` folder of the Δ = 2 mm dam break, the 50 000-node
// slump or the Δ = 1 mm dam break; bench/ldd_floor.sh makes them), on its scene's initial cloud
// (the solver's neighbour radius h + skin, 1.9 Δ, wall nodes included): one StencilMatrix product
// and one AMG V-cycle (the solver's settings: unit-diagonal rows for the 3D PPE) of a PPE-like
// matrix and of a momentum-like one, and their AMG set-ups. PPE-like: fluid rows W-weighted
// Laplacians, Dirichlet where the support is not full (Σ W below 0.85 of the median fluid node's:
// the free surface), wall rows the Shepard extrapolation from their fluid neighbours;
// momentum-like: ρ + δt μ L with δt μ / (ρ Δ²) = 5 (the slump's ratio at μ = 255 Pa·s) on fluid
// rows, identity on wall rows (their entries stored as zeros, as the solver's pattern keeps them).
// BiCGStab costs 2 products and 2 V-cycles per iteration; the iterations per step and the
// measured ms per step are the run's (summary.json), which must have run on two threads.
void krylov_floor(const std::vector<std::filesystem::path>& runs) {
  std::printf(
      "| scene | nodes | pairs/node | threads | product ms | PPE V-cycle ms | velocity V-cycle ms | "
      "PPE set-up ms | velocity set-up ms | PPE / velocity iterations | Krylov floor ms/step | measured step ms | "
      "measured / floor |\n");
  std::printf("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  std::vector<std::string> notes;
  for (const auto& run : runs) {
    const nlohmann::json summary = core::read_json(run / "summary.json");
    const ldd::Case c = ldd::load_case(run / "case.yaml");
    const auto& l = c.settings;
    if (l.scene_type != "dam_break" && l.scene_type != "slump")
      throw std::invalid_argument(run.string() + ": the floor is built for dam_break and slump runs, not " +
                                  l.scene_type);
    if (summary.at("threads").get<int>() != 2 || summary.at("steps").get<int>() < 1)
      throw std::invalid_argument(run.string() + ": the floor compares with a run of at least one step on two threads");
    const double spacing = l.spacing;
    const double pressure_iterations = summary.at("iterations_per_step").at("pressure").get<double>();
    const double velocity_iterations = summary.at("iterations_per_step").at("velocity").get<double>();
    const double measured_ms = summary.at("ms_per_step").get<double>();
    // 2D rebuilds the velocity hierarchy every step, 3D keeps it (run_free_surface.cpp).
    const int velocity_setups_per_step = l.dimension == 2 ? 1 : 0;
    const std::string name = fmt::format("{} {}D, Δ = {:g} mm, δt = {:g} s, {} steps", l.scene_type, l.dimension,
                                         1e3 * spacing, l.time_step, summary.at("steps").get<int>());
    const ldd::FreeSurfaceScene built = l.dimension == 3
                                            ? ldd::slump_scene(std::get<ldd::SlumpScene>(l.scene), spacing, l.walls)
                                            : ldd::dam_break_scene(std::get<ldd::DamBreakScene>(l.scene), spacing);
    const ldd::NodeCloud& cloud = built.cloud;
    // The run's own support h and neighbour radius h + skin (1.6 Δ and 1.9 Δ in the shipped cases).
    const ldd::SolverParams params = ldd::free_surface_params(l);
    const double support = params.smoothing_ratio * spacing;
    const numerics::NeighbourList nb =
        numerics::find_neighbours(cloud.positions, l.dimension, support + params.neighbour_skin * spacing);
    const std::size_t n = nb.node_count();
    std::vector<double> weights(nb.pair_count()), kernel_sum(n, 0.0);  // W of each pair, Σ W of each node
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
        weights[k] = ldd::weight(nb.distances[k], support);
        kernel_sum[i] += weights[k];
      }
    std::vector<double> fluid_sums;      // a full support: the median fluid node's (walls packed
    for (std::size_t i = 0; i < n; ++i)  // densely make some supports fuller than a full one)
      if (!cloud.is_wall(i)) fluid_sums.push_back(kernel_sum[i]);
    std::nth_element(fluid_sums.begin(), fluid_sums.begin() + static_cast<std::ptrdiff_t>(fluid_sums.size() / 2),
                     fluid_sums.end());
    const double full = fluid_sums[fluid_sums.size() / 2];
    numerics::StencilMatrix pressure{&nb, std::vector<double>(n), std::vector<double>(nb.pair_count())};
    numerics::StencilMatrix velocity{&nb, std::vector<double>(n, 1.0), std::vector<double>(nb.pair_count(), 0.0)};
    const double viscous_ratio = 5.0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t begin = nb.offsets[i], end = nb.offsets[i + 1];
      pressure.diagonal[i] = 1.0;
      if (cloud.is_wall(i)) {
        double fluid_sum = 0;
        for (std::size_t k = begin; k < end; ++k)
          if (!cloud.is_wall(nb.indices[k])) fluid_sum += weights[k];
        for (std::size_t k = begin; k < end; ++k)
          if (!cloud.is_wall(nb.indices[k]) && fluid_sum > 0) pressure.off_diagonal[k] = -weights[k] / fluid_sum;
        continue;
      }
      const bool surface = kernel_sum[i] < 0.85 * full;
      for (std::size_t k = begin; k < end; ++k) {
        if (!surface) pressure.off_diagonal[k] = weights[k];
        velocity.off_diagonal[k] = -viscous_ratio * weights[k];
      }
      if (!surface) pressure.diagonal[i] = -kernel_sum[i];
      velocity.diagonal[i] = 1.0 + viscous_ratio * kernel_sum[i];
    }
    numerics::AmgSettings pressure_settings;
    pressure_settings.unit_diagonal = l.dimension == 3;
    numerics::AmgPreconditioner pressure_amg(pressure_settings), velocity_amg;
    std::vector<double> r(n, 1.0), z(n), out(n);
    for (std::size_t i = 0; i < n; ++i) r[i] = std::sin(0.37 * static_cast<double>(i));
    for (int threads : {1, 2}) {
      omp_set_num_threads(threads);
      const double product = best_seconds(30, [&] { pressure.multiply(r, out); });
      const double pressure_setup = best_seconds(3, [&] { pressure_amg.setup(pressure); });
      const double velocity_setup = best_seconds(3, [&] { velocity_amg.setup(velocity); });
      const double pressure_cycle = best_seconds(20, [&] { pressure_amg.apply(r, z); });
      const double velocity_cycle = best_seconds(20, [&] { velocity_amg.apply(r, z); });
      const double floor_seconds = pressure_iterations * 2.0 * (product + pressure_cycle) +
                                   velocity_iterations * 2.0 * (product + velocity_cycle) +
                                   velocity_setups_per_step * velocity_setup;
      const std::string measured = threads == 2 ? fmt::format("{:.1f}", measured_ms) : "";
      const std::string ratio = threads == 2 ? fmt::format("{:.2f}", measured_ms / (1e3 * floor_seconds)) : "";
      std::printf("| %s | %zu | %.1f | %d | %.3f | %.3f | %.3f | %.1f | %.1f | %.2f / %.2f | %.1f | %s | %s |\n",
                  name.c_str(), n, static_cast<double>(nb.pair_count()) / static_cast<double>(n), threads,
                  1e3 * product, 1e3 * pressure_cycle, 1e3 * velocity_cycle, 1e3 * pressure_setup, 1e3 * velocity_setup,
                  pressure_iterations, velocity_iterations, 1e3 * floor_seconds, measured.c_str(), ratio.c_str());
    }
    const auto sizes = [](const numerics::AmgPreconditioner& amg) {
      std::string text;
      for (std::size_t level = 0; level < amg.levels(); ++level)
        text += (level ? " > " : "") + std::to_string(amg.rows(level));
      return text;
    };
    const auto walls = static_cast<std::size_t>(std::count_if(
        cloud.kinds.begin(), cloud.kinds.end(), [](ldd::NodeKind k) { return k != ldd::NodeKind::interior; }));
    notes.push_back(
        fmt::format("({}: {} wall nodes; PPE rows {}, operator complexity {:.2f}; velocity rows {}, {:.2f}; "
                    "check z[7] = {:g})",
                    name, walls, sizes(pressure_amg), pressure_amg.operator_complexity(), sizes(velocity_amg),
                    velocity_amg.operator_complexity(), z[7]));
  }
  for (const auto& note : notes) std::printf("%s\n", note.c_str());
  std::printf(
      "Krylov floor = PPE iterations × 2 (product + V-cycle) + velocity iterations × 2 (product + V-cycle) + the "
      "velocity set-ups per step (2D: one), the iterations per step as the run measured them.\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "bandwidth") {
    bandwidth();
    return 0;
  }
  if (argc >= 2 && std::string(argv[1]) == "floor") {
    if (argc < 3) {
      std::fprintf(stderr,
                   "usage: bench_ldd floor RUN_DIR... (bench_ldd run folders on two threads; bench/ldd_floor.sh)\n");
      return 2;
    }
    try {
      krylov_floor(std::vector<std::filesystem::path>(argv + 2, argv + argc));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_ldd floor: %s\n", e.what());
      return 2;
    }
    return 0;
  }
  if (argc >= 4 && std::string(argv[1]) == "run") {
    // A refused deck or folder (a ConfigError names file, line and key) is a message, not an abort.
    try {
      ldd::RunControl control;
      for (int a = 4; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--stability-probe" && a + 1 < argc)
          control.stability_probe_iterations = std::stoi(argv[++a]);
        else if (arg == "--divergence-probe")
          control.divergence_probe = true;
        else
          throw std::invalid_argument("unknown option " + arg + " (--stability-probe N, --divergence-probe)");
      }
      const ldd::Case c = ldd::load_case(argv[2]);
      const auto log =
          core::Log::console(core::Verbosity::normal).with_file(std::filesystem::path(argv[3]) / "log.txt");
      const auto outcome = ldd::run_case(c, argv[3], log, control);
      return outcome.status == "diverged" ? 1 : 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_ldd run: %s\n", e.what());
      return 2;
    }
  }
  if (argc >= 2 && std::string(argv[1]) == "accuracy") {
    AccuracyOptions o;
    for (int a = 2; a < argc; ++a) {
      const std::string arg = argv[a];
      const bool has_value = a + 1 < argc;
      if (arg == "--re" && has_value) {
        o.reynolds = std::stoi(argv[++a]);
      } else if (arg == "--interpolation" && has_value) {
        const auto named = ldd::lattice_interpolation_named(argv[++a]);
        if (!named) {
          std::fprintf(stderr, "bench_ldd accuracy: unknown interpolation '%s'\n", argv[a]);
          return 2;
        }
        o.interpolation = *named;
      } else if (arg == "--dt" && has_value) {
        o.dt = std::stod(argv[++a]);
      } else if (arg == "--end" && has_value) {
        o.end = std::stod(argv[++a]);
      } else if (arg == "--threads" && has_value) {
        o.threads = std::stoi(argv[++a]);
      } else {
        o.resolutions.push_back(std::stoi(arg));
      }
    }
    if (o.resolutions.empty() || (o.reynolds != 100 && o.reynolds != 1000)) {
      std::fprintf(stderr,
                   "usage: bench_ldd accuracy [--re 100|1000] [--interpolation quadratic|shepard|gradient_corrected] "
                   "[--dt S] [--end S] [--threads N] CELLS...\n");
      return 2;
    }
    accuracy(o);
    return 0;
  }
  bool quick = false;
  int steps_option = 0;
  std::string dump_dir;
  Preconditioners preconditioners;
  std::vector<int> thread_counts{1, 2}, cell_counts{100, 200};
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--quick") {
      quick = true;
    } else if (arg == "--threads" && a + 1 < argc) {
      thread_counts = {std::stoi(argv[++a])};
    } else if (arg == "--amg-levels" && a + 1 < argc) {
      preconditioners.amg.max_levels = std::stoi(argv[++a]);
    } else if (arg == "--amg-unit-diagonal") {
      preconditioners.amg.unit_diagonal = true;
    } else if (arg == "--amg-plain") {
      preconditioners.amg.smoothed = false;
    } else if (arg == "--steps" && a + 1 < argc) {
      steps_option = std::stoi(argv[++a]);
    } else if (arg == "--dump" && a + 1 < argc) {
      dump_dir = argv[++a];
    } else if (arg == "--cells" && a + 1 < argc) {
      cell_counts = {std::stoi(argv[++a])};
    } else if ((arg == "--pressure" || arg == "--velocity") && a + 1 < argc) {
      auto& target = arg == "--pressure" ? preconditioners.pressure : preconditioners.velocity;
      const auto named = ldd::preconditioner_named(argv[++a]);
      if (!named) {
        std::fprintf(stderr, "bench_ldd: unknown preconditioner '%s' (jacobi, lu, amg)\n", argv[a]);
        return 2;
      }
      target = *named;
    } else {
      std::fprintf(
          stderr,
          "usage: bench_ldd [--quick] [--threads N] [--cells N] [--pressure jacobi|lu|amg] [--velocity jacobi|amg] "
          "[--amg-levels N] [--amg-plain] [--amg-unit-diagonal] [--steps N] [--dump DIR] | run CASE OUT "
          "[--stability-probe N] [--divergence-probe]\n");
      return 2;
    }
  }
  const int steps = steps_option > 0 ? steps_option : quick ? 20 : 200;
  const std::vector<Scenario> scenarios{
      {"square, Casson Re 100 Bn 0.01", 0.0,
       "{model: casson, plastic_viscosity: 0.01, yield_stress: 1.0e-4, regularization: 1000}", 12},
      {"skewed 60°, power law n 1.5 Re 500", std::acos(-1.0) / 3, "{model: power_law, consistency: 0.002, index: 1.5}",
       26}};
  std::printf(
      "| case | nodes | PPE / velocity preconditioner | threads | ms/step | CPU ms/step | seed GPU ms/step | setup | "
      "rheology / pressure / momentum / advection ms | PPE / velocity iterations |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (const auto& s : scenarios)
    for (int cells : cell_counts)
      for (int threads : thread_counts) time_steps(s, cells, threads, steps, preconditioners, dump_dir);
  if (!quick) {
    AccuracyOptions o;
    o.threads = 2;
    o.resolutions = {25, 50, 100, 200};
    accuracy(o);
  }
  return 0;
}
