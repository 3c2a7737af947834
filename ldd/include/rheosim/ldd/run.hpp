#pragma once
// Runs one `kind: ldd` case into a folder (docs/case-files.md): cavity scenes (cavity, skewed_cavity) with
// the lattice Solver, free-surface scenes (dam_break, slump, column) with the FreeSurfaceSolver
// (outputs listed further down).
//
// Files written to out_dir:
//   case.yaml                       the exact input
//   summary.json                    nodes, steps, ms_per_step, centerlines, status, wall time,
//                                   input sha256, phase timings
//   centerline_vertical.csv         y/S, u/U along the line ξ = W/2 (cavity coordinates)
//   centerline_horizontal.csv       x/W, v/U along the line η = S/2
//   residual.csv                    time, steady-state residual, kinetic energy, solver iterations
//   frames/nodes_NNNN.vtk           node cloud with velocity, pressure, shear rate, viscosity, kind
//                                   (NodeKind: 0 interior, 3 wall, 4 corner)
//   frames/field_NNNN.vtk           velocity and stream function ψ resampled on a 101² grid
//                                   (streamlines in ParaView: Stream Tracer, or contours of psi)
//   frames/nodes.vtk.series, frames/field.vtk.series, nodes.pvd   ParaView time-series indexes
//   field.vtk                       final velocity and stream function ψ on a structured grid
//                                   (ParaView: Stream Tracer or contours of psi for streamlines)
//   centerlines.gp, centerlines.png gnuplot script (kept to restyle) and its plot; streamlines.gp/.png
//   ghia.csv                        a square cavity of a Newtonian liquid at Re = 100 or 1000: the
//                                   centre-line velocities at Ghia et al.'s points against their
//                                   table (cavity_reference.hpp); summary.json `ghia` holds the same
//   checkpoint.h5                   the solver's state and the run's records (as for free surfaces, below)
//   log.txt                         (written by the caller's Log)
// The steady-state residual is max over the centre-line probes of |Δu|/U per unit of L/U time
// between two samples. On divergence (NaN, Courant number, failed solves, residual > 1e3) the
// run stops, the last good state is written as a frame and summary.json says "diverged".
#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rheosim/core/log.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/free_surface.hpp"

