#pragma once
// The free surface's scheme of the LDD step (solver.hpp) in 2D and 3D (LDD §3.2): dam break, slump
// test, resting columns. Nodes are Lagrangian; solid walls are fixed (or moving, a lifted mould)
// wall nodes one layer thick, and every fluid node is classified each step as interior, free
// surface (p = p_atm = 0, LDD eq. 17 third line) or splash (too few neighbours to build operators).
//
// One call to Solver::step():
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
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "rheosim/core/rheology.hpp"
#include "rheosim/ldd/boundary.hpp"
#include "rheosim/ldd/dry_walls.hpp"
#include "rheosim/ldd/node_cloud.hpp"
#include "rheosim/ldd/operators.hpp"
#include "rheosim/ldd/preconditioner.hpp"
#include "rheosim/ldd/solver.hpp"
#include "rheosim/ldd/step.hpp"
#include "rheosim/numerics/amg.hpp"
#include "rheosim/numerics/krylov.hpp"
#include "rheosim/numerics/neighbours.hpp"
#include "rheosim/numerics/sparse_lu.hpp"

namespace rheosim::ldd {

namespace detail {
struct Surroundings;  // what a fluid node sees (free_surface_classify.cpp)
}  // namespace detail

// The free surface's parameters are SolverParams (step.hpp) with its defaults; gravity has
// `dimension` entries.
class FreeSurfaceSolver final : public Solver {
 public:
  FreeSurfaceSolver(SolverParams params, std::vector<std::shared_ptr<const Boundary>> boundaries, NodeCloud cloud);

  [[nodiscard]] SolverState state() const override;
  // Continues from a state taken from a solver of the same scene and parameters. Throws
  // std::invalid_argument naming the mismatch (node count, a wall node turned fluid or back, a
  // neighbour list that does not fit the cloud).
  void restore(SolverState state) override;

  // From the next step on, probe the linearised step map with this many power iterations per
  // step (SolverParams::stability_probe_iterations; 0: off).
  void set_stability_probe(int iterations) { params_.stability_probe_iterations = std::max(iterations, 0); }
  // From the next step on (while on), measure how much of the predicted velocity's divergence the
  // projection removes: the mean ⟨∇·u*⟩ and ⟨∇·u⟩ (eq. 13, the PPE's divergence) over the bulk
  // (StepStats::bulk_divergence_*). Off by default: it costs a divergence and a bulk test a step.
  void set_divergence_probe(bool on) { probe_divergence_ = on; }
  // Re-runs the free-surface detection on the current cloud (kinds() then holds the result).
  void classify();
  // Fluid volume [m^d]: Σ Δ^d ρ₀/ρ_i over interior nodes + Δ^d per surface/splash node (a node's
  // share of space from its kernel density; surface kernel sums are truncated by the void).
  [[nodiscard]] double fluid_volume() const;
  // Mean ρ_i/ρ₀ over the bulk: interior nodes with no surface or splash node within h, whose
  // kernel sums the void does not truncate (1 when there are none). Above 1: compressed.
  [[nodiscard]] double bulk_density_ratio() const;
  // Nodes per Δ^d in the bulk, counted in balls of radius bulk_ball_radius·Δ that hold interior
  // nodes only (no surface, splash or wall node), centred on a grid of step bulk_ball_step·Δ over
  // the interior nodes' bounding box (not commensurate with the lattice, so a lattice reads 1 to within
  // the grid's sampling). Unlike a kernel sum, a count over a ball does not depend on how the
  // nodes are arranged: a disordered cloud of the same density reads the same. Empty when fewer
  // than bulk_ball_minimum balls fit in the bulk.
  [[nodiscard]] std::optional<double> bulk_number_density() const;
  static constexpr double bulk_ball_radius = 4.0, bulk_ball_step = 1.37;
  static constexpr std::size_t bulk_ball_minimum = 30;
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
  // The linear solves' settings and factors of one step, from the momentum solve to the end of
  // the pressure solve (the stability probe reuses them).
  struct LinearSolves {
    numerics::SparseLu momentum_lu, pressure_lu, pressure_direct;
    numerics::KrylovSettings velocity, pressure;
  };
  // The phases of step(), in order (free_surface_step.cpp).
  void update_operators(StepStats& stats) override;
  void update_viscosity() override;
  bool solve_momentum(double next_time, StepStats& stats) override;
  [[nodiscard]] double face_viscosity(std::size_t fluid_node, std::size_t neighbour) const;
  numerics::KrylovResult solve_pressure(StepStats& stats) override;
  Correction correct_velocity() override;
  void commit_and_advect(double next_time) override;
  void reorder(StepStats& stats) override;  // the neighbour search and the PBD
  [[nodiscard]] std::string pressure_failure(const StepStats& stats) const override;
  [[nodiscard]] double largest_pbd_shift() const;

