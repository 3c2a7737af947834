#pragma once
// `rheosim run` for `kind: ldd` cases: a thin wrapper around ldd::run_case (ldd/run.hpp) that
// adds the run's log file and maps the outcome to the command's exit codes.
#include <filesystem>

#include "rheosim/core/log.hpp"
#include "rheosim/ldd/case.hpp"

namespace rheosim::app {

// 0: finished (steady, settled, end time) or interrupted by stop_after [s of wall time, 0: never]
// with a checkpoint to go on from; 1: diverged or failed (the message is logged); 2: out_dir holds
// the checkpoint of another deck.
int run_ldd(const ldd::Case& c, const std::filesystem::path& out_dir, double stop_after, const core::Log& log);

}  // namespace rheosim::app
