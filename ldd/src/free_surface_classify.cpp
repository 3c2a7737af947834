// Free-surface detection: interior, surface, splash and wall kinds each step (free_surface.hpp).
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

double FreeSurfaceSolver::kernel_density(std::size_t i) const {
  const auto dim = static_cast<std::size_t>(dimension());
  double rho = weight(0.0, support_radius_);
  for (std::size_t k = neighbours_.offsets[i]; k < neighbours_.offsets[i + 1]; ++k) {
    const std::size_t j = neighbours_.indices[k];
    rho +=
        weight(std::sqrt(detail::squared_distance(&positions_[dim * i], &positions_[dim * j], dim)), support_radius_);
  }
  return rho;
}

// What a fluid node sees within the search radius: the directions to its neighbours, the
// offset of its fluid neighbours' centroid, the distinct normals of the walls nearby, and the
// counts and kernel weight the surface criteria read.
struct detail::Surroundings {
  static constexpr std::size_t max_directions = 96;
  // No initialisers: survey() writes every member it reads (a zeroed 2.4 kB per node per step
  // doubled the classification's cost).
  double seen[3 * max_directions];
  std::size_t directions_seen, walls_near, within_search, within_support;
  double centroid[3];
  double wall_normals[3][3];  // distinct normals of the wall nodes nearby (the first walls_near)
  double fluid_weight;        // Σ W_ij over fluid neighbours: what the PPE row actually couples to
};

namespace {

using detail::Surroundings;

// The fluid neighbours' centroid offset, normalised by all neighbours (walls included: the wall
// nodes stand in for missing fluid); next to a wall the wall-normal part of it is the wall's
// doing, not a free surface's, so it is projected out (Gram–Schmidt on the normals).
double wall_projected_offset(Surroundings& at, std::size_t dim) {
  double basis[3][3] = {};
  std::size_t rank = 0;
  for (std::size_t w = 0; w < at.walls_near; ++w) {
    double v[3] = {at.wall_normals[w][0], at.wall_normals[w][1], at.wall_normals[w][2]};
    for (std::size_t b = 0; b < rank; ++b) {
      double dot = 0;
      for (std::size_t d = 0; d < dim; ++d) dot += v[d] * basis[b][d];
      for (std::size_t d = 0; d < dim; ++d) v[d] -= dot * basis[b][d];
    }
    double length = 0;
    for (std::size_t d = 0; d < dim; ++d) length += v[d] * v[d];
    length = std::sqrt(length);
    if (length < 0.3) continue;
    for (std::size_t d = 0; d < dim; ++d) basis[rank][d] = v[d] / length;
    ++rank;
  }
  for (std::size_t b = 0; b < rank; ++b) {
    double dot = 0;
    for (std::size_t d = 0; d < dim; ++d) dot += at.centroid[d] * basis[b][d];
    for (std::size_t d = 0; d < dim; ++d) at.centroid[d] -= dot * basis[b][d];
  }
  double offset = 0;
  for (std::size_t d = 0; d < dim; ++d) offset += at.centroid[d] * at.centroid[d];
  return std::sqrt(offset) / static_cast<double>(at.within_search);
}

// Whether the probe direction `probe` is covered: it points into a nearby wall (whose nodes may sit
// up to ~1.5 Δ away on a sloped or curved boundary such as the Abrams mould), or a neighbour's
// direction lies within the cone half-angle of it. The search starts at neighbour `hint` and
// leaves it at the covering one (neighbouring probes are mostly covered by the same direction).
bool probe_covered(const Surroundings& at, const double* probe, std::size_t dim, double cone_cosine,
                   std::size_t& hint) {
  for (std::size_t w = 0; w < at.walls_near; ++w) {
    double dot = 0;
    for (std::size_t d = 0; d < dim; ++d) dot -= probe[d] * at.wall_normals[w][d];
    if (dot > 0.3) return true;
  }
  for (std::size_t tried = 0; tried < at.directions_seen; ++tried) {
    const std::size_t m = (hint + tried) % at.directions_seen;
    double dot = 0;
    for (std::size_t d = 0; d < dim; ++d) dot += probe[d] * at.seen[3 * m + d];
    if (dot > cone_cosine) {
      hint = m;
      return true;
    }
  }
  return false;
}

// Empty-cone test: some probe direction with no neighbour (fluid or wall) within the cone
// half-angle of it means a void beside the node — a surface, also under an overhang where the
// centroid stays balanced (the dam-break toe).
bool has_empty_cone(const Surroundings& at, std::span<const double> probe_directions, std::size_t dim,
                    double cone_cosine) {
  std::size_t hint = 0;
  for (std::size_t q = 0; q + dim <= probe_directions.size(); q += dim)
    if (!probe_covered(at, &probe_directions[q], dim, cone_cosine, hint)) return true;
  return false;
}

}  // namespace

