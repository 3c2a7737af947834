#pragma once
// A `kind: ldd` case (docs/case-files.md, "LDD cases"), read by this module from its part of the
// case file: core::CaseFile gives the header and the root Section, read_case() validates every
// LDD key (ranges, the scene's own keys, the keys a cavity does not read) into these structs,
// choosing time.step: auto and refusing a case that cannot fit the machine before anything is
// allocated. Choices arrive as enums; the name tables below are the one mapping between a case
// file's words and them, for the reader, describe() and the benchmarks' command lines.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rheosim/core/case.hpp"
#include "rheosim/ldd/dry_walls.hpp"
#include "rheosim/ldd/node_reordering.hpp"
#include "rheosim/ldd/preconditioner.hpp"
#include "rheosim/ldd/scene.hpp"

namespace rheosim::ldd {

// solver.gradient: the gradient operator (auto: centred for free-surface scenes, LDD eq. 14 for
// cavities; surface_anchored: centred in the interior, eq. 14 on free-surface nodes).
enum class GradientChoice { automatic, centred, renormalised, surface_anchored };
enum class AmgAggregation { smoothed, plain, automatic };  // solver.pressure_amg
// pressure_amg: auto turns to plain aggregation once a pressure solve on a smoothed hierarchy set
// up in the same step needs more iterations than this. Smoothed aggregation needs fewer on compact
// flows (the 2 mm dam break's first 0.3 s: 7.2 against plain's 12.8), plain on thinned layers,
// where smoothed climbs past 40 and to ~100 a step (the 1.25 mm arrest by 1.5 s) while plain stays
// near 10 (docs/ldd.md, "Linear solvers").
constexpr int auto_aggregation_switch_iterations = 30;

// solver: — numerical settings of the LDD solver (all optional; step.hpp, cavity_solver.hpp and
// free_surface.hpp document them).
struct SolverSettings {
  int threads = 0;                   // OpenMP threads; 0: OMP_NUM_THREADS or all cores
  double pressure_tolerance = 1e-6;  // BiCGStab relative residual of the PPE (LDD eq. 17)
  double velocity_tolerance = 1e-8;  // BiCGStab relative residual of LDD eq. 19
  int max_iterations = 2000;         // per linear solve
  LatticeInterpolation interpolation = LatticeInterpolation::quadratic;  // cavities: the return to the lattice
  double max_courant = 1.0;    // stop (diverged) when max|u|δt/Δ exceeds this
  int pbd_sweeps = 3;          // free-surface scenes: volume-keeping PBD sweeps per step
  double moment_rcond = 0.03;  // free-surface scenes: λ_min/λ_max of LDD eq. 13 below which it is pseudo-inverted
  double surface_moment_rcond = 0.01;  // free-surface scenes: λ_min/λ_max of LDD eq. 13 below which a node is surface
  GradientChoice gradient = GradientChoice::automatic;
  // Free-surface scenes: a PBD shift δx changes the velocity by ⟨∇u⟩·δx (pbd_velocity: taylor),
  // or leaves it (none).
  bool pbd_velocity_correction = true;
  // Free-surface scenes: surface nodes take a PBD shift's tangential part only (pbd_surface:
  // tangential) or all of it (full).
  bool pbd_surface_tangential = false;
  // Free-surface scenes: nodes flagged only by the empty cone or the centroid offset stay interior
  // when the void they point to is occupied (surface_detection: umbrella) or not (local).
  bool surface_umbrella = false;
  bool full_viscous_stress = false;  // free-surface scenes: ∇·(2μE) (viscous_stress: full) or ∇·(μ∇u)
  // Free-surface scenes: the surface nodes' pressure, 2μ n·E·n (surface_stress: normal, the
  // traction-free condition's normal part) or p_atm = 0 (none, LDD eq. 17).
  bool surface_normal_stress = false;
  // Free-surface scenes: the viscosity between a fluid and a wall node, the mean of the two
  // (wall_viscosity: mean) or the law at the mean of their shear rates (face_shear_rate).
  bool wall_face_shear_rate = false;
  DryWalls dry_walls = DryWalls::include;  // free-surface scenes: wall nodes above the surface (dry_walls.hpp)
  // Empty: auto, the scene's default (lu: free-surface scenes only).
  std::optional<Preconditioner> pressure_preconditioner, velocity_preconditioner;
  // Free-surface scenes, the pressure solve's AMG: smoothed aggregation (the default), plain
  // (piecewise-constant) aggregation, which keeps the PPE's iterations flat when the flow has
  // thinned into a spread-out layer (docs/ldd.md, the dam break's late steps), or smoothed until a
  // fresh smoothed hierarchy needs more than AmgAggregation's switch count, then plain (auto).
  AmgAggregation pressure_amg = AmgAggregation::smoothed;
};

// output: — what a run writes and how often (all optional).
struct OutputSettings {
  double frame_interval = 0;  // [s] between VTK frames; 0: end/20
  double probe_interval = 0;  // [s] between centre-line samples (residual history); 0: end/200
  // The intervals a run of end_time [s] uses: the given ones, or the defaults above.
  [[nodiscard]] double frame_interval_for(double end_time) const {
    return frame_interval > 0 ? frame_interval : end_time / 20;
  }
  [[nodiscard]] double probe_interval_for(double end_time) const {
    return probe_interval > 0 ? probe_interval : end_time / 200;
  }
};

struct CaseSettings {
  int dimension = 2;
  std::string scene_type;  // cavity | skewed_cavity | dam_break | slump | column
  SceneSettings scene;
  core::FluidProperties fluid;
  std::vector<double> gravity;   // [m/s²], one entry per dimension
  double spacing = 0;            // Δ [m]
  double smoothing_ratio = 1.6;  // h/Δ [-]
  double time_step = 0;          // δt [s]
  // How time.step: auto chose time_step (empty when the case gives a number).
  std::string time_step_rule;
  double end_time = 0;          // [s]
  double steady_tolerance = 0;  // stop when the centre-line residual drops below; 0: never
  // Slump: stop ("settled") once the kinetic energy has fallen below this share of its peak
  // after the mould has cleared; 0: never (run to end_time, e.g. to reach arrest).
  double settle_energy_ratio = 1e-3;
  // Dam breaks and slumps of a yield-stress law: the end state counts as arrested when no fluid
  // node's stress μ(γ̇)γ̇ exceeds (1 + this) τ₀ (RunSummary::arrested).
  double arrest_stress_tolerance = 0.1;
  // Dam breaks and slumps of a yield-stress law: stop ("arrested") once every probe over this
  // long [s] has passed that test, after one that failed it (the material has yielded; a slump's
  // mould has cleared); 0: never.
  double arrest_hold_time = 0;
  SolverSettings solver;
  OutputSettings output;
  std::vector<WallSettings> walls;                 // scene.walls (slump only so far)
  [[nodiscard]] double gravity_magnitude() const;  // |g| [m/s²]
};

struct Case : core::CaseHeader {  // kind: ldd
  CaseSettings settings;
};

// A cavity scene (cavity, skewed_cavity: the cavity solver); every other scene has a free surface.
[[nodiscard]] bool is_cavity(std::string_view scene_type);

// Reads the LDD part of a case file; throws core::ConfigError naming file:line:col, key,
// expectation and fix (also for a kind other than ldd).
[[nodiscard]] Case read_case(const core::CaseFile& file);
[[nodiscard]] Case load_case(const std::string& path);
[[nodiscard]] Case parse_case(std::string_view text, const std::string& name);

// The settings as a human reads them, every value with its SI unit (`rheosim validate`).
[[nodiscard]] std::string describe(const Case& c);

// The case file's words for the choices: nullopt for a word that is not one of them.
[[nodiscard]] std::optional<Preconditioner> preconditioner_named(std::string_view name);
[[nodiscard]] std::optional<LatticeInterpolation> lattice_interpolation_named(std::string_view name);
[[nodiscard]] std::string_view name_of(Preconditioner p);
[[nodiscard]] std::string_view name_of(LatticeInterpolation i);
[[nodiscard]] std::string_view name_of(GradientChoice g);

}  // namespace rheosim::ldd
