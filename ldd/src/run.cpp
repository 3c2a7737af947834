#include "rheosim/ldd/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "checkpoint.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/progress.hpp"
#include "rheosim/core/version.hpp"
#include "rheosim/ldd/cavity_reference.hpp"
#include "rheosim/ldd/cavity_solver.hpp"
#include "rheosim/ldd/domain.hpp"
#include "run_loop.hpp"
#include "run_summary.hpp"

namespace rheosim::ldd {

RunOutcome run_free_surface_case(const Case& c, const std::filesystem::path& out_dir, const core::Log& log,
                                 const RunControl& control);

namespace {

constexpr int probe_count = 101;        // points per centre line
constexpr int field_grid_points = 101;  // structured output grid per direction
constexpr double blow_up_residual = 1e3;

struct Centerlines {
  std::vector<double> y, u;  // vertical line: η/S, u/U
  std::vector<double> x, v;  // horizontal line: ξ/W, v/U
};

std::vector<double> probe_points(const Cavity& cavity) {
  std::vector<double> points;
  for (int k = 0; k < probe_count; ++k) {
    const double f = static_cast<double>(k) / (probe_count - 1);
    const Vec2 p = cavity.point(0.5, f);
    points.insert(points.end(), {p[0], p[1]});
  }
  for (int k = 0; k < probe_count; ++k) {
    const double f = static_cast<double>(k) / (probe_count - 1);
    const Vec2 p = cavity.point(f, 0.5);
    points.insert(points.end(), {p[0], p[1]});
  }
  return points;
}

// Centre lines of the velocities u/U and v/U at the probes (the coordinates are the probes'
// fixed fractions of the lines).
Centerlines centerlines_of(std::vector<double> u, std::vector<double> v) {
  Centerlines c;
  for (int k = 0; k < probe_count; ++k) {
    const double f = static_cast<double>(k) / (probe_count - 1);
    c.y.push_back(f);
    c.x.push_back(f);
  }
  c.u = std::move(u);
  c.v = std::move(v);
  return c;
}

Centerlines sample_centerlines(const CavitySolver& solver, const Cavity& cavity) {
  const auto values = solver.sample_velocity(probe_points(cavity));
  const double lid = cavity.lid_velocity() != 0 ? cavity.lid_velocity() : 1.0;
  const auto n = static_cast<std::size_t>(probe_count);
  std::vector<double> u, v;
  for (std::size_t k = 0; k < n; ++k) {
    u.push_back(values[2 * k] / lid);
    v.push_back(values[2 * (k + n) + 1] / lid);
  }
  return centerlines_of(std::move(u), std::move(v));
}

double residual_between(const Centerlines& a, const Centerlines& b, double interval, const Cavity& cavity) {
  const double lid = std::abs(cavity.lid_velocity()) > 0 ? std::abs(cavity.lid_velocity()) : 1.0;
  double change = 0;
  for (std::size_t k = 0; k < a.u.size(); ++k) {
    change = std::max({change, std::abs(a.u[k] - b.u[k]), std::abs(a.v[k] - b.v[k])});
    if (!std::isfinite(a.u[k]) || !std::isfinite(a.v[k])) return std::numeric_limits<double>::infinity();
  }
  const double convective_time = cavity.width() / lid;
  return change / (interval / convective_time);
}

void write_field(const CavitySolver& s, const Cavity& cavity, const std::filesystem::path& dir,
                 const std::filesystem::path& grid_file, bool with_plot_data);

// One frame: the node cloud (frames/nodes_NNNN.vtk) and the resampled field with the stream
// function (frames/field_NNNN.vtk, for streamlines). Returns the node file, relative to dir.
std::filesystem::path write_frame(const CavitySolver& s, const Cavity& cavity, const std::filesystem::path& dir,
                                  int index) {
  write_field(s, cavity, dir, std::filesystem::path("frames") / fmt::format("field_{:04d}.vtk", index), false);
  return detail::write_node_frame(s, dir, static_cast<std::size_t>(index));
}

// The node frames' indexes and the field frames' series beside them.
void write_frame_indexes(const std::filesystem::path& dir, const std::vector<core::TimeSeriesEntry>& entries) {
  detail::write_node_frame_indexes(dir, entries);
  std::vector<core::TimeSeriesEntry> fields = entries;  // the series file sits in frames/
  for (auto& e : fields) e.file = "field" + e.file.filename().string().substr(std::string("nodes").size());
  core::write_vtk_series(dir / "frames" / "field.vtk.series", fields);
}

// Velocity and stream function ψ (∂ψ/∂y = u, ∂ψ/∂x = −v; ψ = 0 on the walls) on a structured
// grid in cavity coordinates. ψ is integrated along η from the bottom wall (trapezoid rule).
// Writes `grid_file` (relative to dir); with `with_plot_data` also psi.dat for gnuplot.
void write_field(const CavitySolver& s, const Cavity& cavity, const std::filesystem::path& dir,
                 const std::filesystem::path& grid_file, bool with_plot_data) {
  const int m = field_grid_points;
  std::vector<double> points;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const Vec2 p = cavity.point(static_cast<double>(i) / (m - 1), static_cast<double>(j) / (m - 1));
      points.insert(points.end(), {p[0], p[1]});
    }
  std::vector<double> velocity = s.sample_velocity(points);
  for (double& v : velocity)
    if (!std::isfinite(v)) v = 0.0;
  const auto mm = static_cast<std::size_t>(m);
  std::vector<double> psi(mm * mm, 0.0);
  const double step = cavity.side_length() / (m - 1);
  const double dx = std::cos(cavity.skew_angle()) * step, dy = std::sin(cavity.skew_angle()) * step;
  for (std::size_t j = 1; j < mm; ++j)
    for (std::size_t i = 0; i < mm; ++i) {
      const std::size_t a = (j - 1) * mm + i, b = j * mm + i;
      const double u = 0.5 * (velocity[2 * a] + velocity[2 * b]), v = 0.5 * (velocity[2 * a + 1] + velocity[2 * b + 1]);
      psi[b] = psi[a] + u * dy - v * dx;
    }
  core::write_vtk_structured_grid(dir / grid_file, {mm, mm, 1}, points, {{"velocity", 2, velocity}, {"psi", 1, psi}},
                                  {}, 2);
  if (!with_plot_data) return;
  core::write_atomically(dir / "psi.dat", [&](std::ostream& os) {
    os << "# x y psi [m²/s], blocks of constant η for gnuplot\n";
    for (std::size_t j = 0; j < mm; ++j) {
      for (std::size_t i = 0; i < mm; ++i)
        os << points[2 * (j * mm + i)] << ' ' << points[2 * (j * mm + i) + 1] << ' ' << psi[j * mm + i] << '\n';
      os << '\n';
    }
  });
}

void write_plots(const std::filesystem::path& dir, const std::string& title, const core::Log& log) {
  core::write_atomically(dir / "centerlines.gp", [&](std::ostream& os) {
    os << "# Centre-line velocity profiles of an LDD cavity run (rheosim). Regenerate: gnuplot centerlines.gp\n"
          "set terminal pngcairo size 1100,500 noenhanced\nset output 'centerlines.png'\n"
          "set datafile separator ','\nset key autotitle columnhead\nset grid\nset multiplot layout 1,2 title '"
       << title
       << "'\n"
          "set xlabel 'u / U'\nset ylabel 'y / S (vertical centre line)'\n"
          "plot 'centerline_vertical.csv' using 2:1 with lines lw 2 title 'LDD'\n"
          "set xlabel 'x / W (horizontal centre line)'\nset ylabel 'v / U'\n"
          "plot 'centerline_horizontal.csv' using 1:2 with lines lw 2 title 'LDD'\n"
          "unset multiplot\n";
  });
  core::write_atomically(dir / "streamlines.gp", [&](std::ostream& os) {
    os << "# Streamlines (contours of the stream function psi). Regenerate: gnuplot streamlines.gp\n"
          "set terminal pngcairo size 600,600 noenhanced\nset output 'streamlines.png'\n"
          "set title '"
       << title
       << " — streamlines'\nset view map\nunset surface\nset contour base\n"
          "set cntrparam levels 24\n"
          "set size ratio -1\nunset key\nset xlabel 'x [m]'\nset ylabel 'y [m]'\n"
          "splot 'psi.dat' using 1:2:3 with lines lc rgb 'black'\n";
  });
  for (const char* script : {"centerlines.gp", "streamlines.gp"}) {
    const std::string command = fmt::format("cd '{}' && gnuplot {} > gnuplot.log 2>&1", dir.string(), script);
    if (std::system(command.c_str()) != 0)
      log.warn("gnuplot failed or is missing (see {}); {} is kept to plot by hand", (dir / "gnuplot.log").string(),
               script);
  }
}

// The centre-line velocities at Ghia's points against their table (cavity_reference.hpp):
// summary.json `ghia` and ghia.csv.
GhiaComparison compare_with_ghia(const CavitySolver& solver, const Cavity& cavity, int reynolds,
                                 const std::filesystem::path& dir) {
  const auto table = ghia_1982();
  std::vector<double> points;
  for (const auto& g : table) {
    const Vec2 p = g.line == 'u' ? cavity.point(0.5, g.coordinate) : cavity.point(g.coordinate, 0.5);
    points.insert(points.end(), {p[0], p[1]});
  }
  const std::vector<double> velocity = solver.sample_velocity(points);
  const double lid = cavity.lid_velocity();
  core::CsvTable csv({{"coordinate", ""}, {"computed", ""}, {"reference", ""}, {"error", ""}},
                     core::CsvTable::Column{"line", ""});
  GhiaComparison out;
  out.reynolds = reynolds;
  for (std::size_t k = 0; k < table.size(); ++k) {
    const auto& g = table[k];
    const double computed = velocity[2 * k + (g.line == 'u' ? 0 : 1)] / lid;
    const double error = computed - g.at(reynolds);
    out.max_error =
        std::max(out.max_error, std::isfinite(error) ? std::abs(error) : std::numeric_limits<double>::infinity());
    csv.add_row({g.coordinate, computed, g.at(reynolds), error}, std::string(1, g.line));
    out.points.push_back({std::string(1, g.line), g.coordinate, computed, g.at(reynolds)});
  }
  core::write_csv(dir / "ghia.csv", csv);
  return out;
}

// The cavity's part of the run loop: the CavitySolver, its centre-line probes and steady
// residual, node and field frames, and the checkpoint the next run into the same folder
// resumes from.
class CavityRun final : public detail::SceneRun {
 public:
  CavityRun(const Case& c, const Cavity& cavity, CavitySolver& solver, const std::filesystem::path& out_dir,
            std::chrono::steady_clock::time_point wall_start, const core::Log& log)
      : l_(c.settings),
        cavity_(cavity),
        solver_(solver),
        out_dir_(out_dir),
        checkpoint_(c, out_dir / "checkpoint.h5", wall_start),
        log_(log) {}

