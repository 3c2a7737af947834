#pragma once
// What every report.html shares: the page head with its inline style (a report opens in a
// browser with no network), a figure with its caption and links, and the gnuplot runs that
// draw the figures from scripts kept beside them.
#include <filesystem>
#include <string>
#include <string_view>

namespace rheosim::core {

// <run_dir>/summary.json, or a ConfigError saying the folder is not that of a finished run.
[[nodiscard]] std::filesystem::path run_summary_file(const std::filesystem::path& run_dir);
// A ConfigError at `summary`'s key `kind`: the summary is of a kind this report does not draw.
[[noreturn]] void refuse_summary_kind(const std::filesystem::path& summary, std::string_view kind,
                                      std::string_view expected, std::string_view hint);

// "<!DOCTYPE html> … <body>" with the shared style sheet; title is escaped.
[[nodiscard]] std::string html_page_head(std::string_view title);
// Closes what html_page_head opened.
[[nodiscard]] std::string html_page_tail();
// NAME.png with its caption (HTML, not escaped) and links to NAME.svg and NAME.gp.
[[nodiscard]] std::string html_figure(std::string_view name, std::string_view caption);

// The head of a gnuplot script NAME.gp that reads the comma-separated files beside it ("nan"
// for a missing value); `what` is its first comment line.
[[nodiscard]] std::string gnuplot_header(std::string_view name, std::string_view what);
// `body` drawn twice, to NAME.png and to NAME.svg.
[[nodiscard]] std::string gnuplot_outputs(std::string_view name, std::string_view body, int width = 1000,
                                          int height = 600);
// Whether the gnuplot command is on the PATH.
[[nodiscard]] bool gnuplot_installed();
// Runs `gnuplot NAME.gp` in dir (its output in NAME.gnuplot.log) when gnuplot is installed,
// after removing a stale NAME.png. True when NAME.png exists afterwards.
bool plot_with_gnuplot(const std::filesystem::path& dir, std::string_view name);

}  // namespace rheosim::core
