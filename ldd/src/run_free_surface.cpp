// `rheosim run` for the free-surface LDD scenes (dam_break, slump, column); see run.hpp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "checkpoint.hpp"
#include "column_references.hpp"
#include "dam_break_references.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/progress.hpp"
#include "rheosim/core/version.hpp"
#include "rheosim/ldd/run.hpp"
#include "rheosim/ldd/scenes.hpp"
#include "run_loop.hpp"
#include "run_summary.hpp"
#include "slump_references.hpp"

namespace rheosim::ldd {
namespace {

// Mass front: largest x of a non-splash fluid node plus half a cell.
double mass_front(const FreeSurfaceSolver& s) {
  const auto dim = static_cast<std::size_t>(s.dimension());
  double front = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.node_count(); ++i)
    if (s.is_continuum(i)) front = std::max(front, s.positions()[dim * i]);
  return front + 0.5 * s.params().spacing;
}

using detail::FinalProfile;

// Dam break: the free surface at the end, the top of the fluid nodes (non-splash) in each Δ-wide
// column plus half a cell, at the columns' centres, ascending in x.
FinalProfile final_profile(const FreeSurfaceSolver& s) {
  const double dx = s.params().spacing;
  std::map<long, double> top;
  for (std::size_t i = 0; i < s.node_count(); ++i)
    if (s.is_continuum(i)) {
      const auto column = static_cast<long>(std::floor(s.positions()[2 * i] / dx));
      const double y = s.positions()[2 * i + 1] + 0.5 * dx;
      const auto [it, fresh] = top.emplace(column, y);
      if (!fresh) it->second = std::max(it->second, y);
    }
  FinalProfile profile;
  for (const auto& [column, height] : top) {
    profile.x.push_back((static_cast<double>(column) + 0.5) * dx);
    profile.height.push_back(height);
  }
  return profile;
}

// profile.csv: the final free surface, and a yield-stress law's shallow arrest beside it.
core::CsvTable profile_table(const FinalProfile& profile, const CaseSettings& l) {
  const std::optional<ThinFilmArrest> arrest = detail::dam_break_thin_film_arrest(l);
  std::vector<core::CsvTable::Column> columns{{"x", "m"}, {"height", "m"}};
  if (arrest) columns.push_back({"thin_film_arrest", "m"});
  core::CsvTable table(columns);
  const double back_wall = std::get<DamBreakScene>(l.scene).reservoir[0];  // distance from the gate
  for (std::size_t k = 0; k < profile.x.size(); ++k) {
    if (arrest)
      table.add_row({profile.x[k], profile.height[k], arrest->height_at(profile.x[k] + back_wall)});
    else
      table.add_row({profile.x[k], profile.height[k]});
  }
  return table;
}

// Slump spread diameter and height (3D, axis z).
std::pair<double, double> spread(const FreeSurfaceSolver& s) {
  double radius = 0, top = 0;
  for (std::size_t i = 0; i < s.node_count(); ++i)
    if (s.is_continuum(i)) {
      const double* x = &s.positions()[3 * i];
      radius = std::max(radius, std::hypot(x[0], x[1]));
      top = std::max(top, x[2]);
    }
  return {2 * radius + s.params().spacing, top + 0.5 * s.params().spacing};
}

// The end state's yield test on the fluid nodes' stress μ(γ̇)γ̇ (LDD eq. 5): the share at or
// above the yield stress τ₀, and the largest over τ₀.
struct YieldTest {
  double yielded_fraction = 0, largest_stress_ratio = 0;
};

YieldTest yield_test(const FreeSurfaceSolver& s, double yield_stress) {
  std::size_t fluid = 0, yielded = 0;
  double largest = 0;
  for (std::size_t i = 0; i < s.node_count(); ++i)
    if (s.is_continuum(i)) {
      ++fluid;
      const double stress = s.viscosity()[i] * s.shear_rate()[i];
      if (stress >= yield_stress) ++yielded;
      largest = std::max(largest, stress / yield_stress);
    }
  return {fluid > 0 ? static_cast<double>(yielded) / static_cast<double>(fluid) : 0.0, largest};
}

// Column: the surface height at the left wall, the top of the fluid nodes within the first cell
// off it (x < Δ) plus half a cell; splash nodes excluded.
double left_wall_height(const FreeSurfaceSolver& s) {
  double top = 0;
  for (std::size_t i = 0; i < s.node_count(); ++i)
    if (s.is_fluid(i) && s.kinds()[i] != NodeKind::splash && s.positions()[2 * i] < s.params().spacing)
      top = std::max(top, s.positions()[2 * i + 1]);
  return top + 0.5 * s.params().spacing;
}

// Height of the fluid's top node plus half a cell (the dam break's; the slump's is spread()'s).
double top_height(const FreeSurfaceSolver& s) {
  const auto dim = static_cast<std::size_t>(s.dimension());
  double top = 0;
  for (std::size_t i = 0; i < s.node_count(); ++i)
    if (s.is_continuum(i)) top = std::max(top, s.positions()[dim * i + dim - 1]);
  return top + 0.5 * s.params().spacing;
}

FreeSurfaceScene build_scene(const ldd::CaseSettings& l) {
  // The case reader refuses dam_break and column outside 2D (ldd/src/case.cpp).
  if (const auto* d = std::get_if<ldd::DamBreakScene>(&l.scene)) return dam_break_scene(*d, l.spacing);
  if (const auto* s = std::get_if<ldd::SlumpScene>(&l.scene)) return slump_scene(*s, l.spacing, l.walls);
  if (const auto* c = std::get_if<ldd::ColumnScene>(&l.scene)) return column_scene(*c, l.spacing);
  throw core::RunError(fmt::format("LDD scene '{}' is not a free-surface scene", l.scene_type));
}

// What a free-surface run has recorded besides the solver's state; with it, the checkpoint.
struct RunRecord {
  std::vector<double> front_time, front;  // dam break: after every step
  std::vector<double> frame_times;
  std::vector<double> resumed_at_steps;  // steps at which this run was continued from a checkpoint
  double volume0 = 0, max_drift = 0, peak_energy = 0;
  double max_compression = 0;  // largest |ρ̄_bulk/ρ₀ − 1| (FreeSurfaceSolver::bulk_density_ratio)
  // Energy balance: potential energy at the start, the most released so far, and the largest
  // excess of kinetic energy over the potential energy released (> 0: the scheme created energy).
  double potential0 = 0, max_released = 0, max_energy_excess = 0;
  double step_seconds = 0;                                  // over all processes that ran the case
  double pressure_iterations = 0, velocity_iterations = 0;  // sums over steps
  double repeated_solves = 0, repeated_with_lu = 0;
  double pressure_amg_plain_from = -1;  // [s]; < 0: not switched (solver.pressure_amg: auto)
  // The bulk's nodes per Δ^d at its first measurement (< 0: none yet), when that was [s], and the
  // largest relative departure from it since (FreeSurfaceSolver::bulk_number_density). The first
  // count comes after the start when too few balls fit in the bulk before, or when the run resumed
  // from a checkpoint that holds no count (written before the count existed).
  double number_density0 = -1, number_density0_time = -1, max_number_compression = 0;
  detail::AcceptedSolves accepted;  // solves accepted above their tolerance
};

// RunRecord's numbers and series in the checkpoint, by name.
constexpr std::pair<const char*, double RunRecord::*> record_numbers[] = {
    {"volume0", &RunRecord::volume0},
    {"max_drift", &RunRecord::max_drift},
    {"max_compression", &RunRecord::max_compression},
    {"peak_energy", &RunRecord::peak_energy},
    {"potential0", &RunRecord::potential0},
    {"max_released", &RunRecord::max_released},
    {"max_energy_excess", &RunRecord::max_energy_excess},
    {"step_seconds", &RunRecord::step_seconds},
    {"pressure_iterations", &RunRecord::pressure_iterations},
    {"velocity_iterations", &RunRecord::velocity_iterations},
    {"repeated_solves", &RunRecord::repeated_solves},
    {"repeated_with_lu", &RunRecord::repeated_with_lu}};
// Numbers that checkpoints of earlier rheosim revisions do not hold: absent, the member keeps its
// default.
constexpr std::pair<const char*, double RunRecord::*> later_record_numbers[] = {
    {"pressure_amg_plain_from", &RunRecord::pressure_amg_plain_from},
    {"number_density0", &RunRecord::number_density0},
    {"number_density0_time", &RunRecord::number_density0_time},
    {"max_number_compression", &RunRecord::max_number_compression}};
constexpr std::pair<const char*, std::vector<double> RunRecord::*> record_series[] = {
    {"front_time", &RunRecord::front_time},
    {"front", &RunRecord::front},
    {"frame_times", &RunRecord::frame_times},
    {"resumed_at_steps", &RunRecord::resumed_at_steps}};

detail::RunRecordContent content_of(const RunRecord& r) {
  detail::RunRecordContent content;
  for (const auto& [name, member] : record_numbers) content.numbers[name] = r.*member;
  for (const auto& [name, member] : later_record_numbers) content.numbers[name] = r.*member;
  for (const auto& [name, member] : record_series) content.series[name] = r.*member;
  detail::add_accepted_solves(r.accepted, content);
  return content;
}

RunRecord record_of(const detail::RunRecordContent& content, const std::filesystem::path& checkpoint) {
  RunRecord r;
  for (const auto& [name, member] : record_numbers) r.*member = content.number(name, checkpoint);
  for (const auto& [name, member] : later_record_numbers)
    if (const auto it = content.numbers.find(name); it != content.numbers.end()) r.*member = it->second;
  for (const auto& [name, member] : record_series) r.*member = content.values(name, checkpoint);
  r.accepted = detail::accepted_solves_of(content);
  return r;
}

// Dam breaks and slumps of a yield-stress law probe the yield test (yield_test) as they run.
bool probes_yield_test(const ldd::CaseSettings& l) {
  const bool arrest_scene =
      std::holds_alternative<ldd::DamBreakScene>(l.scene) || std::holds_alternative<ldd::SlumpScene>(l.scene);
  return arrest_scene && l.fluid.rheology->yield_stress() > 0;
}

// The probe file's columns: time, the scene's probe (front; diameter and height; left-wall
// height), the stability and divergence probes' when asked for, then the energy, volume and
// solver records, and a yield-stress law's largest stress over τ₀.
std::vector<core::CsvTable::Column> probe_columns(const ldd::CaseSettings& l, bool probe_stability,
                                                  bool probe_divergence) {
  const bool dam_break = std::holds_alternative<ldd::DamBreakScene>(l.scene);
  const bool slump = std::holds_alternative<ldd::SlumpScene>(l.scene);
  std::vector<core::CsvTable::Column> columns{{"time", "s"}};
  if (dam_break) columns.push_back({"front", "m"});
  if (slump) {
    columns.push_back({"diameter", "m"});
    columns.push_back({"height", "m"});
  }
  if (!dam_break && !slump) columns.push_back({"left_wall_height", "m"});
  if (probe_stability)
    for (core::CsvTable::Column col : std::vector<core::CsvTable::Column>{
             {"step_map_growth", ""}, {"step_map_node_x", "m"}, {"step_map_node_y", "m"}})
      columns.push_back(col);
  if (probe_divergence) {
    columns.push_back({"bulk_divergence_predicted", "1/s"});
    columns.push_back({"bulk_divergence", "1/s"});
  }
  for (core::CsvTable::Column col :
       std::vector<core::CsvTable::Column>{{"kinetic_energy", l.dimension == 2 ? "J/m" : "J"},
                                           {"potential_energy_released", l.dimension == 2 ? "J/m" : "J"},
                                           {"volume_drift", ""},
                                           {"surface_nodes", ""},
                                           {"splash_nodes", ""},
                                           {"pressure_iterations", ""},
                                           {"velocity_iterations", ""},
                                           {"courant", ""},
                                           {"max_pbd_shift", ""}})
    columns.push_back(col);
  if (probes_yield_test(l)) columns.push_back({"largest_stress_ratio", ""});
  return columns;
}

// summary.json of a finished (or stopped) run: the head every LDD run writes, the energy and
// volume records, the rules the run bent, the probes, and a dam break's or slump's final shape
// (a dam break also writes profile.csv and its references' files).
RunSummary run_summary(const Case& c, const FreeSurfaceSolver& solver, const RunRecord& run, double wall_time,
                       const core::CsvTable& history, const RunOutcome& outcome, int threads,
                       const std::filesystem::path& out_dir, const core::Log& log) {
  const auto& l = c.settings;
  const bool dam_break = std::holds_alternative<ldd::DamBreakScene>(l.scene);
  const bool slump = std::holds_alternative<ldd::SlumpScene>(l.scene);
  RunSummary summary = detail::summary_head(c, l, solver, outcome, threads);
  summary.volume_drift = run.max_drift;
  summary.bulk_compression = run.max_compression;
  const bool bulk_counted = run.number_density0 > 0;  // FreeSurfaceSolver::bulk_number_density
  if (bulk_counted) summary.bulk_number_compression = run.max_number_compression;
  summary.kinetic_energy_peak = run.peak_energy;
  // (KE − released PE)_max / (released PE)_max: ≤ 0 for a scheme that creates no energy. Only
  // where a release drives the flow; a resting column releases nothing but noise (empty).
  const bool released_flow = (dam_break || slump) && run.max_released > 0;
  const double energy_gain = released_flow ? run.max_energy_excess / run.max_released : 0.0;
  if (released_flow) summary.energy_gain = energy_gain;
  summary.repeated_solves = static_cast<std::size_t>(run.repeated_solves);
  // every rule the run bent
  if (const auto w = run.accepted.warning(solver.steps())) summary.warnings.push_back(*w);
  if (run.max_drift > volume_drift_tolerance)
    summary.warnings.push_back(fmt::format("the fluid volume drifted by up to {:.3g} % (more than {:.3g} %)",
                                           1e2 * run.max_drift, 1e2 * volume_drift_tolerance));
  if (run.max_compression > volume_drift_tolerance)
    summary.warnings.push_back(
        fmt::format("the bulk's mean kernel density departed from its rest value by up to {:.3g} % (more than {:.3g} "
                    "%): the fluid was compressed or expanded",
                    1e2 * run.max_compression, 1e2 * volume_drift_tolerance));
  if (bulk_counted && run.number_density0_time > 0)
    summary.warnings.push_back(fmt::format(
        "bulk_number_compression counts from t = {:.6g} s, where the bulk's nodes were first counted, not from "
        "the start (too few balls of {:g} spacings fitted in the bulk before, or the run resumed from a "
        "checkpoint without a count)",
        run.number_density0_time, FreeSurfaceSolver::bulk_ball_radius));
  if (bulk_counted && run.max_number_compression > volume_drift_tolerance)
    summary.warnings.push_back(fmt::format(
        "the bulk's nodes per unit volume (counted in balls of {:g} spacings) departed from their first "
        "count by up to {:.3g} % (more than {:.3g} %): the fluid was compressed or expanded",
        FreeSurfaceSolver::bulk_ball_radius, 1e2 * run.max_number_compression, 1e2 * volume_drift_tolerance));
  if (energy_gain > energy_gain_tolerance)
    summary.warnings.push_back(fmt::format(
        "the kinetic energy exceeded the potential energy released by {:.3g} % of the latter: the scheme created "
        "energy",
        1e2 * energy_gain));
  if (run.repeated_solves > 0)
    summary.warnings.push_back(fmt::format("{} linear solves failed and were repeated ({} with the sparse LU)",
                                           run.repeated_solves, run.repeated_with_lu));
  for (const auto& w : summary.warnings) log.warn("{}", w);
  summary.repeated_with_lu = static_cast<std::size_t>(run.repeated_with_lu);
  if (run.pressure_amg_plain_from >= 0) summary.pressure_amg_plain_from = run.pressure_amg_plain_from;
  // Krylov iterations per step (velocity: all components), to compare preconditioners.
  const double steps_done = std::max(1.0, static_cast<double>(solver.steps()));
  summary.pressure_iterations_per_step = run.pressure_iterations / steps_done;
  summary.velocity_iterations_per_step = run.velocity_iterations / steps_done;
  // Neighbour searches by this process (the other steps filtered the Verlet list).
  summary.neighbour_searches = solver.neighbour_searches();
  summary.wall_time = wall_time;
  summary.resumed_at_steps = detail::as_counts(run.resumed_at_steps);
  for (std::size_t q = 0; q < history.row_count(); ++q) {
    const auto row = history.row(q);
    if (dam_break) summary.front.push_back({row[0], row[1]});
    if (slump) summary.spread.push_back({row[0], row[1], row[2]});
  }
  if (dam_break || slump) {
    // The final shape, and whether the material has stopped by the yield criterion.
    const double yield_stress = l.fluid.rheology->yield_stress();
    if (dam_break) {
      summary.final_spread = mass_front(solver);
      summary.final_height = top_height(solver);
      const FinalProfile profile = final_profile(solver);
      core::write_csv(out_dir / "profile.csv", profile_table(profile, l));
      detail::compare_dam_break_front(l, run.front_time, run.front, profile, out_dir, summary, log);
    } else {
      const auto [diameter, height] = spread(solver);
      summary.final_spread = diameter;
      summary.final_height = height;
    }
    if (yield_stress > 0) {
      // At rest the yielded part of a deposit sits on the yield surface (the shallow arrest's
      // basal stress is τ₀, so is the lower part of Pashias' column), where a regularised law's
      // nodes carry τ₀ plus the stress of the cloud's jitter: arrested means no node above
      // (1 + tolerance) τ₀, where a Bingham material flows no faster than tolerance·τ₀/μ_p.
      const YieldTest test = yield_test(solver, yield_stress);
      summary.yielded_fraction = test.yielded_fraction;
      summary.largest_stress_ratio = test.largest_stress_ratio;
      summary.arrested = outcome.status != "diverged" && test.largest_stress_ratio <= 1.0 + l.arrest_stress_tolerance;
      std::string verdict;
      if (summary.arrested)
        verdict = fmt::format("arrested (every node within {:g} % of τ₀ or below it)", 1e2 * l.arrest_stress_tolerance);
      else if (outcome.status == "diverged")
        verdict = "not arrested (the run diverged)";
      else
        verdict = fmt::format("not arrested (time.arrest_stress_tolerance {:g})", l.arrest_stress_tolerance);
      log.info("yield test at the end: {:.3g} of the fluid nodes at or above τ₀, the largest stress {:.4g} τ₀: {}",
               test.yielded_fraction, test.largest_stress_ratio, verdict);
    }  // else no yield stress: a liquid does not arrest
  }
  if (slump) detail::compare_slump(l, summary, log);
  if (const auto* column = std::get_if<ColumnScene>(&l.scene); column && column->wave_amplitude > 0)
    detail::compare_with_linear_sloshing(l, history, out_dir, summary, log);
  return summary;
}

// The free surfaces' part of the run loop: the FreeSurfaceSolver, the scene's probes (the dam
// break's front after every step; spread; left-wall height), the energy and volume records, node
// frames and the checkpoint the next run into the same folder resumes from.
class FreeSurfaceRun final : public detail::SceneRun {
 public:
  FreeSurfaceRun(const Case& c, FreeSurfaceSolver& solver, const std::filesystem::path& out_dir,
                 const RunControl& control, std::chrono::steady_clock::time_point wall_start, const core::Log& log)
      : l_(c.settings),
        solver_(solver),
        out_dir_(out_dir),
        dam_break_(std::holds_alternative<ldd::DamBreakScene>(l_.scene)),
        slump_(std::holds_alternative<ldd::SlumpScene>(l_.scene)),
        stability_probe_iterations_(control.stability_probe_iterations),
        divergence_probe_(control.divergence_probe),
        history_(probe_columns(l_, probe_stability(), divergence_probe_)),
        probe_file_(probe_file_name(l_.scene_type)),
        checkpoint_(c, out_dir / "checkpoint.h5", wall_start),
        log_(log) {
    // Slump: the mould clears the fluid when its bottom passes the initial height.
    if (const auto* s = std::get_if<ldd::SlumpScene>(&l_.scene)) mould_clear_time_ = s->cone_height / s->lift_velocity;
  }

