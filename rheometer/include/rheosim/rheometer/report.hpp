#pragma once
// report.html for a run folder (rheometer run or sweep): what a rheologist reads. It opens in a
// browser with no network (every link is relative, styles inline) and is built only from
// summary.json (points and the analysis of run_analysis.hpp) and case.yaml. Layout and the
// meaning of every table: docs/report.md.
//
// Beside it, for a user to re-plot or restyle (gnuplot NAME.gp regenerates NAME.png/.svg):
//   flow_curve.csv, fits.csv, fit_curves.csv, residuals.csv, torque_lines.csv, yield_stress.csv,
//   relative_viscosity.csv, relative_viscosity_curves.csv, speed_error.csv      data
//   torque.gp, stress.gp, viscosity.gp, residuals.gp, relative_viscosity.gp, yield_stress.gp
//   and their .png and .svg                                                    plots
// Every number in the HTML is in summary.json or one of these CSV files.
#include <filesystem>
#include <string>
#include <vector>

namespace rheosim::rheometer {

struct ReportFiles {
  std::filesystem::path html;              // report.html
  std::vector<std::string> plots;          // plot names written (torque, stress, …)
  std::vector<std::string> missing_plots;  // scripts written whose PNG gnuplot did not produce
};

// Reads <run_dir>/summary.json (and case.yaml when present), writes the CSV files, the gnuplot
// scripts, runs gnuplot (when installed; otherwise the report says how to plot) and writes
// <run_dir>/report.html atomically. A folder without summary.json is a ConfigError.
ReportFiles write_report(const std::filesystem::path& run_dir);

}  // namespace rheosim::rheometer
