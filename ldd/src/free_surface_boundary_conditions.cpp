// Boundary values of the free-surface step: the Laplacian guard, the gradients that see boundary values, p_{n−1} on the
// current classification, the wall clearance (free_surface.hpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "free_surface_internal.hpp"
#include "rheosim/ldd/free_surface.hpp"
#include "rheosim/numerics/row_blocks.hpp"

namespace rheosim::ldd {

// Positivity guard: on one-sided neighbourhoods (free surface, a flow's toe) the offset factor
// 1 − x_ij·B_i o_i of eq. 15 turns some coefficients negative, the PPE and momentum rows lose
// diagonal dominance and a lone node's pressure runs away (seen at the dam-break toe). Such nodes
// use eq. 15 without the offset correction (o_i = 0): first order there, all coefficients ≥ 0.
void FreeSurfaceSolver::keep_laplacian_positive() {
  const auto dim = static_cast<std::size_t>(dimension());
  const numerics::NeighbourList& nb = neighbours_;
  const auto count = static_cast<std::ptrdiff_t>(kinds_.size());
  std::size_t guarded = 0;
#pragma omp parallel for schedule(static) reduction(+ : guarded)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const std::size_t begin = nb.offsets[i], end = nb.offsets[i + 1];
    bool negative = false;
    for (std::size_t k = begin; k < end && !negative; ++k) negative = operators_.laplacian[k] < 0;
    if (!negative) continue;
    ++guarded;
    double denominator = 0;
    for (std::size_t k = begin; k < end; ++k)
      denominator +=
          operators_.weights[k] * detail::squared_distance(&positions_[dim * i], &positions_[dim * nb.indices[k]], dim);
    const double scale = denominator > 0 ? 2.0 * static_cast<double>(dim) / denominator : 0.0;
    for (std::size_t k = begin; k < end; ++k) operators_.laplacian[k] = scale * operators_.weights[k];
  }
  laplacian_guarded_ = guarded;
}

// Dry wall nodes: active wall nodes without an interior fluid node within h. They stand above the
// surface and take p = p_atm (the PPE's wall rows, impose_boundary_pressure).
//
// Gradients that must see the boundary values as they are: free-surface nodes their own p = 0
// (anchored_surface_gradient), and fluid nodes beside a dry wall node not that wall node
// (DryWalls::exclude): its p = 0 is not the hydrostatic field's extension there, and a
// contact-line node that counts it loses part of the support that balances gravity.
void FreeSurfaceSolver::regradient_for_boundary_values() {
  const std::size_t n = kinds_.size();
  const numerics::NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  dry_wall_.resize(n);
  numerics::for_balanced_rows(nb.offsets, [&](std::size_t i) {
    dry_wall_[i] = 0;
    if (kinds_[i] != NodeKind::wall && kinds_[i] != NodeKind::corner) return;
    bool wet = false;
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1] && !wet; ++k)
      wet = kinds_[nb.indices[k]] == NodeKind::interior && ops.weights[k] > 0;
    dry_wall_[i] = wet ? 0 : 1;
  });
  const std::span<const std::uint8_t> skip = params_.dry_walls == DryWalls::exclude
                                                 ? std::span<const std::uint8_t>(dry_wall_)
                                                 : std::span<const std::uint8_t>();
  const auto beside_dry_wall = [&](std::size_t i) {
    if (skip.empty()) return false;
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k)
      if (dry_wall_[nb.indices[k]] && ops.weights[k] > 0) return true;
    return false;
  };
  std::vector<std::size_t> centred, anchored;
  for (std::size_t i = 0; i < n; ++i) {
    if (kinds_[i] == NodeKind::surface && params_.anchored_surface_gradient)
      anchored.push_back(i);
    else if (is_continuum(i) && beside_dry_wall(i))
      centred.push_back(i);
  }
  rebuild_gradients(positions_, nb,
                    OperatorSettings{support_radius_, params_.min_moment_rcond, params_.centred_gradient}, centred,
                    skip, operators_);
  rebuild_gradients(positions_, nb, OperatorSettings{support_radius_, params_.min_moment_rcond, false}, anchored, skip,
                    operators_);
}

