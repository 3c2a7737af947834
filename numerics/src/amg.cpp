#include "rheosim/numerics/amg.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include "blocks.hpp"
#include "sparse_product.hpp"

namespace rheosim::numerics {
namespace {

using SparseRows = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using SparseColumns = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// Below this many rows a level's loops run on one thread: the parallel region costs more than
// the work (and the split still depends only on the size and the thread count).
constexpr std::size_t parallel_rows = 4096;
constexpr int power_iterations = 15;  // for ρ(D⁻¹A) in the prolongator damping

// A square matrix stored like a StencilMatrix: diagonal apart, then the off-diagonal entries of
// each row.
struct Rows {
  std::vector<double> diagonal;
  std::vector<std::size_t> offsets;  // rows + 1
  std::vector<std::size_t> columns;
  std::vector<double> values;
  [[nodiscard]] std::size_t size() const { return diagonal.size(); }
  [[nodiscard]] std::size_t nonzeros() const { return diagonal.size() + values.size(); }
};

// Row-parallel loop (each row written by one thread: independent of the thread count).
template <class Body>
void for_rows(std::size_t n, Body&& body) {
  const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static) if (n >= parallel_rows)
  for (std::ptrdiff_t s = 0; s < count; ++s) body(static_cast<std::size_t>(s));
}

// The stencil matrix with every row scaled so that its diagonal is positive (or one, with
// unit_diagonal): the LDD systems mix rows of both signs and units (the PPE's Laplacian rows have
// a diagonal ~ −1/Δ², its wall rows +1), and an aggregate summing such rows would cancel or drop
// some of them from the Galerkin operator.
// Written into `out`, whose storage is reused (copy-assignment keeps a large enough capacity).
// Copied and scaled in one row-parallel pass (a serial copy of the pattern and values was ~27 MB
// a solve in the 85 000-node slump, with the other thread idle).
void scaled_rows_of(const StencilMatrix& a, bool unit_diagonal, std::vector<double>& row_scale, Rows& out) {
  const std::vector<std::size_t>& offsets = a.pattern->offsets;
  const std::size_t n = a.diagonal.size();
  out.diagonal.resize(n);
  out.offsets.resize(n + 1);
  out.columns.resize(a.pattern->indices.size());
  out.values.resize(a.off_diagonal.size());
  row_scale.resize(n);
  out.offsets[0] = offsets[0];
  const auto copy_row = [&](std::size_t i) {
    const double d = a.diagonal[i];
    const double scale = d == 0.0 ? 1.0 : unit_diagonal ? 1.0 / d : (d < 0.0 ? -1.0 : 1.0);
    row_scale[i] = scale;
    out.diagonal[i] = scale * d;
    out.offsets[i + 1] = offsets[i + 1];
    for (std::size_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      out.columns[k] = a.pattern->indices[k];
      out.values[k] = scale * a.off_diagonal[k];
    }
  };
  if (n < parallel_rows) {
    for (std::size_t i = 0; i < n; ++i) copy_row(i);
    return;
  }
  for_balanced_rows(offsets, copy_row);
}

// Row by row in column order, the diagonal merged in its place (columns within a row ascend, as
// in a NeighbourList and in galerkin_product): no triplet sort. Zero off-diagonal values are left out.
SparseRows sparse_of(const Rows& a) {
  const auto n = static_cast<Eigen::Index>(a.size());
  SparseRows m(n, n);
  m.reserve(static_cast<Eigen::Index>(a.nonzeros()));
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    m.startVec(row);
    bool diagonal_done = false;
    for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k) {
      if (!diagonal_done && a.columns[k] > i) {
        m.insertBackByOuterInner(row, row) = a.diagonal[i];
        diagonal_done = true;
      }
      if (a.values[k] != 0.0) m.insertBackByOuterInner(row, static_cast<Eigen::Index>(a.columns[k])) = a.values[k];
    }
    if (!diagonal_done) m.insertBackByOuterInner(row, row) = a.diagonal[i];
  }
  m.finalize();
  return m;
}

