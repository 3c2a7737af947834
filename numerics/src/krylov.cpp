#include "rheosim/numerics/krylov.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "blocks.hpp"

namespace rheosim::numerics {
namespace {

using detail::block_range;
using detail::for_blocks;

constexpr int max_blocks = 256;
// |r̂·r| below this fraction of ‖r̂‖‖r‖ restarts BiCGStab with a new shadow residual.
constexpr double restart_threshold = 1e-12;

// K sums over contiguous node blocks, one block per thread: body(begin, end) returns its block's
// K sums (kept in local variables: accumulating through a reference to memory stalls every
// iteration on a store), and the blocks' sums are added in block order (deterministic).
template <std::size_t K, class Body>
std::array<double, K> block_sums(std::size_t n, Body&& body) {
  struct alignas(64) Partial {
    std::array<double, K> s{};
  };
  std::array<Partial, max_blocks> partials{};
  int used_blocks = 1;
#pragma omp parallel
  {
    const int blocks = std::min(omp_get_num_threads(), max_blocks);
    const int t = omp_get_thread_num();
    if (t == 0) used_blocks = blocks;
    if (t < blocks) {
      const auto [begin, end] = block_range(n, t, blocks);
      partials[static_cast<std::size_t>(t)].s = body(begin, end);
    }
  }
  std::array<double, K> total{};
  for (int t = 0; t < used_blocks; ++t)
    for (std::size_t k = 0; k < K; ++k) total[k] += partials[static_cast<std::size_t>(t)].s[k];
  return total;
}

// Σ over blocks of partial(begin, end), added in block order.
template <class Partial>
double block_sum(std::size_t n, Partial&& partial) {
  return block_sums<1>(
      n, [&](std::size_t begin, std::size_t end) { return std::array<double, 1>{partial(begin, end)}; })[0];
}

}  // namespace

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
  detail::for_balanced_blocks(nb.offsets, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      double sum = diagonal[i] * x[i];
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) sum += off_diagonal[k] * x[nb.indices[k]];
      out[i] = sum;
    }
  });
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

namespace {

// bicgstab_jacobi_pair's iteration, one method per fused pass over memory. Per component c:
// the scalars of bicgstab() (ρ, α, ω, the residual and its target); `active` until it
// converges or breaks down.
class JacobiPairBicgstab {
 public:
  JacobiPairBicgstab(const StencilMatrix& a, std::span<const double> b, std::span<double> x,
                     const KrylovSettings& settings, PairKrylovWorkspace& w)
      : n_(a.size()), a_(a), b_(b), x_(x), settings_(settings), w_(w) {
    if (b.size() != 2 * n_ || x.size() != 2 * n_ || a.pattern == nullptr || a.pattern->node_count() != n_ ||
        a.off_diagonal.size() != a.pattern->pair_count())
      throw std::invalid_argument(fmt::format("bicgstab_jacobi_pair: sizes do not match a {}-row stencil matrix", n_));
    if (settings.preconditioner) throw std::invalid_argument("bicgstab_jacobi_pair: Jacobi only");
    if (a.pattern->pair_count() >= std::numeric_limits<std::uint32_t>::max())
      throw std::invalid_argument("bicgstab_jacobi_pair: more than 2³² pairs");
    // p and v enter the first update p = r + β (p − ω v) and start at 0; the others are written
    // before they are read.
    for (auto* v : {&w.p, &w.v}) v->assign(2 * n_, 0.0);
    for (auto* v : {&w.r, &w.r_hat, &w.s, &w.t, &w.p_hat, &w.s_hat}) v->resize(2 * n_);
    copy_pattern();
    diagonal_ = a.diagonal.data();
    off_diagonal_ = a.off_diagonal.data();
  }

  std::array<KrylovResult, 2> solve() {
    start();
    for (int it = 1; it <= settings_.max_iterations && (active_[0] || active_[1]); ++it) {
      if (!next_rho(it)) break;
      update_direction();
      multiply_direction();
      intermediate_residual();
      multiply_intermediate();
      update_solution();
    }
    for (std::size_t c = 0; c < 2; ++c)
      if (active_[c]) finish(c, residual_[c]);
    return result_;
  }

