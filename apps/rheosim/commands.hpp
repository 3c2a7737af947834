#pragma once
// One function per subcommand; main.cpp only parses the command line.
// Each returns the process exit code: 0 success, 2 bad input, 1 run failure.
#include <filesystem>
#include <optional>
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
// export-openfoam's options as given on the command line; an unset one takes its exporter's
// default. The first three are the simpleFoam export's, max_courant the interFoam export's.
struct ExportRequest {
  std::optional<double> rim_shear_rate;  // [1/s]; unset: the case's last rate
  std::optional<std::string> mesh;       // preset M1 | M2 | M3
  std::optional<std::string> rim;        // shear_free | slip
  std::optional<double> max_courant;     // (0, 1]
};
// A single-phase rheometer case as a simpleFoam case, or an LDD dam break as an interFoam case;
// the options of the other export are named in a warning.
int export_openfoam(const std::string& case_file, const std::filesystem::path& dir, const ExportRequest& request,
                    const core::Log& log);

}  // namespace rheosim::app
