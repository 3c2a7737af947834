#pragma once
// `rheosim run` for `kind: ldd` cases: a thin wrapper around ldd::run_case (ldd/run.hpp) that
// adds the run's log file and maps the outcome to the command's exit codes.
#include <filesystem>

#include "rheosim/core/case.hpp"
#include "rheosim/core/log.hpp"

namespace rheosim::app {

// 0: finished (steady or end time); 1: diverged or failed (the message is logged).
int run_ldd(const core::Case& c, const std::filesystem::path& out_dir, const core::Log& log);

}  // namespace rheosim::app