  // Continues from checkpoint.h5 when the folder holds one, else records the start.
  void resume_or_start(std::size_t total_steps) {
    if (checkpoint_.exists()) {
      run_ = record_of(checkpoint_.resume(solver_, history_, total_steps, log_), checkpoint_.file());
      run_.resumed_at_steps.push_back(static_cast<double>(solver_.steps()));
      return;
    }
    run_.volume0 = solver_.fluid_volume();
    run_.potential0 = solver_.potential_energy();
    add_frame();
    record(StepStats{});
    if (dam_break_) {
      run_.front_time.push_back(0.0);
      run_.front.push_back(mass_front(solver_));
    }
  }

  [[nodiscard]] double time() const override { return solver_.time(); }
  [[nodiscard]] std::size_t steps() const override { return solver_.steps(); }
  [[nodiscard]] bool step(bool probed, RunOutcome& outcome) override {
    // The step map is probed only on the steps that are recorded (it costs ~3 solves an iteration).
    if (probe_stability()) solver_.set_stability_probe(probed ? stability_probe_iterations_ : 0);
    if (divergence_probe_) solver_.set_divergence_probe(probed);
    if (!detail::timed_step(solver_, stats_, outcome, run_.step_seconds)) return false;
    run_.pressure_iterations += stats_.pressure_iterations;
    run_.velocity_iterations += stats_.velocity_iterations;
    run_.accepted.add(stats_, solver_.params());
    if (stats_.repeated_solves > 0) {
      run_.repeated_solves += stats_.repeated_solves;
      run_.repeated_with_lu += stats_.repeated_with_lu;
      log_.warn(
          "t = {:.6g} s: {} linear solve(s) failed and were repeated ({} with a fresh AMG hierarchy, {} with "
          "the pressure matrix's sparse LU)",
          solver_.time(), stats_.repeated_solves, stats_.repeated_solves - stats_.repeated_with_lu,
          stats_.repeated_with_lu);
    }
    if (stats_.pressure_amg_to_plain > 0) {
      run_.pressure_amg_plain_from = solver_.time();
      log_.info(
          "t = {:.6g} s: a fresh smoothed-aggregation hierarchy needed {} pressure iterations (more than {}): "
          "plain aggregation from here on (solver.pressure_amg: auto)",
          solver_.time(), stats_.pressure_amg_to_plain, solver_.params().pressure_amg_switch_iterations);
    }
    if (dam_break_) {
      run_.front_time.push_back(solver_.time());
      run_.front.push_back(mass_front(solver_));
    }
    return true;
  }
  [[nodiscard]] std::optional<std::string> probe(std::size_t step, core::Progress& progress,
                                                 RunOutcome& outcome) override {
    const double energy = record(stats_);
    run_.peak_energy = std::max(run_.peak_energy, energy);
    progress.update(step,
                    fmt::format("t {:.3f} s, KE {:.3g}, {} surface", solver_.time(), energy, stats_.surface_nodes));
    if (slump_ && solver_.time() > mould_clear_time_ && energy < l_.settle_energy_ratio * run_.peak_energy)
      return "settled";
    if (const std::optional<double> since = arrested_since()) {
      outcome.message = fmt::format(
          "arrested: no fluid node's stress above {:g} τ₀ at any probe from t = {:.4g} s to {:.4g} s "
          "(time.stop_at_arrest {:g} s)",
          1.0 + l_.arrest_stress_tolerance, *since, solver_.time(), l_.arrest_hold_time);
      return "arrested";
    }
    return std::nullopt;
  }
  void add_frame() override {
    detail::write_node_frame(solver_, out_dir_, run_.frame_times.size());
    run_.frame_times.push_back(solver_.time());
    detail::write_node_frame_indexes(out_dir_, frame_entries());
  }
  [[nodiscard]] double last_frame_time() const override { return run_.frame_times.back(); }
  void save() override {
    core::write_csv(out_dir_ / probe_file_, history_);
    checkpoint();
  }
  [[nodiscard]] const detail::RunCheckpoint& run_checkpoint() const override { return checkpoint_; }
  void checkpoint() override { checkpoint_.write(solver_.state(), content_of(run_), history_); }