// body(i) for each row of a compressed row-major matrix (a prolongator or restrictor), in
// parallel above parallel_rows with blocks balanced by the rows' entries.
template <class Body>
void for_sparse_rows(const SparseRows& m, Body&& body) {
  const auto n = static_cast<std::size_t>(m.rows());
  if (n < parallel_rows || !m.isCompressed()) {
    for_rows(n, body);
    return;
  }
  for_balanced_rows(std::span<const SparseRows::StorageIndex>(m.outerIndexPtr(), n + 1), body);
}

// Contiguous blocks of rows, one per thread, balanced by the rows' entries (one block below
// parallel_rows).
template <class Body>
void for_row_blocks(const Rows& a, Body&& body) {
  if (a.size() < parallel_rows) return body(std::size_t{0}, a.size());
  detail::for_balanced_blocks(a.offsets, body);
}

// out = b − A x.
void residual(const Rows& a, std::span<const double> b, std::span<const double> x, std::span<double> out) {
  for_row_blocks(a, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      double sum = b[i] - a.diagonal[i] * x[i];
      for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k) sum -= a.values[k] * x[a.columns[k]];
      out[i] = sum;
    }
  });
}

// One hybrid Gauss–Seidel sweep on A x = b: Gauss–Seidel inside each block of rows (forward or
// backward), the previous sweep's values (`frozen`) for columns in other blocks.
void gauss_seidel(const Rows& a, std::span<const double> b, std::span<double> x, std::vector<double>& frozen,
                  bool forward) {
  const std::size_t n = a.size();
  // One block reads only its own rows: nothing to freeze.
  if (n >= parallel_rows && omp_get_max_threads() > 1) {
    frozen.resize(n);
    for_rows(n, [&](std::size_t i) { frozen[i] = x[i]; });
  }
  for_row_blocks(a, [&](std::size_t begin, std::size_t end) {
    const auto relax = [&](std::size_t i) {
      if (a.diagonal[i] == 0.0) return;
      double sum = b[i];
      for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k) {
        const std::size_t j = a.columns[k];
        sum -= a.values[k] * (j >= begin && j < end ? x[j] : frozen[j]);
      }
      x[i] = sum / a.diagonal[i];
    };
    if (forward) {
      for (std::size_t i = begin; i < end; ++i) relax(i);
    } else {
      for (std::size_t i = end; i-- > begin;) relax(i);
    }
  });
}

// Strong connections, symmetrised (j strong for i or i strong for j); rows without any
// off-diagonal entry (Dirichlet rows) take part in none. Each node's strong neighbours ascend
// (compressed rows), and `entries` flags each off-diagonal entry of a whose column is among them.
struct Strength {
  std::vector<std::size_t> offsets;  // node i's strong neighbours at [offsets[i], offsets[i + 1])
  std::vector<std::size_t> neighbours;
  std::vector<std::uint8_t> entries;  // per off-diagonal entry of a
  [[nodiscard]] std::size_t size() const { return offsets.size() - 1; }
  [[nodiscard]] std::span<const std::size_t> of(std::size_t i) const {
    return {neighbours.data() + offsets[i], offsets[i + 1] - offsets[i]};
  }
};