  void rebuild_neighbours();
  void keep_laplacian_positive();
  void keep_off_boundaries(std::size_t node, double t, std::span<double> velocity);
  void update_surface_pressure();         // surface_pressure_ (surface_normal_stress), after μ(γ̇)
  void impose_boundary_pressure();        // previous_pressure_ from pressure_
  void regradient_for_boundary_values();  // dry walls; anchored_surface_gradient, DryWalls::exclude
  void apply_pbd(std::span<const double> velocity_gradient);
  // Power iteration of the linearised step map on this step's matrices: growth per step and the
  // node where the mode is largest (SolverParams::stability_probe_iterations).
  void probe_step_map(const numerics::KrylovSettings& velocity_settings,
                      const numerics::KrylovSettings& pressure_settings, StepStats& stats);
  [[nodiscard]] double kernel_density(std::size_t node) const;
  // An interior node with no surface or splash node within h: its kernel sum and its operators
  // are not truncated by the void.
  [[nodiscard]] bool in_bulk(std::size_t node) const;
  // The mean of value_of(node) over the bulk; `none` when the bulk is empty.
  template <class Value>
  [[nodiscard]] double bulk_mean(const Value& value_of, double none) const {
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < kinds_.size(); ++i)
      if (in_bulk(i)) {
        sum += value_of(i);
        ++count;
      }
    return count > 0 ? sum / static_cast<double>(count) : none;
  }
  // Shepard average (eq. 12) of pressure_j + ρ g·(x_node − x_j) over the neighbours j that pass
  // `use`: a wall's (or a newly interior node's) pressure from the fluid with the hydrostatic
  // offset; at least 0 when `clip`; 0 without such neighbours (free_surface_internal.hpp).
  template <class Use>
  [[nodiscard]] double extrapolated_pressure(std::size_t node, std::span<const double> pressure, const Use& use,
                                             bool clip) const;
  // classify()'s parts (free_surface_classify.cpp).
  [[nodiscard]] bool void_is_open(std::size_t i, const double* direction) const;
  void survey(std::size_t node, double search_radius_squared, double support_radius_squared,
              detail::Surroundings& surroundings) const;
  void classify_walls(double support_radius_squared);

  std::vector<std::shared_ptr<const Boundary>> boundaries_;
  LinearSolves solves_;               // this step's (solve_momentum to solve_pressure)
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
  std::vector<double> surface_pressure_;   // 2μ n·E·n on surface nodes (surface_normal_stress), else 0
  std::vector<double> transpose_stress_;  // ∇·(μ(∇u)ᵀ) − ∇·(μ∇u_{n−1}) on interior nodes (viscous_stress: full)
  double rest_density_ = 0;               // ρ₀ of the PBD constraint and the volume (kernel sum, dimensionless)
  std::vector<double> shift_;             // this step's PBD displacement per node
  std::vector<double> pbd_lambda_, pbd_step_;  // PBD: λ per node, each sweep's step per node (apply_pbd)
  std::vector<double> pair_dw_;                // PBD: ∇W/(r ρ₀) per neighbour pair (apply_pbd)
  std::vector<std::uint8_t> dry_wall_;         // this step's dry wall nodes (regradient_for_boundary_values)
  // set_divergence_probe: on, and this step's bulk means of ⟨∇·u*⟩ and ⟨∇·u⟩ [1/s]
  // (correct_velocity), handed to the step's stats in reorder().
  bool probe_divergence_ = false;
  double bulk_divergence_predicted_ = 0, bulk_divergence_ = 0;
};

}  // namespace rheosim::ldd
