#pragma once
// LDD's discrete differential operators on a point cloud (LDD §3.1, eqs. 12–16), precomputed as
// one coefficient set per neighbour pair so that applying them (and the matrix-free solvers
// built on them) is a sparse product over the neighbour list.
//
//   weight       W(r, h) = (1 − r/h)³ for r < h, else 0                          (LDD §3.1)
//   Shepard      ⟨f(x)⟩ = Σ W_j f_j / Σ W_j                                       (LDD eq. 12)
//   moment       B_i = (Σ_j W_ij x_ij x_ijᵀ)⁻¹,  x_ij = x_j − x_i                 (LDD eq. 13)
//   gradient     ⟨∇f⟩_i = B_i Σ_j W_ij f_ij x_ij,  f_ij = f_j − f_i               (LDD eq. 14)
//   Laplacian    ⟨∇²f⟩_i = 2d Σ_j W_ij f_ij (1 − x_ij·B_i o_i)
//                          / Σ_j W_ij |x_ij|² (1 − x_ij·B_i o_i)                  (LDD eq. 15)
//   offset       o_i = Σ_j W_ij x_ij                                              (LDD eq. 16)
//   centred gradient (OperatorSettings::centred_gradient, a departure used by the free-surface
//                solver): ⟨∇f⟩_i = C_i Σ_j W_ij f_ij (x_ij − c_i),  c_i = o_i / Σ_j W_ij,
//                C_i = (Σ_j W_ij (x_ij − c_i)(x_ij − c_i)ᵀ)⁻¹
//
// The gradient is exact for linear fields on any cloud whose moment matrix is invertible. The
// Laplacian is exact for quadratics on symmetric lattices (o_i = 0); on disordered clouds its
// error for anisotropic second derivatives (∂²f/∂x² ≠ ∂²f/∂y², ∂²f/∂x∂y ≠ 0) is O(1) and does
// not vanish under refinement (measured in tests/ldd/test_operators.cpp), so node
// quality is an accuracy control (see the PBD in free_surface.hpp).
//
// Guards (documented in docs/ldd.md):
//  * moment matrix near-singular (too few or collinear neighbours): when its reciprocal
//    condition number λ_min/λ_max < min_moment_rcond, B_i is the pseudo-inverse over the
//    eigen-directions with λ >= min_moment_rcond·λ_max (exact along the directions the
//    neighbours span, zero across them; zero for a node without neighbours);
//  * Laplacian denominator ≤ 0.05 Σ W r² (the offset factors 1 − x·Bo cancelling): the offset
//    correction is dropped for that node (o_i = 0).
// Both are counted per node in Operators::guarded.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rheosim/numerics/neighbours.hpp"

namespace rheosim::ldd {

// W(r, h) = (1 − r/h)³ for 0 <= r < h, else 0 (LDD §3.1).
[[nodiscard]] inline double weight(double r, double h) {
  if (!(r < h)) return 0.0;
  const double s = 1.0 - r / h;
  return s * s * s;
}
// dW/dr [1/m].
[[nodiscard]] inline double weight_derivative(double r, double h) {
  if (!(r < h)) return 0.0;
  const double s = 1.0 - r / h;
  return -3.0 * s * s / h;
}

struct OperatorSettings {
  double support_radius = 0;       // h [m], > 0; pairs farther apart than h get W = 0
  double min_moment_rcond = 1e-3;  // guard threshold on λ_min/λ_max of Σ W x xᵀ
  // Gradient about the neighbours' weighted centroid c_i = o_i / Σ W_ij instead of x_i (see
  // above): coefficients W_ij (Σ W (x_ij − c_i)(x_ij − c_i)ᵀ)⁻¹ (x_ij − c_i), still exact for
  // linear fields, identical to eq. 14 where o_i = 0, and summing to zero, so f_i itself does not
  // enter ⟨∇f⟩_i. Eq. 14's coefficients sum to B_i o_i ≠ 0 on one-sided stencils, which couples
  // a node's pressure to its own velocity and its own divergence (docs/ldd.md, "Small time steps
  // gain energy"). Not for wall rows that impose n·∇p through the wall node's own gradient.
  bool centred_gradient = false;
};

// Per-pair coefficients aligned with a NeighbourList (pair k = neighbour offsets[i] + m of i).
struct Operators {
  int dimension = 2;
  std::vector<double> weights;        // W_ij per pair
  std::vector<double> gradient;       // per pair, dimension values: W_ij B_i x_ij   (eq. 14)
  std::vector<double> laplacian;      // per pair: coefficient a_ij of f_ij         (eq. 15)
  std::vector<double> offset;         // per node, dimension values: o_i            (eq. 16)
  std::vector<std::uint8_t> guarded;  // per node: bit 0 moment-matrix guard, bit 1 Laplacian guard
  std::vector<double> conditioning;   // per node: λ_min/λ_max of the moment matrix (0 without neighbours)

  [[nodiscard]] std::size_t node_count() const { return guarded.size(); }
  [[nodiscard]] std::size_t guarded_count() const;
};

// Coefficients for the cloud `positions` (interleaved, stride dimension = 2 or 3) with
// neighbours `neighbours` (found with a radius >= h; pairs at r >= h get zero weight).
// Parallel over nodes (OpenMP); the result does not depend on the thread count.
[[nodiscard]] Operators build_operators(std::span<const double> positions, int dimension,
                                        const numerics::NeighbourList& neighbours, const OperatorSettings& settings);
// The same into `out`, reusing its storage (a solver rebuilding every step: no fresh pages to
// fault in and zero).
void build_operators(std::span<const double> positions, int dimension, const numerics::NeighbourList& neighbours,
                     const OperatorSettings& settings, Operators& out);

// Rewrites the gradient coefficients of the listed nodes from their pair weights with the
// neighbours j flagged in skip (one flag per node) left out, centred or eq. 14 as settings say:
// the gradient of a node that must not see some of its neighbours' values.
void rebuild_gradients(std::span<const double> positions, const numerics::NeighbourList& neighbours,
                       const OperatorSettings& settings, std::span<const std::size_t> nodes,
                       std::span<const std::uint8_t> skip, Operators& ops);

// ⟨∇f⟩ for every node (eq. 14): out has dimension values per node.
void gradient(const numerics::NeighbourList& neighbours, const Operators& ops, std::span<const double> f,
              std::span<double> out);
// ⟨∇·v⟩ for a vector field v (dimension values per node), from eq. 14 per component.
void divergence(const numerics::NeighbourList& neighbours, const Operators& ops, std::span<const double> v,
                std::span<double> out);
// ⟨∇²f⟩ for every node (eq. 15).
void laplacian(const numerics::NeighbourList& neighbours, const Operators& ops, std::span<const double> f,
               std::span<double> out);
// ⟨∇·(μ(∇u)ᵀ)⟩, the part of the viscous force ∇·(2μE) that ∇·(μ∇u) leaves out:
// out[d·i + a] = Σ_b ∂_b(μ ∂u_b/∂x_a), eq. 14 on each product μ ∂u_b/∂x_a. velocity_gradient
// holds d² values per node, [d²·i + a·d + b] = ∂u_a/∂x_b; viscosity one per node.
void transposed_viscous_force(const numerics::NeighbourList& neighbours, const Operators& ops,
                              std::span<const double> viscosity, std::span<const double> velocity_gradient,
                              std::span<double> out);

}  // namespace rheosim::ldd