  // Continues from checkpoint.h5 when the folder holds one, else writes the first frame.
  void resume_or_start(std::size_t total_steps) {
    if (!checkpoint_.exists()) {
      last_ = sample_centerlines(solver_, cavity_);
      add_frame();
      return;
    }
    const detail::RunRecordContent r = checkpoint_.resume(solver_, history_, total_steps, log_);
    const std::filesystem::path& file = checkpoint_.file();
    last_probe_time_ = r.number("last_probe_time", file);
    quiet_probes_ = static_cast<int>(r.number("quiet_probes", file));
    step_seconds_ = r.number("step_seconds", file);
    accepted_ = detail::accepted_solves_of(r);
    last_ = centerlines_of(r.values("last_u", file), r.values("last_v", file));
    for (double t : r.values("frame_times", file)) frames_.push_back({t, detail::frame_name(frames_.size())});
    resumed_at_steps_ = r.values("resumed_at_steps", file);
    resumed_at_steps_.push_back(static_cast<double>(solver_.steps()));
  }

  [[nodiscard]] double time() const override { return solver_.time(); }
  [[nodiscard]] std::size_t steps() const override { return solver_.steps(); }
  [[nodiscard]] bool step(bool, RunOutcome& outcome) override {
    if (!detail::timed_step(solver_, stats_, outcome, step_seconds_)) return false;
    accepted_.add(stats_, solver_.params());
    return true;
  }
  [[nodiscard]] std::optional<std::string> probe(std::size_t step, core::Progress& progress,
                                                 RunOutcome& outcome) override {
    const Centerlines now = sample_centerlines(solver_, cavity_);
    const double residual = residual_between(now, last_, solver_.time() - last_probe_time_, cavity_);
    history_.add_row({solver_.time(), residual, solver_.kinetic_energy(),
                      static_cast<double>(stats_.pressure_iterations), static_cast<double>(stats_.velocity_iterations),
                      stats_.max_divergence, stats_.courant});
    last_ = now;
    last_probe_time_ = solver_.time();
    progress.update(step, fmt::format("t {:.3f} s, residual {:.2e}", solver_.time(), residual));
    if (!(residual < blow_up_residual)) {
      outcome.message = fmt::format("steady-state residual {:.3g} at t = {:.6g} s (blow-up limit {:g})", residual,
                                    solver_.time(), blow_up_residual);
      return "diverged";
    }
    quiet_probes_ = (l_.steady_tolerance > 0 && residual < l_.steady_tolerance) ? quiet_probes_ + 1 : 0;
    if (quiet_probes_ >= 3) return "steady";
    return std::nullopt;
  }
  void add_frame() override {
    frames_.push_back({solver_.time(), write_frame(solver_, cavity_, out_dir_, static_cast<int>(frames_.size()))});
    write_frame_indexes(out_dir_, frames_);
  }
  [[nodiscard]] double last_frame_time() const override { return frames_.back().time; }
  void save() override {
    write_frame_indexes(out_dir_, frames_);
    checkpoint();
  }
  [[nodiscard]] const detail::RunCheckpoint& run_checkpoint() const override { return checkpoint_; }
  void checkpoint() override {
    detail::RunRecordContent r;
    r.numbers = {{"last_probe_time", last_probe_time_},
                 {"quiet_probes", static_cast<double>(quiet_probes_)},
                 {"step_seconds", step_seconds_}};
    detail::add_accepted_solves(accepted_, r);
    r.series["last_u"] = last_.u;
    r.series["last_v"] = last_.v;
    r.series["resumed_at_steps"] = resumed_at_steps_;
    for (const auto& frame : frames_) r.series["frame_times"].push_back(frame.time);
    checkpoint_.write(solver_.state(), std::move(r), history_);
  }

