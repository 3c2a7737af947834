#include "rheosim/coupling/void_fraction.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "rheosim/core/config.hpp"
#include "void_fraction/centre.hpp"
#include "void_fraction/divided.hpp"

namespace rheosim::coupling {

void check(const ParticleView& particles, bool need_velocities) {
  const std::size_t n = particles.radii.size();
  if (particles.positions.size() != 3 * n)
    throw std::invalid_argument(
        fmt::format("particles: {} radii but {} position values (expected {})", n, particles.positions.size(), 3 * n));
  if (need_velocities && particles.velocities.size() != 3 * n)
    throw std::invalid_argument(
        fmt::format("particles: {} radii but {} velocity values (expected {})", n, particles.velocities.size(), 3 * n));
  for (const double x : particles.positions)
    if (!std::isfinite(x)) throw std::invalid_argument("particles: a position is not finite");
  for (const double v : particles.velocities)
    if (!std::isfinite(v)) throw std::invalid_argument("particles: a velocity is not finite");
  for (const double r : particles.radii)
    if (!(std::isfinite(r) && r > 0.0))
      throw std::invalid_argument(fmt::format("particles: radius {} is out of range, expected a finite value > 0", r));
}

CellLocator::CellLocator(const fluid::CylindricalGrid& grid)
    : grid_(&grid),
      azimuthal_cells_(grid.azimuthal_cells()),
      axial_cells_(grid.axial_cells()),
      axial_width_(grid.params().gap / static_cast<double>(grid.axial_cells())),
      radial_width_(
          grid.params().radial_grading == 1.0 ? grid.params().radius / static_cast<double>(grid.radial_cells()) : 0.0) {
  // Cells are found by z/Δz: a stretched axial grid has no single Δz.
  if (!grid.is_axially_uniform())
    throw std::invalid_argument(fmt::format("CellLocator: axial_stretching = {}, expected 0 (uniform axial cells)",
                                            grid.params().axial_stretching));
  for (std::size_t j = 0; j <= azimuthal_cells_; ++j) {
    const double theta = grid.azimuthal_faces()[j];
    face_cos_.push_back(std::cos(theta));
    face_sin_.push_back(std::sin(theta));
  }
}

CellLocator::Location CellLocator::locate(const Vector3& point) const { return locate(point, -1); }

CellLocator::Location CellLocator::locate_near(const Vector3& point, std::size_t near_azimuthal) const {
  return locate(point, static_cast<std::ptrdiff_t>(near_azimuthal));
}

CellLocator::Location CellLocator::locate(const Vector3& point, std::ptrdiff_t near_azimuthal) const {
  const double radius = grid_->params().radius;
  const double gap = grid_->params().gap;
  Location out;
  double r = std::hypot(point[0], point[1]);
  double z = point[2];
  // Mirror about the plates and the rim (see the header); clamp what is still outside.
  if (z < 0.0) {
    z = -z;
    out.mapped = true;
  } else if (z > gap) {
    z = 2.0 * gap - z;
    out.mapped = true;
  }
  if (r > radius) {
    r = 2.0 * radius - r;
    out.mapped = true;
  }
  z = std::clamp(z, 0.0, gap);
  r = std::clamp(r, 0.0, radius);

  const std::size_t radial_cells = grid_->radial_cells();
  std::size_t i = 0;
  if (radial_width_ > 0.0) {
    i = static_cast<std::size_t>(r / radial_width_);
  } else {
    const std::span<const double> faces = grid_->radial_faces();
    const auto above = std::upper_bound(faces.begin(), faces.end(), r);
    i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(above - faces.begin() - 1, 0));
  }
  i = std::min(i, radial_cells - 1);

  std::size_t j = 0;
  if (azimuthal_cells_ > 1) {
    bool found = false;
    if (near_azimuthal >= 0 && azimuthal_cells_ >= 3) {
      // Side tests: the point is in sector j if it is left of face j and right of face j + 1.
      const auto inside = [&](std::size_t s) {
        return face_cos_[s] * point[1] - face_sin_[s] * point[0] >= 0.0 &&
               face_cos_[s + 1] * point[1] - face_sin_[s + 1] * point[0] < 0.0;
      };
      const std::size_t n = azimuthal_cells_, near = static_cast<std::size_t>(near_azimuthal);
      for (const std::size_t s : {near, (near + 1) % n, (near + n - 1) % n})
        if (inside(s)) {
          j = s;
          found = true;
          break;
        }
    }
    if (!found) {
      double theta = std::atan2(point[1], point[0]);
      if (theta < 0.0) theta += 2.0 * std::numbers::pi;
      j = std::min(static_cast<std::size_t>(theta / grid_->azimuthal_width()), azimuthal_cells_ - 1);
    }
  }
  const std::size_t k = std::min(static_cast<std::size_t>(z / axial_width_), axial_cells_ - 1);
  out.cell = cell_index(i, j, k);
  out.azimuthal = j;
  return out;
}

