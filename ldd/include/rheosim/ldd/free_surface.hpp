#pragma once
// The LDD time step for free-surface flows in 2D and 3D (LDD §3.2): dam break, slump
// test, resting columns. Nodes are Lagrangian; solid walls are fixed (or moving, a lifted mould)
// wall nodes one layer thick, and every fluid node is classified each step as interior, free
// surface (p = p_atm = 0, LDD eq. 17 third line) or splash (too few neighbours to build operators).
//
// One call to FreeSurfaceSolver::step():
//   1. operators (eqs. 13–16; the gradient centred on the neighbours' centroid unless
//      centred_gradient is off, operators.hpp) on the current cloud; free-surface detection;
//   2. ∇u (eq. 14), E (eq. 4), γ̇ = √(2E:E) (eq. 5), μ(γ̇);
//   3. semi-implicit momentum (eq. 19) with the previous pressure and gravity, p_{n−1} first put
//      on the current classification and geometry (p = 0 on surface, splash and idle wall nodes;
//      nodes that have just turned interior extrapolated from their neighbours; wall pressures
//      re-extrapolated as in the PPE's wall rows), so that a node that has changed kind or a wall
//      node that has moved is seen by the implicit viscous solve rather than corrected by the
//      inviscid projection alone (impose_boundary_pressure, docs/ldd.md):
//        ρ u* − δt ∇·(μ∇u*) = ρ u_{n−1} + δt (−⟨∇p_{n−1}⟩ + ρ g)
//      with the pair viscosity ½(μ_i + μ_j) on eq. 15's coefficients. Departure: eq. 18's
//      explicit 2E∇μ (and the cavity solver's explicit ∇·(μ(∇u)ᵀ)) is left out by default; with
//      transpose_stress it is added, stabilised by a second implicit μ-Laplacian; wall nodes Dirichlet (no slip at the
//      wall's velocity; free-slip walls: the fluid's tangential velocity and the wall's normal one, or the fluid's
//      whole velocity where it moves away from the wall — a wall pushes but never pulls), splash
//      nodes ballistic (u* = u + δt g, no coupling);
//   4. PPE (eq. 17) for the increment φ = p_n − p_{n−1}: interior ⟨∇²φ⟩ = ρ/δt ⟨∇·u*⟩, wall
//      and corner nodes the pressure extrapolated from the fluid (eq. 12 with the hydrostatic
//      offset, which gives n·∇p = ρ n·g at rest; p = 0 where they see only surface nodes), free-surface and
//      splash nodes φ = −p_{n−1} (so p_n = 0; φ = 0 after step 3's update), wall nodes without fluid
//      neighbours φ = −p_{n−1};
//      then u_n = u* − δt/ρ ⟨∇φ⟩ on interior and surface nodes;
//   5. divergence checks (NaN, Courant number, failed solves): DivergenceError, state unchanged;
//   6. advection (eq. 20), moving walls move, fluid nodes are kept wall_clearance·Δ off the walls;
//   7. PBD (Macklin & Müller 2013) that keeps the volume: Jacobi sweeps of the kernel-density
//      constraint C_i = ρ_i/ρ₀ − 1 (ρ_i = W(0) + Σ_j W_ij over fluid and wall neighbours) —
//      two-sided for interior nodes, one-sided (only C_i > 0, i.e. push apart) for surface nodes
//      whose kernel sum is truncated by the void — with each shift capped; velocities follow the
//      shift to first order, u += ⟨∇u⟩·δx (pbd_velocity_correction; off: they keep their velocity).
//
// Free-surface criterion (documented in docs/ldd.md, tested in tests/ldd/test_free_surface.cpp):
// over the neighbours within the search radius R = (h/Δ + skin)·Δ, a fluid node is on the surface
// when any of
//   * empty cone: a probe direction (every 10° in 2D, 64 on the sphere in 3D) has no neighbour,
//     fluid or wall, within surface_cone_angle (35° in 2D, 50° in 3D) of it, directions into a
//     nearby wall counting as covered — a void beside the node;
//   * centroid: |c_i| > surface_offset·Δ, c_i = Σ_fluid x_ij / n_i (n_i counting wall neighbours
//     too) with the components along nearby wall normals removed (a wall is not a free surface);
//   * count: n_i < surface_count·n₀ (fluid + wall neighbours; n₀ the initial median),
//   * fluid support: Σ_fluid W_ij < surface_fluid_weight·(ρ₀ − W(0)) — wall pressures are
//     extrapolated from the fluid, so a node seeing mostly walls has no pressure level of its own
//     (as interior it floated with its wall nodes to 9·10⁶ Pa in the slump),
//   * degenerate stencil: λ_min/λ_max of the moment matrix (eq. 13) < surface_moment_rcond (the
//     neighbours do not span space; below min_moment_rcond it is pseudo-inverted, see docs/ldd.md),
// and a splash node when it has fewer than dimension + 1 neighbours within h. A full
// neighbourhood, including one cut by a wall (the wall nodes stand in for the missing fluid),
// passes all five; a flat surface fails the first two (|c_i| ≈ 0.6 Δ on a square lattice).
#include <algorithm>
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rheosim/core/rheology.hpp"
#include "rheosim/ldd/boundary.hpp"
#include "rheosim/ldd/dry_walls.hpp"
#include "rheosim/ldd/node_cloud.hpp"
#include "rheosim/ldd/node_state.hpp"
#include "rheosim/ldd/operators.hpp"
#include "rheosim/ldd/preconditioner.hpp"
#include "rheosim/ldd/step.hpp"
#include "rheosim/numerics/amg.hpp"
#include "rheosim/numerics/krylov.hpp"
#include "rheosim/numerics/neighbours.hpp"

