// report.html of a rheometer or sweep run, section by section (report_parts.hpp, docs/report.md).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "report_parts.hpp"
#include "rheosim/core/case.hpp"
#include "rheosim/core/report_page.hpp"

namespace rheosim::rheometer::report_detail {

namespace {

// A figure of the report, or nothing when its plot was not drawn.
struct Figures {
  const ReportFiles& files;
  std::string operator()(const std::string& name, const std::string& caption) const {
    if (std::find(files.plots.begin(), files.plots.end(), name) == files.plots.end()) return std::string();
    return core::html_figure(name, caption);
  }
};

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// The run at a glance: the case, plates, grid, points, time, version; the rules it bent, the
// points without a result and the plots gnuplot did not draw.
std::string header_section(const ReportData& d, const ReportFiles& files, bool have_gnuplot) {
  const Json& points = d.points;
  const double radius = d.radius;
  const Json& summary = d.summary;
  std::string html;
  html += fmt::format("<h1>rheosim report: {}</h1>\n", esc(text(summary, "case")));
  const int failed = static_cast<int>(num(summary, "points_failed"));
  int converged = 0;
  for (const auto& p : points) converged += p.value("converged", false) ? 1 : 0;
  html += "<table>\n";
  const auto row = [&](const std::string& key, const std::string& value) {
    html += fmt::format("<tr><th class=l>{}</th><td class=l>{}</td></tr>\n", key, value);
  };
  row("kind", esc(text(summary, "kind")));
  row("plates", fmt::format("radius R = {} m, gap H = {} m", g4(radius), g4(d.gap)));
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

  return html;
}

// Torque vs rim shear rate.
std::string torque_section(const Figures& figure) {
  std::string html;
  html += "<h2>Torque vs rim shear rate</h2>\n";
  html += figure("torque",
                 "Measured torque per flow curve (data: <a href=\"flow_curve.csv\">flow_curve.csv</a>), "
                 "the seed's straight-line fit T = T₀ + b γ̇_R (CD §4, <a href=\"torque_lines.csv\">"
                 "torque_lines.csv</a>) and, dashed, the creeping-flow closed form where one exists.");

  return html;
}

// The flow curves: plots and one table per curve.
std::string flow_curve_section(const ReportData& d, const Figures& figure) {
  std::string html;
  const Json& points = d.points;
  const Json& series_json = d.series_json;
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
      if (d.label_of(p) != label || !p.value("converged", false)) continue;
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

  return html;
}

// Every model fitted to every flow curve, ranked, with its parameter correlations.
std::string fits_section(const ReportData& d, const Figures& figure) {
  std::string html;
  const Json& series_json = d.series_json;
  const Json& fits = d.fits;
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

  return html;
}

// The yield-stress estimates.
std::string yield_stress_section(const ReportData& d, const Figures& figure) {
  std::string html;
  const Json& yields = d.yields;
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

  return html;
}

// η_r(φ) per liquid against the correlations.
std::string relative_viscosity_section(const ReportData& d, const Figures& figure) {
  std::string html;
  const Json& points = d.points;
  const Json& relative = d.relative;
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

  return html;
}

// The plates' normal force and the normal stress differences.
std::string normal_stress_section(const ReportData& d, const Figures& figure) {
  std::string html;
  const Json& points = d.points;
  if (d.any_normal_force) {
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
          esc(d.label_of(p)), g4(num(p, "shear_rate")), g4(num(p, "normal_force")), g4(num(p, "n1_minus_n2")),
          g4(num(p, "n1")), g4(num(p, "n2")), g4(num(p, "n1") / tau), g4(num(p, "n2") / tau));
    }
    html += "</table>\n";
    html += figure("normal_stress", "N1 − N2 from the normal force, and the model's N1 and N2, per flow curve.");
  }

  return html;
}

// Speed and error of every point.
std::string speed_section(const ReportData& d) {
  std::string html;
  const Json& points = d.points;
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
        esc(d.label_of(p)), g4(num(p, "shear_rate")), esc(text(p, "method")), g4(num(p, "wall_time")),
        num(p, "iterations"), g4(num(p, "torque")), g4(num(p, "torque_analytic")), pct(num(p, "rel_error")),
        pct(num(p, "creeping_rel_error")), g4(num(p, "gap_reynolds_number")));
  }
  html += fmt::format("</table>\n<p class=small>Sum of point wall times: {} s.</p>\n", g4(total_wall));

  return html;
}

// What the run folder holds.
std::string files_section() {
  std::string html;
  html +=
      "<h2>Files</h2>\n<p class=small>summary.json holds every number above. Data: flow_curve.csv, fits.csv, "
      "fit_curves.csv, residuals.csv, torque_lines.csv, yield_stress.csv, relative_viscosity.csv, "
      "relative_viscosity_curves.csv, speed_error.csv, torque.csv. Plots: NAME.png and NAME.svg from NAME.gp "
      "(edit and run <code>gnuplot NAME.gp</code> here to restyle). Points: points/point_NNNN.h5 (one per "
      "finished point, with its fields), sweep.h5.</p>\n";

  return html;
}

// The input deck, verbatim.
std::string deck_section(const fs::path& run_dir) {
  std::string html;
  const auto deck = run_dir / "case.yaml";
  if (fs::exists(deck)) {
    const std::string deck_text = read_text(deck);
    html += fmt::format("<h2>Input deck</h2>\n<p>case.yaml, sha256 <code>{}</code></p>\n<pre>{}</pre>\n",
                        core::sha256_hex(deck_text), esc(deck_text));
  }

  return html;
}

}  // namespace

std::string report_html(const ReportData& d, const ReportFiles& files, bool have_gnuplot, const fs::path& run_dir) {
  const Figures figure{files};
  std::string html = core::html_page_head("rheosim report");
  html += header_section(d, files, have_gnuplot);
  html += torque_section(figure);
  html += flow_curve_section(d, figure);
  html += fits_section(d, figure);
  html += yield_stress_section(d, figure);
  html += relative_viscosity_section(d, figure);
  html += normal_stress_section(d, figure);
  html += speed_section(d);
  html += files_section();
  html += deck_section(run_dir);
  return html + core::html_page_tail();
}

}  // namespace rheosim::rheometer::report_detail
