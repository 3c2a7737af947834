#pragma once
// Matrix-free Krylov solvers over a neighbour pattern: the LDD pressure (LDD eq. 17) and
// velocity (LDD eq. 19) systems.
//
// A StencilMatrix is a row per node: (A x)_i = diagonal_i x_i + Σ_j off_diagonal_ij x_j over the
// node's neighbours (the pattern of a NeighbourList, which it refers to, never owns). The LDD
// operators are applied pair by pair, so no global sparse matrix is assembled.
//
// bicgstab() is van der Vorst's BiCGStab with right preconditioning (Jacobi unless a
// preconditioner is given). The
// LDD Laplacian is not symmetric, so CG does not apply. Every vector loop and reduction runs
// with OpenMP over contiguous node blocks whose partial sums are added in block order, so the
// iterates are bit-identical for a given thread count (no atomics, no reduction clauses).
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "rheosim/numerics/neighbours.hpp"

namespace rheosim::numerics {

struct StencilMatrix {
  const NeighbourList* pattern = nullptr;  // not owned; must outlive the matrix
  std::vector<double> diagonal;            // per node
  std::vector<double> off_diagonal;        // per pair of `pattern`

  [[nodiscard]] std::size_t size() const { return diagonal.size(); }
  // out = A x (parallel, deterministic).
  void multiply(std::span<const double> x, std::span<double> out) const;
};

// Groups of unknowns that no uncoupled row (a Dirichlet row such as p = p_atm on a free
// surface) reaches through the matrix's couplings, in either direction: each is a Neumann block,
// singular up to the offset terms. A diagnosis for a failed pressure solve.
struct FloatingGroups {
  std::size_t groups = 0, nodes = 0;  // how many, and their nodes in all
  std::size_t largest = 0;            // nodes in the largest
  std::size_t largest_member = 0;     // one node of the largest
};
[[nodiscard]] FloatingGroups floating_groups(const StencilMatrix& a);

struct KrylovSettings {
  double relative_tolerance = 1e-8;    // stop when ‖b − A x‖₂ <= tol · ‖b‖₂ ...
  double absolute_tolerance = 1e-300;  // ... or <= this
  int max_iterations = 1000;
  // Right preconditioner z = M⁻¹ r; empty: Jacobi (1/diagonal).
  std::function<void(std::span<const double> r, std::span<double> z)> preconditioner;
};

struct KrylovResult {
  int iterations = 0;
  double residual = 0;           // final ‖b − A x‖₂
  double relative_residual = 0;  // residual / ‖b‖₂ (residual itself when b = 0)
  bool converged = false;
};

// Reusable work vectors, so a time loop does not allocate.
struct KrylovWorkspace {
  std::vector<double> r, r_hat, p, v, s, t, p_hat, s_hat;
};

// Solves A x = b, starting from the given x (a warm start). Never throws on non-convergence:
// the caller reads KrylovResult (a breakdown, e.g. ρ = 0, ends the iteration unconverged).
KrylovResult bicgstab(const StencilMatrix& a, std::span<const double> b, std::span<double> x,
                      const KrylovSettings& settings, KrylovWorkspace& work);

// Two systems sharing one matrix, A x_c = b_c for c = 0, 1 (the velocity components of LDD
// eq. 19), with Jacobi right preconditioning; b and x interleaved (b_c of node i at 2i + c).
// Each component runs exactly the arithmetic of bicgstab() with Jacobi (same operations in the
// same order, so the result is bit-identical to two separate calls), but the two share every
// pass over the stencil and the vector updates and dot products of an iteration are fused into
// five passes over memory. A component that has converged (or broken down) stops updating while
// the other continues. settings.preconditioner must be empty.
struct PairKrylovWorkspace {
  std::vector<double> r, r_hat, p, v, s, t, p_hat, s_hat;  // interleaved, 2 values per node
  std::vector<std::uint32_t> offsets, columns;             // the matrix pattern, 32-bit
};
std::array<KrylovResult, 2> bicgstab_jacobi_pair(const StencilMatrix& a, std::span<const double> b, std::span<double> x,
                                                 const KrylovSettings& settings, PairKrylovWorkspace& work);

// Deterministic parallel dot product (block partial sums added in block order).
[[nodiscard]] double parallel_dot(std::span<const double> a, std::span<const double> b);

}  // namespace rheosim::numerics
