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

// The kind's name in messages ("free-surface", "idle wall", …).
[[nodiscard]] inline const char* kind_name(NodeKind k) {
  switch (k) {
    case NodeKind::interior:
      return "interior";
    case NodeKind::surface:
      return "free-surface";
    case NodeKind::splash:
      return "splash";
    case NodeKind::wall:
      return "wall";
    case NodeKind::corner:
      return "corner";
    default:
      return "idle wall";
  }
}

}  // namespace rheosim::ldd::detail