namespace rheosim::ldd {

namespace detail {
struct Surroundings;  // what a fluid node sees (free_surface_classify.cpp)
}  // namespace detail

// StepParams (step.hpp) and what a free surface adds; gravity has `dimension` entries.
// Its defaults where a free surface needs others than the cavity: eq. 19 solved to 1e-6, three
// PBD sweeps, a 0.3 Δ search skin, sparse-LU preconditioners (2D; case runs choose AMG).
struct FreeSurfaceParams : StepParams {
  FreeSurfaceParams() {
    velocity_tolerance = 1e-6;
    pbd_iterations = 3;
    neighbour_skin = 0.3;
    velocity_preconditioner = Preconditioner::sparse_lu;
  }

  int dimension = 2;
  double surface_offset = 0.3;         // |c_i|/Δ above which a node is on the surface
  double surface_count = 0.7;          // n_i/n₀ below which a node is on the surface
  double surface_cone_angle = 35;      // [°] half-angle of the empty-cone test
  double min_moment_rcond = 0.03;      // λ_min/λ_max of eq. 13's moment matrix below which it is
                                       // pseudo-inverted (weak directions dropped)
  double surface_moment_rcond = 0.01;  // λ_min/λ_max below which the node counts as surface
  bool centred_gradient = true;        // operators.hpp: no self-coupling of ⟨∇p⟩ and ⟨∇·u⟩ (docs/ldd.md)
  // Free-surface nodes use eq. 14 about the node (their own value, p = p_atm, enters) instead of
  // the centred gradient; interior nodes keep centred_gradient. Case key gradient: surface_anchored.
  bool anchored_surface_gradient = false;
  // Wall nodes above the surface (no interior fluid within h): p = p_atm in the gradients (include),
  // p = p_atm left out of them (exclude), or the fluid's extrapolated pressure with every wall
  // pressure unclipped (extrapolate). Case key solver.dry_walls (dry_walls.hpp).
  DryWalls dry_walls = DryWalls::include;
  double surface_fluid_weight = 0.1;  // Σ_fluid W_ij / (ρ₀ − W(0)) below which a node is on the surface
  // Verlet skin [Δ] of the neighbour list: candidates are searched within the search radius +
  // this, and each step keeps those now within the search radius (the same list a fresh search
  // gives) until some node has moved half of it. 0: a fresh search every step.
  double neighbour_reuse_skin = 0.3;
  // A PBD shift δx carries the velocity along to first order, u += ⟨∇u⟩·δx (true), or the node
  // keeps its velocity (false; LDD §3.2 interpolates only after large reorderings).
  bool pbd_velocity_correction = true;
  bool hydrostatic_start = true;  // initial p = ρ|g|·depth below the top fluid node
  // The preconditioners (StepParams) of the PPE and eq. 19: sparse_lu refactorised every step (2D
  // only; in 3D its fill is unusable, >90 s/step at 85k nodes, and it falls back to Jacobi), amg
  // (amg.hpp), or jacobi. Case files: `auto` is amg; in 2D the velocity hierarchy is rebuilt every
  // step and the PPE's kept for 4 steps, in 3D both are reused (and the PPE rows unit-diagonal)
  // (free_surface_params in run_free_surface.cpp, docs/performance.md).
  // Diagnostic: when > 0, every step also runs this many power iterations of its linearised
  // step map (u, p) → (u', p') — predictor, PPE and correction on the step's own matrices, without
  // advection or the no-tension clip — and reports the growth per step in
  // FreeSurfaceStats::step_map_growth (≤ 1: perturbations do not grow). Costs ~3 solves each.
  int stability_probe_iterations = 0;
  // ∇·(2μE) rather than ∇·(μ∇u): ∇·(μ(∇u)ᵀ) on interior nodes, stabilised by a second implicit
  // μ-Laplacian (update_viscosity). Case key solver.viscous_stress: full.
  bool transpose_stress = false;

