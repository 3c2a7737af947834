// The report's reading of summary.json and its CSV data files (report_parts.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "report_parts.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/report_page.hpp"
#include "rheosim/rheometer/analysis.hpp"
#include "rheosim/rheometer/flow_models.hpp"

namespace rheosim::rheometer::report_detail {

namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double or_nan(const MaybeNumber& x) { return x.value_or(nan); }

std::string csv_number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, x).ptr;
  return std::string(buffer, end);
}
std::string csv_number(const MaybeNumber& x) { return csv_number(or_nan(x)); }

std::string g4(double x) { return std::isfinite(x) ? fmt::format("{:.4g}", x) : std::string("–"); }
std::string g4(const MaybeNumber& x) { return g4(or_nan(x)); }
std::string esc(const std::string& s) { return core::escape_markup(s); }

const PointChecks& checks_of(const SweepPointRecord& point) {
  static const PointChecks none{};
  return point.validity ? *point.validity : none;
}

std::string ReportData::label_of(const SweepPointRecord& point) const {
  for (const auto& s : summary.series)
    if (s.fluid == point.fluid && s.volume_fraction == point.volume_fraction) return s.label;
  return point.fluid;
}

ReportData read_report_data(const fs::path& run_dir) {
  ReportData d;
  d.summary = read_sweep_summary(run_dir);
  for (const auto& s : d.summary.series)  // plots show only flow curves with data
    if (s.points > 0)
      d.series.push_back({s.label, s.volume_fraction, s.best_model.value_or(""), s.best_model.has_value()});
  for (const auto& f : d.summary.fits) d.model_names.insert(f.model);
  d.any_normal_force = std::any_of(d.summary.points.begin(), d.summary.points.end(),
                                   [](const SweepPointRecord& p) { return p.converged && p.normal_force; });
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
  DataTable flow({"series", "fluid", "volume_fraction", "shear_rate [1/s]", "torque [N m]", "torque_std_error [N m]",
                  "torque_analytic [N m]", "log_slope", "log_slope_std_error", "apparent_stress [Pa]",
                  "rim_stress [Pa]", "apparent_viscosity [Pa s]", "viscosity [Pa s]", "gap_reynolds",
                  "particle_reynolds", "stokes", "gap_to_diameter", "valid", "used_in_fits"});
  DataTable speed({"series", "shear_rate [1/s]", "method", "wall_time [s]", "iterations", "torque [N m]",
                   "torque_analytic [N m]", "rel_error", "torque_creeping [N m]", "creeping_rel_error",
                   "gap_reynolds_number"});
  for (const auto& p : d.summary.points) {
    if (!p.converged) continue;
    const PointChecks& v = checks_of(p);
    flow.add({d.label_of(p), p.fluid, csv_number(p.volume_fraction), csv_number(p.shear_rate), csv_number(p.torque),
              csv_number(p.torque_std_error), csv_number(p.torque_analytic), csv_number(p.log_slope),
              csv_number(p.log_slope_std_error), csv_number(p.apparent_stress), csv_number(p.rim_stress),
              csv_number(p.apparent_viscosity), csv_number(p.viscosity), csv_number(v.gap_reynolds),
              csv_number(v.particle_reynolds), csv_number(v.stokes), csv_number(v.gap_to_diameter),
              p.validity ? (v.valid ? "1" : "0") : "nan", p.used_in_fits ? (*p.used_in_fits ? "1" : "0") : "nan"});
    speed.add({d.label_of(p), csv_number(p.shear_rate), p.method, csv_number(p.wall_time), csv_number(p.iterations),
               csv_number(p.torque), csv_number(p.torque_analytic), csv_number(p.rel_error),
               csv_number(p.torque_creeping), csv_number(p.creeping_rel_error), csv_number(p.gap_reynolds_number)});
  }
  flow.write(run_dir / "flow_curve.csv");
  speed.write(run_dir / "speed_error.csv");
}

