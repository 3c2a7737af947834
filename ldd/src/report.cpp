#include "rheosim/ldd/report.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/report_page.hpp"
#include "rheosim/core/run_summary.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

constexpr std::string_view summary_hint = "pass the --out folder of a finished 'rheosim run' of a kind: ldd case";

[[noreturn]] void missing(const fs::path& file, std::string_view key, std::string_view expected) {
  core::refuse_summary_value(file, key, expected, summary_hint);
}

std::string esc(std::string_view s) { return core::escape_markup(s); }

std::string figure_or_note(const ReportFiles& files, const std::string& name, const std::string& caption) {
  if (std::find(files.plots.begin(), files.plots.end(), name) != files.plots.end())
    return core::html_figure(name, caption);
  return fmt::format(
      "<p class=warn>{}.png was not drawn (gnuplot missing or failed; see {}.gnuplot.log). "
      "Run <code>gnuplot {}.gp</code> in this folder.</p>\n",
      name, name, name);
}

// 1-based gnuplot column of the probe file's column `name`, 0 when it has none.
int column_of(const core::CsvTable& table, std::string_view name) {
  const auto& columns = table.numeric_columns();
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i].name == name) return static_cast<int>(i) + 1;
  return 0;
}

}  // namespace

namespace {

// What the run folder holds beside summary.json, which decides the figures and tables.
struct RunFolder {
  fs::path dir;
  bool table1 = false;        // LDD §4.3's dam break: table1.csv
  bool martin_moyce = false;  // a water column: martin_moyce.csv
  bool profile = false;       // a dam break's final free surface: profile.csv
  bool wall_height = false;   // a sloshing column's probe file has the height at the left wall
  bool yield_test = false;    // a yield-stress law's probe file has the largest stress over τ₀
};

// The free-surface run's gnuplot scripts and plots: the scene's probe, energy, volume.
void write_free_surface_plots(const RunSummary& s, RunFolder& run, ReportFiles& files) {
  const auto plot = [&](const std::string& name, const std::string& what, const std::string& body) {
    core::write_atomically(run.dir / (name + ".gp"), [&](std::ostream& os) {
      os << core::gnuplot_header(name, what) << core::gnuplot_outputs(name, body);
    });
    (core::plot_with_gnuplot(run.dir, name) ? files.plots : files.missing_plots).push_back(name);
  };
  const std::string energy_unit = s.dimension == 2 ? "J/m" : "J";
  const std::string probes = probe_file_name(s.scene);
  const core::CsvTable table = core::read_csv(run.dir / probes);
  const auto col = [&](std::string_view name) {
    const int c = column_of(table, name);
    if (c == 0) missing(run.dir / probes, name, "a column of the probe file");
    return c;
  };
  if (s.scene == "dam_break") {
    std::string curves = fmt::format("'{}' using 1:{} with lines lw 2 title 'LDD (this run)'", probes, col("front"));
    if (run.table1)
      curves +=
          ", 'table1.csv' using 1:2 with points pt 7 ps 1.4 title 'experiment (LDD Table 1)', "
          "'table1.csv' using 1:5 with points pt 6 ps 1.4 title 'seed LDD (same Δ, δt)'";
    if (run.martin_moyce)
      curves += ", 'martin_moyce.csv' using 1:2 with points pt 7 ps 1.4 title 'experiment (Martin and Moyce 1952)'";
    if (s.thin_film_arrest)
      curves += fmt::format(", {:.6g} with lines dt 2 lw 2 title 'shallow yield-stress arrest (thin film)'",
                            s.thin_film_arrest->front);
    plot("front", "Mass front position vs time", "set xlabel 't [s]'\nset ylabel 'front x [m]'\nplot " + curves + "\n");
    if (run.profile) {
      const core::CsvTable shape = core::read_csv(run.dir / "profile.csv");
      std::string lines = "'profile.csv' using 1:2 with steps lw 2 title 'LDD (this run, end)'";
      if (const int c = column_of(shape, "thin_film_arrest"); c > 0)
        lines += fmt::format(", 'profile.csv' using 1:{} with lines dt 2 lw 2 title 'shallow yield-stress arrest'", c);
      plot("profile", "Free surface at the end of the run",
           "set xlabel 'x [m] (from the gate)'\nset ylabel 'height [m]'\nplot " + lines + "\n");
    }
  } else if (s.scene == "slump") {
    plot("spread", "Slump spread and height vs time",
         fmt::format("set xlabel 't [s]'\nset ylabel 'length [m]'\nplot '{0}' using 1:{1} with lines lw 2 title "
                     "'spread (diameter)', '{0}' using 1:{2} with lines lw 2 title 'height'\n",
                     probes, col("diameter"), col("height")));
  } else if (column_of(table, "left_wall_height") > 0) {
    run.wall_height = true;
    const std::string theory =
        s.sloshing ? ", 'sloshing.csv' using 1:3 with lines lw 2 dt 2 title 'linear theory (first mode)'" : "";
    plot("wall_height", "Free-surface height at the left wall vs time",
         fmt::format("set xlabel 't [s]'\nset ylabel 'height [m]'\nplot '{}' using 1:{} with lines lw 2 title "
                     "'LDD'{}\n",
                     probes, col("left_wall_height"), theory));
  }
  if (column_of(table, "largest_stress_ratio") > 0) {
    run.yield_test = true;
    plot("yield_test", "Largest stress over the yield stress vs time",
         fmt::format("set xlabel 't [s]'\nset ylabel 'max μ(γ̇)γ̇ / τ₀ [-]'\nset logscale y\nset yrange [0.5:*]\n"
                     "plot '{}' using 1:{} with lines lw 2 title 'largest stress over τ₀', "
                     "1 with lines dt 2 lw 2 title 'yield stress'\n",
                     probes, col("largest_stress_ratio")));
  }
  plot("energy", "Kinetic energy and released potential energy vs time",
       fmt::format("set xlabel 't [s]'\nset ylabel 'energy [{0}]'\nplot '{1}' using 1:{2} with lines lw 2 title "
                   "'kinetic energy', '{1}' using 1:{3} with lines lw 2 title 'potential energy released'\n",
                   energy_unit, probes, col("kinetic_energy"), col("potential_energy_released")));
  plot("volume", "Relative fluid volume drift vs time",
       fmt::format("set xlabel 't [s]'\nset ylabel 'volume drift [-]'\nplot '{}' using 1:{} with lines lw 2 title "
                   "'(V − V₀)/V₀'\n",
                   probes, col("volume_drift")));
}

// The run at a glance: the head table and the rules the run bent.
std::string header_html(const RunSummary& s) {
  std::string html = fmt::format("<h1>rheosim LDD report: {}</h1>\n", esc(s.head.case_name));
  if (s.status == "diverged")
    html += fmt::format("<div class=fail><b>The run diverged</b>: {}</div>\n", esc(s.message));
  html += "<table>\n";
  const auto row = [&](std::string_view key, const std::string& value) {
    html += fmt::format("<tr><th class=l>{}</th><td class=l>{}</td></tr>\n", key, value);
  };
  row("scene", fmt::format("{} ({}D)", esc(s.scene), s.dimension));
  row("status", esc(s.status));
  row("nodes", fmt::format("{}", s.nodes));
  row("spacing Δ", fmt::format("{:g} m", s.spacing));
  row("time step δt",
      fmt::format("{:g} s{}", s.time_step, s.time_step_rule.empty() ? "" : " (" + esc(s.time_step_rule) + ")"));
  row("steps, simulated time", fmt::format("{}, {:.6g} s", s.steps, s.time));
  row("cost",
      fmt::format("{:.3g} ms per step on {} thread(s), {:.3g} s wall time", s.ms_per_step, s.threads, s.wall_time));
  if (s.free_surface()) {
    row("volume drift (largest)", fmt::format("{:.3g} %", 100 * s.volume_drift));
    row("energy gain", s.energy_gain ? fmt::format("{:.3g} % of the potential energy released", 100 * *s.energy_gain)
                                     : std::string("— (nothing released: a resting column)"));
    row("repeated linear solves", fmt::format("{}", s.repeated_solves));
    if (s.final_spread) {
      // The yield stress a slump formula reads from the run's final shape, when it gives one.
      const auto read_as = [](const MaybeNumber& implied) {
        return implied ? fmt::format(", read as τ₀ = {:.4g} Pa", *implied) : std::string();
      };
      row("final spread, height", fmt::format("{:.4g} m, {:.4g} m", *s.final_spread, *s.final_height));
      row("yielded fraction",
          s.yielded_fraction ? fmt::format("{:.3g}", *s.yielded_fraction) : std::string("— (no yield stress)"));
      row("arrested (yield criterion)",
          std::string(s.arrested ? "yes" : "no") +
              (s.largest_stress_ratio ? fmt::format(": the largest stress {:.4g} τ₀", *s.largest_stress_ratio)
                                      : std::string()));
      if (const auto& p = s.pashias)
        row("cylinder slump (Pashias et al. 1996)",
            fmt::format("τ′ = τ₀/(ρgH) = {:.3g}: s/H {:.3f} at rest ({:.3f} with the von Mises criterion); this run {}",
                        p->yield_stress_ratio, p->slump, p->von_mises_slump,
                        p->measured_slump ? fmt::format("{:.3f} ({:+.3f})", *p->measured_slump, *p->difference)
                                          : std::string("—")) +
                read_as(p->implied_yield_stress));
      if (const auto& r = s.roussel_coussot)
        row("yield-stress pancake (Roussel &amp; Coussot 2005)",
            fmt::format("spread {:.4g} m; this run {}", r->diameter,
                        r->relative_error ? fmt::format("{:+.1f} %", 100 * *r->relative_error) : std::string("—")) +
                read_as(r->implied_yield_stress));
      if (const auto& a = s.thin_film_arrest) {
        row("shallow arrest (thin film)",
            fmt::format("length {:.4g} m from the back wall, front {:.4g} m; this run's runout {}", a->length, a->front,
                        a->relative_error ? fmt::format("{:+.1f} %", 100 * *a->relative_error) : std::string("—")));
        if (a->fitted_yield_stress && a->fitted_length)
          row("final surface read as a shallow arrest",
              fmt::format("yield stress {:.4g} Pa, runout {:.4g} m from the back wall, rms height error {} (a fit "
                          "of h² to the columns two spacings high; meaningful at rest)",
                          *a->fitted_yield_stress, *a->fitted_length,
                          a->fitted_rms_height_error ? fmt::format("{:.3g} m", *a->fitted_rms_height_error)
                                                     : std::string("—")));
      }
    }
  } else {
    row("Reynolds number", fmt::format("{:.4g}", s.reynolds_number));
    row("final steady residual", fmt::format("{:.3g}", s.final_residual));
    if (s.ghia)
      row("centre lines against Ghia et al. (1982)",
          fmt::format("Re = {}: max |error| {:.4f} U over their 34 points (ghia.csv)", s.ghia->reynolds,
                      s.ghia->max_error));
  }
  html += "</table>\n";
  if (!s.warnings.empty()) {
    html += "<div class=note><b>Rules the run bent</b> (also in summary.json <code>warnings</code> and the log):<ul>\n";
    for (const auto& w : s.warnings) html += fmt::format("<li>{}</li>\n", esc(w));
    html += "</ul></div>\n";
  }
  return html;
}

// A dam break's front against its references, with their tables, and its final shape.
std::string dam_break_html(const RunSummary& s, const RunFolder& run, const ReportFiles& files) {
  std::string html = "<h2>Front</h2>\n";
  std::string caption = "Mass front x(t) from the gate of this run (front.csv)";
  if (run.martin_moyce)
    caption +=
        "; points: the water column of Martin &amp; Moyce (1952, n² = 2) at the same a and g "
        "(martin_moyce.csv)";
  if (run.table1)
    caption +=
        "; points: the experiment and the seed's LDD column of LDD Table 1 where the case's Δ and δt have "
        "one (table1.csv)";
  if (s.thin_film_arrest) caption += "; dashed: the shallow yield-stress arrest front (summary thin_film_arrest)";
  html += figure_or_note(files, "front", caption + ".");
  if (run.martin_moyce) {
    const core::CsvTable t = core::read_csv(run.dir / "martin_moyce.csv");
    html +=
        "<table>\n<tr><th>T = t√(2g/a)</th><th>Z = x/a, Martin &amp; Moyce</th><th>Z, this run</th>"
        "<th>difference</th></tr>\n";
    for (std::size_t i = 0; i < t.row_count(); ++i) {
      const auto r = t.row(i);  // time, experiment, front, T, Z_experiment, Z, relative_error
      html += fmt::format("<tr><td>{:.3f}</td><td>{:.3f}</td><td>{}</td><td>{}</td></tr>\n", r[3], r[4],
                          std::isfinite(r[5]) ? fmt::format("{:.3f}", r[5]) : std::string("not reached"),
                          std::isfinite(r[6]) ? fmt::format("{:+.1f} %", 100 * r[6]) : std::string("—"));
    }
    html += "</table>\n";
  }
  if (run.table1) {
    const core::CsvTable t = core::read_csv(run.dir / "table1.csv");
    html +=
        "<table>\n<tr><th>t [s]</th><th>experiment [m]</th><th>this run [m]</th><th>error [m]</th>"
        "<th>seed LDD [m]</th></tr>\n";
    const auto cell = [](double v) { return std::isfinite(v) ? fmt::format("{:.3f}", v) : std::string("—"); };
    for (std::size_t i = 0; i < t.row_count(); ++i) {
      const auto r = t.row(i);
      html += fmt::format("<tr><td>{:.2f}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n", r[0], cell(r[1]),
                          cell(r[2]), cell(r[3]), cell(r[4]));
    }
    html += "</table>\n";
  }
  if (run.profile) {
    html += "<h2>Final shape</h2>\n";
    html += figure_or_note(files, "profile",
                           s.thin_film_arrest ? "Free surface at the end of the run, the top of the fluid nodes per "
                                                "Δ column (profile.csv); dashed: the shallow yield-stress arrest "
                                                "h = √(2τ₀(ℓ − s)/(ρg)) of the same reservoir."
                                              : "Free surface at the end of the run, the top of the fluid nodes "
                                                "per Δ column (profile.csv).");
  }
  return html;
}

// A free surface's figures: the scene's probe, then energy and volume.
std::string free_surface_html(const RunSummary& s, const RunFolder& run, const ReportFiles& files) {
  std::string html;
  if (s.scene == "dam_break") {
    html += dam_break_html(s, run, files);
  } else if (s.scene == "slump") {
    html += "<h2>Spread</h2>\n";
    html += figure_or_note(files, "spread", "Spread (diameter) and height of the slump against time (spread.csv).");
  } else if (run.wall_height) {
    html += "<h2>Free surface at the left wall</h2>\n";
    html += figure_or_note(files, "wall_height",
                           s.sloshing ? "Free-surface height at the left wall (column.csv); dashed: the first "
                                        "sloshing mode in linear theory, H + A cos ωt (sloshing.csv)."
                                      : "Free-surface height at the left wall (column.csv).");
    if (const auto& w = s.sloshing) {
      const auto number = [](const MaybeNumber& v, const char* format) {
        return v ? fmt::format(fmt::runtime(format), *v) : std::string("—");
      };
      html += fmt::format(
          "<table>\n<tr><th>period, linear theory [s]</th><th>period, this run [s]</th><th>difference</th>"
          "<th>zero crossings (up to t [s])</th><th>first crossing [s] (theory)</th></tr>\n"
          "<tr><td>{:.4f}</td><td>{}</td><td>{}</td><td>{} ({:.3g})</td><td>{} ({:.4f})</td></tr>\n</table>\n",
          w->period, number(w->measured_period, "{:.4f}"),
          w->relative_error ? fmt::format("{:+.2f} %", 100 * *w->relative_error) : std::string("—"), w->crossings,
          w->compared_until, number(w->first_crossing, "{:.4f}"), w->period / 4);
    }
  }
  if (run.yield_test) {
    html += "<h2>Yield test</h2>\n";
    html += figure_or_note(files, "yield_test",
                           "The largest stress μ(γ̇)γ̇ among the fluid nodes over τ₀ at each probe "
                           "(largest_stress_ratio in the probe file): the end state is arrested at most 1 + "
                           "time.arrest_stress_tolerance, and time.stop_at_arrest stops once it has stayed there.");
  }
  html += "<h2>Energy and volume</h2>\n";
  html += figure_or_note(files, "energy",
                         "Kinetic energy against the potential energy released: with no energy source the "
                         "first stays below the second (energy_gain in the table).");
  html += figure_or_note(files, "volume", "Relative volume drift of the fluid nodes.");
  return html;
}

// A cavity's centre-line and streamline plots, drawn by the run.
std::string cavity_html(const RunFolder& run) {
  std::string html = "<h2>Centre lines and streamlines</h2>\n";
  for (const char* name : {"centerlines", "streamlines"})
    html += fs::exists(run.dir / (std::string(name) + ".png"))
                ? fmt::format(
                      "<figure><img src=\"{0}.png\" alt=\"{0}\"><figcaption>{0}.png, drawn by the run "
                      "({0}.gp)</figcaption></figure>\n",
                      name)
                : fmt::format("<p class=warn>{0}.png was not drawn; run <code>gnuplot {0}.gp</code> here.</p>\n", name);
  return html;
}

}  // namespace

ReportFiles write_report(const fs::path& run_dir) {
  const RunSummary s = read_run_summary(core::run_summary_file(run_dir));
  ReportFiles files;
  RunFolder run{run_dir};
  run.table1 = s.scene == "dam_break" && fs::exists(run_dir / "table1.csv");
  run.martin_moyce = s.scene == "dam_break" && fs::exists(run_dir / "martin_moyce.csv");
  run.profile = s.scene == "dam_break" && fs::exists(run_dir / "profile.csv");
  if (s.free_surface()) write_free_surface_plots(s, run, files);

  std::string html = core::html_page_head("rheosim LDD report");
  html += header_html(s);
  html += s.free_surface() ? free_surface_html(s, run, files) : cavity_html(run);
  html +=
      "<p class=small>Every number above is in summary.json or the CSV files of this folder; the node "
      "clouds are in frames/ (nodes.pvd for ParaView).</p>\n";
  html += core::html_page_tail();
  files.html = run_dir / "report.html";
  core::write_atomically(files.html, [&](std::ostream& os) { os << html; });
  return files;
}

}  // namespace rheosim::ldd
