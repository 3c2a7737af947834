#pragma once
// Row-parallel sparse products for the AMG set-up's Galerkin operator Pᵀ A P (Gustavson's
// row-by-row scheme with a dense accumulator). Each entry sums its terms in the order the row's
// terms are given, so the result does not depend on the thread count.
#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include "blocks.hpp"  // block_range

namespace rheosim::numerics::detail {

// Compressed rows: row i's entries at [offsets[i], offsets[i + 1]), columns ascending.
struct CompressedRows {
  std::size_t column_count = 0;
  std::vector<std::size_t> offsets{0};
  std::vector<std::size_t> columns;
  std::vector<double> values;
  [[nodiscard]] std::size_t rows() const { return offsets.size() - 1; }
};

// Row i of the result is Σ_t c_t · (row r_t of b), with for_terms(i, emit) calling
// emit(c_t, r_t) for every term in a fixed order. Rows are split into `blocks` contiguous
// blocks computed in parallel (blocks = 1: serial).
template <class ForTerms>
CompressedRows combine_rows(std::size_t rows, const CompressedRows& b, int blocks, ForTerms&& for_terms) {
  struct Block {
    std::vector<std::size_t> counts, columns;
    std::vector<double> values;
  };
  blocks = std::max(blocks, 1);
  std::vector<Block> parts(static_cast<std::size_t>(blocks));
  const auto range = [&](int t) { return block_range(rows, t, blocks); };
#pragma omp parallel for schedule(static) if (blocks > 1)
  for (int t = 0; t < blocks; ++t) {
    constexpr std::size_t unmarked = std::numeric_limits<std::size_t>::max();
    Block& part = parts[static_cast<std::size_t>(t)];
    std::vector<double> sum(b.column_count, 0.0);
    std::vector<std::size_t> mark(b.column_count, unmarked), touched;
    const auto [begin, end] = range(t);
    part.counts.reserve(end - begin);
    for (std::size_t i = begin; i < end; ++i) {
      touched.clear();
      for_terms(i, [&](double coefficient, std::size_t row) {
        for (std::size_t k = b.offsets[row]; k < b.offsets[row + 1]; ++k) {
          const std::size_t c = b.columns[k];
          if (mark[c] != i) {
            mark[c] = i;
            sum[c] = coefficient * b.values[k];
            touched.push_back(c);
          } else {
            sum[c] += coefficient * b.values[k];
          }
        }
      });
      std::sort(touched.begin(), touched.end());
      for (std::size_t c : touched) {
        part.columns.push_back(c);
        part.values.push_back(sum[c]);
      }
      part.counts.push_back(touched.size());
    }
  }
  CompressedRows out;
  out.column_count = b.column_count;
  out.offsets.assign(rows + 1, 0);
  std::vector<std::size_t> first_entry(parts.size() + 1, 0);
  for (int t = 0; t < blocks; ++t) {
    const auto [begin, end] = range(t);
    const Block& part = parts[static_cast<std::size_t>(t)];
    for (std::size_t i = begin; i < end; ++i) out.offsets[i + 1] = out.offsets[i] + part.counts[i - begin];
    first_entry[static_cast<std::size_t>(t) + 1] = out.offsets[end];
  }
  out.columns.resize(out.offsets.back());
  out.values.resize(out.offsets.back());
#pragma omp parallel for schedule(static) if (blocks > 1)
  for (int t = 0; t < blocks; ++t) {
    const Block& part = parts[static_cast<std::size_t>(t)];
    std::copy(part.columns.begin(), part.columns.end(),
              out.columns.begin() + static_cast<std::ptrdiff_t>(first_entry[static_cast<std::size_t>(t)]));
    std::copy(part.values.begin(), part.values.end(),
              out.values.begin() + static_cast<std::ptrdiff_t>(first_entry[static_cast<std::size_t>(t)]));
  }
  return out;
}

}  // namespace rheosim::numerics::detail
