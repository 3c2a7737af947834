#include "commands.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <optional>
#include <tuple>

#include "rheosim/core/case.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/run_lock.hpp"
#include "rheosim/core/version.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/openfoam.hpp"
#include "rheosim/ldd/report.hpp"
#include "rheosim/rheometer/box_point.hpp"
#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/openfoam.hpp"
#include "rheosim/rheometer/report.hpp"
#include "rheosim/rheometer/shear_cell.hpp"
#include "rheosim/rheometer/sweep.hpp"
#include "run_ldd.hpp"

namespace rheosim::app {

namespace {

// Prints a user error in one block: "error: file:line:col: key: problem" + expected + hint.
int bad_input(const core::Log& log, const std::exception& e) {
  log.error("{}", e.what());
  return exit_bad_input;
}

// A sweep runs (or resumes) into `out`: φ = 0 points by the steady swirl solve, φ > 0 points by
// CFD-DEM, each within the point budget (rheometer/sweep.hpp).
int run_sweep_case(const rheometer::Case& c, const std::string& case_file, const std::filesystem::path& out,
                   double point_budget, const core::Log& log) {
  try {
    const auto log_file = log.with_file(out / "log.txt");
    log_file.info("rheosim {} (git {}): running sweep {} into {}", core::version, core::git_revision, case_file,
                  out.string());
    const auto& sweep = std::get<rheometer::SweepCase>(c.spec);
    auto runners = rheometer::default_point_runners(sweep.rheometer);
    runners.suspension =
        rheometer::make_coupled_suspension_runner(sweep.rheometer, out / "dem", point_budget, sweep.volume_fractions);
    const auto outcome = rheometer::run_sweep(c, out, log_file, runners);
    log_file.info("{} points: {} computed now, {} read back from an earlier run, {} failed; summary: {}; report: {}",
                  outcome.points, outcome.computed_points, outcome.reused_points, outcome.failed_points,
                  outcome.summary.string(), (out / "report.html").string());
    if (outcome.failed_points > 0)
      log_file.error("{} of {} sweep points have no result (listed in summary.json and the report)",
                     outcome.failed_points, outcome.points);
    return outcome.failed_points == 0 ? exit_success : exit_run_failure;
  } catch (const core::ConfigError& e) {
    return bad_input(log, e);
  } catch (const std::exception& e) {
    log.error("run failed: {}", e.what());
    return exit_run_failure;
  }
}

// The model each suspension φ of the case would run, and the box's settings where it is chosen.
void describe_suspension_model(const rheometer::Case& c) {
  const rheometer::RheometerCase* r = nullptr;
  std::vector<double> fractions;
  if (const auto* sweep = std::get_if<rheometer::SweepCase>(&c.spec)) {
    r = &sweep->rheometer;
    fractions = sweep->volume_fractions;
  } else if (const auto* single = std::get_if<rheometer::RheometerCase>(&c.spec); single && single->particles) {
    r = single;
    fractions = {single->particles->volume_fraction};
  }
  if (!r || !r->particles) return;
  for (const double phi : fractions) {
    if (!(phi > 0.0)) continue;
    const auto choice = rheometer::choose_suspension_model(*r, phi, default_point_budget);
    std::cout << fmt::format("  φ = {:g}: {} — {}\n", phi, rheometer::name_of(choice.model), choice.reason);
    if (choice.model == rheometer::RheometerCase::SuspensionModel::lees_edwards ||
        choice.model == rheometer::RheometerCase::SuspensionModel::walled_box)
      std::cout << fmt::format("    {}\n", rheometer::describe_box(*r, phi));
  }
}

}  // namespace

int validate(const std::vector<std::string>& case_files, const core::Log& log) {
  int status = exit_success;
  for (const auto& file : case_files) {
    try {
      // The kind names the module that reads the rest of the file.
      const core::CaseFile case_file = core::CaseFile::open(file);
      if (case_file.header().kind == "ldd") {
        const ldd::Case c = ldd::read_case(case_file);
        std::cout << fmt::format("{}: valid {} case\n{}", file, c.kind, ldd::describe(c));
      } else {
        const rheometer::Case c = rheometer::read_case(case_file);
        std::cout << fmt::format("{}: valid {} case\n{}", file, c.kind, rheometer::describe(c));
        describe_suspension_model(c);
      }
    } catch (const core::ConfigError& e) {
      status = bad_input(log, e);
    }
  }
  return status;
}

int run(const std::string& case_file, const std::filesystem::path& out_dir, double point_budget, double stop_after,
        const core::Log& log) {
  std::optional<core::CaseFile> file;
  std::optional<rheometer::Case> rheometer_or_sweep;
  std::optional<ldd::Case> ldd_case;
  try {
    // The kind names the module that reads the rest of the file.
    file.emplace(core::CaseFile::open(case_file));
    if (file->header().kind == "ldd")
      ldd_case.emplace(ldd::read_case(*file));
    else
      rheometer_or_sweep.emplace(rheometer::read_case(*file));
  } catch (const core::ConfigError& e) {
    return bad_input(log, e);
  }
  const std::filesystem::path out = out_dir.empty() ? std::filesystem::path("results") / file->header().name : out_dir;
  std::optional<core::RunDirectoryLock> lock;  // one writer per run folder, for the whole run
  try {
    lock.emplace(out);
  } catch (const core::RunError& e) {
    log.error("{}", e.what());
    return exit_run_failure;
  }
  if (ldd_case) return run_ldd(*ldd_case, out, stop_after, log);
  // Every rheometer case runs as a sweep (rheometer::as_sweep): points stored as they finish,
  // resumed when run again into the same folder, one analysis and report.
  return run_sweep_case(rheometer::as_sweep(*rheometer_or_sweep), case_file, out, point_budget, log);
}

int export_openfoam(const std::string& case_file, const std::filesystem::path& dir, const ExportRequest& request,
                    const core::Log& log) {
  try {
    const core::CaseFile file = core::CaseFile::open(case_file);
    file.require_kind({"rheometer", "ldd"},
                      "export-openfoam (simpleFoam for a single-phase rheometer case, interFoam "
                      "for an LDD dam break)");
    if (file.header().kind == "ldd") {
      if (request.rim_shear_rate || request.mesh || request.rim)
        log.warn("--shear-rate, --mesh and --rim are for a rheometer case; an LDD dam break ignores them");
      ldd::InterFoamExportOptions options;
      if (request.max_courant) options.max_courant = *request.max_courant;
      const auto exported = ldd::export_interfoam(ldd::read_case(file), dir, options);
      log.info("interFoam case written to {} ({} x {} cells of {} m, {}); run it with:\n{}", dir.string(),
               exported.cells_x, exported.cells_y, exported.cell_size, exported.transport.model, exported.commands);
      if (!exported.transport.note.empty()) log.warn("{}", exported.transport.note);
      return exit_success;
    }
    if (request.max_courant)
      log.warn("--max-courant is for an LDD dam break; a rheometer case (simpleFoam, steady) ignores it");
    const rheometer::Case c = rheometer::read_case(file);
    double rim_shear_rate = request.rim_shear_rate.value_or(0.0);  // <= 0: the case's last
    if (rim_shear_rate <= 0)
      if (const auto* r = std::get_if<rheometer::RheometerCase>(&c.spec)) rim_shear_rate = r->shear_rates.back();
    rheometer::OpenFoamExportOptions options;
    if (request.mesh) options.mesh = rheometer::OpenFoamMesh::preset(*request.mesh);
    if (request.rim) options.rim = rheometer::parse_openfoam_rim(*request.rim);
    const auto exported = rheometer::export_openfoam(c, rim_shear_rate, dir, options);
    log.info("OpenFOAM case written to {} ({} cells, {}, {} rim); run it with:\n{}", dir.string(), exported.cells,
             exported.transport.model, rheometer::name_of(options.rim), exported.commands);
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
    // The summary's kind picks the report: an LDD run has its own.
    const auto summary = run_dir / "summary.json";
    const bool ldd_run = std::filesystem::exists(summary) && core::read_json(summary).value("kind", "") == "ldd";
    const auto [html, plots, missing_plots] = [&] {
      if (ldd_run) {
        const auto f = ldd::write_report(run_dir);
        return std::tuple{f.html, f.plots.size(), f.missing_plots.size()};
      }
      const auto f = rheometer::write_report(run_dir);
      return std::tuple{f.html, f.plots.size(), f.missing_plots.size()};
    }();
    log.info("report written to {} ({} plots)", html.string(), plots);
    if (missing_plots > 0)
      log.warn("{} plot(s) not drawn (gnuplot missing or failed); their .gp scripts are in {}", missing_plots,
               run_dir.string());
    return exit_success;
  } catch (const core::ConfigError& e) {
    return bad_input(log, e);
  } catch (const std::exception& e) {
    log.error("report failed: {}", e.what());
    return exit_run_failure;
  }
}

}  // namespace rheosim::app
