#pragma once
// The one LDD run loop, `rheosim run` for every scene: the steps to the end time, the probes
// every probe interval, a frame every frame interval, a checkpoint where the scene keeps one,
// the stops (the end time, the scene's own, a divergence, the caller's step and wall-time
// limits) and the last frame. A scene (SceneRun: run.cpp for the cavities,
// run_free_surface.cpp for the free surfaces) supplies its solver's step and what it records.
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include "checkpoint.hpp"
#include "rheosim/core/log.hpp"
#include "rheosim/core/progress.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd::detail {

// The run's threads (solver.threads, else OpenMP's default; returned) and its folder: frames/ and
// the exact input deck, case.yaml.
int start_run(const Case& c, const std::filesystem::path& out_dir);

// When the loop steps, records and writes frames: the steps to the end time and the intervals
// in steps (at least 1).
struct RunSchedule {
  std::size_t total_steps = 0, frame_every = 1, probe_every = 1;
  [[nodiscard]] static RunSchedule of(const CaseSettings& l);
};

// What a scene adds to the loop. The scene owns its solver, its records and its files.
class SceneRun {
 public:
  virtual ~SceneRun() = default;
  [[nodiscard]] virtual double time() const = 0;
  [[nodiscard]] virtual std::size_t steps() const = 0;
  // The next step, timed into the scene's records; false when it diverged (outcome says why,
  // the solver keeps the last good state). `probed`: the loop probes after it.
  [[nodiscard]] virtual bool step(bool probed, RunOutcome& outcome) = 0;
  // Records the probes after `step`; a status ("steady", "settled", "arrested", "diverged") ends
  // the run, outcome.message saying why where there is something to say.
  [[nodiscard]] virtual std::optional<std::string> probe(std::size_t step, core::Progress& progress,
                                                         RunOutcome& outcome) = 0;
  // Writes a frame of the current state and its indexes.
  virtual void add_frame() = 0;
  [[nodiscard]] virtual double last_frame_time() const = 0;
  // The files a run stopped from outside keeps (the probes so far, the checkpoint), written
  // after every frame of the loop and once when it stops.
  virtual void save() = 0;
  // The checkpoint the next run into the same folder continues from (checkpoint.hpp).
  [[nodiscard]] virtual const RunCheckpoint& run_checkpoint() const = 0;
  virtual void checkpoint() = 0;
};

// Steps `scene` from its current step to the schedule's end or a stop, then writes the last
// frame (a diverged run's: its last good state) and saves. `wall_start`: when the run began
// (for the wall-time limit). Returns the status and message; never throws for divergence.
[[nodiscard]] RunOutcome run_steps(SceneRun& scene, const RunSchedule& schedule, const RunControl& control,
                                   std::chrono::steady_clock::time_point wall_start, const core::Log& log);

}  // namespace rheosim::ldd::detail