// Whether the void beside node i in the unit direction `direction` is open: no fluid neighbour
// within 0.7 Δ of x_i + Δ·direction (SolverParams::surface_umbrella).
bool FreeSurfaceSolver::void_is_open(std::size_t i, const double* direction) const {
  const auto dim = static_cast<std::size_t>(dimension());
  // 0.7 Δ, not ~Δ: a contact-line node a little below the surface row beside it must still see
  // its void open (at 0.9 Δ viscous sloshing's contact-line nodes turned interior and lagged).
  const double spacing = params_.spacing, reach2 = 0.49 * spacing * spacing;
  double target[3] = {0, 0, 0};
  for (std::size_t d = 0; d < dim; ++d) target[d] = positions_[dim * i + d] + spacing * direction[d];
  for (std::size_t k = neighbours_.offsets[i]; k < neighbours_.offsets[i + 1]; ++k) {
    const std::size_t j = neighbours_.indices[k];
    // Fluid occupants only: the wall above a contact line is not fluid, and a void reaching it
    // is open (the cone and offset tests already discount directions into a wall).
    if (!is_fluid(j) || kinds_[j] == NodeKind::splash) continue;
    if (detail::squared_distance(target, &positions_[dim * j], dim) < reach2) return false;
  }
  return true;
}

// A fluid node's surroundings within the search radius (r2: its square; h2: the support's).
void FreeSurfaceSolver::survey(std::size_t i, double r2, double h2, Surroundings& at) const {
  const auto dim = static_cast<std::size_t>(dimension());
  const numerics::NeighbourList& nb = neighbours_;
  // Counters and sums in locals (kept in registers: through `at` every update would be a store
  // the compiler cannot prove does not alias `at.seen`), copied out at the end.
  std::size_t directions_seen = 0, walls_near = 0, within_search = 0, within_support = 0;
  double centroid[3] = {0, 0, 0};
  double fluid_weight = 0;
  for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
    const std::size_t j = nb.indices[k];
    const double r = detail::squared_distance(&positions_[dim * i], &positions_[dim * j], dim);
    if (r >= r2) continue;
    ++within_search;
    if (r < h2) ++within_support;
    if (r > 0 && directions_seen < Surroundings::max_directions) {
      const double inverse = 1.0 / std::sqrt(r);
      for (std::size_t d = 0; d < dim; ++d)
        at.seen[directions_seen * 3 + d] = (positions_[dim * j + d] - positions_[dim * i + d]) * inverse;
      ++directions_seen;
    }
    if (is_fluid(j)) {
      fluid_weight += weight(std::sqrt(r), support_radius_);
      for (std::size_t d = 0; d < dim; ++d) centroid[d] += positions_[dim * j + d] - positions_[dim * i + d];
      continue;
    }
    const double* normal = &normals_[dim * j];
    bool known = corner_[j] != 0;  // corners have no normal of their own
    for (std::size_t w = 0; w < walls_near && !known; ++w) {
      double dot = 0;
      for (std::size_t d = 0; d < dim; ++d) dot += at.wall_normals[w][d] * normal[d];
      known = dot > 0.9;
    }
    if (!known && walls_near < 3) {
      for (std::size_t d = 0; d < dim; ++d) at.wall_normals[walls_near][d] = normal[d];
      ++walls_near;
    }
  }
  at.directions_seen = directions_seen;
  at.walls_near = walls_near;
  at.within_search = within_search;
  at.within_support = within_support;
  for (std::size_t d = 0; d < 3; ++d) at.centroid[d] = centroid[d];
  at.fluid_weight = fluid_weight;
}

