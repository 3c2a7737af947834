#include "run_ldd.hpp"

#include <exception>

#include "commands.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/version.hpp"
#include "rheosim/ldd/report.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::app {

int run_ldd(const ldd::Case& c, const std::filesystem::path& out_dir, double stop_after, const core::Log& log) {
  try {
    const auto log_file = log.with_file(out_dir / "log.txt");
    log_file.info("rheosim {} (git {}): running {} into {}", core::version, core::git_revision, c.file,
                  out_dir.string());
    ldd::RunControl control;
    control.wall_time_limit = stop_after;
    const auto outcome = ldd::run_case(c, out_dir, log_file, control);
    if (!outcome.summary.empty()) {
      try {  // a report that cannot be drawn does not fail the run
        const auto files = ldd::write_report(out_dir);
        log_file.info("report: {}", files.html.string());
        if (!files.missing_plots.empty())
          log_file.warn("{} plot(s) not drawn (gnuplot missing or failed); their .gp scripts are in {}",
                        files.missing_plots.size(), out_dir.string());
      } catch (const std::exception& e) {
        log_file.warn("report not written: {}", e.what());
      }
    }
    return outcome.status == "diverged" ? exit_run_failure : exit_success;
  } catch (const core::ConfigError& e) {
    log.error("{}", e.what());
    return exit_bad_input;
  } catch (const std::exception& e) {
    log.error("run failed: {}", e.what());
    return exit_run_failure;
  }
}

}  // namespace rheosim::app
