// The rheometer report's gnuplot scripts, one per figure, each writing NAME.png and NAME.svg
// from the CSV data files (report_parts.hpp).
#include <fmt/format.h>

#include <algorithm>

#include "report_parts.hpp"
#include "rheosim/core/report_page.hpp"

namespace rheosim::rheometer::report_detail {

namespace {

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

// torque: the torques per flow curve, the straight-line fits and the creeping closed form.
void add_torque_plot(const ReportData& d, Scripts& scripts) {
  const auto& points = d.summary.points;
  const std::vector<SeriesInfo>& series = d.series;
  const bool any_torque_error = std::any_of(points.begin(), points.end(),
                                            [](const SweepPointRecord& p) { return or_nan(p.torque_std_error) > 0; });
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
}

// stress and viscosity: the rim flow curves, points left out of the fits, the best fit.
void add_flow_curve_plots(const ReportData& d, Scripts& scripts) {
  const auto& points = d.summary.points;
  const std::vector<SeriesInfo>& series = d.series;
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
      const bool has_unfitted = std::any_of(points.begin(), points.end(), [&](const SweepPointRecord& p) {
        return d.label_of(p) == s.label && p.used_in_fits && !*p.used_in_fits;
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
}

// residuals: one panel per model over every flow curve.
void add_residuals_plot(const ReportData& d, Scripts& scripts) {
  const auto& fits = d.summary.fits;
  const std::vector<SeriesInfo>& series = d.series;
  const std::set<std::string>& model_names = d.model_names;
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
}

// relative_viscosity: η_r(φ) against the correlations and two measured curves.
void add_relative_viscosity_plot(const ReportData& d, Scripts& scripts) {
  const auto& relative = d.summary.relative_viscosity;
  if (!relative.empty()) {
    std::string plot;
    bool any_particles = false;
    for (std::size_t i = 0; i < relative.size(); ++i) {
      const std::string& fluid = relative[i].fluid;
      for (const auto& p : relative[i].points) any_particles = any_particles || p.volume_fraction > 0;
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
}

// normal_stress: N1 − N2 from F, and the model's N1 and N2.
void add_normal_stress_plot(const ReportData& d, Scripts& scripts) {
  const std::vector<SeriesInfo>& series = d.series;
  if (d.any_normal_force) {
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
}

// yield_stress: τ_y(φ) by four methods.
void add_yield_stress_plot(const ReportData& d, Scripts& scripts) {
  const auto& yields = d.summary.yield_stress;
  if (!yields.empty()) {
    const std::vector<std::string> methods = {"bingham_intercept", "casson_intercept", "herschel_bulkley",
                                              "torque_intercept"};
    double phi_lo = 1, phi_hi = 0;
    for (const auto& y : yields) {
      phi_lo = std::min(phi_lo, y.volume_fraction);
      phi_hi = std::max(phi_hi, y.volume_fraction);
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
}

}  // namespace

Scripts plot_scripts(const ReportData& d) {
  Scripts scripts;
  add_torque_plot(d, scripts);
  add_flow_curve_plots(d, scripts);
  add_residuals_plot(d, scripts);
  add_relative_viscosity_plot(d, scripts);
  add_normal_stress_plot(d, scripts);
  add_yield_stress_plot(d, scripts);
  return scripts;
}

}  // namespace rheosim::rheometer::report_detail
