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
  const SweepSummary& summary = d.summary;
  const auto& points = summary.points;
  std::string html;
  html += fmt::format("<h1>rheosim report: {}</h1>\n", esc(summary.head.case_name));
  const std::size_t failed = summary.points_failed;
  int converged = 0;
  for (const auto& p : points) converged += p.converged ? 1 : 0;
  html += "<table>\n";
  const auto row = [&](const std::string& key, const std::string& value) {
    html += fmt::format("<tr><th class=l>{}</th><td class=l>{}</td></tr>\n", key, value);
  };
  row("kind", esc(summary.head.kind));
  row("plates", fmt::format("radius R = {} m, gap H = {} m", g4(summary.radius), g4(summary.gap)));
  if (summary.grid)
    row("fluid grid",
        fmt::format("N_r = {}, N_z = {}, radial grading {}, axial stretching {}; inertia {}",
                    summary.grid->radial_cells, summary.grid->axial_cells, g4(summary.grid->radial_grading),
                    g4(summary.grid->axial_stretching), summary.inertia ? "on" : "off (creeping limit)"));
  row("points", fmt::format("{} finished, {} failed{}", converged, failed,
                            summary.points_resumed ? fmt::format(" ({} read back from an earlier, interrupted run)",
                                                                 *summary.points_resumed)
                                                   : std::string()));
  row("wall time", fmt::format("{} s", g4(summary.wall_time)));
  row("rheosim", fmt::format("{} (git {})", esc(summary.head.rheosim_version), esc(summary.head.git_revision)));
  row("input sha256", fmt::format("<code>{}</code>", esc(summary.head.input_sha256)));
  html += "</table>\n";

  if (!summary.warnings.empty()) {
    html += "<div class=note><b>Rules the run bent</b> (also in summary.json <code>warnings</code> and the log):<ul>\n";
    for (const auto& w : summary.warnings)
      html += fmt::format("<li>{} <span class=small>({} point(s))</span></li>\n", esc(w.warning), w.points);
    html += "</ul></div>\n";
  }
  if (failed > 0) {
    html += fmt::format(
        "<div class=fail><b>{} point(s) have no result.</b> They are listed here and left out of every "
        "fit, plot and table below; no number was invented for them.<table>\n<tr><th>fluid</th><th>φ</th>"
        "<th>γ̇_R [1/s]</th><th class=l>reason</th></tr>\n",
        failed);
    for (const auto& p : points)
      if (!p.converged)
        html += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td class=l>{}</td></tr>\n", esc(p.fluid),
                            g4(p.volume_fraction), g4(p.shear_rate), esc(p.failure));
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
  const auto& points = d.summary.points;
  html +=
      "<h2>Flow curves</h2>\n<p class=small>Apparent rim stress τ_app = 2T/(πR³) (the Newtonian value) and the "
      "plate-corrected rim stress τ_R = T/(2πR³)(3 + n′), n′ = d ln T/d ln γ̇_R from a local weighted quadratic in "
      "ln γ̇_R (not a two-point difference). Validity: gap Reynolds ρΩH²/η ≤ 1, particle Reynolds ρ_f γ̇ d²/η_f ≤ "
      "0.1, Stokes ρ_p γ̇ d²/η_f ≤ 0.1, H/d ≥ 10 (particle checks only for φ &gt; 0).</p>\n";
  html += figure("stress",
                 "Rim shear stress, log–log; line: the best model of each flow curve by AICc "
                 "(<a href=\"fit_curves.csv\">fit_curves.csv</a>).");
  html += figure("viscosity", "Viscosity τ/γ̇ at the rim, log–log, with the best fit.");
  for (const auto& s : d.summary.series) {
    const std::string& label = s.label;
    html += fmt::format("<h3>{}</h3>\n", esc(label));
    for (const auto& w : s.warnings) html += fmt::format("<p class=warn>⚠ {}</p>\n", esc(w));
    if (s.points == 0) continue;
    html +=
        "<table>\n<tr><th>γ̇_R [1/s]</th><th>T [N m]</th><th>n′</th><th>τ_app [Pa]</th><th>τ_R [Pa]</th>"
        "<th>η = τ_R/γ̇_R [Pa s]</th><th>Re_gap</th><th>Re_p</th><th>St</th><th>H/d</th><th class=l>valid</th></tr>\n";
    for (const auto& p : points) {
      if (d.label_of(p) != label || !p.converged) continue;
      const PointChecks& v = checks_of(p);
      std::string valid = "–";
      if (p.validity) {
        valid = v.valid ? "<span class=ok>✓</span>" : "<span class=bad>✗</span>";
        if (p.used_in_fits && !*p.used_in_fits) valid += " not fitted";
        for (const auto& m : v.messages) valid += "<br><span class=warn>" + esc(m) + "</span>";
      }
      const double se = or_nan(p.torque_std_error);
      html += fmt::format(
          "<tr><td>{}</td><td>{}{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
          "<td>{}</td><td>{}</td><td class=l>{}</td></tr>\n",
          g4(p.shear_rate), g4(p.torque), std::isfinite(se) ? " ± " + g4(se) : "", g4(p.log_slope),
          g4(p.apparent_stress), g4(p.rim_stress), g4(p.viscosity), g4(v.gap_reynolds), g4(v.particle_reynolds),
          g4(v.stokes), g4(v.gap_to_diameter), valid);
    }
    html += "</table>\n";
  }

  return html;
}

