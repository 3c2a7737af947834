#pragma once
// Sparse LU factorisation of a StencilMatrix (Eigen's SparseLU underneath), as a direct solve
// or as a Krylov preconditioner.
//
// Two methods:
// - colamd: COLAMD ordering with partial pivoting, Eigen's solve. For a matrix refactorised
//   every step (a Lagrangian cloud).
// - nested_dissection (2D clouds): nested dissection of the node positions with threshold
//   pivoting at 1e-3 (the diagonal is kept unless it is below 1e-3 of its column's largest
//   entry). At 200² nodes the factors hold 3.2 M entries against 5.6 M with COLAMD, and the
//   solve, bound by reading them, takes half the time. The factors are copied out of Eigen's
//   supernodal storage into row-compressed triangles (32-bit columns) and solved row by row.
//   A test solve checks them; when it fails, COLAMD factors are copied and checked the same way.
//   For a matrix factorised once and solved every step.
#include <functional>
#include <memory>
#include <span>

#include "rheosim/numerics/krylov.hpp"  // StencilMatrix

namespace rheosim::numerics {

namespace detail {
struct CopiedLuFactors;
struct EigenLuFactors;
}  // namespace detail

class SparseLu {
 public:
  enum class Method { colamd, nested_dissection };

  SparseLu();
  ~SparseLu();
  SparseLu(SparseLu&&) noexcept;
  SparseLu& operator=(SparseLu&&) noexcept;

  // Factorises a (the previous factors are dropped). nested_dissection needs the 2D node
  // positions {x0, y0, x1, y1, ...} of a's pattern. False when the factorisation (or, for
  // nested_dissection, its test solve) fails; the object is then not ready().
  bool factorise(const StencilMatrix& a, Method method = Method::colamd, std::span<const double> positions = {});
  [[nodiscard]] bool ready() const;

  // x = A⁻¹ b (x and b must not alias). Requires ready().
  void solve(std::span<const double> b, std::span<double> x) const;
  // solve() as a preconditioner callable; refers to *this, which must outlive it.
  [[nodiscard]] std::function<void(std::span<const double>, std::span<double>)> as_preconditioner() const;

 private:
  std::unique_ptr<detail::CopiedLuFactors> copied_;  // nested_dissection
  std::unique_ptr<detail::EigenLuFactors> eigen_;    // colamd
};

}  // namespace rheosim::numerics
