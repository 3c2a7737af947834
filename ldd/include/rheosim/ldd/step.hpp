#pragma once
// What every LDD step reads and reports (solver.hpp), whatever its scheme: the one parameter set
// (SolverParams), the statistics of a step (StepStats), the divergence checks of its phase 5 and
// the phase timings. Each field says which scheme reads it where only one does: the lattice
// cavity (cavity_solver.hpp) or the free surface (free_surface.hpp).
#include <cstddef>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "rheosim/core/rheology.hpp"
#include "rheosim/ldd/dry_walls.hpp"
#include "rheosim/ldd/node_reordering.hpp"
#include "rheosim/ldd/preconditioner.hpp"
#include "rheosim/numerics/amg.hpp"
#include "rheosim/numerics/krylov.hpp"

namespace rheosim::ldd {

// The settings of an LDD step (LDD §3.2). The defaults are the free surface's; for_cavity()
// gives the cavity's where they differ.
struct SolverParams {
  int dimension = 2;                               // 2 or 3 (cavities: 2)
  double density = 1.0;                            // ρ [kg/m³], > 0
  std::shared_ptr<const core::Rheology> rheology;  // μ(γ̇), not null
  std::vector<double> gravity{0.0, 0.0};           // F_ext/ρ = g [m/s²], one entry per dimension
  double spacing = 0;                              // Δ [m], > 0
  double smoothing_ratio = 1.6;                    // h/Δ, [1.2, 3]
  double time_step = 0;                            // δt [s], > 0
  double pressure_tolerance = 1e-6;                // BiCGStab relative residual of the PPE (eq. 17), (0, 1)
  double velocity_tolerance = 1e-6;                // BiCGStab relative residual of eq. 19, (0, 1)
  int max_iterations = 2000;                       // per linear solve, >= 1
  double max_courant = 1.0;                        // stop (diverged) when max|u| δt/Δ exceeds this, > 0
  double neighbour_skin = 0.3;                     // search radius h + skin·Δ, [0, 1] (PBD moves nodes)
  // Preconditioners of the PPE and eq. 19: sparse_lu, amg (amg.hpp) or jacobi. The cavity
  // factorises its constant PPE once and offers no sparse LU for eq. 19; the free surface
  // refactorises every step (2D only; in 3D its fill is unusable, >90 s/step at 85k nodes, and it
  // falls back to Jacobi). Case files: `auto` is AMG for a free surface; in 2D its velocity
  // hierarchy is rebuilt every step and the PPE's kept for 4 steps, in 3D both are reused (and the
  // PPE rows unit-diagonal) (free_surface_params in run_free_surface.cpp, docs/performance.md).
  Preconditioner pressure_preconditioner = Preconditioner::sparse_lu;
  Preconditioner velocity_preconditioner = Preconditioner::sparse_lu;
  numerics::AmgSettings pressure_amg, velocity_amg;  // when the preconditioner is amg
  // Free surface, smoothed pressure AMG: plain aggregation from the next set-up on once a solve on
  // a hierarchy set up in the same step needs more than this many iterations (0: never).
  int pressure_amg_switch_iterations = 0;

  // Cavity: U [m/s] and L [m]: the PPE also stops when the RMS divergence left is
  // < pressure_tolerance·U/L; how the velocity returns to the lattice (node_reordering.hpp).
  double velocity_scale = 1.0;
  double length_scale = 1.0;
  LatticeInterpolation interpolation = LatticeInterpolation::quadratic;