void FreeSurfaceSolver::classify() {
  const auto dim = static_cast<std::size_t>(dimension());
  const auto count = static_cast<std::ptrdiff_t>(kinds_.size());
  const double h2 = support_radius_ * support_radius_, r2 = search_radius_ * search_radius_;
  const double offset_limit = params_.surface_offset * params_.spacing;
  const double count_limit = params_.surface_count * rest_count_;
  const double weight_limit = params_.surface_fluid_weight * (rest_density_ - weight(0.0, support_radius_));
  const std::size_t splash_limit = dim + 1;
  // 3D clouds leave wider empty cones near curved walls (64 probes, 26 lattice neighbours), so
  // the 3D half-angle is 15° wider.
  const double cone_angle = params_.surface_cone_angle + (dimension() == 3 ? 15.0 : 0.0);
  const double cone_cosine = std::cos(cone_angle * std::numbers::pi / 180.0);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (!is_fluid(i)) continue;
    Surroundings at;
    survey(i, r2, h2, at);
    if (at.within_support < splash_limit) {
      kinds_[i] = NodeKind::splash;
      continue;
    }
    const double offset = wall_projected_offset(at, dim);  // leaves at.centroid wall-projected
    const bool empty_cone = has_empty_cone(at, probe_directions_, dim, cone_cosine);
    // Fluid support: wall pressures are extrapolated from the fluid (the PPE's wall rows), so a
    // node whose kernel sees mostly wall nodes has no pressure level of its own — as interior it
    // formed a floating block with its walls (the slump cake's edge reached 9·10⁶ Pa, docs/ldd.md).
    // Degenerate stencil: the neighbours (eq. 13's moment matrix) do not span all directions —
    // the node is at an edge of the fluid. A bound of its own, lower than the pseudo-inverse's: a
    // flattened interior stencil needs its weak direction dropped, not p = p_atm, which next to
    // hydrostatic neighbours kicks it by δt·g·h/Δ (the δt = 1e-2 slump, docs/ldd.md).
    const bool degenerate =
        operators_.conditioning.size() == kinds_.size() && operators_.conditioning[i] < params_.surface_moment_rcond;
    const bool thin_support = at.fluid_weight < weight_limit || degenerate;
    const bool sparse = static_cast<double>(at.within_search) < count_limit;
    bool surface = empty_cone || thin_support || offset > offset_limit || sparse;
    if (surface && params_.surface_umbrella && !thin_support && !sparse) {
      // Flagged by the cone or the offset alone: surface only if one of those voids is open.
      bool open = false;
      if (offset > offset_limit) {
        double length = 0, away[3] = {0, 0, 0};
        for (std::size_t d = 0; d < dim; ++d) length += at.centroid[d] * at.centroid[d];
        length = std::sqrt(length);
        for (std::size_t d = 0; d < dim; ++d) away[d] = length > 0 ? -at.centroid[d] / length : 0.0;
        open = length > 0 && void_is_open(i, away);
      }
      std::size_t hint = 0;  // each uncovered probe direction in turn
      for (std::size_t q = 0; !open && empty_cone && q + dim <= probe_directions_.size(); q += dim)
        open =
            !probe_covered(at, &probe_directions_[q], dim, cone_cosine, hint) && void_is_open(i, &probe_directions_[q]);
      surface = open;
    }
    kinds_[i] = surface ? NodeKind::surface : NodeKind::interior;
  }
  classify_walls(h2);
}

// Wall nodes: active (Neumann/Dirichlet rows) when a fluid node is within h, else idle.
void FreeSurfaceSolver::classify_walls(double h2) {
  const auto dim = static_cast<std::size_t>(dimension());
  const numerics::NeighbourList& nb = neighbours_;
  const auto count = static_cast<std::ptrdiff_t>(kinds_.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (is_fluid(i)) continue;
    bool active = false;
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1] && !active; ++k) {
      const std::size_t j = nb.indices[k];
      active = kinds_[j] <= NodeKind::splash &&
               detail::squared_distance(&positions_[dim * i], &positions_[dim * j], dim) < h2;
    }
    kinds_[i] = !active ? NodeKind::idle_wall : (corner_[i] ? NodeKind::corner : NodeKind::wall);
  }
}

}  // namespace rheosim::ldd
