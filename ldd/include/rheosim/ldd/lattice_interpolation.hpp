#pragma once
// Second-order return of the advected velocity to the node lattice (the lattice reordering of
// LDD §3.2, taken every step; cavity_solver.hpp, step 7).
//
// Why not eq. 12 on the advected cloud: Shepard's average Σ W u_j / Σ W is not the identity even
// when nothing moved (δt → 0), so every step smooths the field by O(Δ²): a numerical viscosity
// ∝ Δ²/δt that grows as δt shrinks. Adding the gradient term ⟨∇u⟩_j·(X_i − x'_j) makes the
// average exact for linear fields, but its leading error at zero displacement is
// −½ ⟨r·∇∇u·r⟩_W: an anti-diffusion ∝ Δ²/δt, which is why that form diverged at Re = 1000.
//
// Here instead the node's own value is kept and moved back along its path (semi-Lagrangian): the
// value arriving at lattice place X_i is the one at the departure point X_i − r_i of the field on
// the lattice before advection, from node i's quadratic Taylor polynomial
//   u(X_i − r_i) ≈ u_i − r_i·∇u_i + ½ r_iᵀ ∇∇u_i r_i,
// with the derivatives from a weighted least-squares fit over the neighbours (W of LDD §3.1).
// At zero displacement it returns u_i exactly, so there is no Δ²/δt term; it is exact for
// quadratic fields. The departure offset uses the midpoint rule, r_i = δt (a_i − ½ δt (a·∇)a_i),
// a the advection velocity of eq. 20. Like any second-order scheme it can overshoot near the lid
// corners' velocity jump, so the result is clamped to the range of node i and its upwind
// neighbours ((X_j − X_i)·r_i < 0, i.e. the nodes around the departure point), as in limited
// semi-Lagrangian schemes (Bermejo & Staniforth 1992).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rheosim/ldd/domain.hpp"
#include "rheosim/numerics/neighbours.hpp"

namespace rheosim::ldd {

// Weighted least-squares quadratic fit about every node of a 2D cloud: the derivatives
// D_i = (∂f/∂x, ∂f/∂y, ∂²f/∂x², ∂²f/∂x∂y, ∂²f/∂y²) from the differences f_j − f_i, weights W_ij,
// so that p_i(X_i + r) = f_i + D_i·b(r), b(r) = (r_x, r_y, ½r_x², r_x r_y, ½r_y²). Nodes whose
// neighbours do not determine a quadratic (fewer than 5 in general position) get a linear fit;
// nodes without a linear fit get zero coefficients (p_i = f_i).
class QuadraticFit {
 public:
  static constexpr std::size_t terms = 5;

  QuadraticFit() = default;
  // Coefficients for `positions` (interleaved x, y) and its neighbour list (pairs at r >= h get
  // W = 0). Parallel over nodes; independent of the thread count.
  QuadraticFit(std::span<const double> positions, const numerics::NeighbourList& neighbours, double support_radius);

  [[nodiscard]] bool empty() const { return coefficients_.empty(); }
  // D_i for component `component` of a field with `stride` values per node.
  [[nodiscard]] std::array<double, terms> derivatives(const numerics::NeighbourList& neighbours,
                                                      std::span<const double> field, std::size_t stride,
                                                      std::size_t component, std::size_t node) const;
  [[nodiscard]] std::size_t linear_only_count() const;  // nodes that fell back to a linear fit (or to none)
  [[nodiscard]] double support_radius() const { return support_radius_; }  // h [m]

 private:
  double support_radius_ = 0;
  std::vector<double> coefficients_;  // terms per pair: D_i = Σ_k c_k (f_j − f_i)
  std::vector<std::uint8_t> linear_only_;
};

// b(r) of QuadraticFit: p_i(X_i + r) − f_i = D_i·b(r).
[[nodiscard]] std::array<double, QuadraticFit::terms> taylor_basis(double rx, double ry);

// The semi-Lagrangian return of the velocity to the lattice (header comment). velocity: u on the
// lattice after the momentum step; advection: a of eq. 20 on every node (walls: their own
// velocity); both interleaved x, y. Non-fluid nodes copy their velocity. `limit` = false skips the
// clamp (for tests and the comparison in docs/ldd.md). out is resized to velocity.size().
void return_to_lattice(std::span<const double> positions, std::span<const NodeKind> kinds,
                       const numerics::NeighbourList& neighbours, const QuadraticFit& fit,
                       std::span<const double> velocity, std::span<const double> advection, double time_step,
                       bool limit, std::vector<double>& out);

}  // namespace rheosim::ldd
