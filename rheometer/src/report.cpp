// report.html, its data CSVs and gnuplot plots (rheometer/report.hpp, docs/report.md).
#include "rheosim/rheometer/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "rheosim/core/case.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/report_page.hpp"
#include "rheosim/rheometer/analysis.hpp"
#include "rheosim/rheometer/flow_models.hpp"

namespace rheosim::rheometer {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

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

// Shortest exact form for CSV (as core::write_csv); "nan" for missing.
std::string csv_number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, x).ptr;
  return std::string(buffer, end);
}

// Readable form for HTML: 4 significant digits; "–" for missing.
std::string g4(double x) { return std::isfinite(x) ? fmt::format("{:.4g}", x) : std::string("–"); }
std::string esc(const std::string& s) { return core::escape_markup(s); }

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

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// ---------------------------------------------------------------------------------------------
// Plots: one gnuplot script per figure, writing NAME.png and NAME.svg.

struct SeriesInfo {
  std::string label;
  double volume_fraction = 0;
  std::string best_model;
  bool has_fits = false;
};

std::string filter(const std::string& label, int column) {
  return fmt::format("(strcol(1) eq '{}' ? ${} : NaN)", label, column);
}

// Model and method names in plot legends: gnuplot's enhanced text would subscript after '_'.
std::string display_name(std::string name) {
  std::replace(name.begin(), name.end(), '_', ' ');
  return name;
}

// gnuplot's own line styles cycle through 8 colours; keep series colours stable across plots.
int colour(std::size_t i) { return static_cast<int>(i % 8) + 1; }

}  // namespace