  [[nodiscard]] const RunRecord& record_so_far() const { return run_; }
  // Over every process that ran the case, up to the last checkpoint (written when the loop stops).
  [[nodiscard]] double wall_time() const { return checkpoint_.wall_seconds(); }
  [[nodiscard]] const core::CsvTable& history() const { return history_; }

 private:
  [[nodiscard]] bool probe_stability() const { return stability_probe_iterations_ > 0; }
  std::vector<core::TimeSeriesEntry> frame_entries() const {
    std::vector<core::TimeSeriesEntry> entries;
    for (std::size_t q = 0; q < run_.frame_times.size(); ++q)
      entries.push_back({run_.frame_times[q], detail::frame_name(q)});
    return entries;
  }
  // One probe row; returns the kinetic energy.
  double record(const StepStats& st) {
    const double drift = solver_.fluid_volume() / run_.volume0 - 1;
    run_.max_drift = std::max(run_.max_drift, std::abs(drift));
    run_.max_compression = std::max(run_.max_compression, std::abs(solver_.bulk_density_ratio() - 1));
    if (const std::optional<double> density = solver_.bulk_number_density()) {
      if (run_.number_density0 < 0) {
        run_.number_density0 = *density;
        run_.number_density0_time = solver_.time();
        if (solver_.time() > 0)
          log_.info(
              "t = {:.6g} s: the bulk's nodes counted for the first time; bulk_number_compression counts from here",
              solver_.time());
      }
      run_.max_number_compression =
          std::max(run_.max_number_compression, std::abs(*density / run_.number_density0 - 1));
    }
    const double energy = solver_.kinetic_energy();
    const double released = run_.potential0 - solver_.potential_energy();
    run_.max_released = std::max(run_.max_released, released);
    run_.max_energy_excess = std::max(run_.max_energy_excess, energy - released);
    std::vector<double> row{solver_.time()};
    if (dam_break_) row.push_back(mass_front(solver_));
    if (slump_) {
      const auto [diameter, height] = spread(solver_);
      row.push_back(diameter);
      row.push_back(height);
    }
    if (!dam_break_ && !slump_) row.push_back(left_wall_height(solver_));
    if (probe_stability()) {
      const std::size_t at = st.step_map_node * static_cast<std::size_t>(solver_.dimension());
      row.push_back(st.step_map_growth);
      row.push_back(st.step_map_growth > 0 ? solver_.positions()[at] : 0.0);
      row.push_back(st.step_map_growth > 0 ? solver_.positions()[at + 1] : 0.0);
    }
    if (divergence_probe_) {
      row.push_back(st.bulk_divergence_predicted);
      row.push_back(st.bulk_divergence);
    }
    for (double v : {energy, released, drift, static_cast<double>(st.surface_nodes),
                     static_cast<double>(st.splash_nodes), static_cast<double>(st.pressure_iterations),
                     static_cast<double>(st.velocity_iterations), st.courant, st.max_pbd_shift})
      row.push_back(v);
    if (probes_yield_test(l_))
      row.push_back(yield_test(solver_, l_.fluid.rheology->yield_stress()).largest_stress_ratio);
    history_.add_row(row);
    return energy;
  }