  void check() const;  // throws std::invalid_argument naming the field and its range
};

// The free-surface step's statistics: StepStats (step.hpp) and its own.
struct FreeSurfaceStats : StepStats {
  std::size_t surface_nodes = 0, splash_nodes = 0;
  std::size_t positivity_guarded = 0;  // nodes whose Laplacian dropped the offset correction
  // Solves that failed and were repeated: with a fresh AMG hierarchy when the kept one was built
  // for an older cloud, and in 2D a pressure solve with the matrix's sparse LU as preconditioner
  // (the failed iterations are counted in the totals).
  int repeated_solves = 0;
  int repeated_with_lu = 0;  // of which: pressure solves repeated with the sparse LU (the rest: fresh AMG)
  // FreeSurfaceParams::stability_probe_iterations > 0: largest growth factor per step of the
  // linearised step map (power iteration) and the node where its mode is largest; 0 otherwise.
  double step_map_growth = 0;
  std::size_t step_map_node = 0;
};

class FreeSurfaceSolver : public NodeState {
 public:
  FreeSurfaceSolver(FreeSurfaceParams params, std::vector<std::shared_ptr<const Boundary>> boundaries, NodeCloud cloud);

  // One time step; throws DivergenceError (state of the last good step kept) on divergence.
  FreeSurfaceStats step();

  [[nodiscard]] int dimension() const { return dim_; }
  [[nodiscard]] const FreeSurfaceParams& params() const { return params_; }

  [[nodiscard]] SolverState state() const;
  // Continues from a state taken from a solver of the same scene and parameters. Throws
  // std::invalid_argument naming the mismatch (node count, a wall node turned fluid or back, a
  // neighbour list that does not fit the cloud).
  void restore(SolverState state);

  // From the next step on, probe the linearised step map with this many power iterations per
  // step (FreeSurfaceParams::stability_probe_iterations; 0: off).
  void set_stability_probe(int iterations) { params_.stability_probe_iterations = std::max(iterations, 0); }
  // Re-runs the free-surface detection on the current cloud (kinds() then holds the result).
  void classify();
  // Fluid volume [m^d]: Σ Δ^d ρ₀/ρ_i over interior nodes + Δ^d per surface/splash node (a node's
  // share of space from its kernel density; surface kernel sums are truncated by the void).
  [[nodiscard]] double fluid_volume() const;
  // Kinetic energy Σ ½ ρ |u|² Δ^d over fluid nodes [J, or J/m in 2D].
  [[nodiscard]] double kinetic_energy() const;
  // Potential energy −Σ ρ g·x Δ^d over fluid nodes [J, or J/m in 2D], with the same node volume
  // as kinetic_energy(): their sum may only fall (gravity's work goes to kinetic energy and
  // viscous dissipation).
  [[nodiscard]] double potential_energy() const;
  // ρ₀ (kernel sum of a full neighbourhood) and n₀ (neighbour count within the search radius).
  [[nodiscard]] double rest_density() const { return rest_density_; }
  [[nodiscard]] double rest_count() const { return rest_count_; }
  // Neighbour searches so far (the rest of the steps filtered the Verlet list).
  [[nodiscard]] std::size_t neighbour_searches() const { return candidate_searches_; }

