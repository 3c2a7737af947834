#include "rheosim/core/report_page.hpp"

#include <cstdlib>
#include <utility>

#include <fmt/format.h>

#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"

namespace rheosim::core {

std::filesystem::path run_summary_file(const std::filesystem::path& run_dir) {
  const std::filesystem::path summary = run_dir / "summary.json";
  if (std::filesystem::exists(summary)) return summary;
  ConfigError::Details d;
  d.where = FileLocation{run_dir.string(), 0, 0};
  d.problem = "no summary.json in this folder";
  d.expected = "a folder written by 'rheosim run'";
  d.hint = "pass the --out folder of a finished run";
  throw ConfigError(d);
}

void refuse_summary_kind(const std::filesystem::path& summary, std::string_view kind, std::string_view expected,
                         std::string_view hint) {
  ConfigError::Details d;
  d.where = FileLocation{summary.string(), 0, 0};
  d.key_path = "kind";
  d.problem = fmt::format("summary.json is of a kind '{}' run", kind);
  d.expected = std::string(expected);
  d.hint = std::string(hint);
  throw ConfigError(d);
}

std::string html_page_head(std::string_view title) {
  std::string head = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>";
  head += escape_markup(title);
  head += R"(</title>
<style>
body{font-family:'DejaVu Sans',sans-serif;max-width:80em;margin:1.5em auto;padding:0 1em;color:#222;line-height:1.35}
h1{font-size:1.6em}h2{border-bottom:2px solid #ccd;padding-bottom:.15em;margin-top:1.6em}h3{margin-bottom:.3em}
table{border-collapse:collapse;margin:.6em 0;font-size:.9em}td,th{border:1px solid #bbb;padding:.2em .5em;text-align:right;vertical-align:top}
th{background:#eef}td.l,th.l{text-align:left}pre{background:#f6f6f6;padding:1em;overflow-x:auto;font-size:.85em}
img{max-width:100%;border:1px solid #ddd}.warn{color:#a40;font-size:.85em}.bad{color:#b00;font-weight:bold}.ok{color:#070}
.note{background:#fff6e0;border-left:4px solid #e0a000;padding:.5em 1em;margin:.8em 0}
.fail{background:#fde8e8;border-left:4px solid #c00;padding:.5em 1em;margin:.8em 0}
td.p{white-space:nowrap;text-align:left}figure{margin:1em 0}figcaption{font-size:.85em;color:#444}.small{font-size:.85em;color:#555}
)";
  head += "</style></head><body>\n";
  return head;
}

std::string html_page_tail() { return "</body></html>\n"; }

std::string html_figure(std::string_view name, std::string_view caption) {
  return fmt::format(
      "<figure><img src=\"{0}.png\" alt=\"{0} plot\"><figcaption>{1} "
      "<span class=small>[<a href=\"{0}.svg\">SVG</a> · <a href=\"{0}.gp\">gnuplot script</a>]</span>"
      "</figcaption></figure>\n",
      name, caption);
}

std::string gnuplot_header(std::string_view name, std::string_view what) {
  return fmt::format(
      "# {}\n# Data: the CSV files beside this script (written by rheosim).\n"
      "# Regenerate: gnuplot {}.gp\nset datafile separator ','\nset datafile missing 'nan'\nset grid\n"
      "set key outside right top\nset encoding utf8\n",
      what, name);
}

std::string gnuplot_outputs(std::string_view name, std::string_view body, int width, int height) {
  std::string s;
  for (const auto& [terminal, extension] : {std::pair{"pngcairo", "png"}, std::pair{"svg", "svg"}})
    s += fmt::format("set terminal {} size {},{}{} font 'DejaVu Sans,10'\nset output '{}.{}'\n{}", terminal, width,
                     height, std::string_view(extension) == "svg" ? " dynamic" : "", name, extension, body);
  return s + "unset output\n";
}

bool gnuplot_installed() { return std::system("command -v gnuplot > /dev/null 2>&1") == 0; }

bool plot_with_gnuplot(const std::filesystem::path& dir, std::string_view name) {
  const std::filesystem::path png = dir / (std::string(name) + ".png");
  std::filesystem::remove(png);
  if (gnuplot_installed()) {
    const std::string command = fmt::format("cd '{}' && gnuplot {}.gp > {}.gnuplot.log 2>&1", dir.string(), name, name);
    const int status = std::system(command.c_str());  // a failure shows as a missing PNG
    (void)status;
  }
  return std::filesystem::exists(png);
}

}  // namespace rheosim::core