  // Free surface: the PBD (Macklin & Müller 2013) after each advection.
  int pbd_iterations = 3;       // sweeps per step (0: none)
  double pbd_stiffness = 0.5;   // fraction of the PBD shift applied per sweep, (0, 1]
  double pbd_max_shift = 0.05;  // per sweep, in units of Δ, (0, 0.5]
  double wall_clearance = 0.5;  // min fluid-node distance to a wall, units of Δ, (0, 1)
  // A PBD shift δx carries the velocity along to first order, u += ⟨∇u⟩·δx (true), or the node
  // keeps its velocity (false; LDD §3.2 interpolates only after large reorderings).
  bool pbd_velocity_correction = true;
  // Surface nodes keep only the part of a PBD shift along the surface, its component along the
  // outward normal (away from the kernel-weighted neighbours, walls included) removed, and interior
  // nodes within h of a surface node correct only compression, as surface nodes do (true; Lind et
  // al. 2012, J. Comput. Phys. 231, 1499); or surface nodes take the whole shift and the interior
  // nodes beside them correct both ways (false). Case key solver.pbd_surface.
  bool pbd_surface_tangential = false;
  // Free surface: the classification (free_surface.hpp).
  double surface_offset = 0.3;         // |c_i|/Δ above which a node is on the surface
  double surface_count = 0.7;          // n_i/n₀ below which a node is on the surface
  double surface_cone_angle = 35;      // [°] half-angle of the empty-cone test
  double surface_moment_rcond = 0.01;  // λ_min/λ_max below which the node counts as surface
  double surface_fluid_weight = 0.1;   // Σ_fluid W_ij / (ρ₀ − W(0)) below which a node is on the surface
  // A node flagged only by the empty cone or the centroid offset stays interior when every void it
  // points to is occupied: a fluid neighbour within 0.7 Δ of the point Δ beyond the node in that
  // direction (the umbrella test of Marrone et al. 2010, Comput. Phys. Commun. 181, 1745). A gap
  // in a disordered interior is not a free surface. Case key solver.surface_detection: umbrella.
  bool surface_umbrella = false;
  // Free surface: the operators and boundary values.
  double min_moment_rcond = 0.03;  // λ_min/λ_max of eq. 13's moment matrix below which it is
                                   // pseudo-inverted (weak directions dropped)
  bool centred_gradient = true;    // operators.hpp: no self-coupling of ⟨∇p⟩ and ⟨∇·u⟩ (docs/ldd.md)
  // Free-surface nodes use eq. 14 about the node (their own value, p = p_atm, enters) instead of
  // the centred gradient; interior nodes keep centred_gradient. Case key gradient: surface_anchored.
  bool anchored_surface_gradient = false;
  // Wall nodes above the surface (no interior fluid within h): p = p_atm in the gradients (include),
  // p = p_atm left out of them (exclude), or the fluid's extrapolated pressure with every wall
  // pressure unclipped (extrapolate). Case key solver.dry_walls (dry_walls.hpp).
  DryWalls dry_walls = DryWalls::include;
  // ∇·(2μE) rather than ∇·(μ∇u): ∇·(μ(∇u)ᵀ) on interior nodes, stabilised by a second implicit
  // μ-Laplacian (update_viscosity). Case key solver.viscous_stress: full. (The cavity always
  // takes ∇·(μ(∇u)ᵀ) explicitly.)
  bool transpose_stress = false;
  // Free-surface nodes carry p = 2μ n·E·n (the normal part of the traction-free condition
  // σ·n = 0, with u_{n−1}'s E and the outward normal of the fluid neighbours) instead of p_atm = 0
  // (LDD eq. 17); the no-tension clip keeps it ≥ 0. Case key solver.surface_stress: normal.
  bool surface_normal_stress = false;
  // The viscosity of the momentum equation's coupling between a fluid node and a wall node: the
  // law at the mean of their shear rates (true), or the mean of their viscosities (false, as
  // between fluid nodes). Next to a no-slip wall the shear rate varies linearly across the sheared
  // layer, and a yield-stress or shear-thinning μ(γ̇) is convex, so the mean viscosity is larger
  // than the viscosity at the mean rate and holds a thin yielded layer back (docs/ldd.md, "The
  // wall's coupling viscosity"). Identical for a Newtonian fluid. Case key
  // solver.wall_viscosity: face_shear_rate.
  bool wall_face_shear_rate = false;
  // Verlet skin [Δ] of the neighbour list: candidates are searched within the search radius +
  // this, and each step keeps those now within the search radius (the same list a fresh search
  // gives) until some node has moved half of it. 0: a fresh search every step.
  double neighbour_reuse_skin = 0.3;
  bool hydrostatic_start = true;  // initial p = ρ|g|·depth below the top fluid node
  // Diagnostic: when > 0, every step also runs this many power iterations of its linearised
  // step map (u, p) → (u', p') — predictor, PPE and correction on the step's own matrices, without
  // advection or the no-tension clip — and reports the growth per step in
  // StepStats::step_map_growth (≤ 1: perturbations do not grow). Costs ~3 solves each.
  int stability_probe_iterations = 0;

