#pragma once
// report.html for an LDD run folder: the run's figures (nodes, steps, cost, status and the
// rules it bent), for a free-surface run the front or spread, the energy balance and the volume
// drift against time (with the experiment of LDD Table 1 beside a dam break's front), for a
// cavity the centre-line profiles and streamlines its run drew. Built from summary.json (read
// by read_run_summary, which names any missing key) and the probe CSV; opens with no network.
// Beside it: NAME.gp (gnuplot NAME.gp redraws NAME.png and NAME.svg).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace rheosim::ldd {

// The summary.json of an LDD run as a type: every key an LDD run writes for its scene.
struct RunSummary {
  std::string case_name, scene, status, message;  // message: why a run stopped early ("" if none)
  int dimension = 2;
  std::size_t nodes = 0, steps = 0, threads = 1;
  double spacing = 0, time_step = 0, time = 0, ms_per_step = 0, wall_time = 0;
  std::string time_step_rule;         // "" when the case gave the step
  std::vector<std::string> warnings;  // every rule the run bent
  bool free_surface = false;          // dam_break, slump, column
  // Free-surface runs.
  double volume_drift = 0, kinetic_energy_peak = 0;
  std::optional<double> energy_gain;  // null for a resting column
  std::size_t repeated_solves = 0;
  std::optional<double> final_spread, final_height, yielded_fraction;  // dam break and slump
  bool arrested = false;
  // A dam break of a yield-stress material: the shallow arrest (ThinFilmArrest) and the final
  // runout's difference from its length (null if the run has no front).
  std::optional<double> thin_film_length, thin_film_front, thin_film_error;
  // Cavity runs.
  double reynolds_number = 0, final_residual = 0;
  // A square cavity of a Newtonian liquid at Re = 100 or 1000: its centre lines against Ghia et
  // al. (1982) (cavity_reference.hpp), the largest difference in units of the lid speed.
  std::optional<double> ghia_reynolds, ghia_max_error;
};

// Reads <summary_json>; a missing key, or one of the wrong type, is a core::ConfigError naming
// the file and the key; a summary of another kind (rheometer, sweep) is one too.
[[nodiscard]] RunSummary read_run_summary(const std::filesystem::path& summary_json);

struct ReportFiles {
  std::filesystem::path html;              // report.html
  std::vector<std::string> plots;          // plots drawn (front, energy, volume, …)
  std::vector<std::string> missing_plots;  // scripts written whose PNG gnuplot did not produce
};

// Writes <run_dir>/report.html (atomically) and its plot scripts and plots. A folder without
// summary.json is a core::ConfigError.
ReportFiles write_report(const std::filesystem::path& run_dir);

}  // namespace rheosim::ldd
