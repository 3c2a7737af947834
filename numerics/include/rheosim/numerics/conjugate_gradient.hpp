#pragma once
// Preconditioned conjugate gradients (Hestenes & Stiefel 1952) for a symmetric positive
// definite A given as a callable, apply(x, out): out = A x, with a symmetric positive definite
// preconditioner callable, precondition(r, z): z = M⁻¹ r. Serial loops in a fixed order, so a
// solve is bit-identical from run to run. Users: the transient fluid solver's pressure (the
// preconditioner is its DFT-in-θ direct solve), the near field's and the suspension box's
// implicit particle velocities (block-Jacobi over each particle's 6×6 block).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <vector>

#include "rheosim/numerics/krylov.hpp"  // KrylovResult

namespace rheosim::numerics {

struct ConjugateGradientSettings {
  double relative_tolerance = 1e-10;  // stop when ‖b − A x‖₂ <= tol · max(‖b‖₂, reference_norm)
  int max_iterations = 1000;
  // A scale at least ‖b‖ for the stopping test, when b is itself the round-off of terms that
  // cancel (a divergence of face fluxes): then tol · ‖b‖ would ask for the impossible.
  double reference_norm = 0;
  // Iterations done even when the start already meets the tolerance (a projection that always
  // applies its correction, however small).
  int min_iterations = 0;
};

// Reusable work vectors, so a time loop does not allocate.
struct ConjugateGradientWorkspace {
  std::vector<double> r, z, p, q;
};

// Solves A x = b from the given x (a warm start). b = 0 gives x = 0. Stops unconverged, without
// throwing, on max_iterations, on a breakdown (pᵀA p <= 0: A or M not positive definite) or on
// a residual that is not finite; the caller reads the result.
template <class Apply, class Precondition>
KrylovResult conjugate_gradient(const Apply& apply, const Precondition& precondition, std::span<const double> b,
                                std::span<double> x, const ConjugateGradientSettings& settings,
                                ConjugateGradientWorkspace& work) {
  const std::size_t n = b.size();
  if (x.size() != n) throw std::invalid_argument("conjugate_gradient: x and b differ in size");
  KrylovResult result;
  double b_norm = 0.0;
  for (double v : b) b_norm += v * v;
  b_norm = std::sqrt(b_norm);
  if (b_norm == 0.0) {
    std::fill(x.begin(), x.end(), 0.0);
    result.converged = true;
    return result;
  }
  const double scale = std::max(b_norm, settings.reference_norm);
  work.r.resize(n);
  work.z.resize(n);
  work.p.resize(n);
  work.q.resize(n);
  std::span<double> r(work.r), z(work.z), p(work.p), q(work.q);
  apply(std::span<const double>(x), q);
  for (std::size_t k = 0; k < n; ++k) r[k] = b[k] - q[k];
  precondition(std::span<const double>(r), z);
  double rz = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    p[k] = z[k];
    rz += r[k] * z[k];
  }
  const auto relative_residual = [&] {
    double s = 0.0;
    for (double v : r) s += v * v;
    result.residual = std::sqrt(s);
    return result.residual / scale;
  };
  result.relative_residual = relative_residual();
  while (true) {
    if (!std::isfinite(result.relative_residual)) break;
    if (result.relative_residual <= settings.relative_tolerance &&
        (result.iterations >= settings.min_iterations || result.residual == 0.0)) {
      result.converged = true;
      break;
    }
    if (result.iterations >= std::max(settings.max_iterations, settings.min_iterations)) break;
    apply(std::span<const double>(p), q);
    double pq = 0.0;
    for (std::size_t k = 0; k < n; ++k) pq += p[k] * q[k];
    if (!(pq > 0.0)) break;
    const double alpha = rz / pq;
    for (std::size_t k = 0; k < n; ++k) {
      x[k] += alpha * p[k];
      r[k] -= alpha * q[k];
    }
    ++result.iterations;
    result.relative_residual = relative_residual();
    precondition(std::span<const double>(r), z);
    double rz_new = 0.0;
    for (std::size_t k = 0; k < n; ++k) rz_new += r[k] * z[k];
    const double beta = rz_new / rz;
    rz = rz_new;
    for (std::size_t k = 0; k < n; ++k) p[k] = z[k] + beta * p[k];
  }
  return result;
}

}  // namespace rheosim::numerics