Strength strong_connections(const Rows& a, double threshold) {
  const std::size_t n = a.size();
  std::vector<std::uint8_t> dirichlet(n);
  for_rows(n, [&](std::size_t i) {
    bool coupled = false;
    for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1] && !coupled; ++k) coupled = a.values[k] != 0.0;
    dirichlet[i] = coupled ? 0 : 1;
  });
  // One-sided strength of each entry, then its reverse entry (j, i) looked up in row j (columns
  // ascend). Patterns from neighbour lists and Galerkin products are structurally symmetric; a
  // strong entry without a reverse falls back to the serial scatter below.
  Strength out;
  std::vector<std::uint8_t> one_sided(a.values.size(), 0);
  for_rows(n, [&](std::size_t i) {
    if (dirichlet[i]) return;
    for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k) {
      const std::size_t j = a.columns[k];
      if (j == i || dirichlet[j] || a.values[k] == 0.0) continue;
      one_sided[k] = std::abs(a.values[k]) >= threshold * std::sqrt(std::abs(a.diagonal[i] * a.diagonal[j])) ? 1 : 0;
    }
  });
  out.entries.assign(a.values.size(), 0);
  std::vector<std::size_t> counts(n, 0);
  std::size_t unpaired = 0;
  const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static) reduction(+ : unpaired) if (n >= parallel_rows)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k) {
      const std::size_t j = a.columns[k];
      const auto row_j = a.columns.begin() + static_cast<std::ptrdiff_t>(a.offsets[j]);
      const auto row_j_end = a.columns.begin() + static_cast<std::ptrdiff_t>(a.offsets[j + 1]);
      const auto reverse = std::lower_bound(row_j, row_j_end, i);
      const bool paired = reverse != row_j_end && *reverse == i;
      if (!paired && one_sided[k]) ++unpaired;
      const bool strong = one_sided[k] || (paired && one_sided[static_cast<std::size_t>(reverse - a.columns.begin())]);
      out.entries[k] = strong ? 1 : 0;
      counts[i] += strong ? 1 : 0;
    }
  }
  out.offsets.assign(n + 1, 0);
  if (unpaired == 0) {
    for (std::size_t i = 0; i < n; ++i) out.offsets[i + 1] = out.offsets[i] + counts[i];
    out.neighbours.resize(out.offsets.back());
    for_rows(n, [&](std::size_t i) {
      std::size_t next = out.offsets[i];
      for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k)
        if (out.entries[k]) out.neighbours[next++] = a.columns[k];
    });
    return out;
  }
  std::vector<std::vector<std::size_t>> strong(n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k)
      if (one_sided[k]) {
        strong[i].push_back(a.columns[k]);
        strong[a.columns[k]].push_back(i);
      }
  for (std::size_t i = 0; i < n; ++i) {
    std::sort(strong[i].begin(), strong[i].end());
    strong[i].erase(std::unique(strong[i].begin(), strong[i].end()), strong[i].end());
    out.neighbours.insert(out.neighbours.end(), strong[i].begin(), strong[i].end());
    out.offsets[i + 1] = out.neighbours.size();
  }
  for_rows(n, [&](std::size_t i) {
    for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k)
      out.entries[k] = std::binary_search(strong[i].begin(), strong[i].end(), a.columns[k]) ? 1 : 0;
  });
  return out;
}

constexpr std::ptrdiff_t unassigned = -1;

// Greedy aggregation (Vaněk et al. 1996): 1) roots whose strong neighbourhood is still free
// become aggregates; 2) the rest join a neighbouring aggregate of step 1; 3) what is left forms
// aggregates of its free neighbourhood. Nodes without strong connections stay unassigned.
std::vector<std::ptrdiff_t> aggregate(const Strength& strength, std::size_t& count) {
  const std::size_t n = strength.size();
  std::vector<std::ptrdiff_t> of(n, unassigned);
  std::ptrdiff_t next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (of[i] != unassigned || strength.of(i).empty()) continue;
    if (std::any_of(strength.of(i).begin(), strength.of(i).end(), [&](std::size_t j) { return of[j] != unassigned; }))
      continue;
    of[i] = next;
    for (std::size_t j : strength.of(i)) of[j] = next;
    ++next;
  }
  const std::vector<std::ptrdiff_t> first = of;
  for (std::size_t i = 0; i < n; ++i) {
    if (of[i] != unassigned) continue;
    for (std::size_t j : strength.of(i))
      if (first[j] != unassigned) {
        of[i] = first[j];
        break;
      }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (of[i] != unassigned || strength.of(i).empty()) continue;
    of[i] = next;
    for (std::size_t j : strength.of(i))
      if (of[j] == unassigned) of[j] = next;
    ++next;
  }
  count = static_cast<std::size_t>(next);
  return of;
}

