#include "commands.hpp"

#include <fmt/format.h>

#include <iostream>

#include "rheosim/core/case.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/version.hpp"
#include "rheosim/rheometer/openfoam.hpp"
#include "rheosim/rheometer/report.hpp"
#include "rheosim/rheometer/run.hpp"

namespace rheosim::app {

namespace {

// Prints a user error in one block: "error: file:line:col: key: problem" + expected + hint.
int bad_input(const core::Log& log, const std::exception& e) {
  log.error("{}", e.what());
  return exit_bad_input;
}

}  // namespace

int validate(const std::vector<std::string>& case_files, const core::Log& log) {
  int status = exit_success;
  for (const auto& file : case_files) {
    try {
      const core::Case c = core::load_case(file);
      std::cout << fmt::format("{}: valid {} case\n{}", file, c.kind(), core::describe(c));
    } catch (const core::ConfigError& e) {
      status = bad_input(log, e);
    }
  }
  return status;
}

int run(const std::string& case_file, const std::filesystem::path& out_dir, const core::Log& log) {
  core::Case c;
  try {
    c = core::load_case(case_file);
  } catch (const core::ConfigError& e) {
    return bad_input(log, e);
  }
  const std::filesystem::path out = out_dir.empty() ? std::filesystem::path("results") / c.name : out_dir;
  const auto* rheometer_case = std::get_if<core::RheometerCase>(&c.spec);
  if (!rheometer_case || rheometer_case->particles) {
    // Not built yet: say so plainly instead of writing anything that looks like a result.
    const std::string what = c.kind() == "ldd" ? "the LDD solver" : c.kind() == "sweep" ? "sweeps" : "CFD-DEM suspensions";
    log.error("'{}' is a valid {} case, but {} are not built yet in rheosim {}; nothing was run and nothing was "
              "written to {}",
              case_file, c.kind(), what, core::version, out.string());
    return exit_run_failure;
  }
  try {
    const auto log_file = log.with_file(out / "log.txt");
    log_file.info("rheosim {} (git {}): running {} into {}", core::version, core::git_revision, case_file, out.string());
    const auto outcome = rheometer::run_single_phase(c, out, log_file);
    log_file.info("{} points, {} failed; summary: {}; report: {}", outcome.points, outcome.failed_points,
                  outcome.summary.string(), (out / "report.html").string());
    return outcome.failed_points == 0 ? exit_success : exit_run_failure;
  } catch (const std::exception& e) {
    log.error("run failed: {}", e.what());
    return exit_run_failure;
  }
}

int export_openfoam(const std::string& case_file, const std::filesystem::path& dir, double rim_shear_rate,
                    const std::string& mesh, const core::Log& log) {
  try {
    const core::Case c = core::load_case(case_file);
    if (rim_shear_rate <= 0)
      if (const auto* r = std::get_if<core::RheometerCase>(&c.spec)) rim_shear_rate = r->shear_rates.back();
    rheometer::OpenFoamExportOptions options;
    options.mesh = rheometer::OpenFoamMesh::preset(mesh);
    const auto exported = rheometer::export_openfoam(c, rim_shear_rate, dir, options);
    log.info("OpenFOAM case written to {} ({} cells, {}); run it with:\n{}", dir.string(), exported.cells,
             exported.transport.model, exported.commands);
    if (!exported.transport.note.empty()) log.warn("{}", exported.transport.note);
    return exit_success;
  } catch (const core::ConfigError& e) {
    return bad_input(log, e);
  } catch (const std::exception& e) {
    log.error("export failed: {}", e.what());
    return exit_run_failure;
  }
}

int report(const std::filesystem::path& run_dir, const core::Log& log) {
  try {
    const auto html = rheometer::write_report(run_dir);
    log.info("report written to {}", html.string());
    return exit_success;
  } catch (const core::ConfigError& e) {
    return bad_input(log, e);
  } catch (const std::exception& e) {
    log.error("report failed: {}", e.what());
    return exit_run_failure;
  }
}

}  // namespace rheosim::app