void add_builtin_void_fraction_schemes(VoidFractionRegistry& registry) {
  core::add<CentreVoidFraction>(registry);
  core::add<DividedVoidFraction>(registry);
}

const VoidFractionRegistry& builtin_void_fraction_schemes() {
  return core::builtin_registry<VoidFractionScheme, add_builtin_void_fraction_schemes>();
}

std::unique_ptr<const VoidFractionScheme> make_void_fraction_scheme(const core::Section& section) {
  return builtin_void_fraction_schemes().make(section);
}

std::unique_ptr<const VoidFractionScheme> make_void_fraction_scheme(std::string_view name) {
  return builtin_void_fraction_schemes().make(name);
}

VoidFractionField::VoidFractionField(const fluid::CylindricalGrid& grid, double floor, int max_floor_passes,
                                     double min_particle_volumes_per_cell)
    : grid_(&grid),
      locator_(grid),
      floor_(floor),
      max_floor_passes_(max_floor_passes),
      min_particle_volumes_per_cell_(min_particle_volumes_per_cell) {
  if (!(std::isfinite(min_particle_volumes_per_cell) && min_particle_volumes_per_cell >= 0.0))
    throw std::invalid_argument(fmt::format("min_particle_volumes_per_cell = {} is out of range, expected >= 0",
                                            min_particle_volumes_per_cell));
  if (!(floor > 0.0 && floor < 1.0))
    throw std::invalid_argument(fmt::format("void fraction floor = {} is out of range, expected (0, 1)", floor));
  if (max_floor_passes < 1)
    throw std::invalid_argument(fmt::format("max_floor_passes = {} is out of range, expected >= 1", max_floor_passes));
  const std::size_t n_theta = grid.azimuthal_cells(), n_z = grid.axial_cells();
  cell_volume_.resize(grid.cell_count());
  for (std::size_t i = 0; i < grid.radial_cells(); ++i)
    for (std::size_t j = 0; j < n_theta; ++j)
      for (std::size_t k = 0; k < n_z; ++k) cell_volume_[locator_.cell_index(i, j, k)] = grid.cell_volume(i, k);
  solid_volume_.assign(grid.cell_count(), 0.0);
  void_fraction_.assign(grid.cell_count(), 1.0);
}

const VoidFractionReport& VoidFractionField::update(const VoidFractionScheme& scheme, const ParticleView& particles) {
  check(particles, false);
  scheme.split(locator_, particles, map_);
  report_ = {};
  std::fill(solid_volume_.begin(), solid_volume_.end(), 0.0);
  for (const VolumeShare& share : map_.shares) solid_volume_[share.cell] += share.volume;
  for (const double r : particles.radii) report_.particle_volume += sphere_volume_from_radius(r);
  double raw_min = 1.0;
  for (std::size_t c = 0; c < solid_volume_.size(); ++c)
    raw_min = std::min(raw_min, 1.0 - solid_volume_[c] / cell_volume_[c]);
  report_.min_void_fraction_raw = raw_min;
  report_.mapped_points = map_.mapped_points;
  if (!particles.radii.empty()) merge_small_rings(report_.particle_volume / static_cast<double>(particles.size()));
  apply_floor();
  double carried = 0.0, eps_min = 1.0;
  for (std::size_t c = 0; c < solid_volume_.size(); ++c) {
    carried += solid_volume_[c];
    // Left below the floor only if the passes could not place the excess (reported); keep ε > 0.
    void_fraction_[c] = std::max(1.0 - solid_volume_[c] / cell_volume_[c], 0.1 * floor_);
    eps_min = std::min(eps_min, void_fraction_[c]);
  }
  report_.grid_volume = carried;
  report_.min_void_fraction = eps_min;
  report_.relative_error =
      report_.particle_volume > 0.0 ? std::abs(carried - report_.particle_volume) / report_.particle_volume : 0.0;
  return report_;
}