// previous_pressure_: p_{n−1} evaluated on the current cloud and classification before the
// momentum predictor (pressure_ itself is kept until the step passes its divergence checks).
// Where the classification or the geometry changed, last step's value is not a pressure the
// node can have now:
//   * surface, splash and idle wall nodes: p = p_atm = 0. Left at its old value, a node that had
//     just turned surface kept its hydrostatic pressure until the PPE set φ = −p_{n−1}, and the
//     projection kicked it by δt/ρ · p/Δ — inviscid, unseen by the implicit viscous solve (the
//     viscous time ρΔ²/μ is far below δt in the slump and the dam break);
//   * nodes that have just turned interior: Shepard over their neighbours of known pressure
//     (interior before and now, or surface) with the hydrostatic offset, as a wall node's —
//     instead of the 0 they had as surface nodes. Only the first item made the opposite jump
//     (0 → ρgh, inviscid) the one left, so nodes flickering between the two kinds pushed their
//     neighbours outwards every cycle: the Δ = 10 mm dam break's front ran 24–31 % ahead;
//   * wall nodes: re-extrapolated from the fluid as in the PPE's wall rows (φ = 0 there at rest).
//     A moved wall node (the rising mould, δz = v δt) otherwise kept a pressure off by ρ g δz —
//     a Neumann source over the whole mould that the PPE can drain only through the small top
//     surface: φ ≈ −10 kPa in the 50 000-node slump at δt = 1e-2, clipped to p = 0 everywhere.
// The traction-free surface's normal part: n·σ·n = −p + 2μ n·E·n = 0, so p = 2μ n·E·n on surface
// nodes, with E of u_{n−1} (update_viscosity's gradient) and n the outward unit normal, opposite
// the kernel-weighted offset of the fluid neighbours. A node whose fluid neighbours balance (no
// direction) keeps p = 0.
void FreeSurfaceSolver::update_surface_pressure() {
  const auto dim = static_cast<std::size_t>(dimension());
  const std::size_t n = kinds_.size(), dd = dim * dim;
  if (!params_.surface_normal_stress) {
    surface_pressure_.resize(n, 0.0);  // p_atm everywhere, written once
    return;
  }
  surface_pressure_.assign(n, 0.0);
  const numerics::NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (kinds_[i] != NodeKind::surface) continue;
    double offset[3] = {0, 0, 0};
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
      const std::size_t j = nb.indices[k];
      if (!is_fluid(j)) continue;
      for (std::size_t d = 0; d < dim; ++d)
        offset[d] += ops.weights[k] * (positions_[dim * j + d] - positions_[dim * i + d]);
    }
    double length = 0;
    for (std::size_t d = 0; d < dim; ++d) length += offset[d] * offset[d];
    length = std::sqrt(length);
    if (!(length > 1e-12 * params_.spacing)) continue;
    const double* grad = &velocity_gradient_[dd * i];  // ∂u_a/∂x_b at [a·dim + b]
    double normal_strain = 0;                          // n·E·n = n_a n_b ∂u_a/∂x_b
    for (std::size_t a = 0; a < dim; ++a)
      for (std::size_t b = 0; b < dim; ++b) normal_strain += offset[a] * offset[b] * grad[a * dim + b];
    surface_pressure_[i] = 2.0 * viscosity_[i] * normal_strain / (length * length);
  }
}

void FreeSurfaceSolver::impose_boundary_pressure() {
  const auto count = static_cast<std::ptrdiff_t>(kinds_.size());
  std::vector<double>& p = previous_pressure_;
  p = pressure_;
  for (std::size_t i = 0; i < kinds_.size(); ++i)
    if (kinds_[i] == NodeKind::surface || kinds_[i] == NodeKind::splash || kinds_[i] == NodeKind::idle_wall)
      p[i] = surface_pressure_[i];  // 0 but on surface nodes under surface_normal_stress
  const bool history = last_kinds_.size() == kinds_.size();
  const auto known = [&](std::size_t j) {
    return kinds_[j] == NodeKind::surface || (kinds_[j] == NodeKind::interior && last_kinds_[j] == NodeKind::interior);
  };
  const auto newly_interior = [&](std::size_t i) {
    return history && kinds_[i] == NodeKind::interior && last_kinds_[i] != NodeKind::interior;
  };
  // Two passes, so that each reads only values the other does not write.
  std::vector<double> estimate(kinds_.size(), 0.0);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (newly_interior(i)) estimate[i] = extrapolated_pressure(i, p, known, true);
  }
  for (std::size_t i = 0; i < kinds_.size(); ++i)
    if (newly_interior(i)) p[i] = estimate[i];

  // Walls as the PPE's wall rows: over interior and surface neighbours; p = 0 on dry walls unless
  // DryWalls::extrapolate, which extrapolates to every wall node without the clip.
  const bool extrapolated = params_.dry_walls == DryWalls::extrapolate;
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (kinds_[i] != NodeKind::wall && kinds_[i] != NodeKind::corner) continue;
    const auto fluid = [&](std::size_t j) { return is_continuum(j); };
    p[i] = dry_wall_[i] && !extrapolated ? 0.0 : extrapolated_pressure(i, p, fluid, !extrapolated);
  }
}

void FreeSurfaceSolver::keep_off_boundaries(std::size_t i, double t, std::span<double> velocity) {
  const auto dim = static_cast<std::size_t>(dimension());
  const double clearance = params_.wall_clearance * params_.spacing;
  double normal[3] = {0, 0, 0}, wall_velocity[3] = {0, 0, 0};
  for (const auto& b : boundaries_) {
    double distance = 0;
    if (!b->distance(std::span<const double>(&positions_[dim * i], dim), t, distance, std::span<double>(normal, dim)))
      continue;
    if (distance >= clearance) continue;
    for (std::size_t d = 0; d < dim; ++d) positions_[dim * i + d] += (clearance - distance) * normal[d];
    if (velocity.empty()) continue;
    // Held off the wall, a node must not keep running into it: drop the approach velocity
    // relative to the wall.
    b->velocity(t, std::span<double>(wall_velocity, dim));
    double approach = 0;
    for (std::size_t d = 0; d < dim; ++d) approach += normal[d] * (velocity[dim * i + d] - wall_velocity[d]);
    if (approach < 0)
      for (std::size_t d = 0; d < dim; ++d) velocity[dim * i + d] -= approach * normal[d];
  }
}

}  // namespace rheosim::ldd
