#pragma once
// Deterministic OpenMP work split shared by the Krylov solver and the AMG preconditioner: node
// ranges are contiguous blocks, one per thread, that depend only on the size and the thread
// count, so partial results can be combined in block order (no atomics, no reduction clauses).
#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <span>
#include <utility>

#include "rheosim/numerics/row_blocks.hpp"  // balanced_block_range

namespace rheosim::numerics::detail {

// [begin, end) of block `t` out of `blocks` over n entries.
inline std::pair<std::size_t, std::size_t> block_range(std::size_t n, int t, int blocks) {
  const auto b = static_cast<std::size_t>(blocks);
  const auto tt = static_cast<std::size_t>(t);
  return {n * tt / b, n * (tt + 1) / b};
}

// Calls body(begin, end) on contiguous blocks, one per thread, in parallel. The split depends
// only on n and the thread count.
template <class Body>
void for_blocks(std::size_t n, Body&& body) {
#pragma omp parallel
  {
    const int blocks = omp_get_num_threads();
    const auto [begin, end] = block_range(n, omp_get_thread_num(), blocks);
    body(begin, end);
  }
}

// for_blocks over a sparse pattern's rows, blocks balanced by work (balanced_block_range).
template <class Body>
void for_balanced_blocks(std::span<const std::size_t> offsets, Body&& body) {
#pragma omp parallel
  {
    const auto [begin, end] =
        numerics::balanced_block_range<std::size_t>(offsets, omp_get_thread_num(), omp_get_num_threads());
    body(begin, end);
  }
}

}  // namespace rheosim::numerics::detail