 private:
  struct LinearSolves;  // free_surface_step.cpp
  // What the velocity correction leaves for the divergence checks.
  struct Correction {
    bool finite = true;       // every velocity and pressure finite
    double max_speed = 0;     // over interior and surface nodes [m/s]
    std::size_t fastest = 0;  // the node that has it
  };
  // The phases of step(), in order (free_surface_step.cpp).
  void update_operators(FreeSurfaceStats& stats);
  void update_viscosity();
  bool solve_momentum(double next_time, LinearSolves& solves, FreeSurfaceStats& stats);
  numerics::KrylovResult solve_pressure(LinearSolves& solves, FreeSurfaceStats& stats);
  Correction correct_velocity();
  void check_divergence(double next_time, const Correction& correction, const numerics::KrylovResult& pressure,
                        bool velocity_converged, FreeSurfaceStats& stats) const;
  void commit_and_advect(double next_time);
  [[nodiscard]] double largest_pbd_shift() const;

  void rebuild_neighbours();
  void keep_laplacian_positive();
  void keep_off_boundaries(std::size_t node, double t, std::span<double> velocity);
  void impose_boundary_pressure();        // previous_pressure_ from pressure_
  void regradient_for_boundary_values();  // dry walls; anchored_surface_gradient, DryWalls::exclude
  void reorder(std::span<const double> velocity_gradient);
  // Power iteration of the linearised step map on this step's matrices: growth per step and the
  // node where the mode is largest (FreeSurfaceParams::stability_probe_iterations).
  void probe_step_map(const numerics::KrylovSettings& velocity_settings,
                      const numerics::KrylovSettings& pressure_settings, FreeSurfaceStats& stats);
  [[nodiscard]] double kernel_density(std::size_t node) const;
  // Shepard average (eq. 12) of pressure_j + ρ g·(x_node − x_j) over the neighbours j that pass
  // `use`: a wall's (or a newly interior node's) pressure from the fluid with the hydrostatic
  // offset; at least 0 when `clip`; 0 without such neighbours (free_surface_internal.hpp).
  template <class Use>
  [[nodiscard]] double extrapolated_pressure(std::size_t node, std::span<const double> pressure, const Use& use,
                                             bool clip) const;
  // classify()'s parts (free_surface_classify.cpp).
  void survey(std::size_t node, double search_radius_squared, double support_radius_squared,
              detail::Surroundings& surroundings) const;
  void classify_walls(double support_radius_squared);

  FreeSurfaceParams params_;
  int dim_;
  std::vector<std::shared_ptr<const Boundary>> boundaries_;
  std::vector<NodeKind> last_kinds_;  // the classification of the previous step
  std::vector<std::uint8_t> corner_;
  std::vector<int> boundary_of_;
  std::vector<double> probe_directions_;
  double search_radius_ = 0, rest_count_ = 0;
  std::size_t laplacian_guarded_ = 0;
  numerics::NeighbourList candidates_;       // Verlet list (neighbour_reuse_skin); empty after a plain search
  std::vector<double> candidate_positions_;  // where the nodes were at the last search
  std::size_t candidate_searches_ = 0, steps_since_search_ = 0;
  std::vector<double> increment_gradient_;
  std::vector<double> previous_pressure_;  // p_{n−1} on the current cloud (impose_boundary_pressure)
  std::vector<double> transpose_stress_;  // ∇·(μ(∇u)ᵀ) − ∇·(μ∇u_{n−1}) on interior nodes (viscous_stress: full)
  std::vector<double> pair_dw_;         // PBD: ∇W/(r ρ₀) per neighbour pair (reorder)
  std::vector<std::uint8_t> dry_wall_;  // this step's dry wall nodes (regradient_for_boundary_values)
};

}  // namespace rheosim::ldd