  // The cavity's defaults where they differ: eq. 19 solved to 1e-8 with Jacobi, a 0.2 Δ skin.
  [[nodiscard]] static SolverParams for_cavity();

  // Throws std::invalid_argument "LDD solver: <field> = <value> is out of range, expected <range>"
  // for the first field out of its range (gravity: one entry per dimension).
  void check() const;
};

// Thrown by a solver's step() when the solution diverges (NaN, Courant number, failed solves).
// The solver's state is the last good step's.
class DivergenceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What one step reports. The fields a scheme does not have stay 0.
struct StepStats {
  int pressure_iterations = 0;   // BiCGStab iterations (a direct LU solve counts as 1)
  double pressure_residual = 0;  // relative
  int velocity_iterations = 0;   // all components
  double velocity_residual = 0;  // relative, the largest of the components'
  double max_speed = 0;          // [m/s]
  double courant = 0;            // max|u| δt/Δ
  double max_pbd_shift = 0;      // largest PBD displacement this step, in units of Δ
  // The step's pressure / velocity solve did not converge and was accepted (its residual below
  // 1000× the tolerance; beyond that the step stops as diverged).
  bool pressure_accepted_unconverged = false, velocity_accepted_unconverged = false;
  // Cavity: max |⟨∇·u⟩| over fluid nodes before the pressure step [1/s]; nodes using an operator
  // guard (operators.hpp).
  double max_divergence = 0;
  std::size_t guarded_nodes = 0;
  // Free surface: the classification; nodes whose Laplacian dropped the offset correction.
  std::size_t surface_nodes = 0, splash_nodes = 0;
  std::size_t positivity_guarded = 0;
  // Free surface: solves that failed and were repeated: with a fresh AMG hierarchy when the kept
  // one was built for an older cloud, and in 2D a pressure solve with the matrix's sparse LU as
  // preconditioner (the failed iterations are counted in the totals).
  int repeated_solves = 0;
  int repeated_with_lu = 0;  // of which: pressure solves repeated with the sparse LU (the rest: fresh AMG)
  // solver.pressure_amg: auto turned the pressure AMG to plain aggregation after this step's solve:
  // the iterations of the solve on the step's fresh smoothed hierarchy that did it (0: no switch).
  int pressure_amg_to_plain = 0;
  // SolverParams::stability_probe_iterations > 0: largest growth factor per step of the
  // linearised step map (power iteration) and the node where its mode is largest; 0 otherwise.
  double step_map_growth = 0;
  std::size_t step_map_node = 0;
  // FreeSurfaceSolver::set_divergence_probe: the mean ⟨∇·u*⟩ of the predicted velocity and ⟨∇·u⟩
  // of the projected one over the bulk [1/s]; 0 otherwise.
  double bulk_divergence_predicted = 0, bulk_divergence = 0;
};

// Phase 5 of the step, before anything is committed: what the checks read.
struct StepCheck {
  double next_time = 0;             // [s]
  std::size_t step = 0;             // this step's number
  bool finite = true;               // every new velocity and pressure
  double max_speed = 0;             // over the nodes that limit the Courant number [m/s]
  numerics::KrylovResult pressure;  // the PPE's solve
  bool velocity_converged = true;   // eq. 19's solves (their residual is in the stats)
  // What the solver adds to a message: where the fastest node is (" at a wall node at …"), and
  // after "… after N iterations " why a pressure solve may have failed ("(tolerance 1e-6)").
  std::function<std::string()> where_fastest, pressure_failure;
};
// Sets stats' max_speed, courant and accepted-unconverged flags; throws DivergenceError for a
// non-finite value, a Courant number above params.max_courant, or a solve 10³ above its tolerance.
void check_step(const StepCheck& check, const SolverParams& params, StepStats& stats);

// Wall-clock seconds per phase, accumulated over all steps (for the benchmark and summary.json).
struct PhaseTimes {
  double neighbours = 0, operators = 0, rheology = 0, pressure = 0, momentum = 0, advection = 0, reordering = 0;
  friend bool operator==(const PhaseTimes&, const PhaseTimes&) = default;
  [[nodiscard]] double total() const {
    return neighbours + operators + rheology + pressure + momentum + advection + reordering;
  }
};

}  // namespace rheosim::ldd
