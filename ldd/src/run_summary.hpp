#pragma once
// What every LDD runner (cavity and free-surface scenes) shares: one timed step that turns a
// divergence into the run's outcome, and the part of the RunSummary every run fills (the case,
// the build, the outcome, the cloud, the step and where the time went), so both report the same
// keys.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "checkpoint.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/run_summary.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/run.hpp"
#include "rheosim/ldd/solver.hpp"
#include "rheosim/ldd/summary.hpp"

namespace rheosim::ldd::detail {

// One step of `solver`, its wall time added to step_seconds, its statistics into `stats`. On
// DivergenceError diverged(message) is called (the solver keeps the last good state) and false
// is returned: the caller stops stepping.
template <class Diverged>
[[nodiscard]] bool timed_step(Solver& solver, StepStats& stats, double& step_seconds, Diverged&& diverged) {
  const auto start = std::chrono::steady_clock::now();
  bool ok = true;
  try {
    stats = solver.step();
  } catch (const DivergenceError& e) {
    diverged(e.what());
    ok = false;
  }
  step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return ok;
}
// A case run's step: a divergence becomes the outcome "diverged" with the message.
[[nodiscard]] inline bool timed_step(Solver& solver, StepStats& stats, RunOutcome& outcome, double& step_seconds) {
  return timed_step(solver, stats, step_seconds, [&](const char* message) {
    outcome.status = "diverged";
    outcome.message = message;
  });
}
// Steps whose pressure or velocity solve did not converge and was accepted (up to 1000× its
// tolerance, the solver's limit before it stops as diverged), and the largest ratio
// residual/tolerance among them: a rule the run bent, for its log and summary.json.
struct AcceptedSolves {
  double pressure = 0, velocity = 0, worst_ratio = 0;  // counts as doubles: a checkpoint stores them so
  void add(const StepStats& s, const SolverParams& p) {
    if (s.pressure_accepted_unconverged) {
      ++pressure;
      worst_ratio = std::max(worst_ratio, s.pressure_residual / p.pressure_tolerance);
    }
    if (s.velocity_accepted_unconverged) {
      ++velocity;
      worst_ratio = std::max(worst_ratio, s.velocity_residual / p.velocity_tolerance);
    }
  }
  // The warning of a run of `steps` steps, or nothing when every solve met its tolerance.
  [[nodiscard]] std::optional<std::string> warning(std::size_t steps) const {
    if (pressure + velocity == 0) return std::nullopt;
    return fmt::format(
        "linear solves accepted above their tolerance: {} pressure and {} velocity solves of {} steps, at most {:.3g}× "
        "the tolerance (a step stops as diverged beyond 1000×)",
        pressure, velocity, steps, worst_ratio);
  }
};

// AcceptedSolves in a checkpoint's record (checkpoint.hpp); a checkpoint without them (an older
// rheosim's) reads as none accepted.
inline void add_accepted_solves(const AcceptedSolves& a, RunRecordContent& content) {
  content.numbers["pressure_above_tolerance"] = a.pressure;
  content.numbers["velocity_above_tolerance"] = a.velocity;
  content.numbers["worst_tolerance_ratio"] = a.worst_ratio;
}
inline AcceptedSolves accepted_solves_of(const RunRecordContent& content) {
  AcceptedSolves a;
  for (auto [name, value] : {std::pair<const char*, double*>{"pressure_above_tolerance", &a.pressure},
                             {"velocity_above_tolerance", &a.velocity},
                             {"worst_tolerance_ratio", &a.worst_ratio}})
    if (const auto it = content.numbers.find(name); it != content.numbers.end()) *value = it->second;
  return a;
}

// A frame of the node cloud, frames/nodes_NNNN.vtk (relative to the run folder), and writing it
// with velocity, pressure, shear rate, viscosity and node kind.
inline std::filesystem::path frame_name(std::size_t index) {
  return std::filesystem::path("frames") / fmt::format("nodes_{:04d}.vtk", index);
}
inline std::filesystem::path write_node_frame(const Solver& s, const std::filesystem::path& dir, std::size_t index) {
  const auto name = frame_name(index);
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
// The ParaView indexes of the node frames: frames/nodes.vtk.series and nodes.pvd.
inline void write_node_frame_indexes(const std::filesystem::path& dir,
                                     const std::vector<core::TimeSeriesEntry>& entries) {
  std::vector<core::TimeSeriesEntry> beside_frames = entries;  // the series file sits in frames/
  for (auto& e : beside_frames) e.file = e.file.filename();
  core::write_vtk_series(dir / "frames" / "nodes.vtk.series", beside_frames);
  core::write_pvd(dir / "nodes.pvd", entries);
}

// The settings of a case every LDD step reads, whatever the scheme: the dimension, the material,
// the resolution, the step and the solver block's tolerances and Courant guard.
inline void set_step_params(const ldd::CaseSettings& l, SolverParams& p) {
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
}

// The part of summary.json every LDD run writes: the head, the cloud, the step and where the
// time went.
[[nodiscard]] inline RunSummary summary_head(const Case& c, const ldd::CaseSettings& l, const Solver& solver,
                                             const RunOutcome& outcome, int threads) {
  RunSummary s;
  s.head = core::summary_head_of(c, "ldd");
  s.scene = l.scene_type;
  s.dimension = l.dimension;
  s.status = outcome.status;
  s.message = outcome.message;
  s.nodes = solver.node_count();
  s.fluid_nodes = solver.fluid_node_count();
  s.spacing = l.spacing;
  s.time_step = l.time_step;
  s.time_step_rule = l.time_step_rule;
  s.steps = solver.steps();
  s.time = solver.time();
  s.threads = threads;
  s.ms_per_step = outcome.ms_per_step;
  s.phase_seconds = solver.phase_times();
  return s;
}

}  // namespace rheosim::ldd::detail
