#pragma once
// Small helpers shared by the free-surface solver's translation units (free_surface*.cpp).
#include <cstddef>

#include "rheosim/ldd/free_surface.hpp"

namespace rheosim::ldd::detail {

// |a − b|² of two points with dim coordinates each.
[[nodiscard]] inline double squared_distance(const double* a, const double* b, std::size_t dim) {
  double s = 0;
  for (std::size_t d = 0; d < dim; ++d) s += (a[d] - b[d]) * (a[d] - b[d]);
  return s;
}

}  // namespace rheosim::ldd::detail