// Every model fitted to every flow curve, ranked, with its parameter correlations.
std::string fits_section(const ReportData& d, const Figures& figure) {
  std::string html;
  html +=
      "<h2>Model fits</h2>\n<p class=small>Each model fitted to (γ̇_R, τ_R) by weighted least squares on relative "
      "residuals (τ_model − τ_R)/τ_R. Parameters: value ± standard error [95 % interval, Student t with n − p degrees "
      "of freedom]. s: relative residual scatter. Ranked by AICc (Δ: difference to the best; w: Akaike weight); "
      "only differences between fits of the same curve mean anything. All numbers: <a href=\"fits.csv\">fits.csv</a>, "
      "summary.json <code>fits</code>.</p>\n";
  for (const auto& s : d.summary.series) {
    const std::string& label = s.label;
    std::vector<const FitRecord*> ranked;
    for (const auto& f : d.summary.fits)
      if (f.label == label) ranked.push_back(&f);
    if (ranked.empty()) continue;
    std::sort(ranked.begin(), ranked.end(), [](const FitRecord* a, const FitRecord* b) { return a->rank < b->rank; });
    html += fmt::format(
        "<h3>{}</h3>\n<table>\n<tr><th>rank</th><th class=l>model</th><th class=l>parameters</th>"
        "<th>s</th><th>n − p</th><th>AICc</th><th>Δ</th><th>w</th><th class=l>warnings</th></tr>\n",
        esc(label));
    std::string correlations;
    for (const FitRecord* fp : ranked) {
      const FitRecord& f = *fp;
      std::string params;
      for (const auto& p : f.parameters) {
        const std::string unit = p.unit == "-" ? std::string() : fmt::format(" {}", esc(p.unit));
        params += fmt::format("{}{} = {} ± {}{}, 95 %: [{}, {}]", params.empty() ? "" : "<br>", esc(p.symbol),
                              g4(p.value), g4(p.std_error), unit, g4(p.ci95.lower), g4(p.ci95.upper));
      }
      // The first warning in full, the rest folded: a model that cannot be identified from the
      // data says so once, not in a wall of text.
      std::string warnings, more;
      int count = 0;
      for (const auto& w : f.warnings) {
        const std::string message = esc(w.message);
        if (count == 0)
          warnings = message;
        else
          more += (count > 1 ? "<br>" : "") + message;
        ++count;
      }
      if (count > 1) warnings += fmt::format("<details><summary>{} more</summary>{}</details>", count - 1, more);
      if (!f.converged) warnings = "<span class=bad>not converged</span> " + warnings;
      html += fmt::format(
          "<tr><td>{}</td><td class=l>{}<br><span class=small>{}</span></td><td class=p>{}</td><td>{}</td>"
          "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=l><span class=warn>{}</span></td></tr>\n",
          f.rank, esc(f.model), esc(f.equation), params, g4(f.residual_std), f.degrees_of_freedom, g4(f.aicc),
          g4(f.delta), g4(f.akaike_weight), warnings);
      const auto& corr = f.correlation;
      if (corr.size() > 1) {
        correlations += fmt::format("<table><tr><th class=l>{}</th>", esc(f.model));
        for (const auto& p : f.parameters) correlations += "<th>" + esc(p.symbol) + "</th>";
        correlations += "</tr>\n";
        for (std::size_t r = 0; r < corr.size(); ++r) {
          correlations += "<tr><th>" + (r < f.parameters.size() ? esc(f.parameters[r].symbol) : "") + "</th>";
          for (const auto& c : corr[r]) correlations += "<td>" + (c ? fmt::format("{:.3f}", *c) : "–") + "</td>";
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
  const auto& yields = d.summary.yield_stress;
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
      html += fmt::format(
          "<tr><td class=l>{}</td><td>{}</td><td class=l>{}</td><td>{}</td><td>{}</td><td>[{}, {}]</td>"
          "<td class=l>{}</td><td>{}</td></tr>\n",
          esc(y.label), g4(y.volume_fraction), esc(y.method), g4(y.value), g4(y.std_error), g4(y.ci95.lower),
          g4(y.ci95.upper), y.significant ? "yes" : "no (interval includes 0)", g4(y.akaike_weight));
    }
    html += "</table>\n";
  }
  html += figure("yield_stress", "Yield stress vs φ by method with 95 % intervals.");

  return html;
}

// η_r(φ) per liquid against the correlations.
std::string relative_viscosity_section(const ReportData& d, const Figures& figure) {
  std::string html;
  const auto& points = d.summary.points;
  html += "<h2>Relative viscosity</h2>\n";
  const bool any_suspension = std::any_of(
      points.begin(), points.end(), [](const SweepPointRecord& p) { return p.converged && p.volume_fraction > 0; });
  if (!any_suspension)
    html +=
        "<p class=note>No finished point with φ &gt; 0, so there is no measured η_r(φ): the plot shows the "
        "correlations with φ_m = 0.63 (nothing fitted) and η_r(0) = 1 of each liquid. Per liquid: "
        "<a href=\"relative_viscosity.csv\">relative_viscosity.csv</a>, summary.json "
        "<code>relative_viscosity</code>.</p>\n";
  for (const auto& rv : d.summary.relative_viscosity) {
    if (!any_suspension) break;
    html += fmt::format(
        "<p class=small>η_r = η(φ)/η_f at the reference rim shear rate {} 1/s (the largest every φ "
        "reached), each η from that flow curve's best fit, η_f = {} Pa s from {}. Error bars: first-order "
        "propagation of the fits' standard errors. <a href=\"relative_viscosity.csv\">"
        "relative_viscosity.csv</a>.</p>\n",
        g4(rv.reference_shear_rate), g4(rv.liquid_viscosity), esc(rv.liquid_viscosity_source));
    for (const auto& w : rv.warnings) html += fmt::format("<p class=warn>⚠ {}</p>\n", esc(w));
    html += "<table>\n<tr><th>φ</th><th>η_r</th><th>± se</th><th class=l>fit used</th>";
    const auto& correlations = rv.correlations;
    for (const auto& c : correlations) html += "<th>" + esc(c.name) + "</th>";
    html += "</tr>\n";
    const auto& rvp = rv.points;
    for (std::size_t i = 0; i < rvp.size(); ++i) {
      html += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td class=l>{}</td>", g4(rvp[i].volume_fraction),
                          g4(rvp[i].relative_viscosity), g4(rvp[i].std_error), esc(rvp[i].model));
      for (const auto& c : correlations)
        html += "<td>" + (i < c.predicted.size() ? g4(c.predicted[i]) : std::string("–")) + "</td>";
      html += "</tr>\n";
    }
    html += "</table>\n";
    if (!correlations.empty()) {
      html +=
          "<table>\n<tr><th class=l>correlation</th><th>φ_m</th><th>95 % interval</th><th>Σ residual²</th><th>AIC</th>"
          "<th class=l>warnings</th></tr>\n";
      for (const auto& c : correlations) {
        std::string warnings;
        for (const auto& w : c.warnings) warnings += (warnings.empty() ? "" : "<br>") + esc(w);
        html += fmt::format(
            "<tr><td class=l>{}</td><td>{}</td><td>[{}, {}]</td><td>{}</td><td>{}</td><td class=l>"
            "<span class=warn>{}</span></td></tr>\n",
            esc(c.name), g4(c.max_packing), g4(c.max_packing_ci95.lower), g4(c.max_packing_ci95.upper),
            g4(c.sum_of_squares), g4(c.aic), warnings);
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
  if (d.any_normal_force) {
    html +=
        "<h2>Normal stresses</h2>\n<p class=small>The plates' normal force F (positive: pushing them apart), "
        "N1 − N2 at the rim from it by the parallel-plate relation N1 − N2 = (F/πR²)(2 + d ln F/d ln γ̇_R), and "
        "the model's local first and second normal stress differences at the rim rate. Measured non-Brownian "
        "suspensions: N2/τ ≈ −4.4φ³, N1/τ ≈ −0.8φ³ (Dai, Bertevas, Qi &amp; Tanner 2013). "
        "<a href=\"normal_stress.csv\">normal_stress.csv</a>.</p>\n<table>\n<tr><th class=l>flow curve</th>"
        "<th>γ̇_R [1/s]</th><th>F [N]</th><th>N1 − N2 [Pa]</th><th>N1 [Pa]</th><th>N2 [Pa]</th><th>N1/τ_R</th>"
        "<th>N2/τ_R</th></tr>\n";
    for (const auto& p : d.summary.points) {
      if (!p.converged || !p.normal_force) continue;
      const double tau = or_nan(p.rim_stress);
      html += fmt::format(
          "<tr><td class=l>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
          "<td>{}</td></tr>\n",
          esc(d.label_of(p)), g4(p.shear_rate), g4(p.normal_force), g4(p.n1_minus_n2), g4(p.n1), g4(p.n2),
          g4(or_nan(p.n1) / tau), g4(or_nan(p.n2) / tau));
    }
    html += "</table>\n";
    html += figure("normal_stress", "N1 − N2 from the normal force, and the model's N1 and N2, per flow curve.");
  }

  return html;
}

// Speed and error of every point.
std::string speed_section(const ReportData& d) {
  std::string html;
  html +=
      "<h2>Speed and error of the run</h2>\n<p class=small>Per point: how it was computed, wall time, iterations, "
      "and the error against the creeping-flow closed form where one exists. With inertia on, the difference "
      "includes the physical torque rise from secondary flow (see Re_gap); the creeping column isolates the "
      "discretisation error. <a href=\"speed_error.csv\">speed_error.csv</a>.</p>\n<table>\n<tr><th class=l>flow "
      "curve</th><th>γ̇_R [1/s]</th><th class=l>method</th><th>wall time [s]</th><th>iterations</th><th>T [N m]</th>"
      "<th>closed form [N m]</th><th>error</th><th>error, creeping solve</th><th>Re_gap</th></tr>\n";
  double total_wall = 0;
  for (const auto& p : d.summary.points) {
    if (!p.converged) continue;
    total_wall += or_nan(p.wall_time);
    const auto pct = [](double x) { return std::isfinite(x) ? fmt::format("{:.3g} %", 100 * x) : std::string("–"); };
    html += fmt::format(
        "<tr><td class=l>{}</td><td>{}</td><td class=l>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
        "<td>{}</td><td>{}</td><td>{}</td></tr>\n",
        esc(d.label_of(p)), g4(p.shear_rate), esc(p.method), g4(p.wall_time), or_nan(p.iterations), g4(p.torque),
        g4(p.torque_analytic), pct(or_nan(p.rel_error)), pct(or_nan(p.creeping_rel_error)), g4(p.gap_reynolds_number));
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