 private:
  // 32-bit copies of the pattern: the matrix products stream the stencil from cache, and
  // 4-byte columns cut the bytes per pair from 16 to 12 (the copy costs a fraction of one product).
  void copy_pattern() {
    const NeighbourList& pattern = *a_.pattern;
    w_.offsets.resize(n_ + 1);
    w_.columns.resize(pattern.pair_count());
    for_blocks(n_, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        w_.offsets[i] = static_cast<std::uint32_t>(pattern.offsets[i]);
        for (std::size_t k = pattern.offsets[i]; k < pattern.offsets[i + 1]; ++k)
          w_.columns[k] = static_cast<std::uint32_t>(pattern.indices[k]);
      }
    });
    w_.offsets[n_] = static_cast<std::uint32_t>(pattern.pair_count());
    offsets_ = w_.offsets.data();
    columns_ = w_.columns.data();
  }

  // (A in)_i for both components, summed in StencilMatrix::multiply's order.
  void row(const double* in, std::size_t i, double& out0, double& out1) const {
    double sum0 = diagonal_[i] * in[2 * i], sum1 = diagonal_[i] * in[2 * i + 1];
    for (std::size_t k = offsets_[i]; k < offsets_[i + 1]; ++k) {
      const std::size_t j = columns_[k];
      sum0 += off_diagonal_[k] * in[2 * j];
      sum1 += off_diagonal_[k] * in[2 * j + 1];
    }
    out0 = sum0;
    out1 = sum1;
  }
  // Jacobi: 1/diagonal (1 where the diagonal vanishes), as bicgstab().
  double jacobi(double value, std::size_t i) const { return diagonal_[i] != 0 ? value / diagonal_[i] : value; }

  void finish(std::size_t c, double final_residual) {
    result_[c].residual = final_residual;
    result_[c].relative_residual = b_norm_[c] > 0 ? final_residual / b_norm_[c] : final_residual;
    result_[c].converged = final_residual <= target_[c];
    active_[c] = false;
  }

  // ‖b‖, the targets, r = b − A x, r̂ = r.
  void start() {
    const auto bb = block_sums<2>(n_, [&](std::size_t begin, std::size_t end) {
      double s0 = 0, s1 = 0;
      for (std::size_t i = begin; i < end; ++i) {
        s0 += b_[2 * i] * b_[2 * i];
        s1 += b_[2 * i + 1] * b_[2 * i + 1];
      }
      return std::array<double, 2>{s0, s1};
    });
    b_norm_ = {std::sqrt(bb[0]), std::sqrt(bb[1])};
    for (std::size_t c = 0; c < 2; ++c)
      target_[c] = std::max(settings_.relative_tolerance * b_norm_[c], settings_.absolute_tolerance);
    residual_squared_ = block_sums<2>(n_, [&](std::size_t begin, std::size_t end) {
      double s0 = 0, s1 = 0;
      for (std::size_t i = begin; i < end; ++i) {
        double ax0, ax1;
        row(x_.data(), i, ax0, ax1);
        const double r0 = b_[2 * i] - ax0, r1 = b_[2 * i + 1] - ax1;
        w_.r[2 * i] = w_.r_hat[2 * i] = r0;
        w_.r[2 * i + 1] = w_.r_hat[2 * i + 1] = r1;
        s0 += r0 * r0;
        s1 += r1 * r1;
      }
      return std::array<double, 2>{s0, s1};
    });
    for (std::size_t c = 0; c < 2; ++c) {
      residual_[c] = std::sqrt(residual_squared_[c]);
      r_hat_squared_[c] = rho_next_[c] = residual_squared_[c];  // r̂ = r
      if (residual_[c] <= target_[c]) finish(c, residual_[c]);
    }
  }

  // ρ and β of iteration `it`, or a restart; false when no component is left.
  bool next_rho(int it) {
    beta_ = {};
    restart_ = {false, false};
    for (std::size_t c = 0; c < 2; ++c) {
      if (!active_[c]) continue;
      result_[c].iterations = it;
      double rho_new = rho_next_[c];
      if (!std::isfinite(rho_new)) {
        finish(c, residual_[c]);
        continue;
      }
      beta_[c] = (rho_new / rho_[c]) * (alpha_[c] / omega_[c]);
      if (std::abs(rho_new) <= restart_threshold * std::sqrt(r_hat_squared_[c]) * residual_[c]) {
        // The shadow residual became orthogonal to r: restart with r̂ = r (see bicgstab()).
        restart_[c] = true;
        r_hat_squared_[c] = residual_squared_[c];
        rho_new = residual_[c] * residual_[c];
        beta_[c] = 0;
        omega_[c] = 1;
      }
      rho_[c] = rho_new;
    }
    return active_[0] || active_[1];
  }

  // p = r + β (p − ω v), p̂ = M⁻¹ p.
  void update_direction() {
    const std::array<bool, 2> running = active_;
    for_blocks(n_, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        for (std::size_t c = 0; c < 2; ++c) {
          if (!running[c]) continue;
          const std::size_t m = 2 * i + c;
          if (restart_[c]) {
            w_.r_hat[m] = w_.r[m];
            w_.p[m] = w_.v[m] = 0.0;
          }
          w_.p[m] = w_.r[m] + beta_[c] * (w_.p[m] - omega_[c] * w_.v[m]);
          w_.p_hat[m] = jacobi(w_.p[m], i);
        }
    });
  }

  // v = A p̂, r̂·v, α.
  void multiply_direction() {
    const auto r_hat_v = block_sums<2>(n_, [&](std::size_t begin, std::size_t end) {
      double s0 = 0, s1 = 0;
      for (std::size_t i = begin; i < end; ++i) {
        double v0, v1;
        row(w_.p_hat.data(), i, v0, v1);
        w_.v[2 * i] = v0;
        w_.v[2 * i + 1] = v1;
        s0 += w_.r_hat[2 * i] * v0;
        s1 += w_.r_hat[2 * i + 1] * v1;
      }
      return std::array<double, 2>{s0, s1};
    });
    for (std::size_t c = 0; c < 2; ++c) {
      if (!active_[c]) continue;
      if (r_hat_v[c] == 0 || !std::isfinite(r_hat_v[c])) {
        finish(c, residual_[c]);
        continue;
      }
      alpha_[c] = rho_[c] / r_hat_v[c];
    }
  }

  // s = r − α v, ŝ = M⁻¹ s, s·s. A component whose s is already small takes x += α p̂ and stops
  // (`half` an iteration); the others go on (`full`).
  void intermediate_residual() {
    const std::array<bool, 2> solving = active_;
    const auto s_s = block_sums<2>(n_, [&](std::size_t begin, std::size_t end) {
      double sums[2] = {0, 0};
      for (std::size_t i = begin; i < end; ++i)
        for (std::size_t c = 0; c < 2; ++c) {
          if (!solving[c]) continue;
          const std::size_t m = 2 * i + c;
          const double value = w_.r[m] - alpha_[c] * w_.v[m];
          w_.s[m] = value;
          w_.s_hat[m] = jacobi(value, i);
          sums[c] += value * value;
        }
      return std::array<double, 2>{sums[0], sums[1]};
    });
    half_ = {false, false};
    full_ = {false, false};
    s_norm_ = {};
    for (std::size_t c = 0; c < 2; ++c) {
      if (!solving[c]) continue;
      s_norm_[c] = std::sqrt(s_s[c]);
      (s_norm_[c] <= target_[c] ? half_ : full_)[c] = true;
    }
  }

  // t = A ŝ, t·t, t·s, ω.
  void multiply_intermediate() {
    if (!full_[0] && !full_[1]) return;
    const auto t_sums = block_sums<4>(n_, [&](std::size_t begin, std::size_t end) {
      double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
      for (std::size_t i = begin; i < end; ++i) {
        double t0, t1;
        row(w_.s_hat.data(), i, t0, t1);
        w_.t[2 * i] = t0;
        w_.t[2 * i + 1] = t1;
        s0 += t0 * t0;
        s1 += t1 * t1;
        s2 += t0 * w_.s[2 * i];
        s3 += t1 * w_.s[2 * i + 1];
      }
      return std::array<double, 4>{s0, s1, s2, s3};
    });
    for (std::size_t c = 0; c < 2; ++c)
      if (full_[c]) omega_[c] = t_sums[c] > 0 ? t_sums[2 + c] / t_sums[c] : 0.0;
  }

  // x += α p̂ + ω ŝ, r = s − ω t, r·r and r̂·r (the next ρ); or x += α p̂ (half).
  void update_solution() {
    const auto r_sums = block_sums<4>(n_, [&](std::size_t begin, std::size_t end) {
      double sums[4] = {0, 0, 0, 0};
      for (std::size_t i = begin; i < end; ++i)
        for (std::size_t c = 0; c < 2; ++c) {
          const std::size_t m = 2 * i + c;
          if (half_[c]) {
            x_[m] += alpha_[c] * w_.p_hat[m];
          } else if (full_[c]) {
            x_[m] += alpha_[c] * w_.p_hat[m] + omega_[c] * w_.s_hat[m];
            const double value = w_.s[m] - omega_[c] * w_.t[m];
            w_.r[m] = value;
            sums[c] += value * value;
            sums[2 + c] += w_.r_hat[m] * value;
          }
        }
      return std::array<double, 4>{sums[0], sums[1], sums[2], sums[3]};
    });
    for (std::size_t c = 0; c < 2; ++c) {
      if (half_[c]) {
        finish(c, s_norm_[c]);
      } else if (full_[c]) {
        residual_squared_[c] = r_sums[c];
        residual_[c] = std::sqrt(r_sums[c]);
        rho_next_[c] = r_sums[2 + c];
        if (!std::isfinite(residual_[c]) || residual_[c] <= target_[c] || omega_[c] == 0) finish(c, residual_[c]);
      }
    }
  }

  std::size_t n_;
  const StencilMatrix& a_;
  std::span<const double> b_;
  std::span<double> x_;
  const KrylovSettings& settings_;
  PairKrylovWorkspace& w_;
  const std::uint32_t* offsets_ = nullptr;
  const std::uint32_t* columns_ = nullptr;
  const double* diagonal_ = nullptr;
  const double* off_diagonal_ = nullptr;

  std::array<KrylovResult, 2> result_{};
  std::array<bool, 2> active_{true, true};
  std::array<double, 2> b_norm_{}, target_{}, residual_{}, residual_squared_{}, r_hat_squared_{}, rho_next_{};
  std::array<double, 2> rho_{1, 1}, alpha_{1, 1}, omega_{1, 1};
  // Of the current iteration.
  std::array<double, 2> beta_{}, s_norm_{};
  std::array<bool, 2> restart_{}, half_{}, full_{};
};

}  // namespace

