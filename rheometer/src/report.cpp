#include "rheosim/rheometer/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include "rheosim/core/case.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"

namespace rheosim::rheometer {

namespace {


std::string cell(const nlohmann::json& value) {
  if (value.is_number_float()) return fmt::format("{:.6g}", value.get<double>());
  if (value.is_string()) return core::escape_markup(value.get<std::string>());
  return core::escape_markup(value.dump());
}

// A table of an array of flat objects (e.g. summary.json's points), columns in first-seen order.
std::string table(const nlohmann::json& rows) {
  std::vector<std::string> columns;
  for (const auto& row : rows)
    if (row.is_object())
      for (const auto& [key, value] : row.items())
        if (std::find(columns.begin(), columns.end(), key) == columns.end()) columns.push_back(key);
  std::string out = "<table>\n<tr>";
  for (const auto& c : columns) out += "<th>" + core::escape_markup(c) + "</th>";
  out += "</tr>\n";
  for (const auto& row : rows) {
    out += "<tr>";
    for (const auto& c : columns) out += "<td>" + (row.contains(c) ? cell(row.at(c)) : std::string()) + "</td>";
    out += "</tr>\n";
  }
  return out + "</table>\n";
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace

std::filesystem::path write_report(const std::filesystem::path& run_dir) {
  const auto summary_path = run_dir / "summary.json";
  if (!std::filesystem::exists(summary_path))
    throw core::ConfigError({core::FileLocation{run_dir.string(), 0, 0}, "", "no summary.json in this folder",
                             "a folder written by 'rheosim run'", "pass the --out folder of a finished run"});
  const nlohmann::json summary = core::read_json(summary_path);

  std::string html = R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>rheosim report</title>
<style>
body{font-family:sans-serif;max-width:72em;margin:2em auto;color:#222}
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:.25em .6em;text-align:right}
th{background:#eee}pre{background:#f6f6f6;padding:1em;overflow-x:auto}img{max-width:100%}
</style></head><body>
)";
  html += fmt::format("<h1>rheosim report: {}</h1>\n", core::escape_markup(summary.value("case", std::string("run"))));
  html += "<h2>Run</h2>\n<table>\n";
  for (const auto& [key, value] : summary.items())
    if (!value.is_array() && !value.is_object())
      html += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", core::escape_markup(key), cell(value));
  html += "</table>\n";
  for (const auto& [key, value] : summary.items())
    if (value.is_array() && !value.empty() && value.front().is_object())
      html += fmt::format("<h2>{}</h2>\n{}", core::escape_markup(key), table(value));

  // Plots written by the run, in name order.
  std::set<std::filesystem::path> plots;
  for (const auto& entry : std::filesystem::directory_iterator(run_dir)) {
    const auto ext = entry.path().extension();
    if (ext == ".png" || ext == ".svg") plots.insert(entry.path().filename());
  }
  if (!plots.empty()) html += "<h2>Plots</h2>\n";
  for (const auto& p : plots) html += fmt::format("<p><img src=\"{}\" alt=\"{}\"></p>\n", p.string(), p.string());

  const auto deck = run_dir / "case.yaml";
  if (std::filesystem::exists(deck)) {
    const std::string text = read_text(deck);
    html += fmt::format("<h2>Input deck</h2>\n<p>sha256 {}</p>\n<pre>{}</pre>\n", core::sha256_hex(text),
                        core::escape_markup(text));
  }
  html += "</body></html>\n";

  const auto out = run_dir / "report.html";
  core::write_atomically(out, [&](std::ostream& os) { os << html; });
  return out;
}

}  // namespace rheosim::rheometer
