#pragma once
// The rheometer report's parts (report.cpp puts them together): what it reads from summary.json,
// the CSV data files, the gnuplot scripts and the HTML sections. Private to the module.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "rheosim/rheometer/report.hpp"

namespace rheosim::rheometer::report_detail {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// Reading summary.json: a missing or mistyped number is NaN, a missing text empty, a missing
// list empty (the report shows "–" for them).
[[nodiscard]] double num(const Json& j, const char* key);
[[nodiscard]] double num(const Json& j);
[[nodiscard]] std::string text(const Json& j, const char* key);
[[nodiscard]] const Json& array(const Json& j, const char* key);
[[nodiscard]] std::string csv_number(double x);  // shortest exact form; "nan" for missing
[[nodiscard]] std::string g4(double x);          // 4 significant digits for HTML; "–" for missing
[[nodiscard]] std::string esc(const std::string& s);

struct SeriesInfo {  // a flow curve with data
  std::string label;
  double volume_fraction = 0;
  std::string best_model;
  bool has_fits = false;
};

// summary.json of a rheometer or sweep run, and what every part of the report derives from it.
struct ReportData {
  Json summary;
  Json points, series_json, fits, yields, relative;  // its lists (empty when absent)
  double radius = 0, gap = 0;         // [m]
  std::vector<SeriesInfo> series;     // the flow curves with data, in summary order
  std::set<std::string> model_names;  // every fitted model
  bool any_normal_force = false;      // a converged point has a normal force
  // The flow-curve label of a point (its fluid and φ), or its fluid.
  [[nodiscard]] std::string label_of(const Json& point) const;
};

// Reads <run_dir>/summary.json; ConfigError when it is missing, of another kind of run, or lacks
// (or mistypes) a key the report reads, naming the key.
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
