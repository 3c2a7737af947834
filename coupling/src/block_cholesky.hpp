#pragma once
// Cholesky factor and solve of one symmetric positive-definite 6×6 block (a particle's
// translation + rotation block of a resistance matrix): the block-Jacobi preconditioner of the
// implicit near-field solves.
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>

namespace rheosim::coupling {

// In-place Cholesky factor (lower triangle) of a row-major 6×6 block.
inline void cholesky_6(double* a) {
  for (std::size_t j = 0; j < 6; ++j) {
    double d = a[7 * j];
    for (std::size_t k = 0; k < j; ++k) d -= a[6 * j + k] * a[6 * j + k];
    if (!(d > 0.0)) throw std::runtime_error("near field: preconditioner block is not positive definite");
    a[7 * j] = std::sqrt(d);
    for (std::size_t i = j + 1; i < 6; ++i) {
      double x = a[6 * i + j];
      for (std::size_t k = 0; k < j; ++k) x -= a[6 * i + k] * a[6 * j + k];
      a[6 * i + j] = x / a[7 * j];
    }
  }
}

// x = (L Lᵀ)⁻¹ b for the factor l of cholesky_6.
inline void cholesky_6_solve(const double* l, const double* b, double* x) {
  std::array<double, 6> y{};
  for (std::size_t i = 0; i < 6; ++i) {
    double v = b[i];
    for (std::size_t k = 0; k < i; ++k) v -= l[6 * i + k] * y[k];
    y[i] = v / l[7 * i];
  }
  for (std::size_t i = 6; i-- > 0;) {
    double v = y[i];
    for (std::size_t k = i + 1; k < 6; ++k) v -= l[6 * k + i] * x[k];
    x[i] = v / l[7 * i];
  }
}

}  // namespace rheosim::coupling
