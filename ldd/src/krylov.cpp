#include "rheosim/ldd/krylov.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "blocks.hpp"

namespace rheosim::ldd {
namespace {

using detail::block_range;
using detail::for_blocks;

constexpr int max_blocks = 256;
// |r̂·r| below this fraction of ‖r̂‖‖r‖ restarts BiCGStab with a new shadow residual.
constexpr double restart_threshold = 1e-12;
constexpr std::size_t padding = 8;  // doubles between partial sums: one cache line each

// Σ over blocks of partial(begin, end), added in block order.
template <class Partial>
double block_sum(std::size_t n, Partial&& partial) {
  std::array<double, max_blocks * padding> sums{};
  int used_blocks = 1;
#pragma omp parallel
  {
    const int blocks = std::min(omp_get_num_threads(), max_blocks);
    const int t = omp_get_thread_num();
    if (t == 0) used_blocks = blocks;
    if (t < blocks) {
      const auto [begin, end] = block_range(n, t, blocks);
      sums[static_cast<std::size_t>(t) * padding] = partial(begin, end);
    }
  }
  double total = 0;
  for (int t = 0; t < used_blocks; ++t) total += sums[static_cast<std::size_t>(t) * padding];
  return total;
}

}  // namespace

Preconditioner preconditioner_named(std::string_view name, Preconditioner fallback) {
  if (name == "jacobi") return Preconditioner::jacobi;
  if (name == "lu") return Preconditioner::sparse_lu;
  if (name == "amg") return Preconditioner::amg;
  return fallback;
}

double parallel_dot(std::span<const double> a, std::span<const double> b) {
  if (a.size() != b.size()) throw std::invalid_argument("parallel_dot: sizes differ");
  return block_sum(a.size(), [&](std::size_t begin, std::size_t end) {
    double s = 0;
    for (std::size_t i = begin; i < end; ++i) s += a[i] * b[i];
    return s;
  });
}

void StencilMatrix::multiply(std::span<const double> x, std::span<double> out) const {
  const NeighbourList& nb = *pattern;
  const std::size_t n = size();
  const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    double sum = diagonal[i] * x[i];
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) sum += off_diagonal[k] * x[nb.indices[k]];
    out[i] = sum;
  }
}

KrylovResult bicgstab(const StencilMatrix& a, std::span<const double> b, std::span<double> x,
                      const KrylovSettings& settings, KrylovWorkspace& w) {
  const std::size_t n = a.size();
  if (b.size() != n || x.size() != n || a.pattern == nullptr || a.pattern->node_count() != n ||
      a.off_diagonal.size() != a.pattern->pair_count())
    throw std::invalid_argument(fmt::format("bicgstab: sizes do not match a {}-row stencil matrix", n));
  for (auto* v : {&w.r, &w.r_hat, &w.p, &w.v, &w.s, &w.t, &w.p_hat, &w.s_hat}) v->assign(n, 0.0);

  // Right preconditioner M⁻¹ = 1/diagonal (1 where the diagonal vanishes).
  const auto precondition = [&](std::span<const double> in, std::span<double> out) {
    if (settings.preconditioner) return settings.preconditioner(in, out);
    for_blocks(n, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) out[i] = a.diagonal[i] != 0 ? in[i] / a.diagonal[i] : in[i];
    });
  };

  KrylovResult result;
  const double b_norm = std::sqrt(parallel_dot(b, b));
  const double target = std::max(settings.relative_tolerance * b_norm, settings.absolute_tolerance);
  const auto finish = [&](double residual) {
    result.residual = residual;
    result.relative_residual = b_norm > 0 ? residual / b_norm : residual;
    result.converged = residual <= target;
    return result;
  };

  a.multiply(x, w.r);
  for_blocks(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      w.r[i] = b[i] - w.r[i];
      w.r_hat[i] = w.r[i];
    }
  });
  double residual = std::sqrt(parallel_dot(w.r, w.r));
  if (residual <= target) return finish(residual);

  double rho = 1, alpha = 1, omega = 1;
  for (int it = 1; it <= settings.max_iterations; ++it) {
    result.iterations = it;
    double rho_new = parallel_dot(w.r_hat, w.r);
    if (!std::isfinite(rho_new)) return finish(residual);
    double beta = (rho_new / rho) * (alpha / omega);
    if (std::abs(rho_new) <= restart_threshold * std::sqrt(parallel_dot(w.r_hat, w.r_hat)) * residual) {
      // The shadow residual became orthogonal to r (it happens, e.g., when b lives on Dirichlet
      // rows only): restart with r̂ = r, which makes ρ = ‖r‖² > 0.
      for_blocks(n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          w.r_hat[i] = w.r[i];
          w.p[i] = w.v[i] = 0.0;
        }
      });
      rho_new = residual * residual;
      beta = 0;
      omega = 1;
    }
    rho = rho_new;
    for_blocks(n, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) w.p[i] = w.r[i] + beta * (w.p[i] - omega * w.v[i]);
    });
    precondition(w.p, w.p_hat);
    a.multiply(w.p_hat, w.v);
    const double r_hat_v = parallel_dot(w.r_hat, w.v);
    if (r_hat_v == 0 || !std::isfinite(r_hat_v)) return finish(residual);
    alpha = rho / r_hat_v;
    for_blocks(n, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) w.s[i] = w.r[i] - alpha * w.v[i];
    });
    const double s_norm = std::sqrt(parallel_dot(w.s, w.s));
    if (s_norm <= target) {
      for_blocks(n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) x[i] += alpha * w.p_hat[i];
      });
      return finish(s_norm);
    }
    precondition(w.s, w.s_hat);
    a.multiply(w.s_hat, w.t);
    const double t_t = parallel_dot(w.t, w.t);
    omega = t_t > 0 ? parallel_dot(w.t, w.s) / t_t : 0.0;
    for_blocks(n, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        x[i] += alpha * w.p_hat[i] + omega * w.s_hat[i];
        w.r[i] = w.s[i] - omega * w.t[i];
      }
    });
    residual = std::sqrt(parallel_dot(w.r, w.r));
    if (!std::isfinite(residual)) return finish(residual);
    if (residual <= target) return finish(residual);
    if (omega == 0) return finish(residual);  // breakdown
  }
  return finish(residual);
}

}  // namespace rheosim::ldd