ReportFiles write_report(const fs::path& run_dir) {
  const auto summary_path = core::run_summary_file(run_dir);
  const Json summary = core::read_json(summary_path);
  if (const std::string kind = text(summary, "kind"); kind != "rheometer" && kind != "sweep")
    core::refuse_summary_kind(summary_path, kind, "the summary of a rheometer or sweep run",
                              "'rheosim report' writes the report of an LDD run with the LDD report");
  const Json& points = array(summary, "points");
  const Json& series_json = array(summary, "series");
  const Json& fits = array(summary, "fits");
  const Json& yields = array(summary, "yield_stress");
  const Json& relative = array(summary, "relative_viscosity");
  const bool is_sweep = text(summary, "kind") == "sweep";
  const double radius = num(summary, "radius");
  const ParallelPlate plate{radius, num(summary, "gap")};

  std::vector<SeriesInfo> series;
  for (const auto& s : series_json)  // plots show only flow curves with data
    if (num(s, "points") > 0)
      series.push_back({text(s, "label"), num(s, "volume_fraction"), text(s, "best_model"), s.contains("best_model")});
  const auto label_of = [&](const Json& p) {
    const std::string fluid = text(p, "fluid");
    const double phi = p.contains("volume_fraction") ? num(p, "volume_fraction") : 0.0;
    for (const auto& s : series_json)
      if (text(s, "fluid") == fluid && num(s, "volume_fraction") == phi) return text(s, "label");
    return fluid;
  };

  // ------------------------------------------------------------------ data files
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
        {label_of(p), text(p, "fluid"), csv_number(p.contains("volume_fraction") ? num(p, "volume_fraction") : 0.0),
         csv_number(num(p, "shear_rate")), csv_number(num(p, "torque")), csv_number(num(p, "torque_std_error")),
         csv_number(num(p, "torque_analytic")), csv_number(num(p, "log_slope")),
         csv_number(num(p, "log_slope_std_error")), csv_number(num(p, "apparent_stress")),
         csv_number(num(p, "rim_stress")), csv_number(num(p, "apparent_viscosity")), csv_number(num(p, "viscosity")),
         csv_number(num(v, "gap_reynolds")), csv_number(num(v, "particle_reynolds")), csv_number(num(v, "stokes")),
         csv_number(num(v, "gap_to_diameter")), v.contains("valid") ? (v.at("valid").get<bool>() ? "1" : "0") : "nan",
         p.contains("used_in_fits") ? (p.at("used_in_fits").get<bool>() ? "1" : "0") : "nan"});
    speed.add({label_of(p), csv_number(num(p, "shear_rate")), text(p, "method"), csv_number(num(p, "wall_time")),
               csv_number(num(p, "iterations")), csv_number(num(p, "torque")), csv_number(num(p, "torque_analytic")),
               csv_number(num(p, "rel_error")), csv_number(num(p, "torque_creeping")),
               csv_number(num(p, "creeping_rel_error")), csv_number(num(p, "gap_reynolds_number"))});
  }
  flow.write(run_dir / "flow_curve.csv");
  speed.write(run_dir / "speed_error.csv");

  DataTable fit_table({"series", "model", "rank", "delta_aicc", "akaike_weight", "aicc", "aic", "residual_std",
                       "degrees_of_freedom", "converged", "parameter", "unit", "value", "std_error", "ci95_lower",
                       "ci95_upper", "warnings"});
  DataTable curves({"series", "model", "shear_rate [1/s]", "stress [Pa]", "viscosity [Pa s]"});
  DataTable residuals({"series", "model", "shear_rate [1/s]", "relative_residual [%]"});
  std::set<std::string> model_names;
  for (const auto& f : fits) {
    const std::string label = text(f, "label"), model = text(f, "model");
    model_names.insert(model);
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

  // The seed's straight torque lines (CD §4, Fig. 7), from γ̇ = 0 to the largest rate.
  DataTable lines({"series", "shear_rate [1/s]", "torque_line [N m]"});
  for (const auto& s : series_json) {
    if (!s.contains("torque_line")) continue;
    const Json& line = s.at("torque_line");
    double max_rate = 0;
    for (const auto& p : points)
      if (label_of(p) == text(s, "label") && p.value("converged", false))
        max_rate = std::max(max_rate, num(p, "shear_rate"));
    for (double rate : {0.0, max_rate})
      lines.add({text(s, "label"), csv_number(rate), csv_number(num(line, "intercept") + num(line, "slope") * rate)});
  }
  lines.write(run_dir / "torque_lines.csv");

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

  // Normal stresses: the plate's normal force, N1 − N2 from it, and the model's N1, N2.
  DataTable normal_table({"series", "volume_fraction", "shear_rate [1/s]", "normal_force [N]", "n1_minus_n2 [Pa]",
                          "n1 [Pa]", "n2 [Pa]", "rim_stress [Pa]"});
  for (const auto& p : points)
    if (p.value("converged", false) && p.contains("normal_force"))
      normal_table.add({label_of(p), csv_number(num(p, "volume_fraction")), csv_number(num(p, "shear_rate")),
                        csv_number(num(p, "normal_force")), csv_number(num(p, "n1_minus_n2")), csv_number(num(p, "n1")),
                        csv_number(num(p, "n2")), csv_number(num(p, "rim_stress"))});
  const bool any_normal_force = !normal_table.empty();
  if (any_normal_force) normal_table.write(run_dir / "normal_stress.csv");
  rv_curves.write(run_dir / "relative_viscosity_curves.csv");

  // ------------------------------------------------------------------ plots
  std::map<std::string, std::string> scripts;
  const bool any_torque_error =
      std::any_of(points.begin(), points.end(), [](const Json& p) { return num(p, "torque_std_error") > 0; });
  {
    std::string plot;
    for (std::size_t i = 0; i < series.size(); ++i) {
      const auto& s = series[i];
      const int lc = colour(i);
      plot += fmt::format("{}'flow_curve.csv' every ::1 using 4:{} with points pt 7 ps 1.3 lc {} title '{}'",
                          plot.empty() ? "" : ", \\\n  ", filter(s.label, 5), lc, s.label);
      // Error bars only where the point has a steady-state error (transient points).
      if (any_torque_error)
        plot += fmt::format(", \\\n  'flow_curve.csv' every ::1 using 4:{}:6 with yerrorbars pt 7 ps 0 lc {} notitle",
                            filter(s.label, 5), lc);
      plot += fmt::format(", \\\n  'torque_lines.csv' every ::1 using 2:{} with lines lw 2 lc {} title 'line fit, {}'",
                          filter(s.label, 3), lc, s.label);
      plot += fmt::format(", \\\n  'flow_curve.csv' every ::1 using 4:{} with lines dt 2 lc {} {}", filter(s.label, 7),
                          lc, i == 0 ? "title 'creeping closed form'" : "notitle");
    }
    std::string body =
        "set xlabel 'rim shear rate γ̇_R [1/s]'\nset ylabel 'torque T [N m]'\nset format y '%.1e'\n"
        "set xrange [0:*]\nset yrange [0:*]\n"
        "set title \"points: measured;  solid: T = T_0 + b γ̇_R (CD §4);  dashed: creeping closed form\" "
        "font ',10'\n";
    if (!plot.empty())
      scripts["torque"] = core::gnuplot_header("torque", "Torque vs rim shear rate per φ") +
                          core::gnuplot_outputs("torque", body + "plot " + plot + "\n");
  }
  {
    std::string stress_plot, viscosity_plot;
    bool cross_titled = false;
    for (std::size_t i = 0; i < series.size(); ++i) {
      const auto& s = series[i];
      const int lc = colour(i);
      const std::string sep = stress_plot.empty() ? "" : ", \\\n  ";
      stress_plot += fmt::format("{}'flow_curve.csv' every ::1 using 4:{} with points pt 7 lc {} title '{} τ_R'", sep,
                                 filter(s.label, 11), lc, s.label);
      stress_plot +=
          fmt::format(", \\\n  'flow_curve.csv' every ::1 using 4:{} with points pt 6 lc {} title '{} τ_{{app}}'",
                      filter(s.label, 10), lc, s.label);
      viscosity_plot += fmt::format("{}'flow_curve.csv' every ::1 using 4:{} with points pt 7 lc {} title '{} τ_R/γ̇_R'",
                                    sep, filter(s.label, 13), lc, s.label);
      viscosity_plot +=
          fmt::format(", \\\n  'flow_curve.csv' every ::1 using 4:{} with points pt 6 lc {} title '{} apparent'",
                      filter(s.label, 12), lc, s.label);
      // Points that fail the validity checks and were left out of the fits: a black cross on top.
      const auto not_fitted = [&](int column) {
        return fmt::format("(strcol(1) eq '{}' && strcol(19) eq '0' ? ${} : NaN)", s.label, column);
      };
      const bool has_unfitted = std::any_of(points.begin(), points.end(), [&](const Json& p) {
        return label_of(p) == s.label && p.contains("used_in_fits") && !p.at("used_in_fits").get<bool>();
      });
      if (has_unfitted) {
        const std::string cross_title = cross_titled ? "notitle" : "title 'not fitted (fails validity checks)'";
        cross_titled = true;
        stress_plot +=
            fmt::format(", \\\n  'flow_curve.csv' every ::1 using 4:{} with points pt 2 ps 2 lc rgb 'black' {}",
                        not_fitted(11), cross_title);
        viscosity_plot +=
            fmt::format(", \\\n  'flow_curve.csv' every ::1 using 4:{} with points pt 2 ps 2 lc rgb 'black' {}",
                        not_fitted(13), cross_title);
      }
      if (s.has_fits) {
        const std::string curve_filter =
            fmt::format("(strcol(1) eq '{}' && strcol(2) eq '{}' ? ${{}} : NaN)", s.label, s.best_model);
        stress_plot +=
            fmt::format(", \\\n  'fit_curves.csv' every ::1 using 3:{} with lines lw 2 lc {} title '{} fit: {}'",
                        fmt::format(fmt::runtime(curve_filter), 4), lc, s.label, display_name(s.best_model));
        viscosity_plot +=
            fmt::format(", \\\n  'fit_curves.csv' every ::1 using 3:{} with lines lw 2 lc {} title '{} fit: {}'",
                        fmt::format(fmt::runtime(curve_filter), 5), lc, s.label, display_name(s.best_model));
      }
    }
    const std::string common = "set logscale xy\nset format y '%.1e'\nset xlabel 'rim shear rate γ̇_R [1/s]'\n";
    if (!stress_plot.empty()) {
      scripts["stress"] =
          core::gnuplot_header(
              "stress",
              "Rim stress: plate-corrected τ_R (filled) and apparent τ_app = 2T/(πR³) (open), best fit by AICc") +
          core::gnuplot_outputs("stress",
                                common +
                                    "set ylabel 'rim shear stress [Pa]'\nset title 'Flow curve: τ_R = T/(2πR³)(3 + "
                                    "d ln T/d ln γ̇_R) filled, apparent open, line: best fit (AICc)' font ',10'\nplot " +
                                    stress_plot + "\n");
      scripts["viscosity"] =
          core::gnuplot_header("viscosity",
                               "Viscosity τ/γ̇ at the rim, corrected (filled) and apparent (open), best fit") +
          core::gnuplot_outputs("viscosity",
                                common +
                                    "set ylabel 'viscosity η [Pa s]'\nset title 'Viscosity curve: τ_R/γ̇_R filled, "
                                    "apparent open, line: best fit (AICc)' font ',10'\nplot " +
                                    viscosity_plot + "\n");
    }
  }
  if (!fits.empty()) {
    std::string body = fmt::format(
        "set multiplot layout 2,{} title 'Relative residuals (τ_{{model}} − τ_R)/τ_R of each "
        "model, in %' font ',11'\nset logscale x\nset key off\nset xlabel 'γ̇_R [1/s]'\n"
        "set ylabel 'residual [%]'\nset xzeroaxis lt -1\n",
        (model_names.size() + 1) / 2);
    for (const auto& model : model_names) {
      std::string plot;
      for (std::size_t i = 0; i < series.size(); ++i)
        plot += fmt::format(
            "{}'residuals.csv' every ::1 using 3:(strcol(1) eq '{}' && strcol(2) eq '{}' ? $4 : NaN) "
            "with linespoints pt 7 lc {} title '{}'",
            plot.empty() ? "" : ", ", series[i].label, model, colour(i), series[i].label);
      body += fmt::format("set title '{}' noenhanced\nplot {}\n", model, plot);
    }
    // The last panel carries the legend.
    if (model_names.size() % 2 == 1) {
      std::string plot;
      for (std::size_t i = 0; i < series.size(); ++i)
        plot += fmt::format("{}NaN with linespoints pt 7 lc {} title '{}'", plot.empty() ? "" : ", ", colour(i),
                            series[i].label);
      body +=
          "set title 'series'\nunset border\nunset tics\nunset xlabel\nunset ylabel\nunset grid\nunset xzeroaxis\n"
          "set key center center\nset yrange [0:1]\nplot " +
          plot + "\n";
    }
    body += "unset multiplot\n";
    scripts["residuals"] = core::gnuplot_header("residuals", "Relative residuals of every fitted model") +
                           core::gnuplot_outputs("residuals", body, 1400, 650);
  }
  if (!relative.empty()) {
    std::string plot;
    bool any_particles = false;
    for (std::size_t i = 0; i < relative.size(); ++i) {
      const std::string fluid = text(relative[i], "fluid");
      for (const auto& p : array(relative[i], "points")) any_particles = any_particles || num(p, "volume_fraction") > 0;
      const std::string f = fmt::format("(strcol(1) eq '{}' ? ${{}} : NaN)", fluid);
      const auto col = [&](int c) { return fmt::format(fmt::runtime(f), c); };
      plot += fmt::format(
          "{}'relative_viscosity.csv' every ::1 using 2:{}:4 with yerrorbars pt 7 ps 1.3 lc {} title "
          "'η_r measured{}'",
          plot.empty() ? "" : ", ", col(3), colour(i), relative.size() > 1 ? ", " + fluid : "");
      if (i == 0) {
        plot += fmt::format(
            ", 'relative_viscosity_curves.csv' every ::1 using 2:{} with lines lw 2 lc rgb '#555555' dt 3 title "
            "'Einstein 1 + 2.5φ'",
            col(3));
        plot += fmt::format(
            ", 'relative_viscosity_curves.csv' every ::1 using 2:{} with lines lw 2 lc rgb '#1b9e77' dt 2 title "
            "'Batchelor 1 + 2.5φ + 6.2φ²'",
            col(4));
        plot += fmt::format(
            ", 'relative_viscosity_curves.csv' every ::1 using 2:{} with lines lw 2 lc rgb '#d95f02' title "
            "'Krieger–Dougherty'",
            col(5));
        plot += fmt::format(
            ", 'relative_viscosity_curves.csv' every ::1 using 2:{} with lines lw 2 lc rgb '#7570b3' dt 4 title "
            "'Maron–Pierce'",
            col(6));
        plot += fmt::format(
            ", 'relative_viscosity_curves.csv' every ::1 using 2:{} with lines lw 3 lc rgb '#e7298a' title 'measured: "
            "Boyer et al. 2011'",
            col(7));
        plot += fmt::format(
            ", 'relative_viscosity_curves.csv' every ::1 using 2:{} with lines lw 3 lc rgb '#66a61e' dt 5 title "
            "'measured: Zarraga et al. 2000'",
            col(8));
      }
    }
    const std::string title =
        any_particles ? "Relative viscosity η_r(φ) at the reference shear rate, φ_m fitted"
                      : "Relative viscosity: no finished point with φ > 0, curves use φ_m = 0.63 (not fitted)";
    scripts["relative_viscosity"] =
        core::gnuplot_header("relative_viscosity", "Relative viscosity against the classic correlations") +
        core::gnuplot_outputs(
            "relative_viscosity",
            fmt::format("set xlabel 'volume fraction φ'\nset ylabel 'relative viscosity η_r'\nset logscale y\n"
                        "set xrange [0:*]\nset yrange [0.9:*]\nset key inside left top\nset title '{}' font ',10'\n"
                        "plot {}\n",
                        title, plot));
  }
  if (any_normal_force) {
    // N1 − N2 from the plates' normal force (filled) and the model's local N1 (open) and N2 (crosses).
    std::string plot;
    for (std::size_t i = 0; i < series.size(); ++i) {
      const std::string& label = series[i].label;
      const std::string sep = plot.empty() ? "" : ", \\\n  ";
      plot += fmt::format(
          "{}'normal_stress.csv' every ::1 using 3:{} with linespoints pt 7 lc {} title '{} N1 − N2 (from F)'", sep,
          filter(label, 5), colour(i), label);
      plot +=
          fmt::format(", \\\n  'normal_stress.csv' every ::1 using 3:{} with points pt 6 ps 1.5 lc {} title '{} N1'",
                      filter(label, 6), colour(i), label);
      plot +=
          fmt::format(", \\\n  'normal_stress.csv' every ::1 using 3:{} with points pt 2 ps 1.5 lc {} title '{} N2'",
                      filter(label, 7), colour(i), label);
    }
    if (!plot.empty())
      scripts["normal_stress"] =
          core::gnuplot_header("normal_stress", "Normal stress differences vs rim shear rate") +
          core::gnuplot_outputs("normal_stress",
                                "set xlabel 'rim shear rate γ̇_R [1/s]'\nset ylabel 'normal stress difference [Pa]'\n"
                                "set format y '%.2e'\nset key outside right\nplot " +
                                    plot + "\n");
  }
  if (!yields.empty()) {
    const std::vector<std::string> methods = {"bingham_intercept", "casson_intercept", "herschel_bulkley",
                                              "torque_intercept"};
    double phi_lo = 1, phi_hi = 0;
    for (const auto& y : yields) {
      phi_lo = std::min(phi_lo, num(y, "volume_fraction"));
      phi_hi = std::max(phi_hi, num(y, "volume_fraction"));
    }
    const std::string yield_xrange = fmt::format("set xrange [{}:{}]\n", phi_lo - 0.03, phi_hi + 0.03);
    std::string plot;
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const double offset = (static_cast<double>(m) - 1.5) * 0.004;  // side by side at each φ
      plot += fmt::format(
          "{}'yield_stress.csv' every ::1 using ($2 + {}):(strcol(3) eq '{}' ? $4 : NaN):(valid(6) ? $6 : "
          "$4):(valid(7) ? "
          "$7 : $4) with yerrorbars pt {} ps 1.3 lc {} title '{}' noenhanced",
          plot.empty() ? "" : ", ", offset, methods[m], 5 + 2 * static_cast<int>(m), m + 1, methods[m]);
    }
    scripts["yield_stress"] =
        core::gnuplot_header("yield_stress", "Yield stress vs φ by four methods, with 95 % intervals") +
        core::gnuplot_outputs(
            "yield_stress",
            "set xlabel 'volume fraction φ'\nset ylabel 'yield stress τ_y [Pa]'\nset format y '%.2e'\n" + yield_xrange +
                "set xzeroaxis lt -1\nset title 'Yield stress by method (bars: 95 % interval; "
                "methods offset in φ for legibility)' font ',10'\nplot " +
                plot + "\n");
  }

  ReportFiles files;
  const bool have_gnuplot = core::gnuplot_installed();
  for (const auto& [name, script] : scripts) {
    core::write_atomically(run_dir / (name + ".gp"), [&](std::ostream& os) { os << script; });
    (core::plot_with_gnuplot(run_dir, name) ? files.plots : files.missing_plots).push_back(name);
  }

  // ------------------------------------------------------------------ HTML
  std::string html = core::html_page_head("rheosim report");
  html += fmt::format("<h1>rheosim report: {}</h1>\n", esc(text(summary, "case")));
  const int failed = static_cast<int>(num(summary, "points_failed"));
  int converged = 0;
  for (const auto& p : points) converged += p.value("converged", false) ? 1 : 0;
  html += "<table>\n";
  const auto row = [&](const std::string& key, const std::string& value) {
    html += fmt::format("<tr><th class=l>{}</th><td class=l>{}</td></tr>\n", key, value);
  };
  row("kind", esc(text(summary, "kind")));
  row("plates", fmt::format("radius R = {} m, gap H = {} m", g4(radius), g4(plate.gap)));
  if (summary.contains("grid"))
    row("fluid grid", fmt::format("N_r = {}, N_z = {}, radial grading {}, axial stretching {}; inertia {}",
                                  num(summary.at("grid"), "radial_cells"), num(summary.at("grid"), "axial_cells"),
                                  g4(num(summary.at("grid"), "radial_grading")),
                                  g4(summary.at("grid").value("axial_stretching", 0.0)),
                                  summary.value("inertia", true) ? "on" : "off (creeping limit)"));
  row("points",
      fmt::format("{} finished, {} failed{}", converged, failed,
                  summary.contains("points_resumed")
                      ? fmt::format(" ({} read back from an earlier, interrupted run)", num(summary, "points_resumed"))
                      : std::string()));
  row("wall time", fmt::format("{} s", g4(num(summary, "wall_time"))));
  row("rheosim", fmt::format("{} (git {})", esc(text(summary, "rheosim_version")), esc(text(summary, "git_revision"))));
  row("input sha256", fmt::format("<code>{}</code>", esc(text(summary, "input_sha256"))));
  html += "</table>\n";

  if (const Json& warnings = array(summary, "warnings"); !warnings.empty()) {
    html += "<div class=note><b>Rules the run bent</b> (also in summary.json <code>warnings</code> and the log):<ul>\n";
    for (const auto& w : warnings)
      html += fmt::format("<li>{} <span class=small>({} point(s))</span></li>\n", esc(text(w, "warning")),
                          num(w, "points"));
    html += "</ul></div>\n";
  }
  if (failed > 0) {
    html += fmt::format(
        "<div class=fail><b>{} point(s) have no result.</b> They are listed here and left out of every "
        "fit, plot and table below; no number was invented for them.<table>\n<tr><th>fluid</th><th>φ</th>"
        "<th>γ̇_R [1/s]</th><th class=l>reason</th></tr>\n",
        failed);
    for (const auto& p : points)
      if (!p.value("converged", false))
        html += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td class=l>{}</td></tr>\n", esc(text(p, "fluid")),
                            g4(p.contains("volume_fraction") ? num(p, "volume_fraction") : 0.0),
                            g4(num(p, "shear_rate")), esc(text(p, "failure")));
    html += "</table></div>\n";
  }
  if (!files.missing_plots.empty())
    html += fmt::format(
        "<div class=note>gnuplot {} not produce: {}. The scripts are beside this report: run "
        "<code>gnuplot NAME.gp</code> in this folder (see NAME.gnuplot.log).</div>\n",
        have_gnuplot ? "did" : "is not installed, so these plots could", [&] {
          std::string s;
          for (const auto& m : files.missing_plots) s += (s.empty() ? "" : ", ") + m;
          return s;
        }());

  const auto figure = [&](const std::string& name, const std::string& caption) {
    if (std::find(files.plots.begin(), files.plots.end(), name) == files.plots.end()) return std::string();
    return core::html_figure(name, caption);
  };

  // Torque.
  html += "<h2>Torque vs rim shear rate</h2>\n";
  html += figure("torque",
                 "Measured torque per flow curve (data: <a href=\"flow_curve.csv\">flow_curve.csv</a>), "
                 "the seed's straight-line fit T = T₀ + b γ̇_R (CD §4, <a href=\"torque_lines.csv\">"
                 "torque_lines.csv</a>) and, dashed, the creeping-flow closed form where one exists.");

  // Flow curves.
  html +=
      "<h2>Flow curves</h2>\n<p class=small>Apparent rim stress τ_app = 2T/(πR³) (the Newtonian value) and the "
      "plate-corrected rim stress τ_R = T/(2πR³)(3 + n′), n′ = d ln T/d ln γ̇_R from a local weighted quadratic in "
      "ln γ̇_R (not a two-point difference). Validity: gap Reynolds ρΩH²/η ≤ 1, particle Reynolds ρ_f γ̇ d²/η_f ≤ "
      "0.1, Stokes ρ_p γ̇ d²/η_f ≤ 0.1, H/d ≥ 10 (particle checks only for φ &gt; 0).</p>\n";
  html += figure("stress",
                 "Rim shear stress, log–log; line: the best model of each flow curve by AICc "
                 "(<a href=\"fit_curves.csv\">fit_curves.csv</a>).");
  html += figure("viscosity", "Viscosity τ/γ̇ at the rim, log–log, with the best fit.");
  for (const auto& s : series_json) {
    const std::string label = text(s, "label");
    html += fmt::format("<h3>{}</h3>\n", esc(label));
    for (const auto& w : array(s, "warnings"))
      html += fmt::format("<p class=warn>⚠ {}</p>\n", esc(w.get<std::string>()));
    if (!(num(s, "points") > 0)) continue;
    html +=
        "<table>\n<tr><th>γ̇_R [1/s]</th><th>T [N m]</th><th>n′</th><th>τ_app [Pa]</th><th>τ_R [Pa]</th>"
        "<th>η = τ_R/γ̇_R [Pa s]</th><th>Re_gap</th><th>Re_p</th><th>St</th><th>H/d</th><th class=l>valid</th></tr>\n";
    for (const auto& p : points) {
      if (label_of(p) != label || !p.value("converged", false)) continue;
      const Json v = p.contains("validity") ? p.at("validity") : Json::object();
      std::string valid = "–";
      if (v.contains("valid")) {
        valid = v.at("valid").get<bool>() ? "<span class=ok>✓</span>" : "<span class=bad>✗</span>";
        if (p.contains("used_in_fits") && !p.at("used_in_fits").get<bool>()) valid += " not fitted";
        for (const auto& m : array(v, "messages"))
          valid += "<br><span class=warn>" + esc(m.get<std::string>()) + "</span>";
      }
      const double se = num(p, "torque_std_error");
      html += fmt::format(
          "<tr><td>{}</td><td>{}{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
          "<td>{}</td><td>{}</td><td class=l>{}</td></tr>\n",
          g4(num(p, "shear_rate")), g4(num(p, "torque")), std::isfinite(se) ? " ± " + g4(se) : "",
          g4(num(p, "log_slope")), g4(num(p, "apparent_stress")), g4(num(p, "rim_stress")), g4(num(p, "viscosity")),
          g4(num(v, "gap_reynolds")), g4(num(v, "particle_reynolds")), g4(num(v, "stokes")),
          g4(num(v, "gap_to_diameter")), valid);
    }
    html += "</table>\n";
  }

  // Fits.
  html +=
      "<h2>Model fits</h2>\n<p class=small>Each model fitted to (γ̇_R, τ_R) by weighted least squares on relative "
      "residuals (τ_model − τ_R)/τ_R. Parameters: value ± standard error [95 % interval, Student t with n − p degrees "
      "of freedom]. s: relative residual scatter. Ranked by AICc (Δ: difference to the best; w: Akaike weight); "
      "only differences between fits of the same curve mean anything. All numbers: <a href=\"fits.csv\">fits.csv</a>, "
      "summary.json <code>fits</code>.</p>\n";
  for (const auto& s : series_json) {
    const std::string label = text(s, "label");
    std::vector<const Json*> ranked;
    for (const auto& f : fits)
      if (text(f, "label") == label) ranked.push_back(&f);
    if (ranked.empty()) continue;
    std::sort(ranked.begin(), ranked.end(),
              [](const Json* a, const Json* b) { return num(*a, "rank") < num(*b, "rank"); });
    html += fmt::format(
        "<h3>{}</h3>\n<table>\n<tr><th>rank</th><th class=l>model</th><th class=l>parameters</th>"
        "<th>s</th><th>n − p</th><th>AICc</th><th>Δ</th><th>w</th><th class=l>warnings</th></tr>\n",
        esc(label));
    std::string correlations;
    for (const Json* fp : ranked) {
      const Json& f = *fp;
      std::string params;
      for (const auto& p : array(f, "parameters")) {
        const Json& ci = p.at("ci95");
        const std::string unit = text(p, "unit") == "-" ? std::string() : fmt::format(" {}", esc(text(p, "unit")));
        params += fmt::format("{}{} = {} ± {}{}, 95 %: [{}, {}]", params.empty() ? "" : "<br>", esc(text(p, "symbol")),
                              g4(num(p, "value")), g4(num(p, "std_error")), unit, g4(num(ci[0])), g4(num(ci[1])));
      }
      // The first warning in full, the rest folded: a model that cannot be identified from the
      // data says so once, not in a wall of text.
      std::string warnings, more;
      int count = 0;
      for (const auto& w : array(f, "warnings")) {
        const std::string message = esc(text(w, "message"));
        if (count == 0)
          warnings = message;
        else
          more += (count > 1 ? "<br>" : "") + message;
        ++count;
      }
      if (count > 1) warnings += fmt::format("<details><summary>{} more</summary>{}</details>", count - 1, more);
      if (!f.value("converged", false)) warnings = "<span class=bad>not converged</span> " + warnings;
      html += fmt::format(
          "<tr><td>{}</td><td class=l>{}<br><span class=small>{}</span></td><td class=p>{}</td><td>{}</td>"
          "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=l><span class=warn>{}</span></td></tr>\n",
          num(f, "rank"), esc(text(f, "model")), esc(text(f, "equation")), params, g4(num(f, "residual_std")),
          num(f, "degrees_of_freedom"), g4(num(f, "aicc")), g4(num(f, "delta")), g4(num(f, "akaike_weight")), warnings);
      const Json& corr = array(f, "correlation");
      if (corr.size() > 1) {
        correlations += fmt::format("<table><tr><th class=l>{}</th>", esc(text(f, "model")));
        for (const auto& p : array(f, "parameters")) correlations += "<th>" + esc(text(p, "symbol")) + "</th>";
        correlations += "</tr>\n";
        for (std::size_t r = 0; r < corr.size(); ++r) {
          correlations += "<tr><th>" + esc(text(array(f, "parameters")[r], "symbol")) + "</th>";
          for (const auto& c : corr[r])
            correlations += "<td>" + (c.is_number() ? fmt::format("{:.3f}", c.get<double>()) : "–") + "</td>";
          correlations += "</tr>\n";
        }
        correlations += "</table>\n";
      }
    }
    html += "</table>\n";
    if (!correlations.empty())
      html += "<details><summary>parameter correlation matrices</summary>\n" + correlations + "</details>\n";
  }
  html += figure("residuals",
                 "Relative residuals of every model, one panel per model, all flow curves "
                 "(<a href=\"residuals.csv\">residuals.csv</a>). A trend in a panel means the model misses "
                 "the curve's shape; noise around 0 means it fits.");

  // Yield stress.
  html +=
      "<h2>Yield stress</h2>\n<p class=small>Four estimates, kept apart because they answer different questions: "
      "the intercepts of the Bingham and Casson fits, the Herschel–Bulkley τ_y, and the seed's method (CD §4): the "
      "straight line through the torques extrapolated to γ̇_R = 0, τ_y = 3T₀/(2πR³). An interval that includes 0 "
      "means the data do not show a yield stress. A positive intercept is not proof of one either: the straight line "
      "through the torques of any shear-thinning liquid meets the axis above 0, and an intercept of a model with "
      "Akaike weight near 0 (see Model fits) is an artefact of fitting the wrong law. Points that fail the validity "
      "checks are left out. <a href=\"yield_stress.csv\">yield_stress.csv</a>.</p>\n";
  if (!yields.empty()) {
    html +=
        "<table>\n<tr><th class=l>flow curve</th><th>φ</th><th class=l>method</th><th>τ_y [Pa]</th><th>± se</th>"
        "<th>95 % interval [Pa]</th><th class=l>significant</th><th>Akaike weight of the model</th></tr>\n";
    for (const auto& y : yields) {
      const Json& ci = y.at("ci95");
      html += fmt::format(
          "<tr><td class=l>{}</td><td>{}</td><td class=l>{}</td><td>{}</td><td>{}</td><td>[{}, {}]</td>"
          "<td class=l>{}</td><td>{}</td></tr>\n",
          esc(text(y, "label")), g4(num(y, "volume_fraction")), esc(text(y, "method")), g4(num(y, "value")),
          g4(num(y, "std_error")), g4(num(ci[0])), g4(num(ci[1])),
          y.value("significant", false) ? "yes" : "no (interval includes 0)", g4(num(y, "akaike_weight")));
    }
    html += "</table>\n";
  }
  html += figure("yield_stress", "Yield stress vs φ by method with 95 % intervals.");

  // Relative viscosity.
  html += "<h2>Relative viscosity</h2>\n";
  const bool any_suspension = std::any_of(points.begin(), points.end(), [](const Json& p) {
    return p.value("converged", false) && num(p, "volume_fraction") > 0;
  });
  if (!any_suspension)
    html +=
        "<p class=note>No finished point with φ &gt; 0, so there is no measured η_r(φ): the plot shows the "
        "correlations with φ_m = 0.63 (nothing fitted) and η_r(0) = 1 of each liquid. Per liquid: "
        "<a href=\"relative_viscosity.csv\">relative_viscosity.csv</a>, summary.json "
        "<code>relative_viscosity</code>.</p>\n";
  for (const auto& rv : relative) {
    if (!any_suspension) break;
    const std::string fluid = text(rv, "fluid");
    html += fmt::format(
        "<p class=small>η_r = η(φ)/η_f at the reference rim shear rate {} 1/s (the largest every φ "
        "reached), each η from that flow curve's best fit, η_f = {} Pa s from {}. Error bars: first-order "
        "propagation of the fits' standard errors. <a href=\"relative_viscosity.csv\">"
        "relative_viscosity.csv</a>.</p>\n",
        g4(num(rv, "reference_shear_rate")), g4(num(rv, "liquid_viscosity")), esc(text(rv, "liquid_viscosity_source")));
    for (const auto& w : array(rv, "warnings"))
      html += fmt::format("<p class=warn>⚠ {}</p>\n", esc(w.get<std::string>()));
    html += "<table>\n<tr><th>φ</th><th>η_r</th><th>± se</th><th class=l>fit used</th>";
    const Json& correlations = array(rv, "correlations");
    for (const auto& c : correlations) html += "<th>" + esc(text(c, "name")) + "</th>";
    html += "</tr>\n";
    const Json& rvp = array(rv, "points");
    for (std::size_t i = 0; i < rvp.size(); ++i) {
      html +=
          fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td class=l>{}</td>", g4(num(rvp[i], "volume_fraction")),
                      g4(num(rvp[i], "relative_viscosity")), g4(num(rvp[i], "std_error")), esc(text(rvp[i], "model")));
      for (const auto& c : correlations) {
        const Json& pred = array(c, "predicted");
        html += "<td>" + (i < pred.size() ? g4(num(pred[i])) : std::string("–")) + "</td>";
      }
      html += "</tr>\n";
    }
    html += "</table>\n";
    if (!correlations.empty()) {
      html +=
          "<table>\n<tr><th class=l>correlation</th><th>φ_m</th><th>95 % interval</th><th>Σ residual²</th><th>AIC</th>"
          "<th class=l>warnings</th></tr>\n";
      for (const auto& c : correlations) {
        const Json& ci = c.at("max_packing_ci95");
        std::string warnings;
        for (const auto& w : array(c, "warnings"))
          warnings += (warnings.empty() ? "" : "<br>") + esc(w.get<std::string>());
        html += fmt::format(
            "<tr><td class=l>{}</td><td>{}</td><td>[{}, {}]</td><td>{}</td><td>{}</td><td class=l>"
            "<span class=warn>{}</span></td></tr>\n",
            esc(text(c, "name")), g4(num(c, "max_packing")), g4(num(ci[0])), g4(num(ci[1])),
            g4(num(c, "sum_of_squares")), g4(num(c, "aic")), warnings);
      }
      html += "</table>\n";
    }
  }
  html += figure("relative_viscosity",
                 "η_r(φ) with error bars against Einstein, Batchelor, Krieger–Dougherty "
                 "([η] = 2.5, φ_m fitted) and Maron–Pierce (φ_m fitted) "
                 "(<a href=\"relative_viscosity_curves.csv\">relative_viscosity_curves.csv</a>).");

  // Normal stresses.
  if (any_normal_force) {
    html +=
        "<h2>Normal stresses</h2>\n<p class=small>The plates' normal force F (positive: pushing them apart), "
        "N1 − N2 at the rim from it by the parallel-plate relation N1 − N2 = (F/πR²)(2 + d ln F/d ln γ̇_R), and "
        "the model's local first and second normal stress differences at the rim rate. Measured non-Brownian "
        "suspensions: N2/τ ≈ −4.4φ³, N1/τ ≈ −0.8φ³ (Dai, Bertevas, Qi &amp; Tanner 2013). "
        "<a href=\"normal_stress.csv\">normal_stress.csv</a>.</p>\n<table>\n<tr><th class=l>flow curve</th>"
        "<th>γ̇_R [1/s]</th><th>F [N]</th><th>N1 − N2 [Pa]</th><th>N1 [Pa]</th><th>N2 [Pa]</th><th>N1/τ_R</th>"
        "<th>N2/τ_R</th></tr>\n";
    for (const auto& p : points) {
      if (!p.value("converged", false) || !p.contains("normal_force")) continue;
      const double tau = num(p, "rim_stress");
      html += fmt::format(
          "<tr><td class=l>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
          "<td>{}</td></tr>\n",
          esc(label_of(p)), g4(num(p, "shear_rate")), g4(num(p, "normal_force")), g4(num(p, "n1_minus_n2")),
          g4(num(p, "n1")), g4(num(p, "n2")), g4(num(p, "n1") / tau), g4(num(p, "n2") / tau));
    }
    html += "</table>\n";
    html += figure("normal_stress", "N1 − N2 from the normal force, and the model's N1 and N2, per flow curve.");
  }

  // Speed and error.
  html +=
      "<h2>Speed and error of the run</h2>\n<p class=small>Per point: how it was computed, wall time, iterations, "
      "and the error against the creeping-flow closed form where one exists. With inertia on, the difference "
      "includes the physical torque rise from secondary flow (see Re_gap); the creeping column isolates the "
      "discretisation error. <a href=\"speed_error.csv\">speed_error.csv</a>.</p>\n<table>\n<tr><th class=l>flow "
      "curve</th><th>γ̇_R [1/s]</th><th class=l>method</th><th>wall time [s]</th><th>iterations</th><th>T [N m]</th>"
      "<th>closed form [N m]</th><th>error</th><th>error, creeping solve</th><th>Re_gap</th></tr>\n";
  double total_wall = 0;
  for (const auto& p : points) {
    if (!p.value("converged", false)) continue;
    total_wall += num(p, "wall_time");
    const auto pct = [](double x) { return std::isfinite(x) ? fmt::format("{:.3g} %", 100 * x) : std::string("–"); };
    html += fmt::format(
        "<tr><td class=l>{}</td><td>{}</td><td class=l>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
        "<td>{}</td><td>{}</td><td>{}</td></tr>\n",
        esc(label_of(p)), g4(num(p, "shear_rate")), esc(text(p, "method")), g4(num(p, "wall_time")),
        num(p, "iterations"), g4(num(p, "torque")), g4(num(p, "torque_analytic")), pct(num(p, "rel_error")),
        pct(num(p, "creeping_rel_error")), g4(num(p, "gap_reynolds_number")));
  }
  html += fmt::format("</table>\n<p class=small>Sum of point wall times: {} s.</p>\n", g4(total_wall));

  html +=
      "<h2>Files</h2>\n<p class=small>summary.json holds every number above. Data: flow_curve.csv, fits.csv, "
      "fit_curves.csv, residuals.csv, torque_lines.csv, yield_stress.csv, relative_viscosity.csv, "
      "relative_viscosity_curves.csv, speed_error.csv, torque.csv. Plots: NAME.png and NAME.svg from NAME.gp "
      "(edit and run <code>gnuplot NAME.gp</code> here to restyle)." +
      std::string(is_sweep ? " Sweep points: points/point_NNNN.h5 (one per finished point), sweep.h5."
                           : " Fields: fields.h5.") +
      "</p>\n";

  const auto deck = run_dir / "case.yaml";
  if (fs::exists(deck)) {
    const std::string deck_text = read_text(deck);
    html += fmt::format("<h2>Input deck</h2>\n<p>case.yaml, sha256 <code>{}</code></p>\n<pre>{}</pre>\n",
                        core::sha256_hex(deck_text), esc(deck_text));
  }
  html += core::html_page_tail();

  files.html = run_dir / "report.html";
  core::write_atomically(files.html, [&](std::ostream& os) { os << html; });
  return files;
}

}  // namespace rheosim::rheometer
