#include "run_loop.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "rheosim/core/output.hpp"

namespace rheosim::ldd::detail {

int start_run(const Case& c, const std::filesystem::path& out_dir) {
  if (c.settings.solver.threads > 0) omp_set_num_threads(c.settings.solver.threads);
  std::filesystem::create_directories(out_dir / "frames");
  core::write_atomically(out_dir / "case.yaml", [&](std::ostream& os) { os << c.text; });
  return omp_get_max_threads();
}

RunSchedule RunSchedule::of(const CaseSettings& l) {
  const auto steps_for = [&](double interval) {
    return std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(interval / l.time_step)));
  };
  RunSchedule s;
  s.total_steps = static_cast<std::size_t>(std::llround(l.end_time / l.time_step));
  s.frame_every = steps_for(l.output.frame_interval_for(l.end_time));
  s.probe_every = steps_for(l.output.probe_interval_for(l.end_time));
  return s;
}

RunOutcome run_steps(SceneRun& scene, const RunSchedule& schedule, const RunControl& control,
                     std::chrono::steady_clock::time_point wall_start, const core::Log& log) {
  const auto wall_seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  const RunCheckpoint& checkpoint = scene.run_checkpoint();
  RunOutcome outcome;
  outcome.status = "end_time";
  core::Progress progress = core::Progress::for_stderr("ldd", schedule.total_steps);
  std::size_t steps_now = 0;  // in this process
  for (std::size_t k = scene.steps() + 1; k <= schedule.total_steps; ++k) {
    if ((control.step_limit > 0 && steps_now >= control.step_limit) ||
        (control.wall_time_limit > 0 && wall_seconds() >= control.wall_time_limit)) {
      outcome.status = "interrupted";
      break;
    }
    const bool probed = k % schedule.probe_every == 0 || k == schedule.total_steps;
    if (!scene.step(probed, outcome)) break;
    ++steps_now;
    if (probed) {
      if (const std::optional<std::string> status = scene.probe(k, progress, outcome)) {
        outcome.status = *status;
        break;
      }
    }
    if (k % schedule.frame_every == 0) {
      scene.add_frame();
      scene.save();  // a run stopped from outside keeps its probes and state so far
    } else if (control.checkpoint_interval > 0 && checkpoint.seconds_since_write() >= control.checkpoint_interval) {
      scene.checkpoint();
    }
  }
  if (outcome.status == "diverged")
    log.error("LDD run diverged: {}. The last good state (t = {:.6g} s) is written as the last frame and to {}.",
              outcome.message, scene.time(), checkpoint.file().string());
  else
    progress.finish();
  // An interrupted run adds no frame: the checkpoint holds its state, and the frames of the run
  // that goes on are numbered as if it had never stopped.
  if ((scene.last_frame_time() != scene.time() && outcome.status != "interrupted") || outcome.status == "diverged")
    scene.add_frame();
  scene.save();
  if (outcome.status == "interrupted")
    log.info(
        "interrupted at t = {:.6g} s (step {} of {}): the state is in {}; run the same case into the same folder "
        "to go on",
        scene.time(), scene.steps(), schedule.total_steps, checkpoint.file().string());
  return outcome;
}

}  // namespace rheosim::ldd::detail
