#pragma once
// checkpoint.h5 of an LDD run (run_loop.hpp): the solver's state (SolverState) and what the
// scene has recorded so far (named numbers, named series, the probe table), written atomically.
// Running the same deck into the same folder continues from it, bit for bit; a checkpoint of
// another deck (its input sha256 differs) is refused.
#include <chrono>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "rheosim/core/error.hpp"
#include "rheosim/core/log.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/version.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/solver.hpp"

namespace rheosim::ldd::detail {

// Counts kept as doubles in a checkpoint (exact below 2^53), as counts again.
[[nodiscard]] std::vector<std::size_t> as_counts(const std::vector<double>& values);

// What a scene keeps besides the solver's state, by name.
struct RunRecordContent {
  std::map<std::string, double> numbers;
  std::map<std::string, std::vector<double>> series;
  // The value of `name`; RunError naming the checkpoint when it has none.
  [[nodiscard]] double number(const std::string& name, const std::filesystem::path& checkpoint) const;
  [[nodiscard]] const std::vector<double>& values(const std::string& name,
                                                  const std::filesystem::path& checkpoint) const;
};

void write_checkpoint(const std::filesystem::path& path, const Case& c, SolverState state,
                      const RunRecordContent& record, const core::CsvTable& history);

// The checkpoint's state, record and probe rows (appended to `history`, whose columns it must
// have); returns the git revision that wrote it. ConfigError for another deck's checkpoint,
// RunError for a file that is not a checkpoint of this rheosim.
struct StoredCheckpoint {
  SolverState state;
  RunRecordContent record;
  std::string git_revision;
};
[[nodiscard]] StoredCheckpoint read_checkpoint(const std::filesystem::path& path, const Case& c,
                                               core::CsvTable& history);

// A run resuming from `path`: its state into `solver` (a RunError when it does not fit this
// case's cloud), its probe rows into `history`, the resume and
// a change of build in the log. Returns the scene's record.
[[nodiscard]] inline RunRecordContent resume_from_checkpoint(const std::filesystem::path& path, const Case& c,
                                                             Solver& solver, core::CsvTable& history,
                                                             std::size_t total_steps, const core::Log& log) {
  StoredCheckpoint stored = read_checkpoint(path, c, history);
  try {
    solver.restore(std::move(stored.state));
  } catch (const std::invalid_argument& e) {
    throw core::RunError(fmt::format("checkpoint '{}' does not fit this case's cloud: {}", path.string(), e.what()));
  }
  log.info("resuming from {}: t = {:.6g} s, step {} of {}", path.string(), solver.time(), solver.steps(), total_steps);
  if (stored.git_revision != core::git_revision)
    log.warn("the checkpoint was written by rheosim git {}, this is git {}: the run goes on with this build",
             stored.git_revision, core::git_revision);
  return std::move(stored.record);
}

// A run's checkpoint: its file, and the wall time the run has taken over every process that ran
// it (kept in the record as "wall_seconds"; this process's share counted from `start`).
class RunCheckpoint {
 public:
  RunCheckpoint(const Case& c, std::filesystem::path file, std::chrono::steady_clock::time_point start)
      : c_(c), file_(std::move(file)), start_(start) {}
  [[nodiscard]] const std::filesystem::path& file() const { return file_; }
  [[nodiscard]] bool exists() const { return std::filesystem::exists(file_); }
  // resume_from_checkpoint, and the wall time of the processes before this one.
  [[nodiscard]] RunRecordContent resume(Solver& solver, core::CsvTable& history, std::size_t total_steps,
                                        const core::Log& log) {
    RunRecordContent record = resume_from_checkpoint(file_, c_, solver, history, total_steps, log);
    wall_seconds_ = record.number("wall_seconds", file_);
    return record;
  }
  // Writes the state, the record (with the wall time so far) and the probe rows.
  void write(SolverState state, RunRecordContent record, const core::CsvTable& history) {
    const double now = elapsed();
    wall_seconds_ += now - written_at_;
    written_at_ = now;
    record.numbers["wall_seconds"] = wall_seconds_;
    write_checkpoint(file_, c_, std::move(state), record, history);
  }
  [[nodiscard]] double seconds_since_write() const { return elapsed() - written_at_; }
  // Over every process that ran the case, up to the last write.
  [[nodiscard]] double wall_seconds() const { return wall_seconds_; }

 private:
  [[nodiscard]] double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  const Case& c_;
  std::filesystem::path file_;
  std::chrono::steady_clock::time_point start_;
  double wall_seconds_ = 0, written_at_ = 0;
};

}  // namespace rheosim::ldd::detail
