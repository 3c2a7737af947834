#pragma once
// Small helpers shared by the free-surface solver's translation units (free_surface*.cpp).
#include <algorithm>
#include <cstddef>
#include <span>

#include "rheosim/ldd/free_surface.hpp"

namespace rheosim::ldd {

template <class Use>
double FreeSurfaceSolver::extrapolated_pressure(std::size_t node, std::span<const double> pressure, const Use& use,
                                                bool clip) const {
  const auto dim = static_cast<std::size_t>(dimension());
  double wsum = 0, source = 0;
  for (std::size_t k = neighbours_.offsets[node]; k < neighbours_.offsets[node + 1]; ++k) {
    const std::size_t j = neighbours_.indices[k];
    if (!use(j)) continue;
    double hydrostatic = 0;
    for (std::size_t d = 0; d < dim; ++d)
      hydrostatic += params_.density * params_.gravity[d] * (positions_[dim * node + d] - positions_[dim * j + d]);
    wsum += operators_.weights[k];
    source += operators_.weights[k] * (pressure[j] + hydrostatic);
  }
  if (!(wsum > 0)) return 0.0;
  return clip ? std::max(source / wsum, 0.0) : source / wsum;
}

}  // namespace rheosim::ldd

namespace rheosim::ldd::detail {

// |a − b|² of two points with dim coordinates each.
[[nodiscard]] inline double squared_distance(const double* a, const double* b, std::size_t dim) {
  double s = 0;
  for (std::size_t d = 0; d < dim; ++d) s += (a[d] - b[d]) * (a[d] - b[d]);
  return s;
}

}  // namespace rheosim::ldd::detail
