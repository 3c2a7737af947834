// `rheosim run` for the free-surface LDD scenes (dam_break, slump, column); see run.hpp.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/progress.hpp"
#include "rheosim/core/version.hpp"
#include "run_summary.hpp"
#include "rheosim/ldd/run.hpp"
#include "rheosim/ldd/scenes.hpp"

namespace rheosim::ldd {
namespace {

// Mass front: largest x of a non-splash fluid node plus half a cell.
double mass_front(const FreeSurfaceSolver& s) {
  const auto dim = static_cast<std::size_t>(s.dimension());
  double front = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.node_count(); ++i)
    if (s.kinds()[i] == FreeNode::interior || s.kinds()[i] == FreeNode::surface)
      front = std::max(front, s.positions()[dim * i]);
  return front + 0.5 * s.params().spacing;
}

// Slump spread diameter and height (3D, axis z).
std::pair<double, double> spread(const FreeSurfaceSolver& s) {
  double radius = 0, top = 0;
  for (std::size_t i = 0; i < s.node_count(); ++i)
    if (s.kinds()[i] == FreeNode::interior || s.kinds()[i] == FreeNode::surface) {
      const double* x = &s.positions()[3 * i];
      radius = std::max(radius, std::hypot(x[0], x[1]));
      top = std::max(top, x[2]);
    }
  return {2 * radius + s.params().spacing, top + 0.5 * s.params().spacing};
}

double interpolate(const std::vector<double>& t, const std::vector<double>& v, double at) {
  if (t.empty()) return std::numeric_limits<double>::quiet_NaN();
  if (at <= t.front()) return v.front();
  if (at > t.back() + 1e-9) return std::numeric_limits<double>::quiet_NaN();  // the run did not get there
  if (at >= t.back()) return v.back();
  const auto upper = std::lower_bound(t.begin(), t.end(), at);
  const auto k = static_cast<std::size_t>(upper - t.begin());
  const double w = (at - t[k - 1]) / (t[k] - t[k - 1]);
  return (1 - w) * v[k - 1] + w * v[k];
}

std::filesystem::path write_frame(const FreeSurfaceSolver& s, const std::filesystem::path& dir, int index) {
  const auto name = std::filesystem::path("frames") / fmt::format("nodes_{:04d}.vtk", index);
  std::vector<double> kind(s.node_count());
  for (std::size_t i = 0; i < kind.size(); ++i) kind[i] = static_cast<double>(s.kinds()[i]);
  core::write_vtk_points(dir / name, s.positions(),
                         {{"velocity", s.dimension(), s.velocity()},
                          {"pressure", 1, s.pressure()},
                          {"shear_rate", 1, s.shear_rate()},
                          {"viscosity", 1, s.viscosity()},
                          {"kind", 1, kind}},
                         s.dimension());
  return name;
}

void write_frame_indexes(const std::filesystem::path& dir, const std::vector<core::TimeSeriesEntry>& entries) {
  std::vector<core::TimeSeriesEntry> beside_frames = entries;
  for (auto& e : beside_frames) e.file = e.file.filename();
  core::write_vtk_series(dir / "frames" / "nodes.vtk.series", beside_frames);
  core::write_pvd(dir / "nodes.pvd", entries);
}

// The seed's LDD column for this Δ and δt, if it ran one (Table 1).
const double* table1_column(double spacing, double dt) {
  const auto close = [](double a, double b) { return std::abs(a / b - 1) < 1e-6; };
  if (close(spacing, 1e-3) && close(dt, 1e-3)) return DamBreakReference::ldd_1mm_dt1e3;
  if (close(spacing, 1e-3) && close(dt, 1e-4)) return DamBreakReference::ldd_1mm_dt1e4;
  if (close(spacing, 2e-3) && close(dt, 1e-3)) return DamBreakReference::ldd_2mm_dt1e3;
  if (close(spacing, 2e-3) && close(dt, 1e-4)) return DamBreakReference::ldd_2mm_dt1e4;
  return nullptr;
}

FreeSurfaceScene build_scene(const core::LddCase& l) {
  if (const auto* d = std::get_if<core::DamBreakScene>(&l.scene)) {
    if (l.dimension != 2) throw core::RunError("the LDD dam_break scene is built in 2D only (dimension: 2)");
    return dam_break_scene(*d, l.spacing);
  }
  if (const auto* s = std::get_if<core::SlumpScene>(&l.scene)) return slump_scene(*s, l.spacing, l.walls);
  if (const auto* c = std::get_if<core::ColumnScene>(&l.scene)) {
    if (l.dimension != 2) throw core::RunError("the LDD column scene is built in 2D only (dimension: 2)");
    return column_scene(*c, l.spacing);
  }
  throw core::RunError(fmt::format("LDD scene '{}' is not a free-surface scene", l.scene_type));
}

}  // namespace