// ρ(D⁻¹A_s) by power iteration, A_s = diagonal + strong entries (deterministic start vector).
double spectral_radius(const Rows& a, const std::vector<std::uint8_t>& strong) {
  const std::size_t n = a.size();
  std::vector<double> v(n), w(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = 1.0 + static_cast<double>(i % 7) / 7.0;
  double radius = 1.0;
  for (int it = 0; it < power_iterations; ++it) {
    for_rows(n, [&](std::size_t i) {
      double sum = a.diagonal[i] * v[i];
      for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k)
        if (strong[k]) sum += a.values[k] * v[a.columns[k]];
      w[i] = a.diagonal[i] != 0.0 ? sum / a.diagonal[i] : 0.0;
    });
    // Block sums in block order: deterministic per thread count (on one thread, the serial sum).
    const double norm_v = parallel_dot(v, v), norm_w = parallel_dot(w, w);
    if (norm_w == 0.0) return 1.0;
    radius = std::sqrt(norm_w / norm_v);
    const double scale = 1.0 / std::sqrt(norm_w);
    for_rows(n, [&](std::size_t i) { v[i] = w[i] * scale; });
  }
  return radius;
}

// Prolongator: piecewise constant on the aggregates, smoothed by P = (I − ω D⁻¹A_s) P_tent.
// Row-parallel; each entry sums its terms in the order 1, the diagonal's, the strong entries'
// (exact zeros dropped).
detail::CompressedRows prolongator(const Rows& a, const std::vector<std::uint8_t>& strong,
                                   const std::vector<std::ptrdiff_t>& of, std::size_t aggregates, bool smoothed) {
  const std::size_t n = a.size();
  detail::CompressedRows tentative;
  tentative.column_count = aggregates;
  tentative.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (of[i] != unassigned) {
      tentative.columns.push_back(static_cast<std::size_t>(of[i]));
      tentative.values.push_back(1.0);
    }
    tentative.offsets[i + 1] = tentative.columns.size();
  }
  if (!smoothed) return tentative;
  const double omega = 4.0 / 3.0 / spectral_radius(a, strong);
  const int blocks = n >= parallel_rows ? omp_get_max_threads() : 1;
  detail::CompressedRows p = detail::combine_rows(n, tentative, blocks, [&](std::size_t i, auto&& emit) {
    emit(1.0, i);
    if (a.diagonal[i] == 0.0) return;
    const double factor = -omega / a.diagonal[i];
    emit(factor * a.diagonal[i], i);
    for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k)
      if (strong[k]) emit(factor * a.values[k], a.columns[k]);
  });
  std::size_t kept = 0;  // drop exact zeros (in place: rows only shrink)
  std::size_t row_begin = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = row_begin; k < p.offsets[i + 1]; ++k)
      if (p.values[k] != 0.0) {
        p.columns[kept] = p.columns[k];
        p.values[kept] = p.values[k];
        ++kept;
      }
    row_begin = p.offsets[i + 1];
    p.offsets[i + 1] = kept;
  }
  p.columns.resize(kept);
  p.values.resize(kept);
  return p;
}

SparseRows sparse_of(const detail::CompressedRows& m) {
  SparseRows out(static_cast<Eigen::Index>(m.rows()), static_cast<Eigen::Index>(m.column_count));
  out.reserve(static_cast<Eigen::Index>(m.values.size()));
  for (std::size_t i = 0; i < m.rows(); ++i) {
    out.startVec(static_cast<Eigen::Index>(i));
    for (std::size_t k = m.offsets[i]; k < m.offsets[i + 1]; ++k)
      out.insertBackByOuterInner(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(m.columns[k])) = m.values[k];
  }
  out.finalize();
  return out;
}

detail::CompressedRows compressed_of(const SparseRows& m) {
  detail::CompressedRows out;
  out.column_count = static_cast<std::size_t>(m.cols());
  out.offsets.assign(static_cast<std::size_t>(m.rows()) + 1, 0);
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (SparseRows::InnerIterator it(m, i); it; ++it) {
      out.columns.push_back(static_cast<std::size_t>(it.col()));
      out.values.push_back(it.value());
    }
    out.offsets[static_cast<std::size_t>(i) + 1] = out.columns.size();
  }
  return out;
}

