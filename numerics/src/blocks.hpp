#pragma once
// Deterministic OpenMP work split shared by the Krylov solver and the AMG preconditioner: node
// ranges are contiguous blocks, one per thread, that depend only on the size and the thread
// count, so partial results can be combined in block order (no atomics, no reduction clauses).
#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <span>
#include <utility>

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

// [begin, end) of block `t` out of `blocks` over the rows of a sparse pattern (offsets: rows + 1
// entries), balanced by each row's work, 1 + its off-diagonal entries: a cloud's short wall rows
// (a base plate's ~8 neighbours against the fluid's ~26) would otherwise leave one thread idle.
// Depends only on the pattern and the block count.
inline std::pair<std::size_t, std::size_t> balanced_block_range(std::span<const std::size_t> offsets, int t,
                                                                int blocks) {
  const std::size_t n = offsets.size() - 1;
  const auto work = [&](std::size_t i) { return i + offsets[i] - offsets[0]; };  // before row i
  const std::size_t total = work(n);
  const auto first_row_from = [&](int b) {
    if (b <= 0) return std::size_t{0};
    if (b >= blocks) return n;
    const std::size_t target = total * static_cast<std::size_t>(b) / static_cast<std::size_t>(blocks);
    std::size_t low = 0, high = n;  // the first row i with work(i) >= target
    while (low < high) {
      const std::size_t mid = low + (high - low) / 2;
      if (work(mid) < target)
        low = mid + 1;
      else
        high = mid;
    }
    return low;
  };
  return {first_row_from(t), first_row_from(t + 1)};
}

// for_blocks over a sparse pattern's rows, blocks balanced by work (balanced_block_range).
template <class Body>
void for_balanced_blocks(std::span<const std::size_t> offsets, Body&& body) {
#pragma omp parallel
  {
    const auto [begin, end] = balanced_block_range(offsets, omp_get_thread_num(), omp_get_num_threads());
    body(begin, end);
  }
}

}  // namespace rheosim::numerics::detail