std::array<KrylovResult, 2> bicgstab_jacobi_pair(const StencilMatrix& a, std::span<const double> b, std::span<double> x,
                                                 const KrylovSettings& settings, PairKrylovWorkspace& work) {
  return JacobiPairBicgstab(a, b, x, settings, work).solve();
}

FloatingGroups floating_groups(const StencilMatrix& a) {
  const NeighbourList& nb = *a.pattern;
  const std::size_t n = a.size();
  std::vector<std::size_t> parent(n);
  for (std::size_t i = 0; i < n; ++i) parent[i] = i;
  const auto root = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<char> anchored(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    bool coupled = false;
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k)
      if (a.off_diagonal[k] != 0.0) {
        coupled = true;
        parent[root(i)] = root(nb.indices[k]);
      }
    if (!coupled) anchored[i] = 1;
  }
  std::vector<std::size_t> size(n, 0);
  std::vector<char> group_anchored(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = root(i);
    ++size[r];
    if (anchored[i]) group_anchored[r] = 1;
  }
  FloatingGroups out;
  for (std::size_t r = 0; r < n; ++r) {
    if (size[r] == 0 || group_anchored[r]) continue;
    ++out.groups;
    out.nodes += size[r];
    if (size[r] > out.largest) {
      out.largest = size[r];
      out.largest_member = r;
    }
  }
  return out;
}

}  // namespace rheosim::numerics
