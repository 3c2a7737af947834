// The report's reading of summary.json and its CSV data files (report_parts.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "report_parts.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/report_page.hpp"
#include "rheosim/core/run_summary.hpp"
#include "rheosim/rheometer/analysis.hpp"
#include "rheosim/rheometer/flow_models.hpp"

namespace rheosim::rheometer::report_detail {

namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double num(const Json& j, const char* key) {
  if (!j.is_object() || !j.contains(key) || !j.at(key).is_number()) return nan;
  return j.at(key).get<double>();
}
double num(const Json& j) { return j.is_number() ? j.get<double>() : nan; }
std::string text(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) && j.at(key).is_string() ? j.at(key).get<std::string>() : std::string();
}
const Json& array(const Json& j, const char* key) {
  static const Json empty = Json::array();
  return j.is_object() && j.contains(key) && j.at(key).is_array() ? j.at(key) : empty;
}

std::string csv_number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, x).ptr;
  return std::string(buffer, end);
}

std::string g4(double x) { return std::isfinite(x) ? fmt::format("{:.4g}", x) : std::string("–"); }
std::string esc(const std::string& s) { return core::escape_markup(s); }

std::string ReportData::label_of(const Json& point) const {
  const std::string fluid = text(point, "fluid");
  const double phi = point.contains("volume_fraction") ? num(point, "volume_fraction") : 0.0;
  for (const auto& s : series_json)
    if (text(s, "fluid") == fluid && num(s, "volume_fraction") == phi) return text(s, "label");
  return fluid;
}

ReportData read_report_data(const fs::path& run_dir) {
  const auto summary_path = core::run_summary_file(run_dir);
  ReportData d;
  d.summary = core::read_json(summary_path);
  const core::SummaryReader r(d.summary, summary_path, "every rheometer and sweep run",
                              "pass the --out folder of a finished 'rheosim run' of a rheometer or sweep case");
  if (const std::string kind = r.text("kind"); kind != "rheometer" && kind != "sweep")
    core::refuse_summary_kind(summary_path, kind, "the summary of a rheometer or sweep run",
                              "'rheosim report' writes the report of an LDD run with the LDD report");
  // What every page section reads: a missing or mistyped key is an error naming it, not a
  // table of "–". Per-point values that only some methods have (closed form, validity, normal
  // force) stay optional and show as "–".
  for (const char* key : {"case", "rheosim_version", "git_revision", "input_sha256"}) (void)r.text(key);
  for (const char* key : {"radius", "gap", "wall_time"}) (void)r.number(key);
  (void)r.count("points_failed");
  (void)r.boolean("inertia");
  for (const auto& point : r.objects("points")) {
    (void)point.text("fluid");
    (void)point.number("shear_rate");
    if (point.boolean("converged")) (void)point.number("torque");
  }
  for (const auto& series : r.objects("series")) {
    (void)series.text("label");
    (void)series.text("fluid");
    (void)series.number("volume_fraction");
    (void)series.count("points");
  }
  for (const auto& fit : r.objects("fits")) {
    (void)fit.text("label");
    (void)fit.text("model");
    (void)fit.objects("parameters");
  }
  (void)r.objects("yield_stress");
  (void)r.objects("relative_viscosity");
  d.points = d.summary.at("points");
  d.series_json = d.summary.at("series");
  d.fits = d.summary.at("fits");
  d.yields = d.summary.at("yield_stress");
  d.relative = d.summary.at("relative_viscosity");
  d.radius = num(d.summary, "radius");
  d.gap = num(d.summary, "gap");
  for (const auto& s : d.series_json)  // plots show only flow curves with data
    if (num(s, "points") > 0)
      d.series.push_back(
          {text(s, "label"), num(s, "volume_fraction"), text(s, "best_model"), s.contains("best_model")});
  for (const auto& f : d.fits) d.model_names.insert(text(f, "model"));
  d.any_normal_force = std::any_of(d.points.begin(), d.points.end(), [](const Json& p) {
    return p.value("converged", false) && p.contains("normal_force");
  });
  return d;
}

