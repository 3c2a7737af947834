#pragma once
// One function per subcommand; main.cpp only parses the command line.
// Each returns the process exit code: 0 success, 2 bad input, 1 run failure.
#include <filesystem>
#include <string>
#include <vector>

#include "rheosim/core/log.hpp"

namespace rheosim::app {

inline constexpr int exit_success = 0;
inline constexpr int exit_run_failure = 1;
inline constexpr int exit_bad_input = 2;
// `rheosim run --point-budget` default [s]: the largest estimated one-core cost of a CFD-DEM point.
inline constexpr double default_point_budget = 600;

int validate(const std::vector<std::string>& case_files, const core::Log& log);
// point_budget: the largest estimated one-core wall time [s] of a CFD-DEM point that is started.
// stop_after: free-surface LDD runs stop with a checkpoint after this wall time [s] (0: never).
int run(const std::string& case_file, const std::filesystem::path& out_dir, double point_budget, double stop_after,
        const core::Log& log);
int report(const std::filesystem::path& run_dir, const core::Log& log);
// A single-phase rheometer case as a simpleFoam case (rim_shear_rate, mesh, rim), or an LDD dam
// break as an interFoam case (max_courant).
int export_openfoam(const std::string& case_file, const std::filesystem::path& dir, double rim_shear_rate,
                    const std::string& mesh, const std::string& rim, double max_courant, const core::Log& log);

}  // namespace rheosim::app