  // time.stop_at_arrest: every probe over the last arrest_hold_time has passed the yield test, and
  // one before them failed it (the material has yielded: a deposit still unyielded at the start
  // has not arrested) after a slump's mould had cleared. Read from the probe history, which a
  // resumed run restores. Returns when the passing probes began.
  [[nodiscard]] std::optional<double> arrested_since() const {
    if (!(l_.arrest_hold_time > 0)) return std::nullopt;
    const std::vector<core::CsvTable::Column>& columns = history_.numeric_columns();
    const auto ratio = std::find_if(columns.begin(), columns.end(),
                                    [](const core::CsvTable::Column& c) { return c.name == "largest_stress_ratio"; });
    if (ratio == columns.end()) return std::nullopt;  // no yield test is probed (probes_yield_test)
    const std::size_t rows = history_.row_count();
    const auto ratio_column = static_cast<std::size_t>(ratio - columns.begin());
    const auto time_at = [&](std::size_t r) { return history_.row(r)[0]; };
    const double limit = 1.0 + l_.arrest_stress_tolerance;
    std::size_t first_passing = rows;
    while (first_passing > 0 && history_.row(first_passing - 1)[ratio_column] <= limit) --first_passing;
    if (first_passing == 0 || first_passing == rows) return std::nullopt;  // never yielded, or flowing
    if (slump_ && time_at(first_passing - 1) < mould_clear_time_) return std::nullopt;
    const double since = time_at(first_passing);
    if (time_at(rows - 1) - since < l_.arrest_hold_time) return std::nullopt;
    return since;
  }