namespace rheosim::ldd {

struct RunOutcome {
  // "steady" | "end_time" | "diverged" | "settled" | "arrested" | "interrupted"
  std::string status;
  std::string message;            // why a diverged or arrested run stopped
  std::filesystem::path summary;  // summary.json
  std::size_t steps = 0;
  double ms_per_step = 0;
};

// When an LDD run stops before its end: after step_limit steps of this process, or once wall_time_limit seconds have
// passed, the run writes its checkpoint and returns status "interrupted" (0: no limit).
struct RunControl {
  std::size_t step_limit = 0;
  double wall_time_limit = 0;        // [s]
  double checkpoint_interval = 600;  // [s] of wall time between checkpoints (also at every frame)
  // Free-surface runs: when > 0, each probe step also runs this many power iterations of the
  // linearised step map on the current cloud (SolverParams::stability_probe_iterations) and
  // the probe file gains `step_map_growth` and its node's position (bench_ldd run --stability-probe).
  int stability_probe_iterations = 0;
  // Free-surface runs: each probe step also measures the bulk's mean divergence of the predicted
  // and the projected velocity (FreeSurfaceSolver::set_divergence_probe), and the probe file gains
  // `bulk_divergence_predicted` and `bulk_divergence` (bench_ldd run --divergence-probe).
  bool divergence_probe = false;
};

// Throws core::RunError for a scene in a dimension it is not built for (dam_break and column are
// 2D), core::ConfigError when out_dir holds the checkpoint of another input deck; never throws
// for divergence (see RunOutcome::status: also "settled" for a slump, "arrested" under
// time.stop_at_arrest).
// The probe file a free-surface scene writes beside summary.json: front.csv (dam_break),
// spread.csv (slump), column.csv (column).
[[nodiscard]] std::string probe_file_name(std::string_view scene_type);

RunOutcome run_case(const Case& c, const std::filesystem::path& out_dir, const core::Log& log,
                    const RunControl& control = {});

// ---------------------------------------------------------------- free-surface scenes
// run_case() runs dam_break, slump and column scenes with the FreeSurfaceSolver and writes
//   summary.json   nodes, steps, ms_per_step, status, volume_drift, bulk_compression,
//                  bulk_number_compression,
//                  front: [{t, x}] (dam break),
//                  spread: [{t, diameter, height}] (slump), table1 (dam break), phase timings
//   front.csv / spread.csv / column.csv   the probe history with kinetic energy and volume drift
//   table1.csv, table1.txt                LDD §4.3's dam break: mass front at LDD Table 1's times next
//                                         to the experiment and the seed's LDD column for this Δ and δt
//   profile.csv                           dam break: the final free surface, height per Δ column
//                                         (x, height; a yield-stress law also thin_film_arrest)
//   frames/nodes_NNNN.vtk (+ .vtk.series, nodes.pvd)   the cloud with velocity, pressure, γ̇, μ, kind
//   checkpoint.h5  the solver's state (SolverState) and the run's records so far, written
//                  atomically at every frame, every RunControl::checkpoint_interval of wall time
//                  and when the run stops (after a divergence: the last good state). Running the
//                  same deck into the same folder again continues from it, bit for bit;
//                  a checkpoint of another deck is refused (its input sha256 differs).
// Mass front: largest x of a non-splash fluid node + Δ/2, from the gate (x = 0). Spread: twice the
// largest distance of a non-splash fluid node from the axis + Δ; height: largest z + Δ/2. A slump
// stops early when, after the mould has cleared the fluid, the kinetic energy has decayed to
// time.settle_energy_ratio × its peak (CaseSettings::settle_energy_ratio).
// Free-surface runs compare their kinetic energy with the potential energy released: an excess
// above this fraction of the released energy (summary.json `energy_gain`) is a warning.
inline constexpr double energy_gain_tolerance = 0.01;
// A free-surface run whose fluid volume drifts by more than this fraction warns (summary.json
// `volume_drift` is the largest drift), and so does one whose bulk's mean kernel sum departs from
// ρ₀ by more than it (`bulk_compression`; FreeSurfaceSolver::bulk_density_ratio), or whose bulk's
// nodes per unit volume depart from their first count by more than it
// (`bulk_number_compression`; FreeSurfaceSolver::bulk_number_density).
inline constexpr double volume_drift_tolerance = 0.01;

// LDD Table 1 (seed §4.3): mass front [m] at six times, experiment (Komatina & Jovanović 1997)
// and LDD for Δ = 1 mm / 2 mm and δt = 1e-3 / 1e-4 s.
struct DamBreakReference {
  static constexpr double times[6] = {0.09, 0.23, 0.38, 0.56, 0.74, 1.14};
  static constexpr double experiment[6] = {0.103, 0.198, 0.297, 0.399, 0.499, 0.596};
  static constexpr double ldd_1mm_dt1e3[6] = {0.030, 0.185, 0.328, 0.427, 0.508, 0.705};
  static constexpr double ldd_1mm_dt1e4[6] = {0.048, 0.190, 0.304, 0.414, 0.484, 0.628};
  static constexpr double ldd_2mm_dt1e3[6] = {0.043, 0.195, 0.314, 0.396, 0.467, 0.621};
  static constexpr double ldd_2mm_dt1e4[6] = {0.044, 0.191, 0.308, 0.407, 0.486, 0.625};
};

// The arrested shape of a 2D yield-stress dam break in the shallow (lubrication) limit: at rest the
// basal shear stress ρgh|∂h/∂x| equals τ₀ everywhere, so h(s) = √(2τ₀(ℓ − s)/(ρg)) with s measured
// from the back wall (a symmetry plane of the slump) to the front at s = ℓ; the reservoir's area
// A = L·H fixes ℓ = (3A/(2√(2τ₀/(ρg))))^{2/3} (Liu & Mei 1989, J. Fluid Mech. 207, 505; Matson &
// Hogg 2007, J. Non-Newt. Fluid Mech. 142, 79). It is the m → ∞ limit of a slow, viscous slump:
// a flow carried further by its inertia stops on a flatter shape.
struct ThinFilmArrest {
  double length = 0;                               // ℓ from the back wall [m]
  double wall_height = 0;                          // h at the back wall [m]
  double stress_scale = 0;                         // 2τ₀/(ρg) [m]
  [[nodiscard]] double height_at(double s) const;  // h(s), 0 beyond the front
};
// Throws std::invalid_argument unless area, yield stress, density and gravity are > 0.
[[nodiscard]] ThinFilmArrest thin_film_arrest(double area, double yield_stress, double density, double gravity);

// The yield stress a 2D deposit's shape implies, read as the shallow arrest reads it: a least-
// squares fit of h² = (2τ/(ρg))(ℓ − s) to the final free surface, s from the back wall, over the
// columns at least two spacings from the back wall and at least two spacings high (resolved by
// two nodes or more). τ and ℓ measure the deposit itself, independently of where its thin tip
// ends. Meaningful for a deposit at rest in the shallow limit.
struct ThinFilmFit {
  double yield_stress = 0;      // τ [Pa]
  double length = 0;            // ℓ, where the fitted h² reaches 0 [m from the back wall]
  std::size_t columns = 0;      // fitted
  double rms_height_error = 0;  // of the fitted columns' h against √((2τ/(ρg))(ℓ − s)) [m]
};
// Empty with fewer than three such columns or a surface that does not fall towards the front.
// Throws std::invalid_argument unless the spans have equal sizes and spacing, density and
// gravity are > 0.
[[nodiscard]] std::optional<ThinFilmFit> fit_thin_film_deposit(std::span<const double> distance_from_back_wall,
                                                               std::span<const double> height, double spacing,
                                                               double density, double gravity);

// The slump s′ = s/H of a cylinder of height H of a yield-stress material lifted off its mould,
// at rest, against τ′ = τ₀/(ρgH): the material yields where the weight above exceeds the yield
// stress, s′ = 1 − 2τ′(1 − ln 2τ′) for τ′ < 1/2, 0 above (Pashias, Boger, Summers & Glenister
// 1996, J. Rheol. 40, 1179; the cylinder slump test). Throws std::invalid_argument
// unless τ′ > 0.
[[nodiscard]] double pashias_slump(double yield_stress_ratio);
// The same one-dimensional balance with the yield criterion of the tensor laws rheosim solves
// (|τ| = √(½τ:τ) = τ₀, von Mises): in the column's uniaxial compression the axial stress at
// yield is √3 τ₀, where Pashias et al. took 2τ₀ (Tresca), so s′ = 1 − √3τ′(1 − ln √3τ′) for
// τ′ < 1/√3, 0 above. Throws std::invalid_argument unless τ′ > 0.
[[nodiscard]] double von_mises_cylinder_slump(double yield_stress_ratio);
// What a cylinder slump test reads from a measured slump: the τ′ at which Pashias' s′(τ′) equals
// it (s′ falls from 1 to 0 as τ′ goes from 0 to 1/2). Empty for a slump outside (0, 1), where
// the formula gives no single τ′.
[[nodiscard]] std::optional<double> pashias_yield_stress_ratio(double slump);

// The final spread diameter 2R of a yield-stress material of volume Ω spreading as a thin
// axisymmetric pancake: τ₀ = 225ρgΩ²/(128π²R⁵) (Roussel & Coussot 2005, J. Rheol. 49, 705;
// the m → ∞, spread ≫ height limit of a slump). Throws std::invalid_argument unless
// every argument is > 0.
[[nodiscard]] double roussel_coussot_spread(double volume, double yield_stress, double density, double gravity);
// What a spread test reads from a measured spread: the same relation solved for τ₀. Throws
// std::invalid_argument unless every argument is > 0.
[[nodiscard]] double roussel_coussot_yield_stress(double volume, double spread, double density, double gravity);

// The first sloshing mode of a tank W wide and H deep in linear theory (Lamb 1932, §227):
// ω² = g k tanh(kH), k = π/W, the surface H + A cos(πx/W) cos ωt, and the wave's energy
// E = ρ g A² W / 4 per unit depth (it moves between potential and kinetic). Throws
// std::invalid_argument unless W, H, ρ and g are > 0 and A ≥ 0.
struct LinearSloshing {
  double period = 0;       // 2π/ω [s]
  double wave_energy = 0;  // E [J/m]
};
[[nodiscard]] LinearSloshing linear_sloshing(double width, double depth, double amplitude, double density,
                                             double gravity);

// The times where h(t) crosses `level`, linearly interpolated between the samples on either
// side (a sample on the level itself counts once), over the samples before index `until` (t
// increasing).
[[nodiscard]] std::vector<double> level_crossings(std::span<const double> t, std::span<const double> h, double level,
                                                  std::size_t until);

SolverParams free_surface_params(const ldd::CaseSettings& l);

}  // namespace rheosim::ldd