  [[nodiscard]] const core::CsvTable& history() const { return history_; }
  [[nodiscard]] double step_seconds() const { return step_seconds_; }
  // Over every process that ran the case, up to the last checkpoint (written when the loop stops).
  [[nodiscard]] double wall_time() const { return checkpoint_.wall_seconds(); }
  [[nodiscard]] const std::vector<double>& resumed_at_steps() const { return resumed_at_steps_; }
  [[nodiscard]] const detail::AcceptedSolves& accepted() const { return accepted_; }

 private:
  const CaseSettings& l_;
  const Cavity& cavity_;
  CavitySolver& solver_;
  std::filesystem::path out_dir_;
  detail::RunCheckpoint checkpoint_;
  const core::Log& log_;
  core::CsvTable history_{{{"time", "s"},
                           {"residual", ""},
                           {"kinetic_energy", "J/m"},
                           {"pressure_iterations", ""},
                           {"velocity_iterations", ""},
                           {"max_divergence", "1/s"},
                           {"courant", ""}}};
  std::vector<core::TimeSeriesEntry> frames_;
  Centerlines last_;
  double last_probe_time_ = 0;
  int quiet_probes_ = 0;
  double step_seconds_ = 0;
  std::vector<double> resumed_at_steps_;
  StepStats stats_;
  detail::AcceptedSolves accepted_;
};

}  // namespace

