#pragma once
// report.html for an LDD run folder: the run's figures (nodes, steps, cost, status and the
// rules it bent), for a free-surface run the front or spread, the energy balance and the volume
// drift against time (with the experiment of LDD Table 1 beside a dam break's front), for a
// cavity the centre-line profiles and streamlines its run drew. Built from summary.json (read
// by read_run_summary, summary.hpp, which names any missing key) and the probe CSV; opens with no network.
// Beside it: NAME.gp (gnuplot NAME.gp redraws NAME.png and NAME.svg).
#include <filesystem>
#include <string>
#include <vector>

#include "rheosim/ldd/summary.hpp"

namespace rheosim::ldd {

struct ReportFiles {
  std::filesystem::path html;              // report.html
  std::vector<std::string> plots;          // plots drawn (front, energy, volume, …)
  std::vector<std::string> missing_plots;  // scripts written whose PNG gnuplot did not produce
};

// Writes <run_dir>/report.html (atomically) and its plot scripts and plots. A folder without
// summary.json is a core::ConfigError.
ReportFiles write_report(const std::filesystem::path& run_dir);

}  // namespace rheosim::ldd
