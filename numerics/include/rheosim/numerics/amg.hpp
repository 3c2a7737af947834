#pragma once
// Algebraic multigrid (smoothed aggregation, Vaněk, Mandel & Brezina 1996) as a right
// preconditioner, built for the LDD pressure (LDD eq. 17) and velocity (LDD eq. 19) systems.
//
// Set-up (serial, deterministic): the stencil matrix is assembled with every row scaled to a
// positive diagonal, or optionally a unit one (the PPE mixes Laplacian rows, diagonal < 0, with
// wall rows, diagonal +1; an aggregate summing both would cancel its Galerkin row); strong
// connections |a_ij| ≥ θ √|a_ii a_jj| (in either direction, the matrices are not symmetric; θ
// halves per level) are aggregated greedily in node order; the tentative prolongator is
// piecewise constant on the aggregates and, for smoothed aggregation, smoothed by one damped
// Jacobi step P = (I − ω D⁻¹A_s) P_tent (A_s: the strong entries) with ω = 4/(3 ρ(D⁻¹A_s)) (ρ
// by power iteration); restriction R = Pᵀ and Galerkin coarse operators A_c = R A P, down to a
// coarsest level solved by sparse LU. Rows without off-diagonal entries (Dirichlet rows: walls,
// free-surface nodes) are left out of the aggregates; the smoother solves them.
//
// apply() is one V-cycle from a zero guess with hybrid Gauss–Seidel smoothing: forward sweeps
// before and backward sweeps after the coarse correction, Gauss–Seidel inside each thread's
// contiguous block of rows and Jacobi across blocks, so the result is bit-identical for a given
// thread count.
//
// Reuse on slowly changing matrices (a Lagrangian cloud moves < 0.1 Δ per step, μ(γ̇) changes a
// little): prepare() always takes the current matrix as the finest level (smoother and residual
// are exact) and keeps the prolongators and coarse operators of the last full set-up, which are
// rebuilt every reuse_steps calls or when a solve needed more than reuse_growth × the iterations
// of the first solve after the set-up. The node count must not change between set-ups.
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "rheosim/numerics/krylov.hpp"
#include "rheosim/numerics/neighbours.hpp"

namespace rheosim::numerics {

struct AmgSettings {
  double strength_threshold = 0.08;  // θ of the strong-connection test
  bool smoothed = true;              // smoothed aggregation; false: plain (piecewise-constant) aggregation
  bool unit_diagonal = false;        // scale rows to a unit diagonal (else only to a positive one)
  int pre_sweeps = 1;                // forward Gauss–Seidel sweeps per level before the coarse correction
  int post_sweeps = 1;               // backward sweeps after it
  std::size_t coarsest_size = 500;   // rows at or below which a level is solved directly
  int max_levels = 15;
  int reuse_steps = 50;       // prepare(): full set-up at least every this many calls ...
  double reuse_growth = 1.5;  // ... or when a solve took more than this × the first solve's iterations

  void check() const;  // throws std::invalid_argument naming the field and its range
};

// What a kept hierarchy is made of, for checkpoints: the matrix of its last full set-up (as
// given, with its pattern) and the reuse counters. The set-up is deterministic, so restore()
// rebuilds exactly the hierarchy the preconditioner had. Empty (no matrix) when nothing is kept
// between calls (reuse_steps = 1, or before the first set-up).
struct AmgState {
  std::vector<double> diagonal, off_diagonal;
  std::vector<std::size_t> offsets, columns;  // the pattern of off_diagonal (NeighbourList layout)
  int calls_since_setup = 0;
  int reference_iterations = -1;
  bool setup_due = true;
  std::optional<bool> smoothed;  // the aggregation in use (empty: the settings')
  [[nodiscard]] bool empty() const { return diagonal.empty(); }
};

class AmgPreconditioner {
 public:
  explicit AmgPreconditioner(AmgSettings settings = {});
  ~AmgPreconditioner();
  AmgPreconditioner(AmgPreconditioner&&) noexcept;
  AmgPreconditioner& operator=(AmgPreconditioner&&) noexcept;

  // Full set-up of the hierarchy for a.
  void setup(const StencilMatrix& a);
  // For a time loop: the current a becomes the finest level; the coarse levels are rebuilt only
  // when due (see the header comment). Returns true when it did a full set-up.
  bool prepare(const StencilMatrix& a);
  // Iterations of the Krylov solve that used the hierarchy (drives the reuse policy).
  void record_iterations(int iterations);
  // Plain aggregation from the next set-up on (which becomes due now).
  void use_plain_aggregation();
  [[nodiscard]] bool smoothed() const { return settings_.smoothed; }

  // z = M⁻¹ r, one V-cycle from z = 0.
  void apply(std::span<const double> r, std::span<double> z);
  // apply() as a KrylovSettings::preconditioner (refers to this object, which must outlive it).
  [[nodiscard]] std::function<void(std::span<const double>, std::span<double>)> as_preconditioner();

  [[nodiscard]] AmgState state() const;
  // Rebuilds the hierarchy of `state` (or forgets the hierarchy when the state is empty).
  void restore(const AmgState& state);

  [[nodiscard]] bool ready() const;
  [[nodiscard]] std::size_t levels() const;
  [[nodiscard]] std::size_t rows(std::size_t level) const;
  // Σ nnz(A_l) / nnz(A_0): the memory and smoothing work of a cycle relative to the fine matrix.
  [[nodiscard]] double operator_complexity() const;
  [[nodiscard]] std::size_t setups() const { return setups_; }

 private:
  struct Hierarchy;
  AmgSettings settings_;
  std::unique_ptr<Hierarchy> hierarchy_;
  AmgState kept_;  // the matrix of the last full set-up, when hierarchies are reused (reuse_steps > 1)
  std::size_t setups_ = 0;
  int calls_since_setup_ = 0;
  int reference_iterations_ = -1;  // first solve after the set-up
  bool setup_due_ = true;
};

}  // namespace rheosim::numerics