  const CaseSettings& l_;
  FreeSurfaceSolver& solver_;
  std::filesystem::path out_dir_;
  bool dam_break_, slump_;
  int stability_probe_iterations_;
  bool divergence_probe_;
  double mould_clear_time_ = 0;
  core::CsvTable history_;
  std::string probe_file_;
  detail::RunCheckpoint checkpoint_;
  RunRecord run_;
  StepStats stats_;
  const core::Log& log_;
};

}  // namespace

SolverParams free_surface_params(const ldd::CaseSettings& l) {
  SolverParams p;
  p.dimension = l.dimension;
  detail::set_step_params(l, p);
  p.pbd_iterations = l.solver.pbd_sweeps;
  p.min_moment_rcond = l.solver.moment_rcond;
  p.surface_moment_rcond = l.solver.surface_moment_rcond;
  p.centred_gradient = l.solver.gradient != GradientChoice::renormalised;
  p.anchored_surface_gradient = l.solver.gradient == GradientChoice::surface_anchored;
  p.pbd_velocity_correction = l.solver.pbd_velocity_correction;
  p.pbd_surface_tangential = l.solver.pbd_surface_tangential;
  p.surface_umbrella = l.solver.surface_umbrella;
  p.dry_walls = l.solver.dry_walls;
  p.transpose_stress = l.solver.full_viscous_stress;
  p.surface_normal_stress = l.solver.surface_normal_stress;
  p.wall_face_shear_rate = l.solver.wall_face_shear_rate;
  // auto: AMG (docs/performance.md: 3.4× faster than the per-step LU in the 2 mm dam break, 1.7×
  // faster than Jacobi in the slump). Measured choices: in 2D both hierarchies kept for 50 steps
  // raised the velocity iterations 10 → 16.5 and the coarse dam break diverged with 1e-9
  // tolerances (below: what 2D keeps); in 3D the set-up is dearer and reuse pays (19.3 against
  // 27.6 CPU s for 20 slump steps), and the PPE needs unit-diagonal rows (55 → 12 iterations; in
  // 2D 4 → 34).
  p.pressure_preconditioner = l.solver.pressure_preconditioner.value_or(Preconditioner::amg);
  p.velocity_preconditioner = l.solver.velocity_preconditioner.value_or(Preconditioner::amg);
  p.pressure_amg.unit_diagonal = l.dimension == 3;
  p.pressure_amg.smoothed = l.solver.pressure_amg != AmgAggregation::plain;
  if (l.solver.pressure_amg == AmgAggregation::automatic)
    p.pressure_amg_switch_iterations = auto_aggregation_switch_iterations;
  // 2D: the velocity hierarchy is rebuilt every step (μ(γ̇) changes fast; reused, its iterations
  // rose 8.7 → 12 per step and the saving vanished), the PPE's is kept for 4 steps (the Δ = 2 mm
  // dam break's first 0.3 s: pressure 85 → 58 ms/step, 6.6 → 7.4 iterations, front equal to
  // 1e-5 m; the Δ = 10 mm validation fronts unchanged to 1 mm; docs/performance.md).
  if (l.dimension == 2) {
    p.velocity_amg.reuse_steps = 1;
    p.pressure_amg.reuse_steps = 4;
  }
  return p;
}

