#pragma once
// Deterministic OpenMP work split shared by the Krylov solver and the AMG preconditioner: node
// ranges are contiguous blocks, one per thread, that depend only on the size and the thread
// count, so partial results can be combined in block order (no atomics, no reduction clauses).
#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <span>
#include <utility>

#include "rheosim/numerics/row_blocks.hpp"  // block_range, for_blocks, balanced_block_range

namespace rheosim::numerics::detail {

using numerics::block_range;  // row_blocks.hpp
using numerics::for_blocks;

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