// The Galerkin operator Pᵀ A P as two row-parallel products, (A P) then R (A P) with R = Pᵀ;
// A's row i is taken in column order with its diagonal in place.
Rows galerkin_product(const Rows& a, const detail::CompressedRows& p_rows, const SparseRows& r) {
  const int blocks = a.size() >= parallel_rows ? omp_get_max_threads() : 1;
  const detail::CompressedRows a_p = detail::combine_rows(a.size(), p_rows, blocks, [&](std::size_t i, auto&& emit) {
    bool diagonal_done = false;
    for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k) {
      if (!diagonal_done && a.columns[k] > i) {
        emit(a.diagonal[i], i);
        diagonal_done = true;
      }
      if (a.values[k] != 0.0) emit(a.values[k], a.columns[k]);
    }
    if (!diagonal_done) emit(a.diagonal[i], i);
  });
  const detail::CompressedRows r_rows = compressed_of(r);
  const detail::CompressedRows coarse = detail::combine_rows(
      r_rows.rows(), a_p, r_rows.rows() >= parallel_rows ? blocks : 1, [&](std::size_t c, auto&& emit) {
        for (std::size_t k = r_rows.offsets[c]; k < r_rows.offsets[c + 1]; ++k)
          emit(r_rows.values[k], r_rows.columns[k]);
      });
  // The diagonal apart, exact zeros off it dropped (a Rows never stores them).
  const std::size_t m = coarse.rows();
  Rows out;
  out.diagonal.assign(m, 0.0);
  out.offsets.assign(m + 1, 0);
  out.columns.reserve(coarse.columns.size());
  out.values.reserve(coarse.values.size());
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t k = coarse.offsets[i]; k < coarse.offsets[i + 1]; ++k) {
      if (coarse.columns[k] == i) {
        out.diagonal[i] = coarse.values[k];
      } else if (coarse.values[k] != 0.0) {
        out.columns.push_back(coarse.columns[k]);
        out.values.push_back(coarse.values[k]);
      }
    }
    out.offsets[i + 1] = out.columns.size();
  }
  return out;
}

}  // namespace

struct AmgPreconditioner::Hierarchy {
  struct Level {
    Rows a;
    SparseRows p, r;  // to / from the next level (empty on the coarsest)
    std::vector<double> b, x, residual, frozen;
  };
  std::vector<Level> levels;
  std::vector<double> row_scale;  // level 0 is diag(row_scale) A (scaled_rows_of)
  Eigen::SparseLU<SparseColumns, Eigen::COLAMDOrdering<int>> coarse;
  bool coarse_factorised = false;
  std::size_t fine_nonzeros_at_setup = 0;
  std::size_t coarse_nonzeros = 0;  // Σ over levels ≥ 1

  void cycle(std::size_t l, std::span<const double> b, std::span<double> x, const AmgSettings& s) {
    Level& level = levels[l];
    const std::size_t n = level.a.size();
    if (l + 1 == levels.size()) {
      if (coarse_factorised) {
        const Eigen::Map<const Eigen::VectorXd> in(b.data(), static_cast<Eigen::Index>(n));
        Eigen::Map<Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(n)) = coarse.solve(in);
        return;
      }
      std::fill(x.begin(), x.end(), 0.0);  // coarsening stalled and no LU: smooth only
      for (int k = 0; k < s.pre_sweeps + s.post_sweeps; ++k) gauss_seidel(level.a, b, x, level.frozen, k % 2 == 0);
      return;
    }
    std::fill(x.begin(), x.end(), 0.0);
    for (int k = 0; k < s.pre_sweeps; ++k) gauss_seidel(level.a, b, x, level.frozen, true);
    level.residual.resize(n);
    residual(level.a, b, x, level.residual);
    Level& next = levels[l + 1];
    const std::size_t m = next.a.size();
    next.b.resize(m);
    next.x.resize(m);
    for_sparse_rows(level.r, [&](std::size_t i) {
      double sum = 0;
      for (SparseRows::InnerIterator it(level.r, static_cast<Eigen::Index>(i)); it; ++it)
        sum += it.value() * level.residual[static_cast<std::size_t>(it.col())];
      next.b[i] = sum;
    });
    cycle(l + 1, next.b, next.x, s);
    for_sparse_rows(level.p, [&](std::size_t i) {
      double sum = 0;
      for (SparseRows::InnerIterator it(level.p, static_cast<Eigen::Index>(i)); it; ++it)
        sum += it.value() * next.x[static_cast<std::size_t>(it.col())];
      x[i] += sum;
    });
    for (int k = 0; k < s.post_sweeps; ++k) gauss_seidel(level.a, b, x, level.frozen, false);
  }
};

