// The volume-keeping PBD reordering after advection (Macklin & Müller 2013) (free_surface.hpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "free_surface_internal.hpp"
#include "rheosim/ldd/free_surface.hpp"

namespace rheosim::ldd {

void FreeSurfaceSolver::apply_pbd(std::span<const double> grad_u) {
  const auto dim = static_cast<std::size_t>(dimension());
  const std::size_t n = kinds_.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  shift_.resize(dim * n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < static_cast<std::ptrdiff_t>(dim * n); ++s) shift_[static_cast<std::size_t>(s)] = 0.0;
  if (params_.pbd_iterations == 0) return;
  const numerics::NeighbourList& nb = neighbours_;
  const double h = support_radius_, rho0 = rest_density_;
  const double max_shift = params_.pbd_max_shift * params_.spacing;
  const double h2 = h * h;
  // Every entry of both is written in each sweep before it is read: kept between steps, not cleared.
  std::vector<double>& lambda = pbd_lambda_;
  std::vector<double>& step = pbd_step_;
  lambda.resize(n);
  step.resize(dim * n);
  // pbd_surface_tangential (Lind et al. 2012): each surface node's outward unit normal, opposite
  // the kernel-weighted offset of all its neighbours (wall nodes stand in for fluid), and the
  // interior nodes within h of a surface node, whose kernel sums the void truncates as well; both
  // fixed for the step's sweeps.
  std::vector<double> outward;
  std::vector<char> near_surface;
  if (params_.pbd_surface_tangential) {
    outward.assign(dim * n, 0.0);
    near_surface.assign(n, 0);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      if (kinds_[i] != NodeKind::surface && kinds_[i] != NodeKind::interior) continue;
      double offset[3] = {0, 0, 0};
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
        const std::size_t j = nb.indices[k];
        const double r2 = detail::squared_distance(&positions_[dim * i], &positions_[dim * j], dim);
        if (r2 >= h2) continue;
        if (kinds_[j] == NodeKind::surface) near_surface[i] = 1;
        const double w = weight(std::sqrt(r2), h);
        for (std::size_t d = 0; d < dim; ++d) offset[d] += w * (positions_[dim * i + d] - positions_[dim * j + d]);
      }
      if (kinds_[i] != NodeKind::surface) continue;
      double length = 0;
      for (std::size_t d = 0; d < dim; ++d) length += offset[d] * offset[d];
      length = std::sqrt(length);
      if (!(length > 0)) continue;
      for (std::size_t d = 0; d < dim; ++d) outward[dim * i + d] = offset[d] / length;
    }
  }
  pair_dw_.resize(nb.pair_count());
  const std::span<double> pair_dw(pair_dw_);  // ∇W/(r ρ₀) of each pair within h, else 0
  for (int iteration = 0; iteration < params_.pbd_iterations; ++iteration) {
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      lambda[i] = 0.0;
      if (!is_continuum(i)) continue;
      double density = weight(0.0, h), grad_i[3] = {0, 0, 0}, squares = 0;
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
        const std::size_t j = nb.indices[k];
        pair_dw[k] = 0.0;
        const double r2 = detail::squared_distance(&positions_[dim * i], &positions_[dim * j], dim);
        if (r2 >= h2) continue;  // the skin's pairs: W = 0
        const double r = std::sqrt(r2);
        density += weight(r, h);
        if (r <= 0) continue;
        const double dw = weight_derivative(r, h) / r / rho0;  // ∇_i W_ij / ρ₀ = dw (x_i − x_j)
        pair_dw[k] = dw;
        for (std::size_t d = 0; d < dim; ++d) grad_i[d] += dw * (positions_[dim * i + d] - positions_[dim * j + d]);
        if (is_continuum(j)) squares += dw * dw * r * r;  // |∇_j C_i|² (fixed nodes cannot help)
      }
      double constraint = density / rho0 - 1.0;
      // The surface's kernel sum is truncated by the void: only compression is corrected there
      // (and, under pbd_surface_tangential, within h of it).
      if (kinds_[i] == NodeKind::surface || (!near_surface.empty() && near_surface[i]))
        constraint = std::max(constraint, 0.0);
      double denominator = squares;
      for (std::size_t d = 0; d < dim; ++d) denominator += grad_i[d] * grad_i[d];
      lambda[i] = denominator > 0 ? -constraint / denominator : 0.0;
    }
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      for (std::size_t d = 0; d < dim; ++d) step[dim * i + d] = 0.0;
      if (!is_continuum(i)) continue;
      double shift[3] = {0, 0, 0};
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
        const double dw = pair_dw[k];  // the positions have not moved since λ
        if (dw == 0.0) continue;
        const std::size_t j = nb.indices[k];
        const double factor = (lambda[i] + lambda[j]) * dw * params_.pbd_stiffness;
        for (std::size_t d = 0; d < dim; ++d) shift[d] += factor * (positions_[dim * i + d] - positions_[dim * j + d]);
      }
      if (!outward.empty()) {
        double normal_part = 0;
        for (std::size_t d = 0; d < dim; ++d) normal_part += shift[d] * outward[dim * i + d];
        for (std::size_t d = 0; d < dim; ++d) shift[d] -= normal_part * outward[dim * i + d];
      }
      double length = 0;
      for (std::size_t d = 0; d < dim; ++d) length += shift[d] * shift[d];
      length = std::sqrt(length);
      const double scale = length > max_shift ? max_shift / length : 1.0;
      for (std::size_t d = 0; d < dim; ++d) step[dim * i + d] = scale * shift[d];
    }
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      if (!is_continuum(i)) continue;
      double before[3] = {0, 0, 0};
      for (std::size_t d = 0; d < dim; ++d) {
        before[d] = positions_[dim * i + d];
        positions_[dim * i + d] += step[dim * i + d];
      }
      keep_off_boundaries(i, time_, {});
      for (std::size_t d = 0; d < dim; ++d) shift_[dim * i + d] += positions_[dim * i + d] - before[d];
    }
  }
  // Velocities follow the shift to first order (LDD §3.2: interpolation after reordering).
  if (!params_.pbd_velocity_correction) return;
  const std::size_t dd = dim * dim;
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (!is_continuum(i)) continue;
    for (std::size_t a = 0; a < dim; ++a) {
      double du = 0;
      for (std::size_t b = 0; b < dim; ++b) du += grad_u[dd * i + a * dim + b] * shift_[dim * i + b];
      velocity_[dim * i + a] += du;
      previous_velocity_[dim * i + a] += du;
    }
  }
}

}  // namespace rheosim::ldd
