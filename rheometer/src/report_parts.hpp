#pragma once
// The rheometer report's parts (report.cpp puts them together): what it reads from summary.json,
// the CSV data files, the gnuplot scripts and the HTML sections. Private to the module.
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "rheosim/rheometer/report.hpp"
#include "rheosim/rheometer/sweep_summary.hpp"

namespace rheosim::rheometer::report_detail {

namespace fs = std::filesystem;

[[nodiscard]] double or_nan(const MaybeNumber& x);  // NaN for a value the run did not write
[[nodiscard]] std::string csv_number(double x);     // shortest exact form; "nan" for missing
[[nodiscard]] std::string csv_number(const MaybeNumber& x);
[[nodiscard]] std::string g4(double x);  // 4 significant digits for HTML; "–" for missing
[[nodiscard]] std::string g4(const MaybeNumber& x);
[[nodiscard]] std::string esc(const std::string& s);
// A point's validity checks, or checks with nothing known (every value "–").
[[nodiscard]] const PointChecks& checks_of(const SweepPointRecord& point);

struct SeriesInfo {  // a flow curve with data
  std::string label;
  double volume_fraction = 0;
  std::string best_model;
  bool has_fits = false;
};

// summary.json of a rheometer or sweep run (read typed, sweep_summary.hpp), and what every part
// of the report derives from it.
struct ReportData {
  SweepSummary summary;
  std::vector<SeriesInfo> series;     // the flow curves with data, in summary order
  std::set<std::string> model_names;  // every fitted model
  bool any_normal_force = false;      // a converged point has a normal force
  // The flow-curve label of a point (its fluid and φ), or its fluid.
  [[nodiscard]] std::string label_of(const SweepPointRecord& point) const;
};

// Reads <run_dir>/summary.json (read_sweep_summary: ConfigError naming a missing or mistyped key).
[[nodiscard]] ReportData read_report_data(const fs::path& run_dir);
// flow_curve.csv, speed_error.csv, fits.csv, fit_curves.csv, residuals.csv, torque_lines.csv,
// yield_stress.csv, relative_viscosity.csv, relative_viscosity_curves.csv, normal_stress.csv.
void write_data_tables(const ReportData& d, const fs::path& run_dir);

// name → gnuplot script, for the plots the data allow.
using Scripts = std::map<std::string, std::string>;
[[nodiscard]] Scripts plot_scripts(const ReportData& d);

// report.html's text: the figures drawn (files.plots) are shown, the missing ones named.
[[nodiscard]] std::string report_html(const ReportData& d, const ReportFiles& files, bool have_gnuplot,
                                      const fs::path& run_dir);

}  // namespace rheosim::rheometer::report_detail
