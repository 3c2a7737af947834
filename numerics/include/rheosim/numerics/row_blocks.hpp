#pragma once
// Static OpenMP splits of n rows into one contiguous block per thread, which depend only on the
// size (or pattern) and the thread count, so per-block results can be combined in block order:
// even blocks of rows (for_blocks), and blocks of a sparse pattern's rows (a NeighbourList's or a
// matrix's offsets) balanced by each row's work, 1 + its entries (for_balanced_rows): the nodes of
// a cloud differ in their neighbour counts (a base plate's wall rows ~8, the fluid's ~26 in 3D),
// and `schedule(static)` over rows left one thread idle at the end of every such loop.
#include <omp.h>

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

namespace rheosim::numerics {

// [begin, end) of block `t` out of `blocks` over n entries.
[[nodiscard]] inline std::pair<std::size_t, std::size_t> block_range(std::size_t n, int t, int blocks) {
  const auto b = static_cast<std::size_t>(blocks);
  const auto tt = static_cast<std::size_t>(t);
  return {n * tt / b, n * (tt + 1) / b};
}

// Calls body(begin, end) on contiguous blocks, one per thread, in parallel (the block's thread is
// omp_get_thread_num() inside body).
template <class Body>
void for_blocks(std::size_t n, Body&& body) {
#pragma omp parallel
  {
    const auto [begin, end] = block_range(n, omp_get_thread_num(), omp_get_num_threads());
    body(begin, end);
  }
}

// [begin, end) of block `t` out of `blocks` over the rows of `offsets` (rows + 1 entries, any
// unsigned or non-negative integer type: a NeighbourList's or an Eigen row-major matrix's).
template <class Offset>
[[nodiscard]] std::pair<std::size_t, std::size_t> balanced_block_range(std::span<const Offset> offsets, int t,
                                                                       int blocks) {
  const std::size_t n = offsets.size() - 1;
  const auto work = [&](std::size_t i) {  // before row i
    return i + static_cast<std::size_t>(offsets[i]) - static_cast<std::size_t>(offsets[0]);
  };
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

// body(i) for every row, in parallel, each thread over its balanced block in row order. For
// loops whose rows are independent: the result is the serial loop's, whatever the thread count.
template <class Offset, class Body>
void for_balanced_rows(std::span<const Offset> offsets, Body&& body) {
#pragma omp parallel
  {
    const auto [begin, end] = balanced_block_range(offsets, omp_get_thread_num(), omp_get_num_threads());
    for (std::size_t i = begin; i < end; ++i) body(i);
  }
}

template <class Offset, class Body>
void for_balanced_rows(const std::vector<Offset>& offsets, Body&& body) {
  for_balanced_rows(std::span<const Offset>(offsets), std::forward<Body>(body));
}

}  // namespace rheosim::numerics