void VoidFractionField::merge_small_rings(double mean_particle_volume) {
  const std::size_t n_theta = grid_->azimuthal_cells(), n_z = grid_->axial_cells();
  if (n_theta < 2) return;
  for (std::size_t i = 0; i < grid_->radial_cells(); ++i) {
    bool small = false;
    for (std::size_t k = 0; k < n_z; ++k)
      small =
          small || cell_volume_[locator_.cell_index(i, 0, k)] < min_particle_volumes_per_cell_ * mean_particle_volume;
    if (!small) continue;
    ++report_.merged_rings;
    for (std::size_t k = 0; k < n_z; ++k) {
      double ring = 0.0;
      for (std::size_t j = 0; j < n_theta; ++j) ring += solid_volume_[locator_.cell_index(i, j, k)];
      for (std::size_t j = 0; j < n_theta; ++j)
        solid_volume_[locator_.cell_index(i, j, k)] = ring / static_cast<double>(n_theta);
    }
  }
}

void VoidFractionField::apply_floor() {
  const std::size_t n_r = grid_->radial_cells(), n_theta = grid_->azimuthal_cells(), n_z = grid_->axial_cells();
  const auto capacity = [&](std::size_t c) { return (1.0 - floor_) * cell_volume_[c]; };
  std::vector<std::size_t> neighbours;
  neighbours.reserve(6);
  std::vector<double> weights;
  weights.reserve(6);
  std::vector<char> capped(solid_volume_.size(), 0);
  // Excess below this fraction of a cell volume is round-off from earlier moves, not overfill.
  constexpr double tolerance = 1e-12;
  for (int pass = 0; pass < max_floor_passes_; ++pass) {
    bool moved = false;
    for (std::size_t i = 0; i < n_r; ++i)
      for (std::size_t j = 0; j < n_theta; ++j)
        for (std::size_t k = 0; k < n_z; ++k) {
          const std::size_t c = locator_.cell_index(i, j, k);
          const double excess = solid_volume_[c] - capacity(c);
          if (!(excess > tolerance * cell_volume_[c])) continue;
          neighbours.clear();
          if (i + 1 < n_r) neighbours.push_back(locator_.cell_index(i + 1, j, k));
          if (i > 0)
            neighbours.push_back(locator_.cell_index(i - 1, j, k));
          else if (n_theta % 2 == 0)
            neighbours.push_back(locator_.cell_index(0, (j + n_theta / 2) % n_theta, k));
          if (n_theta > 1) {
            neighbours.push_back(locator_.cell_index(i, (j + 1) % n_theta, k));
            if (n_theta > 2) neighbours.push_back(locator_.cell_index(i, (j + n_theta - 1) % n_theta, k));
          }
          if (k + 1 < n_z) neighbours.push_back(locator_.cell_index(i, j, k + 1));
          if (k > 0) neighbours.push_back(locator_.cell_index(i, j, k - 1));
          std::sort(neighbours.begin(), neighbours.end());
          neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
          if (neighbours.empty()) continue;
          double room = 0.0;
          for (const std::size_t n : neighbours) room += std::max(capacity(n) - solid_volume_[n], 0.0);
          solid_volume_[c] -= excess;
          capped[c] = 1;
          report_.redistributed_volume += excess;
          moved = true;
          // In proportion to the room left; with no room anywhere near, evenly (the
          // neighbours then pass it on in the next pass).
          weights.clear();
          for (const std::size_t n : neighbours)
            weights.push_back(room > 0.0 ? std::max(capacity(n) - solid_volume_[n], 0.0) / room
                                         : 1.0 / static_cast<double>(neighbours.size()));
          for (std::size_t m = 0; m < neighbours.size(); ++m) solid_volume_[neighbours[m]] += weights[m] * excess;
        }
    if (!moved) break;
  }
  for (std::size_t c = 0; c < solid_volume_.size(); ++c) {
    report_.capped_cells += capped[c] ? 1 : 0;
    const double left = solid_volume_[c] - capacity(c);
    if (left > tolerance * cell_volume_[c]) report_.unplaced_volume += left;
  }
}

}  // namespace rheosim::coupling