FreeSurfaceParams free_surface_params(const core::LddCase& l) {
  FreeSurfaceParams p;
  p.dimension = l.dimension;
  p.density = l.fluid.density;
  p.rheology = l.fluid.rheology;
  p.gravity = l.gravity;
  p.spacing = l.spacing;
  p.smoothing_ratio = l.smoothing_ratio;
  p.time_step = l.time_step;
  p.pressure_tolerance = l.solver.pressure_tolerance;
  p.velocity_tolerance = l.solver.velocity_tolerance;
  p.max_iterations = l.solver.max_iterations;
  p.max_courant = l.solver.max_courant;
  p.pbd_iterations = l.solver.pbd_sweeps;
  p.min_moment_rcond = l.solver.moment_rcond;
  p.surface_moment_rcond = l.solver.surface_moment_rcond;
  p.centred_gradient = l.solver.gradient != "renormalised";
  // auto: AMG (docs/performance.md: 3.4× faster than the per-step LU in the 2 mm dam break, 1.7×
  // faster than Jacobi in the slump). Measured choices: in 2D a fresh hierarchy every step (a
  // reused one raised the velocity iterations 10 → 16.5 and the coarse dam break diverged with
  // 1e-9 tolerances); in 3D the set-up is dearer and reuse pays (19.3 against 27.6 CPU s for 20
  // slump steps), and the PPE needs unit-diagonal rows (55 → 12 iterations; in 2D 4 → 34).
  p.pressure_preconditioner = preconditioner_named(l.solver.pressure_preconditioner, Preconditioner::amg);
  p.velocity_preconditioner = preconditioner_named(l.solver.velocity_preconditioner, Preconditioner::amg);
  p.pressure_amg.unit_diagonal = l.dimension == 3;
  if (l.dimension == 2) p.pressure_amg.reuse_steps = p.velocity_amg.reuse_steps = 1;
  return p;
}

