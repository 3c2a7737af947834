// report.html, its data CSVs and gnuplot plots (rheometer/report.hpp, docs/report.md): the data
// read from summary.json (report_data.cpp), the CSV files, the plots (report_plots.cpp) and the
// HTML (report_html.cpp).
#include "rheosim/rheometer/report.hpp"

#include "report_parts.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/report_page.hpp"

namespace rheosim::rheometer {

ReportFiles write_report(const std::filesystem::path& run_dir) {
  using namespace report_detail;
  const ReportData data = read_report_data(run_dir);
  write_data_tables(data, run_dir);
  ReportFiles files;
  const bool have_gnuplot = core::gnuplot_installed();
  for (const auto& [name, script] : plot_scripts(data)) {
    core::write_atomically(run_dir / (name + ".gp"), [&](std::ostream& os) { os << script; });
    (core::plot_with_gnuplot(run_dir, name) ? files.plots : files.missing_plots).push_back(name);
  }
  const std::string html = report_html(data, files, have_gnuplot, run_dir);
  files.html = run_dir / "report.html";
  core::write_atomically(files.html, [&](std::ostream& os) { os << html; });
  return files;
}

}  // namespace rheosim::rheometer
