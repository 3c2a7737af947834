#pragma once
// checkpoint.h5 of an LDD run (run_loop.hpp): the solver's state (SolverState) and what the
// scene has recorded so far (named numbers, named series, the probe table), written atomically.
// Running the same deck into the same folder continues from it, bit for bit; a checkpoint of
// another deck (its input sha256 differs) is refused.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "rheosim/core/output.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/node_state.hpp"

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

}  // namespace rheosim::ldd::detail
