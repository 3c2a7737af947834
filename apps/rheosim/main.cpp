// rheosim: the command line. Parses arguments and calls one function per subcommand.
#include <CLI/CLI.hpp>

#include <iostream>

#include "commands.hpp"
#include "rheosim/core/version.hpp"

int main(int argc, char** argv) {
  using namespace rheosim;
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
  bool verbose = false;
  bool quiet = false;
  cli.add_flag("-v,--verbose", verbose, "Also print debug messages");
  cli.add_flag("-q,--quiet", quiet, "Print only warnings and errors")->excludes("--verbose");

  std::vector<std::string> validate_files;
  auto* validate = cli.add_subcommand("validate", "Check case files without running them");
  validate->add_option("cases", validate_files, "Case files (YAML)")->required()->check(CLI::ExistingFile);
  validate->footer(
      "Every key is checked: its type, its SI value range, cross-key rules, and unknown keys\n"
      "(with the nearest valid name). Errors name file:line:column, the key and the fix.\n"
      "Example:\n"
      "  rheosim validate cases/quickstart.yaml cases/ldd_cavity_casson.yaml");

  std::string run_case;
  std::string run_out;
  auto* run = cli.add_subcommand("run", "Validate a case, run it and write its results");
  run->add_option("case", run_case, "Case file (YAML)")->required()->check(CLI::ExistingFile);
  run->add_option("-o,--out", run_out, "Output folder (default: results/<case name>)");
  double point_budget = app::default_point_budget;
  run->add_option("--point-budget", point_budget,
                  "Largest estimated wall time of one CFD-DEM point, in seconds (default 600); dearer points "
                  "fail at once with their estimate")
      ->check(CLI::PositiveNumber);
  double stop_after = 0;
  run->add_option("--stop-after", stop_after,
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

  std::string report_dir;
  auto* report = cli.add_subcommand("report", "Write report.html for a finished run folder");
  report->add_option("dir", report_dir, "Run folder holding summary.json")->required()->check(CLI::ExistingDirectory);
  report->footer(
      "Reads summary.json and the input deck from the folder and (re)writes report.html.\n"
      "Example:\n"
      "  rheosim report results/quickstart");

  std::string export_case;
  std::string export_dir;
  double export_rate = 0;
  std::string export_mesh, export_rim;
  double export_courant = 0;
  auto* foam = cli.add_subcommand("export-openfoam",
                                  "Write a rheometer case or an LDD dam break as an OpenFOAM v1912 case directory");
  foam->add_option("case", export_case, "Case file (kind: rheometer, single phase; or kind: ldd, a dam break)")
      ->required()
      ->check(CLI::ExistingFile);
  foam->add_option("dir", export_dir, "Output case directory")->required();
  foam->add_option("--shear-rate", export_rate, "Rim shear rate [1/s] (default: the case's last)");
  foam->add_option("--mesh", export_mesh, "Mesh preset M1 | M2 | M3 (default M2; CD §2.3)");
  foam->add_option("--rim", export_rim, "Rim condition shear_free | slip (default shear_free; docs/openfoam.md §2.2)");
  foam->add_option("--max-courant", export_courant,
                   "LDD dam break: interFoam's maxCo and maxAlphaCo, in (0, 1] (default 0.5)");
  foam->footer(
      "A rheometer case: blockMeshDict (O-grid), controlDict with a forces function object, fvSchemes,\n"
      "fvSolution, transportProperties (kinematic units), 0/U and 0/p; run blockMesh then simpleFoam.\n"
      "An LDD dam break: the interFoam case of the same reservoir, channel, fluid and cell size\n"
      "(docs/ldd.md); run blockMesh, setFields, interFoam. Both with WM_PROJECT_DIR=/usr/share/openfoam.\n"
      "Examples:\n"
      "  rheosim export-openfoam cases/quickstart.yaml foam/quickstart --shear-rate 100 --mesh M2\n"
      "  rheosim export-openfoam cases/ldd_dam_break_bingham.yaml foam/dam_break");

  // A first word that names no subcommand: name it and the valid ones (CLI11 would only say
  // that a subcommand is required).
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.starts_with("-")) continue;
    std::string names;
    bool known = false;
    for (const auto* sub : cli.get_subcommands({})) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || sub->get_name() == word;
    }
    if (!known) {
      std::cerr << fmt::format("error: unknown subcommand '{}'\n  expected one of: {}\n  hint: rheosim --help\n", word,
                               names);
      return app::exit_bad_input;
    }
    break;
  }
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = cli.exit(e);  // prints help, version or the parse error
    return code == 0 ? app::exit_success : app::exit_bad_input;
  }

  const auto verbosity =
      quiet ? core::Verbosity::quiet : (verbose ? core::Verbosity::verbose : core::Verbosity::normal);
  const core::Log log = core::Log::console(verbosity);
  if (*validate) return app::validate(validate_files, log);
  if (*run) return app::run(run_case, run_out, point_budget, stop_after, log);
  if (*foam) {
    // Only the options given: an unset one is its exporter's default.
    app::ExportRequest request;
    if (foam->count("--shear-rate") > 0) request.rim_shear_rate = export_rate;
    if (foam->count("--mesh") > 0) request.mesh = export_mesh;
    if (foam->count("--rim") > 0) request.rim = export_rim;
    if (foam->count("--max-courant") > 0) request.max_courant = export_courant;
    return app::export_openfoam(export_case, export_dir, request, log);
  }
  return app::report(report_dir, log);
}