// fits.csv (every parameter of every fit), fit_curves.csv (each fit on a log grid over its data), residuals.csv.
void write_fit_tables(const ReportData& d, const fs::path& run_dir) {
  DataTable fit_table({"series", "model", "rank", "delta_aicc", "akaike_weight", "aicc", "aic", "residual_std",
                       "degrees_of_freedom", "converged", "parameter", "unit", "value", "std_error", "ci95_lower",
                       "ci95_upper", "warnings"});
  DataTable curves({"series", "model", "shear_rate [1/s]", "stress [Pa]", "viscosity [Pa s]"});
  DataTable residuals({"series", "model", "shear_rate [1/s]", "relative_residual [%]"});
  for (const auto& f : d.summary.fits) {
    std::string warnings;
    for (const auto& w : f.warnings) warnings += (warnings.empty() ? "" : "; ") + w.message;
    std::vector<double> values;
    for (const auto& p : f.parameters) {
      values.push_back(or_nan(p.value));
      fit_table.add({f.label, f.model, csv_number(static_cast<double>(f.rank)), csv_number(f.delta),
                     csv_number(f.akaike_weight), csv_number(f.aicc), csv_number(f.aic), csv_number(f.residual_std),
                     csv_number(f.degrees_of_freedom), f.converged ? "1" : "0", p.name, p.unit, csv_number(p.value),
                     csv_number(p.std_error), csv_number(p.ci95.lower), csv_number(p.ci95.upper), warnings});
    }
    for (std::size_t i = 0; i < f.shear_rate.size() && i < f.residuals.size(); ++i)
      residuals.add({f.label, f.model, csv_number(f.shear_rate[i]), csv_number(100.0 * or_nan(f.residuals[i]))});
    // The fitted curve on a log grid over the data range.
    const double lo = f.min_shear_rate, hi = f.max_shear_rate;
    if (!(lo > 0 && hi > lo) || !builtin_flow_models().contains(f.model)) continue;
    if (std::any_of(values.begin(), values.end(), [](double x) { return !std::isfinite(x); })) continue;
    const auto law = make_flow_model(f.model);
    constexpr int samples = 60;
    for (int k = 0; k <= samples; ++k) {
      const double rate = lo * std::pow(hi / lo, static_cast<double>(k) / samples);
      const double stress = law->stress(rate, values);
      curves.add({f.label, f.model, csv_number(rate), csv_number(stress), csv_number(stress / rate)});
    }
  }
  fit_table.write(run_dir / "fits.csv");
  curves.write(run_dir / "fit_curves.csv");
  residuals.write(run_dir / "residuals.csv");
}

// The seed's straight torque lines (CD §4, Fig. 7), from γ̇ = 0 to the largest rate.
void write_torque_lines(const ReportData& d, const fs::path& run_dir) {
  DataTable lines({"series", "shear_rate [1/s]", "torque_line [N m]"});
  for (const auto& s : d.summary.series) {
    if (!s.torque_line) continue;
    double max_rate = 0;
    for (const auto& p : d.summary.points)
      if (d.label_of(p) == s.label && p.converged) max_rate = std::max(max_rate, p.shear_rate);
    for (double rate : {0.0, max_rate})
      lines.add({s.label, csv_number(rate), csv_number(s.torque_line->intercept + s.torque_line->slope * rate)});
  }
  lines.write(run_dir / "torque_lines.csv");
}

// yield_stress.csv: every estimate with its interval.
void write_yield_table(const ReportData& d, const fs::path& run_dir) {
  DataTable yield_table({"series", "volume_fraction", "method", "yield_stress [Pa]", "std_error [Pa]",
                         "ci95_lower [Pa]", "ci95_upper [Pa]", "significant", "converged"});
  for (const auto& y : d.summary.yield_stress)
    yield_table.add({y.label, csv_number(y.volume_fraction), y.method, csv_number(y.value), csv_number(y.std_error),
                     csv_number(y.ci95.lower), csv_number(y.ci95.upper), y.significant ? "1" : "0",
                     y.converged ? "1" : "0"});
  yield_table.write(run_dir / "yield_stress.csv");
}

// relative_viscosity.csv (measured η_r) and relative_viscosity_curves.csv (the correlations).
void write_relative_viscosity_tables(const ReportData& d, const fs::path& run_dir) {
  DataTable rv_table(
      {"fluid", "volume_fraction", "relative_viscosity", "std_error", "reference_shear_rate [1/s]", "model"});
  DataTable rv_curves({"fluid", "volume_fraction", "einstein", "batchelor", "krieger_dougherty", "maron_pierce",
                       "boyer_2011", "zarraga_2000"});
  for (const auto& rv : d.summary.relative_viscosity) {
    for (const auto& p : rv.points)
      rv_table.add({rv.fluid, csv_number(p.volume_fraction), csv_number(p.relative_viscosity), csv_number(p.std_error),
                    csv_number(rv.reference_shear_rate), p.model});
    // Fitted φ_m where the data allowed it; otherwise the classic 0.63 (random close packing).
    double kd_max = 0.63, mp_max = 0.63;
    for (const auto& c : rv.correlations) {
      if (c.name == "krieger_dougherty" && or_nan(c.max_packing) > 0) kd_max = *c.max_packing;
      if (c.name == "maron_pierce" && or_nan(c.max_packing) > 0) mp_max = *c.max_packing;
    }
    const double phi_end = std::min({0.6, 0.9 * kd_max, 0.9 * mp_max});  // η_r up to ~100: a readable axis
    for (int k = 0; k <= 60; ++k) {
      const double phi = phi_end * k / 60.0;
      rv_curves.add({rv.fluid, csv_number(phi), csv_number(einstein_relative_viscosity(phi)),
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
  DataTable normal_table({"series", "volume_fraction", "shear_rate [1/s]", "normal_force [N]", "n1_minus_n2 [Pa]",
                          "n1 [Pa]", "n2 [Pa]", "rim_stress [Pa]"});
  for (const auto& p : d.summary.points)
    if (p.converged && p.normal_force)
      normal_table.add({d.label_of(p), csv_number(p.volume_fraction), csv_number(p.shear_rate),
                        csv_number(p.normal_force), csv_number(p.n1_minus_n2), csv_number(p.n1), csv_number(p.n2),
                        csv_number(p.rim_stress)});
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
