#pragma once
// report.html for a run folder: readable in a browser with no network (everything inline or
// relative), built only from the numbers in summary.json and the files beside it.
#include <filesystem>

namespace rheosim::rheometer {

// Reads <run_dir>/summary.json (and case.yaml when present), writes <run_dir>/report.html
// atomically and returns its path. A folder without summary.json is a ConfigError.
std::filesystem::path write_report(const std::filesystem::path& run_dir);

}  // namespace rheosim::rheometer