RunOutcome run_free_surface_case(const Case& c, const std::filesystem::path& out_dir, const core::Log& log,
                                 const RunControl& control) {
  const auto& l = c.settings;
  const auto wall_start = std::chrono::steady_clock::now();
  const int threads = detail::start_run(c, out_dir);

  FreeSurfaceScene scene = build_scene(l);
  FreeSurfaceSolver solver(free_surface_params(l), std::move(scene.boundaries), std::move(scene.cloud));
  if (!l.time_step_rule.empty()) log.info("time step {}", l.time_step_rule);
  log.info("LDD {} ({}D): {} nodes ({} fluid), Δ = {} m, δt = {} s, {} threads", l.scene_type, l.dimension,
           solver.node_count(), solver.fluid_node_count(), l.spacing, l.time_step, threads);

  const detail::RunSchedule schedule = detail::RunSchedule::of(l);
  FreeSurfaceRun run(c, solver, out_dir, control, wall_start, log);
  run.resume_or_start(schedule.total_steps);
  RunOutcome outcome = detail::run_steps(run, schedule, control, wall_start, log);

  outcome.steps = solver.steps();
  const RunRecord& record = run.record_so_far();
  outcome.ms_per_step = solver.steps() > 0 ? 1e3 * record.step_seconds / static_cast<double>(solver.steps()) : 0.0;
  const RunSummary summary =
      run_summary(c, solver, record, run.wall_time(), run.history(), outcome, threads, out_dir, log);
  core::write_json(out_dir / "summary.json", to_json(summary));
  outcome.summary = out_dir / "summary.json";
  log.info("LDD {} after {} steps (t = {:.6g} s), {:.3g} ms/step, volume drift {:.3g} %; summary: {}", outcome.status,
           outcome.steps, solver.time(), outcome.ms_per_step, 100 * record.max_drift, outcome.summary.string());
  return outcome;
}

std::string probe_file_name(std::string_view scene_type) {
  if (scene_type == "dam_break") return "front.csv";
  if (scene_type == "slump") return "spread.csv";
  return "column.csv";
}

}  // namespace rheosim::ldd