RunOutcome run_free_surface_case(const core::Case& c, const std::filesystem::path& out_dir, const core::Log& log) {
  const auto& l = std::get<core::LddCase>(c.spec);
  const auto wall_start = std::chrono::steady_clock::now();
  if (l.solver.threads > 0) omp_set_num_threads(l.solver.threads);
  const int threads = omp_get_max_threads();
  std::filesystem::create_directories(out_dir / "frames");
  core::write_atomically(out_dir / "case.yaml", [&](std::ostream& os) { os << c.text; });

  FreeSurfaceScene scene = build_scene(l);
  FreeSurfaceSolver solver(free_surface_params(l), std::move(scene.boundaries), std::move(scene.cloud));
  const bool dam_break = std::holds_alternative<core::DamBreakScene>(l.scene);
  const bool slump = std::holds_alternative<core::SlumpScene>(l.scene);
  log.info("LDD {} ({}D): {} nodes ({} fluid), Δ = {} m, δt = {} s, {} threads", l.scene_type, l.dimension,
           solver.node_count(), solver.fluid_node_count(), l.spacing, l.time_step, threads);

  const auto total_steps = static_cast<std::size_t>(std::llround(l.end_time / l.time_step));
  const auto steps_for = [&](double interval, double fallback) {
    const double t = interval > 0 ? interval : fallback;
    return std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(t / l.time_step)));
  };
  const std::size_t frame_every = steps_for(l.output.frame_interval, l.end_time / 20);
  const std::size_t probe_every = steps_for(l.output.probe_interval, l.end_time / 200);
  // Slump: the mould clears the fluid when its bottom passes the initial height.
  double mould_clear_time = 0;
  if (const auto* s = std::get_if<core::SlumpScene>(&l.scene)) mould_clear_time = s->cone_height / s->lift_velocity;

  std::vector<core::CsvTable::Column> columns{{"time", "s"}};
  if (dam_break) columns.push_back({"front", "m"});
  if (slump) {
    columns.push_back({"diameter", "m"});
    columns.push_back({"height", "m"});
  }
  for (core::CsvTable::Column col : std::vector<core::CsvTable::Column>{{"kinetic_energy", l.dimension == 2 ? "J/m" : "J"},
                                                                        {"volume_drift", ""},
                                                                        {"surface_nodes", ""},
                                                                        {"splash_nodes", ""},
                                                                        {"pressure_iterations", ""},
                                                                        {"velocity_iterations", ""},
                                                                        {"courant", ""},
                                                                        {"max_pbd_shift", ""}})
    columns.push_back(col);
  core::CsvTable history(columns);
  const std::string probe_file = dam_break ? "front.csv" : slump ? "spread.csv" : "column.csv";
  std::vector<double> front_t, front_x;
  nlohmann::ordered_json probes = nlohmann::ordered_json::array();
  const double volume0 = solver.fluid_volume();
  double max_drift = 0, peak_energy = 0;

  const auto record = [&](const FreeSurfaceStats& st) {
    const double drift = solver.fluid_volume() / volume0 - 1;
    max_drift = std::max(max_drift, std::abs(drift));
    const double energy = solver.kinetic_energy();
    std::vector<double> row{solver.time()};
    if (dam_break) {
      row.push_back(mass_front(solver));
      probes.push_back({{"t", solver.time()}, {"x", row.back()}});
    }
    if (slump) {
      const auto [diameter, height] = spread(solver);
      row.push_back(diameter);
      row.push_back(height);
      probes.push_back({{"t", solver.time()}, {"diameter", diameter}, {"height", height}});
    }
    for (double v : {energy, drift, static_cast<double>(st.surface_nodes), static_cast<double>(st.splash_nodes),
                     static_cast<double>(st.pressure_iterations), static_cast<double>(st.velocity_iterations), st.courant,
                     st.max_pbd_shift})
      row.push_back(v);
    history.add_row(row);
    return energy;
  };

  std::vector<core::TimeSeriesEntry> frames;
  frames.push_back({0.0, write_frame(solver, out_dir, 0)});
  record(FreeSurfaceStats{});
  if (dam_break) {
    front_t.push_back(0.0);
    front_x.push_back(mass_front(solver));
  }
  RunOutcome outcome;
  outcome.status = "end_time";
  double step_seconds = 0;
  core::Progress progress = core::Progress::for_stderr("ldd", total_steps);
  FreeSurfaceStats stats;
  double pressure_iterations = 0, velocity_iterations = 0;  // sums over steps
  int repeated_solves = 0;
  for (std::size_t k = 1; k <= total_steps; ++k) {
    if (!detail::timed_step(solver, stats, outcome, step_seconds)) break;
    pressure_iterations += stats.pressure_iterations;
    velocity_iterations += stats.velocity_iterations;
    if (stats.repeated_solves > 0) {
      repeated_solves += stats.repeated_solves;
      log.warn("t = {:.6g} s: {} linear solve(s) failed and were repeated (fresh AMG hierarchy, or the pressure "
               "matrix's LU)",
               solver.time(), stats.repeated_solves);
    }
    if (dam_break) {
      front_t.push_back(solver.time());
      front_x.push_back(mass_front(solver));
    }
    if (k % probe_every == 0 || k == total_steps) {
      const double energy = record(stats);
      peak_energy = std::max(peak_energy, energy);
      progress.update(k, fmt::format("t {:.3f} s, KE {:.3g}, {} surface", solver.time(), energy, stats.surface_nodes));
      if (slump && solver.time() > mould_clear_time && energy < slump_energy_decay * peak_energy) {
        outcome.status = "settled";
        break;
      }
    }
    if (k % frame_every == 0) {
      frames.push_back({solver.time(), write_frame(solver, out_dir, static_cast<int>(frames.size()))});
      write_frame_indexes(out_dir, frames);
      core::write_csv(out_dir / probe_file, history);  // a run stopped from outside keeps its probes so far
    }
  }
  if (outcome.status == "diverged")
    log.error("LDD run diverged: {}. The last good state (t = {:.6g} s) is written as the last frame.", outcome.message,
              solver.time());
  else
    progress.finish();
  if (frames.back().time != solver.time() || outcome.status == "diverged")
    frames.push_back({solver.time(), write_frame(solver, out_dir, static_cast<int>(frames.size()))});
  write_frame_indexes(out_dir, frames);
  core::write_csv(out_dir / probe_file, history);

  outcome.steps = solver.steps();
  outcome.ms_per_step = solver.steps() > 0 ? 1e3 * step_seconds / static_cast<double>(solver.steps()) : 0.0;
  nlohmann::ordered_json summary = detail::summary_head(c, l, solver, outcome, threads);
  summary["volume_drift"] = max_drift;
  summary["kinetic_energy_peak"] = peak_energy;
  summary["repeated_solves"] = repeated_solves;
  // Krylov iterations per step (velocity: all components), to compare preconditioners.
  const double steps_done = std::max(1.0, static_cast<double>(solver.steps()));
  summary["iterations_per_step"] = {{"pressure", pressure_iterations / steps_done},
                                    {"velocity", velocity_iterations / steps_done}};
  summary["wall_time"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  if (dam_break) {
    summary["front"] = probes;
    // LDD Table 1 layout: time, experiment, this run, the seed's LDD for the same Δ and δt.
    const double* paper = table1_column(l.spacing, l.time_step);
    core::CsvTable table({{"time", "s"}, {"experiment", "m"}, {"front", "m"}, {"error", "m"}, {"ldd_seed", "m"}});
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    std::string text = fmt::format(
        "Mass front position, LDD Table 1 layout (Δ = {} mm, δt = {:g} s; seed LDD column for the same Δ, δt)\n"
        "{:>8} {:>10} {:>12} {:>10} {:>10}\n",
        l.spacing * 1e3, l.time_step, "Time (s)", "Exp. (m)", "this run (m)", "error (m)", "seed (m)");
    double sum2 = 0, worst = 0;
    int counted = 0;
    for (std::size_t q = 0; q < 6; ++q) {
      const double time = DamBreakReference::times[q], exp = DamBreakReference::experiment[q];
      const double x = interpolate(front_t, front_x, time);
      const double seed = paper ? paper[q] : std::numeric_limits<double>::quiet_NaN();
      table.add_row({time, exp, x, x - exp, seed});
      rows.push_back({{"t", time}, {"experiment", exp}, {"front", x}, {"error", x - exp}, {"ldd_seed", paper ? nlohmann::ordered_json(seed) : nlohmann::ordered_json()}});
      text += fmt::format("{:>8.2f} {:>10.3f} {:>12.3f} {:>+10.3f} {:>10}\n", time, exp, x, x - exp,
                          paper ? fmt::format("{:.3f}", seed) : std::string("-"));
      if (std::isfinite(x)) {
        sum2 += (x - exp) * (x - exp);
        worst = std::max(worst, std::abs(x - exp));
        ++counted;
      }
    }
    const double rms = counted > 0 ? std::sqrt(sum2 / counted) : std::numeric_limits<double>::quiet_NaN();
    text += fmt::format("RMS error vs experiment {:.4f} m, max {:.4f} m ({} of 6 times reached)\n", rms, worst, counted);
    core::write_csv(out_dir / "table1.csv", table);
    core::write_atomically(out_dir / "table1.txt", [&](std::ostream& os) { os << text; });
    summary["table1"] = {{"rows", rows}, {"rms_error", rms}, {"max_error", worst}};
    log.info("{}", text);
  }
  if (slump) summary["spread"] = probes;
  core::write_json(out_dir / "summary.json", summary);
  outcome.summary = out_dir / "summary.json";
  log.info("LDD {} after {} steps (t = {:.6g} s), {:.3g} ms/step, volume drift {:.3g} %; summary: {}", outcome.status,
           outcome.steps, solver.time(), outcome.ms_per_step, 100 * max_drift, outcome.summary.string());
  return outcome;
}