namespace {

// A CSV table with text and number cells (the data files beside the plots).
class DataTable {
 public:
  explicit DataTable(std::vector<std::string> header) : header_(std::move(header)) {}
  void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  [[nodiscard]] bool empty() const { return rows_.empty(); }
  void write(const fs::path& path) const {
    core::write_atomically(path, [&](std::ostream& os) {
      const auto line = [&](const std::vector<std::string>& cells) {
        for (std::size_t i = 0; i < cells.size(); ++i) {
          const std::string& c = cells[i];
          const bool quote = c.find_first_of(",\"\n") != std::string::npos;
          std::string cell = c;
          if (quote) {
            cell.clear();
            for (char ch : c) cell += ch == '"' ? std::string("\"\"") : std::string(1, ch);
            cell = "\"" + cell + "\"";
          }
          os << (i ? "," : "") << cell;
        }
        os << "\n";
      };
      line(header_);
      for (const auto& r : rows_) line(r);
    });
  }

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

// Per converged point: flow_curve.csv (the flow curve and its validity) and speed_error.csv.
void write_flow_tables(const ReportData& d, const fs::path& run_dir) {
  const Json& points = d.points;
  DataTable flow({"series", "fluid", "volume_fraction", "shear_rate [1/s]", "torque [N m]", "torque_std_error [N m]",
                  "torque_analytic [N m]", "log_slope", "log_slope_std_error", "apparent_stress [Pa]",
                  "rim_stress [Pa]", "apparent_viscosity [Pa s]", "viscosity [Pa s]", "gap_reynolds",
                  "particle_reynolds", "stokes", "gap_to_diameter", "valid", "used_in_fits"});
  DataTable speed({"series", "shear_rate [1/s]", "method", "wall_time [s]", "iterations", "torque [N m]",
                   "torque_analytic [N m]", "rel_error", "torque_creeping [N m]", "creeping_rel_error",
                   "gap_reynolds_number"});
  for (const auto& p : points) {
    if (!p.value("converged", false)) continue;
    const Json v = p.contains("validity") ? p.at("validity") : Json::object();
    flow.add(
        {d.label_of(p), text(p, "fluid"), csv_number(p.contains("volume_fraction") ? num(p, "volume_fraction") : 0.0),
         csv_number(num(p, "shear_rate")), csv_number(num(p, "torque")), csv_number(num(p, "torque_std_error")),
         csv_number(num(p, "torque_analytic")), csv_number(num(p, "log_slope")),
         csv_number(num(p, "log_slope_std_error")), csv_number(num(p, "apparent_stress")),
         csv_number(num(p, "rim_stress")), csv_number(num(p, "apparent_viscosity")), csv_number(num(p, "viscosity")),
         csv_number(num(v, "gap_reynolds")), csv_number(num(v, "particle_reynolds")), csv_number(num(v, "stokes")),
         csv_number(num(v, "gap_to_diameter")), v.contains("valid") ? (v.at("valid").get<bool>() ? "1" : "0") : "nan",
         p.contains("used_in_fits") ? (p.at("used_in_fits").get<bool>() ? "1" : "0") : "nan"});
    speed.add({d.label_of(p), csv_number(num(p, "shear_rate")), text(p, "method"), csv_number(num(p, "wall_time")),
               csv_number(num(p, "iterations")), csv_number(num(p, "torque")), csv_number(num(p, "torque_analytic")),
               csv_number(num(p, "rel_error")), csv_number(num(p, "torque_creeping")),
               csv_number(num(p, "creeping_rel_error")), csv_number(num(p, "gap_reynolds_number"))});
  }
  flow.write(run_dir / "flow_curve.csv");
  speed.write(run_dir / "speed_error.csv");
}

// fits.csv (every parameter of every fit), fit_curves.csv (each fit on a log grid over its data), residuals.csv.
void write_fit_tables(const ReportData& d, const fs::path& run_dir) {
  const Json& fits = d.fits;
  DataTable fit_table({"series", "model", "rank", "delta_aicc", "akaike_weight", "aicc", "aic", "residual_std",
                       "degrees_of_freedom", "converged", "parameter", "unit", "value", "std_error", "ci95_lower",
                       "ci95_upper", "warnings"});
  DataTable curves({"series", "model", "shear_rate [1/s]", "stress [Pa]", "viscosity [Pa s]"});
  DataTable residuals({"series", "model", "shear_rate [1/s]", "relative_residual [%]"});
  for (const auto& f : fits) {
    const std::string label = text(f, "label"), model = text(f, "model");
    std::string warnings;
    for (const auto& w : array(f, "warnings")) warnings += (warnings.empty() ? "" : "; ") + text(w, "message");
    std::vector<double> values;
    for (const auto& p : array(f, "parameters")) {
      values.push_back(num(p, "value"));
      const Json& ci = p.at("ci95");
      fit_table.add({label, model, csv_number(num(f, "rank")), csv_number(num(f, "delta")),
                     csv_number(num(f, "akaike_weight")), csv_number(num(f, "aicc")), csv_number(num(f, "aic")),
                     csv_number(num(f, "residual_std")), csv_number(num(f, "degrees_of_freedom")),
                     f.value("converged", false) ? "1" : "0", text(p, "name"), text(p, "unit"),
                     csv_number(num(p, "value")), csv_number(num(p, "std_error")), csv_number(num(ci[0])),
                     csv_number(num(ci[1])), warnings});
    }
    const Json& rates = array(f, "shear_rate");
    const Json& res = array(f, "residuals");
    for (std::size_t i = 0; i < rates.size() && i < res.size(); ++i)
      residuals.add({label, model, csv_number(num(rates[i])), csv_number(100.0 * num(res[i]))});
    // The fitted curve on a log grid over the data range.
    const double lo = num(f, "min_shear_rate"), hi = num(f, "max_shear_rate");
    if (!(lo > 0 && hi > lo) || !builtin_flow_models().contains(model)) continue;
    if (std::any_of(values.begin(), values.end(), [](double x) { return !std::isfinite(x); })) continue;
    const auto law = make_flow_model(model);
    constexpr int samples = 60;
    for (int k = 0; k <= samples; ++k) {
      const double rate = lo * std::pow(hi / lo, static_cast<double>(k) / samples);
      const double stress = law->stress(rate, values);
      curves.add({label, model, csv_number(rate), csv_number(stress), csv_number(stress / rate)});
    }
  }
  fit_table.write(run_dir / "fits.csv");
  curves.write(run_dir / "fit_curves.csv");
  residuals.write(run_dir / "residuals.csv");
}

// The seed's straight torque lines (CD §4, Fig. 7), from γ̇ = 0 to the largest rate.
void write_torque_lines(const ReportData& d, const fs::path& run_dir) {
  const Json& points = d.points;
  const Json& series_json = d.series_json;
  DataTable lines({"series", "shear_rate [1/s]", "torque_line [N m]"});
  for (const auto& s : series_json) {
    if (!s.contains("torque_line")) continue;
    const Json& line = s.at("torque_line");
    double max_rate = 0;
    for (const auto& p : points)
      if (d.label_of(p) == text(s, "label") && p.value("converged", false))
        max_rate = std::max(max_rate, num(p, "shear_rate"));
    for (double rate : {0.0, max_rate})
      lines.add({text(s, "label"), csv_number(rate), csv_number(num(line, "intercept") + num(line, "slope") * rate)});
  }
  lines.write(run_dir / "torque_lines.csv");
}

// yield_stress.csv: every estimate with its interval.
void write_yield_table(const ReportData& d, const fs::path& run_dir) {
  const Json& yields = d.yields;
  DataTable yield_table({"series", "volume_fraction", "method", "yield_stress [Pa]", "std_error [Pa]",
                         "ci95_lower [Pa]", "ci95_upper [Pa]", "significant", "converged"});
  for (const auto& y : yields) {
    const Json& ci = y.at("ci95");
    yield_table.add({text(y, "label"), csv_number(num(y, "volume_fraction")), text(y, "method"),
                     csv_number(num(y, "value")), csv_number(num(y, "std_error")), csv_number(num(ci[0])),
                     csv_number(num(ci[1])), y.value("significant", false) ? "1" : "0",
                     y.value("converged", false) ? "1" : "0"});
  }
  yield_table.write(run_dir / "yield_stress.csv");
}

// relative_viscosity.csv (measured η_r) and relative_viscosity_curves.csv (the correlations).
void write_relative_viscosity_tables(const ReportData& d, const fs::path& run_dir) {
  const Json& relative = d.relative;
  DataTable rv_table(
      {"fluid", "volume_fraction", "relative_viscosity", "std_error", "reference_shear_rate [1/s]", "model"});
  DataTable rv_curves({"fluid", "volume_fraction", "einstein", "batchelor", "krieger_dougherty", "maron_pierce",
                       "boyer_2011", "zarraga_2000"});
  for (const auto& rv : relative) {
    const std::string fluid = text(rv, "fluid");
    for (const auto& p : array(rv, "points"))
      rv_table.add({fluid, csv_number(num(p, "volume_fraction")), csv_number(num(p, "relative_viscosity")),
                    csv_number(num(p, "std_error")), csv_number(num(rv, "reference_shear_rate")), text(p, "model")});
    // Fitted φ_m where the data allowed it; otherwise the classic 0.63 (random close packing).
    double kd_max = 0.63, mp_max = 0.63;
    for (const auto& c : array(rv, "correlations")) {
      if (text(c, "name") == "krieger_dougherty" && num(c, "max_packing") > 0) kd_max = num(c, "max_packing");
      if (text(c, "name") == "maron_pierce" && num(c, "max_packing") > 0) mp_max = num(c, "max_packing");
    }
    const double phi_end = std::min({0.6, 0.9 * kd_max, 0.9 * mp_max});  // η_r up to ~100: a readable axis
    for (int k = 0; k <= 60; ++k) {
      const double phi = phi_end * k / 60.0;
      rv_curves.add({fluid, csv_number(phi), csv_number(einstein_relative_viscosity(phi)),
                     csv_number(batchelor_relative_viscosity(phi)),
                     csv_number(krieger_dougherty_relative_viscosity(phi, kd_max)),
                     csv_number(maron_pierce_relative_viscosity(phi, mp_max)),
                     csv_number(phi < 0.55 ? boyer_relative_viscosity(phi) : std::nan("")),
                     csv_number(phi < 0.58 ? zarraga_relative_viscosity(phi) : std::nan(""))});
    }
  }
  rv_table.write(run_dir / "relative_viscosity.csv");
  rv_curves.write(run_dir / "relative_viscosity_curves.csv");
}

// Normal stresses: the plate's normal force, N1 − N2 from it, and the model's N1, N2.
void write_normal_stress_table(const ReportData& d, const fs::path& run_dir) {
  const Json& points = d.points;
  DataTable normal_table({"series", "volume_fraction", "shear_rate [1/s]", "normal_force [N]", "n1_minus_n2 [Pa]",
                          "n1 [Pa]", "n2 [Pa]", "rim_stress [Pa]"});
  for (const auto& p : points)
    if (p.value("converged", false) && p.contains("normal_force"))
      normal_table.add({d.label_of(p), csv_number(num(p, "volume_fraction")), csv_number(num(p, "shear_rate")),
                        csv_number(num(p, "normal_force")), csv_number(num(p, "n1_minus_n2")), csv_number(num(p, "n1")),
                        csv_number(num(p, "n2")), csv_number(num(p, "rim_stress"))});
  if (!normal_table.empty()) normal_table.write(run_dir / "normal_stress.csv");
}

}  // namespace

void write_data_tables(const ReportData& d, const fs::path& run_dir) {
  write_flow_tables(d, run_dir);
  write_fit_tables(d, run_dir);
  write_torque_lines(d, run_dir);
  write_yield_table(d, run_dir);
  write_relative_viscosity_tables(d, run_dir);
  write_normal_stress_table(d, run_dir);
}

}  // namespace rheosim::rheometer::report_detail
