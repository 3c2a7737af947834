#pragma once
// summary.json of an LDD run as a type: the runners fill a RunSummary and write it with
// to_json; read_run_summary reads the same keys back (a missing or mistyped key is a
// core::ConfigError naming the file and the key's path, a summary of another kind one too).
// Which keys a run has depends on its scene: every run the head, the cloud, the step, the cost
// and the rules it bent; a cavity its residual, centre lines and, for a square Newtonian cavity at
// a Reynolds number Ghia et al. (1982) tabulate, the comparison with them; a free-surface run its
// volume and energy records, a dam break its front and references, a slump its spread.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rheosim/core/run_summary.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/step.hpp"

namespace rheosim::ldd {

using MaybeNumber = std::optional<double>;

struct FrontSample {  // dam break: the mass front x [m] from the gate at time t [s]
  double t = 0, x = 0;
  friend bool operator==(const FrontSample&, const FrontSample&) = default;
};

struct SpreadSample {  // slump: diameter and height [m] at time t [s]
  double t = 0, diameter = 0, height = 0;
  friend bool operator==(const SpreadSample&, const SpreadSample&) = default;
};

struct Table1Row {  // LDD Table 1's experiment, this run's front and the seed's LDD column [m]
  double t = 0, experiment = 0;
  MaybeNumber front, error, ldd_seed;  // empty: not reached, or no seed column for this Δ, δt
  friend bool operator==(const Table1Row&, const Table1Row&) = default;
};

struct Table1Comparison {
  std::vector<Table1Row> rows;
  MaybeNumber rms_error;  // [m] over the times reached
  double max_error = 0;
  friend bool operator==(const Table1Comparison&, const Table1Comparison&) = default;
};

struct MartinMoyceRow {  // Z = x/a against T = t√(2g/a)
  double T = 0, Z_experiment = 0;
  MaybeNumber Z, relative_error;  // empty: not reached
  friend bool operator==(const MartinMoyceRow&, const MartinMoyceRow&) = default;
};

struct MartinMoyceComparison {
  std::vector<MartinMoyceRow> rows;
  MaybeNumber max_relative_error;  // empty when no time was reached
  friend bool operator==(const MartinMoyceComparison&, const MartinMoyceComparison&) = default;
};

struct ThinFilmArrestComparison {                 // the shallow yield-stress arrest of the reservoir (run.hpp)
  double length = 0, front = 0, wall_height = 0;  // [m]: from the back wall, from the gate
  MaybeNumber relative_error;                     // of the final runout against length
  // The final free surface read as a shallow arrest (fit_thin_film_deposit): τ, ℓ, rms error of h.
  MaybeNumber fitted_yield_stress, fitted_length, fitted_rms_height_error;
  friend bool operator==(const ThinFilmArrestComparison&, const ThinFilmArrestComparison&) = default;
};

struct CylinderSlumpComparison {           // Pashias et al. (1996), pashias_slump (run.hpp)
  double yield_stress_ratio = 0;           // τ′ = τ₀/(ρgH)
  double slump = 0;                        // s′ = s/H at rest, theory
  MaybeNumber measured_slump, difference;  // this run's 1 − final height/H, and − theory
  double von_mises_slump = 0;              // s′ with the axial yield stress √3 τ₀ (von_mises_cylinder_slump)
  MaybeNumber implied_yield_stress;        // τ₀ that Pashias' formula reads from measured_slump [Pa]
  friend bool operator==(const CylinderSlumpComparison&, const CylinderSlumpComparison&) = default;
};

struct ConeSpreadComparison {        // Roussel & Coussot (2005), roussel_coussot_spread (run.hpp)
  double diameter = 0;               // the pancake's [m]
  MaybeNumber relative_error;        // of the final spread
  MaybeNumber implied_yield_stress;  // τ₀ that the relation reads from the final spread [Pa]
  friend bool operator==(const ConeSpreadComparison&, const ConeSpreadComparison&) = default;
};

struct SloshingComparison {     // a column's first mode against linear theory (run.hpp, linear_sloshing)
  double period = 0;            // linear theory [s]
  double wave_energy = 0;       // E = ρgA²W/4 [J/m]
  double compared_until = 0;    // [s]: the last sample before the kinetic energy exceeds 1.5 E (or the end)
  std::size_t crossings = 0;    // of the left-wall elevation about H, up to compared_until
  MaybeNumber measured_period;  // from the first and last crossing; empty below three crossings
  MaybeNumber relative_error;   // of the measured period
  MaybeNumber first_crossing;   // [s], theory a quarter period
  friend bool operator==(const SloshingComparison&, const SloshingComparison&) = default;
};

struct CenterlineSample {  // normalised: position along the line, velocity across it
  double position = 0, velocity = 0;
  friend bool operator==(const CenterlineSample&, const CenterlineSample&) = default;
};

struct GhiaPointRecord {
  std::string line;  // "u" (vertical centre line) or "v" (horizontal)
  double coordinate = 0, computed = 0, reference = 0;
  friend bool operator==(const GhiaPointRecord&, const GhiaPointRecord&) = default;
};

struct GhiaComparison {
  int reynolds = 0;
  double max_error = 0;  // largest |computed − reference| in units of the lid speed
  std::vector<GhiaPointRecord> points;
  friend bool operator==(const GhiaComparison&, const GhiaComparison&) = default;
};

struct RunSummary {
  core::SummaryHead head;  // the head every run writes (core/run_summary.hpp), kind "ldd"
  // Every run.
  std::string scene, status, message;  // message: why a run stopped early ("" if none)
  int dimension = 2;
  std::size_t nodes = 0, fluid_nodes = 0;
  double spacing = 0, time_step = 0;
  std::string time_step_rule;  // "" when the case gave the step
  std::size_t steps = 0;
  double time = 0;
  int threads = 1;
  double ms_per_step = 0;
  PhaseTimes phase_seconds;
  double wall_time = 0;
  std::vector<std::size_t> resumed_at_steps;                             // the steps a run went on from its checkpoint
  std::vector<std::string> warnings;                                     // every rule the run bent
  [[nodiscard]] bool free_surface() const { return !is_cavity(scene); }  // dam_break, slump, column
  // Cavity runs.
  double reynolds_number = 0, final_residual = 0;
  std::vector<CenterlineSample> vertical_centerline, horizontal_centerline;  // (y, u) and (x, v)
  std::optional<GhiaComparison> ghia;
  // Free-surface runs.
  double volume_drift = 0, kinetic_energy_peak = 0;
  // Largest |ρ̄/ρ₀ − 1| of the bulk's kernel sums (nodes with no free surface within h); empty in
  // a summary written before it was recorded.
  MaybeNumber bulk_compression;
  // Largest |n/n_first − 1| of the bulk's nodes per unit volume counted in balls of 4 Δ, which the
  // nodes' arrangement does not bias as it biases a kernel sum (FreeSurfaceSolver::
  // bulk_number_density); empty when no ball fitted in the bulk, or in an older summary.
  MaybeNumber bulk_number_compression;
  MaybeNumber energy_gain;  // empty for a resting column
  std::size_t repeated_solves = 0, repeated_with_lu = 0;
  // solver.pressure_amg: auto: the time from which the pressure AMG used plain aggregation (empty:
  // smoothed throughout, or not auto).
  MaybeNumber pressure_amg_plain_from;
  double pressure_iterations_per_step = 0, velocity_iterations_per_step = 0;
  std::size_t neighbour_searches = 0;
  std::vector<FrontSample> front;                            // dam break
  std::optional<ThinFilmArrestComparison> thin_film_arrest;  // dam break of a yield-stress law
  std::optional<Table1Comparison> table1;                    // LDD §4.3's release
  std::optional<MartinMoyceComparison> martin_moyce;         // a Newtonian column with H = 2L
  std::vector<SpreadSample> spread;                          // slump
  MaybeNumber final_spread, final_height, yielded_fraction;  // dam break and slump
  // The largest μ(γ̇)γ̇/τ₀ over the fluid nodes at the end (a yield-stress law); arrested: at most
  // 1 + time.arrest_stress_tolerance, and the run did not diverge.
  MaybeNumber largest_stress_ratio;
  bool arrested = false;
  std::optional<CylinderSlumpComparison> pashias;       // slump of a yield-stress law, cylinder mould
  std::optional<ConeSpreadComparison> roussel_coussot;  // slump of a yield-stress law, cone mould
  std::optional<SloshingComparison> sloshing;           // column with a wave_amplitude
  friend bool operator==(const RunSummary&, const RunSummary&) = default;
};

[[nodiscard]] nlohmann::ordered_json to_json(const RunSummary& summary);
[[nodiscard]] RunSummary read_run_summary(const std::filesystem::path& summary_json);

}  // namespace rheosim::ldd