void AmgSettings::check() const {
  const auto fail = [](const char* field, double value, const char* range) {
    throw std::invalid_argument(fmt::format("AMG: {} = {} is out of range, expected {}", field, value, range));
  };
  if (!(strength_threshold >= 0 && strength_threshold < 1)) fail("strength_threshold", strength_threshold, "[0, 1)");
  if (pre_sweeps < 0 || post_sweeps < 0 || pre_sweeps + post_sweeps < 1)
    fail("pre_sweeps + post_sweeps", pre_sweeps + post_sweeps, ">= 1, each >= 0");
  if (coarsest_size < 1) fail("coarsest_size", static_cast<double>(coarsest_size), ">= 1");
  if (max_levels < 1) fail("max_levels", max_levels, ">= 1");
  if (reuse_steps < 1) fail("reuse_steps", reuse_steps, ">= 1");
  if (!(reuse_growth >= 1)) fail("reuse_growth", reuse_growth, ">= 1");
}

AmgPreconditioner::AmgPreconditioner(AmgSettings settings) : settings_(settings) { settings_.check(); }
AmgPreconditioner::~AmgPreconditioner() = default;
AmgPreconditioner::AmgPreconditioner(AmgPreconditioner&&) noexcept = default;
AmgPreconditioner& AmgPreconditioner::operator=(AmgPreconditioner&&) noexcept = default;

void AmgPreconditioner::setup(const StencilMatrix& a) {
  if (a.pattern == nullptr || a.off_diagonal.size() != a.pattern->pair_count() || a.pattern->node_count() != a.size())
    throw std::invalid_argument("AMG: the stencil matrix does not match its pattern");
  auto h = std::make_unique<Hierarchy>();
  // Room for every level up front: a Level (Eigen matrices inside) is copied, not moved, when the
  // vector grows, and the copies were a tenth of the set-up.
  h->levels.reserve(static_cast<std::size_t>(settings_.max_levels));
  h->levels.emplace_back();
  if (hierarchy_) {  // reuse the old fine level's storage; the old hierarchy is gone either way
    h->levels.back().a = std::move(hierarchy_->levels.front().a);
    hierarchy_.reset();
  }
  scaled_rows_of(a, settings_.unit_diagonal, h->row_scale, h->levels.back().a);
  h->fine_nonzeros_at_setup = h->levels.back().a.nonzeros();
  while (h->levels.size() < static_cast<std::size_t>(settings_.max_levels)) {
    Hierarchy::Level& level = h->levels.back();
    const std::size_t n = level.a.size();
    if (n <= settings_.coarsest_size) break;
    // θ halves per level: Galerkin operators of smoothed aggregation have wider, weaker stencils.
    const double threshold = settings_.strength_threshold * std::pow(0.5, static_cast<double>(h->levels.size() - 1));
    const Strength strength = strong_connections(level.a, threshold);
    std::size_t aggregates = 0;
    const auto of = aggregate(strength, aggregates);
    // Nothing to coarsen, or too little gained for a level's cost.
    if (aggregates == 0 || 10 * aggregates > 9 * n) break;
    const detail::CompressedRows p = prolongator(level.a, strength.entries, of, aggregates, settings_.smoothed);
    level.p = sparse_of(p);
    level.r = level.p.transpose();
    Hierarchy::Level next;
    next.a = galerkin_product(level.a, p, level.r);
    h->levels.push_back(std::move(next));
  }
  for (std::size_t l = 1; l < h->levels.size(); ++l) h->coarse_nonzeros += h->levels[l].a.nonzeros();
  const Hierarchy::Level& last = h->levels.back();
  if (last.a.size() <= 20 * settings_.coarsest_size) {
    const SparseColumns coarse = sparse_of(last.a);
    h->coarse.compute(coarse);
    h->coarse_factorised = h->coarse.info() == Eigen::Success;
  }
  hierarchy_ = std::move(h);
  if (settings_.reuse_steps > 1) {
    kept_.diagonal = a.diagonal;
    kept_.off_diagonal = a.off_diagonal;
    kept_.offsets = a.pattern->offsets;
    kept_.columns = a.pattern->indices;
  }
  ++setups_;
  calls_since_setup_ = 0;
  reference_iterations_ = -1;
  setup_due_ = false;
}

