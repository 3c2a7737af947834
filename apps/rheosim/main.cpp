// rheosim: the command line. Parses arguments and calls one function per subcommand.
#include <CLI/CLI.hpp>

#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "rheosim/core/version.hpp"

namespace {

using namespace rheosim;

// What each subcommand's options fill.
struct Options {
  bool verbose = false, quiet = false;
  std::vector<std::string> validate_files;
  std::string run_case, run_out;
  double point_budget = app::default_point_budget;
  double stop_after = 0;
  std::string report_dir;
  std::string export_case, export_dir, export_mesh, export_rim;
  double export_rate = 0, export_courant = 0;
};

CLI::App* add_validate(CLI::App& cli, Options& o) {
  auto* validate = cli.add_subcommand("validate", "Check case files without running them");
  validate->add_option("cases", o.validate_files, "Case files (YAML)")->required()->check(CLI::ExistingFile);
  validate->footer(
      "Every key is checked: its type, its SI value range, cross-key rules, and unknown keys\n"
      "(with the nearest valid name). Errors name file:line:column, the key and the fix.\n"
      "Example:\n"
      "  rheosim validate cases/quickstart.yaml cases/ldd_cavity_casson.yaml");
  return validate;
}

CLI::App* add_run(CLI::App& cli, Options& o) {
  auto* run = cli.add_subcommand("run", "Validate a case, run it and write its results");
  run->add_option("case", o.run_case, "Case file (YAML)")->required()->check(CLI::ExistingFile);
  run->add_option("-o,--out", o.run_out, "Output folder (default: results/<case name>)");
  run->add_option("--point-budget", o.point_budget,
                  "Largest estimated wall time of one CFD-DEM point, in seconds (default 600); dearer points "
                  "fail at once with their estimate")
      ->check(CLI::PositiveNumber);
  run->add_option("--stop-after", o.stop_after,
                  "LDD runs: after this many seconds of wall time, write the checkpoint and stop "
                  "(status interrupted); the same command goes on from there")
      ->check(CLI::PositiveNumber);
  run->footer(
      "Writes summary.json, CSV tables, HDF5 data, plots and report.html into the output folder.\n"
      "A sweep (kind: sweep) stores each finished point at once; run it again with the same --out\n"
      "after an interruption and only the missing points are computed. An LDD run writes\n"
      "checkpoint.h5 at every frame and every 10 minutes; run it again\n"
      "with the same --out and it continues from the last checkpoint.\n"
      "Examples:\n"
      "  rheosim run cases/quickstart.yaml --out results/quickstart\n"
      "  rheosim run cases/suspension_seed.yaml --out results/seed");
  return run;
}

CLI::App* add_report(CLI::App& cli, Options& o) {
  auto* report = cli.add_subcommand("report", "Write report.html for a finished run folder");
  report->add_option("dir", o.report_dir, "Run folder holding summary.json")->required()->check(CLI::ExistingDirectory);
  report->footer(
      "Reads summary.json and the input deck from the folder and (re)writes report.html.\n"
      "Example:\n"
      "  rheosim report results/quickstart");
  return report;
}

CLI::App* add_export_openfoam(CLI::App& cli, Options& o) {
  auto* foam = cli.add_subcommand("export-openfoam",
                                  "Write a rheometer case or an LDD dam break as an OpenFOAM v1912 case directory");
  foam->add_option("case", o.export_case, "Case file (kind: rheometer, single phase; or kind: ldd, a dam break)")
      ->required()
      ->check(CLI::ExistingFile);
  foam->add_option("dir", o.export_dir, "Output case directory")->required();
  foam->add_option("--shear-rate", o.export_rate, "Rim shear rate [1/s] (default: the case's last)");
  foam->add_option("--mesh", o.export_mesh, "Mesh preset M1 | M2 | M3 (default M2; CD §2.3)");
  foam->add_option("--rim", o.export_rim,
                   "Rim condition shear_free | slip (default shear_free; docs/openfoam.md §2.2)");
  foam->add_option("--max-courant", o.export_courant,
                   "LDD dam break: interFoam's maxCo and maxAlphaCo, in (0, 1] (default 0.5)");
  foam->footer(
      "A rheometer case: blockMeshDict (O-grid), controlDict with a forces function object, fvSchemes,\n"
      "fvSolution, transportProperties (kinematic units), 0/U and 0/p; run blockMesh then simpleFoam.\n"
      "An LDD dam break: the interFoam case of the same reservoir, channel, fluid and cell size\n"
      "(docs/ldd.md); run blockMesh, setFields, interFoam. Both with WM_PROJECT_DIR=/usr/share/openfoam.\n"
      "Examples:\n"
      "  rheosim export-openfoam cases/quickstart.yaml foam/quickstart --shear-rate 100 --mesh M2\n"
      "  rheosim export-openfoam cases/ldd_dam_break_bingham.yaml foam/dam_break");
  return foam;
}

// A first word that names no subcommand: its name and the valid ones (CLI11 would only say that
// a subcommand is required). False when the words are fine.
bool refused_unknown_subcommand(const CLI::App& cli, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.starts_with("-")) continue;
    std::string names;
    bool known = false;
    for (const auto* sub : cli.get_subcommands({})) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || sub->get_name() == word;
    }
    if (!known)
      std::cerr << fmt::format("error: unknown subcommand '{}'\n  expected one of: {}\n  hint: rheosim --help\n", word,
                               names);
    return !known;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{
      "rheosim: a virtual rheometer for particle suspensions and non-Newtonian materials.\n"
      "Parallel-plate rheometry (fluid solver + LIGGGHTS DEM) and LDD free-surface flows,\n"
      "driven by YAML case files in SI units.",
      "rheosim"};
  cli.set_version_flag("--version", fmt::format("rheosim {} (git {})", core::version, core::git_revision));
  cli.require_subcommand(1);
  cli.fallthrough();  // --verbose/--quiet also after the subcommand
  cli.footer(
      "Examples:\n"
      "  rheosim validate cases/quickstart.yaml\n"
      "  rheosim run cases/quickstart.yaml --out results/quickstart\n"
      "  rheosim report results/quickstart\n"
      "  rheosim export-openfoam cases/quickstart.yaml foam/quickstart --shear-rate 100\n"
      "Exit codes: 0 success, 2 bad input (case file or arguments), 1 run failure.\n"
      "Run 'rheosim <command> --help' for the options of a command.");
  Options o;
  cli.add_flag("-v,--verbose", o.verbose, "Also print debug messages");
  cli.add_flag("-q,--quiet", o.quiet, "Print only warnings and errors")->excludes("--verbose");
  const CLI::App* validate = add_validate(cli, o);
  const CLI::App* run = add_run(cli, o);
  add_report(cli, o);
  const CLI::App* foam = add_export_openfoam(cli, o);

  if (refused_unknown_subcommand(cli, argc, argv)) return app::exit_bad_input;
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = cli.exit(e);  // prints help, version or the parse error
    return code == 0 ? app::exit_success : app::exit_bad_input;
  }

  const auto verbosity =
      o.quiet ? core::Verbosity::quiet : (o.verbose ? core::Verbosity::verbose : core::Verbosity::normal);
  const core::Log log = core::Log::console(verbosity);
  if (*validate) return app::validate(o.validate_files, log);
  if (*run) return app::run(o.run_case, o.run_out, o.point_budget, o.stop_after, log);
  if (*foam) {
    // Only the options given: an unset one is its exporter's default.
    app::ExportRequest request;
    if (foam->count("--shear-rate") > 0) request.rim_shear_rate = o.export_rate;
    if (foam->count("--mesh") > 0) request.mesh = o.export_mesh;
    if (foam->count("--rim") > 0) request.rim = o.export_rim;
    if (foam->count("--max-courant") > 0) request.max_courant = o.export_courant;
    return app::export_openfoam(o.export_case, o.export_dir, request, log);
  }
  return app::report(o.report_dir, log);
}