RunOutcome run_case(const Case& c, const std::filesystem::path& out_dir, const core::Log& log,
                    const RunControl& control) {
  const auto& l = c.settings;
  const auto* scene = std::get_if<ldd::CavityScene>(&l.scene);
  if (!scene) return run_free_surface_case(c, out_dir, log, control);
  const auto wall_start = std::chrono::steady_clock::now();
  const int threads = detail::start_run(c, out_dir);

  const Cavity cavity(*scene, l.spacing);
  SolverParams params = SolverParams::for_cavity();
  detail::set_step_params(l, params);
  params.interpolation = l.solver.interpolation;
  params.pressure_preconditioner = l.solver.pressure_preconditioner.value_or(params.pressure_preconditioner);
  params.velocity_preconditioner = l.solver.velocity_preconditioner.value_or(params.velocity_preconditioner);
  params.velocity_scale = std::abs(scene->lid_velocity) > 0 ? std::abs(scene->lid_velocity) : 1.0;
  params.length_scale = cavity.width();
  CavitySolver solver(params, cavity.walls(), cavity.initial_cloud());

  const double reynolds = l.fluid.density * params.velocity_scale * cavity.width() /
                          l.fluid.rheology->viscosity(params.velocity_scale / cavity.width());
  if (!l.time_step_rule.empty()) log.info("time step {}", l.time_step_rule);
  log.info("LDD {}: {} nodes ({} fluid), Δ = {} m, δt = {} s, {} threads, Re(U/L) ≈ {:.4g}", l.scene_type,
           solver.node_count(), solver.fluid_node_count(), l.spacing, l.time_step, threads, reynolds);

  const auto requested_preconditioner = solver.params().pressure_preconditioner;
  CavityRun run(c, cavity, solver, out_dir, wall_start, log);
  const detail::RunSchedule schedule = detail::RunSchedule::of(l);
  run.resume_or_start(schedule.total_steps);
  RunOutcome outcome = detail::run_steps(run, schedule, control, wall_start, log);
  const core::CsvTable& history = run.history();

  const Centerlines final_lines = sample_centerlines(solver, cavity);
  core::CsvTable vertical({{"y", ""}, {"u", ""}}), horizontal({{"x", ""}, {"v", ""}});
  for (std::size_t k = 0; k < final_lines.y.size(); ++k) {
    vertical.add_row({final_lines.y[k], final_lines.u[k]});
    horizontal.add_row({final_lines.x[k], final_lines.v[k]});
  }
  core::write_csv(out_dir / "centerline_vertical.csv", vertical);
  core::write_csv(out_dir / "centerline_horizontal.csv", horizontal);
  core::write_csv(out_dir / "residual.csv", history);
  write_field(solver, cavity, out_dir, "field.vtk", true);

  outcome.steps = solver.steps();
  outcome.ms_per_step = solver.steps() > 0 ? 1e3 * run.step_seconds() / static_cast<double>(solver.steps()) : 0.0;
  RunSummary summary = detail::summary_head(c, l, solver, outcome, threads);
  summary.reynolds_number = reynolds;
  summary.final_residual = history.row_count() > 0 ? history.row(history.row_count() - 1)[1] : 0.0;
  summary.wall_time = run.wall_time();
  summary.resumed_at_steps = detail::as_counts(run.resumed_at_steps());
  for (std::size_t k = 0; k < final_lines.y.size(); ++k) {
    summary.vertical_centerline.push_back({final_lines.y[k], final_lines.u[k]});
    summary.horizontal_centerline.push_back({final_lines.x[k], final_lines.v[k]});
  }
  if (const auto ghia_re = ghia_reynolds(*scene, l.fluid)) {
    summary.ghia = compare_with_ghia(solver, cavity, *ghia_re, out_dir);
    log.info("centre lines against Ghia et al. (1982) at Re = {}: max |error| {:.4f} U over their 34 points", *ghia_re,
             summary.ghia->max_error);
  }
  // every rule the run bent
  if (const auto w = run.accepted().warning(solver.steps())) summary.warnings.push_back(*w);
  if (solver.params().pressure_preconditioner != requested_preconditioner)
    summary.warnings.push_back(
        "the pressure matrix's sparse LU factorisation failed; the pressure solve fell back to Jacobi "
        "preconditioning");
  for (const auto& w : summary.warnings) log.warn("{}", w);
  core::write_json(out_dir / "summary.json", to_json(summary));
  write_plots(out_dir, fmt::format("{} ({} nodes, t = {:.3g} s)", c.name, solver.node_count(), solver.time()), log);
  outcome.summary = out_dir / "summary.json";
  log.info("LDD {} after {} steps (t = {:.6g} s), {:.3g} ms/step; summary: {}", outcome.status, outcome.steps,
           solver.time(), outcome.ms_per_step, outcome.summary.string());
  return outcome;
}

}  // namespace rheosim::ldd