DamBreakResult simulate_dam_break(const core::DamBreakScene& scene, const FreeSurfaceParams& params, double end_time) {
  FreeSurfaceScene built = dam_break_scene(scene, params.spacing);
  FreeSurfaceSolver solver(params, std::move(built.boundaries), std::move(built.cloud));
  DamBreakResult r;
  r.nodes = solver.node_count();
  r.fluid_nodes = solver.fluid_node_count();
  const double volume0 = solver.fluid_volume();
  r.times.push_back(0.0);
  r.front.push_back(mass_front(solver));
  r.kinetic_energy.push_back(solver.kinetic_energy());
  const auto total_steps = static_cast<std::size_t>(std::llround(end_time / params.time_step));
  double seconds = 0;
  for (std::size_t k = 1; k <= total_steps; ++k) {
    const auto start = std::chrono::steady_clock::now();
    try {
      solver.step();
    } catch (const DivergenceError& e) {
      r.diverged = true;
      r.message = e.what();
    }
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (r.diverged) break;
    r.times.push_back(solver.time());
    r.front.push_back(mass_front(solver));
    r.kinetic_energy.push_back(solver.kinetic_energy());
    if (k % 20 == 0 || k == total_steps)
      r.volume_drift = std::max(r.volume_drift, std::abs(solver.fluid_volume() / volume0 - 1));
  }
  r.steps = solver.steps();
  r.ms_per_step = r.steps > 0 ? 1e3 * seconds / static_cast<double>(r.steps) : 0.0;
  for (double t : DamBreakReference::times) r.front_at_table1.push_back(interpolate(r.times, r.front, t));
  r.phases = solver.phase_times();
  return r;
}

}  // namespace rheosim::ldd