bool AmgPreconditioner::prepare(const StencilMatrix& a) {
  const bool full = setup_due_ || !hierarchy_ || calls_since_setup_ >= settings_.reuse_steps ||
                    hierarchy_->levels.front().a.size() != a.size();
  if (full) {
    setup(a);
  } else {
    scaled_rows_of(a, settings_.unit_diagonal, hierarchy_->row_scale, hierarchy_->levels.front().a);
  }
  ++calls_since_setup_;
  return full;
}

void AmgPreconditioner::record_iterations(int iterations) {
  if (reference_iterations_ < 0) {
    reference_iterations_ = iterations;
    return;
  }
  if (static_cast<double>(iterations) > settings_.reuse_growth * std::max(reference_iterations_, 1)) setup_due_ = true;
}

void AmgPreconditioner::use_plain_aggregation() {
  settings_.smoothed = false;
  setup_due_ = true;
}

void AmgPreconditioner::apply(std::span<const double> r, std::span<double> z) {
  if (!hierarchy_) throw std::logic_error("AMG: apply() before setup()");
  if (r.size() != z.size() || r.size() != hierarchy_->levels.front().a.size())
    throw std::invalid_argument("AMG: vector sizes do not match the matrix");
  // (S A)⁻¹ S r = A⁻¹ r with S = diag(row_scale).
  Hierarchy::Level& fine = hierarchy_->levels.front();
  fine.b.resize(r.size());
  for_rows(r.size(), [&](std::size_t i) { fine.b[i] = hierarchy_->row_scale[i] * r[i]; });
  hierarchy_->cycle(0, fine.b, z, settings_);
}

std::function<void(std::span<const double>, std::span<double>)> AmgPreconditioner::as_preconditioner() {
  return [this](std::span<const double> r, std::span<double> z) { apply(r, z); };
}

AmgState AmgPreconditioner::state() const {
  AmgState s = hierarchy_ ? kept_ : AmgState{};
  s.calls_since_setup = calls_since_setup_;
  s.reference_iterations = reference_iterations_;
  s.setup_due = setup_due_;
  s.smoothed = settings_.smoothed;
  return s;
}

void AmgPreconditioner::restore(const AmgState& state) {
  hierarchy_.reset();
  if (state.smoothed) settings_.smoothed = *state.smoothed;
  kept_ = AmgState{};
  if (!state.empty()) {
    NeighbourList pattern;
    pattern.offsets = state.offsets;
    pattern.indices = state.columns;
    pattern.distances.assign(state.columns.size(), 0.0);  // not read by the set-up
    if (pattern.offsets.size() != state.diagonal.size() + 1 || pattern.offsets.back() != state.off_diagonal.size())
      throw std::invalid_argument("AMG: a kept set-up matrix does not match its pattern");
    setup(StencilMatrix{&pattern, state.diagonal, state.off_diagonal});
  }
  calls_since_setup_ = state.calls_since_setup;
  reference_iterations_ = state.reference_iterations;
  setup_due_ = state.empty() || state.setup_due;
}

bool AmgPreconditioner::ready() const { return hierarchy_ != nullptr; }
std::size_t AmgPreconditioner::levels() const { return hierarchy_ ? hierarchy_->levels.size() : 0; }
std::size_t AmgPreconditioner::rows(std::size_t level) const { return hierarchy_->levels.at(level).a.size(); }
double AmgPreconditioner::operator_complexity() const {
  if (!hierarchy_) return 0;
  return 1.0 +
         static_cast<double>(hierarchy_->coarse_nonzeros) / static_cast<double>(hierarchy_->fine_nonzeros_at_setup);
}

}  // namespace rheosim::numerics
