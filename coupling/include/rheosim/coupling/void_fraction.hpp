#pragma once
// Void fraction ε = 1 − (particle volume in a cell)/(cell volume) on the fluid's cylindrical grid
// (CD §3.2: ε_f in CD eqs. 26–27, 30–33), and the particle → cell map that the force
// interpolation and the momentum exchange (CD eq. 29) reuse, so that every particle's volume and
// force go to the same cells with the same weights.
//
// Schemes (one class each in coupling/src/void_fraction/, selected by YAML name):
//   centre   the whole particle volume goes to the cell holding its centre.
//   divided  the volume is split over 29 sub-points of V_p/29 each: the centre, and two shells of
//            14 points (the 6 face and 8 corner directions of a cube) at the volume centroids of
//            the three equal-volume parts core | inner shell | outer shell. The core has radius
//            r (1/29)^(1/3), the inner shell ends at r (15/29)^(1/3); the points sit at the
//            volume-weighted mean radius of each shell, (3/4)(b⁴ − a⁴)/(b³ − a³):
//            0.6276 r and 0.9085 r. (Equal weights per point are an approximation: the 14
//            directions do not have equal solid angles; volume conservation does not depend on it.)
//
// Conservation. Each particle's shares add up to its volume V_p = 4πr³/3 (the last share is
// V_p minus the others), and every share goes to exactly one cell, so Σ_cells (solid volume) =
// Σ_particles V_p to round-off whatever the particles do. Points outside the domain are mapped
// back in by CellLocator:
//   - plates: a point at z < 0 is mirrored to −z, one at z > H to 2H − z (a sub-point poking
//     through a plate lands in the wall cell it pokes out of, where the particle is);
//   - rim: r > R is mirrored to 2R − r at the same θ;
//   - axis: nothing to do — a point "across" the axis is at a positive r on the other side,
//     which is inside the domain; θ = atan2(y, x) is taken modulo 2π;
//   - anything still outside (a centre far outside, e.g. a particle that escaped) is clamped to
//     the nearest cell. The count of mapped points is reported.
//
// Floor. A cell whose ε would fall below the floor ε_min keeps solid volume (1 − ε_min) V_c; the
// excess moves to its face neighbours (r ± 1, θ ± 1, z ± 1; across the axis to the opposite
// cell when N_θ is even) in proportion to the room they have left, over repeated passes until
// no cell exceeds the cap (at most max_floor_passes). The moved volume and the cells involved are
// reported; total volume is unchanged by the moves. If the passes cannot place it all (the
// whole grid over-full), the remainder stays where it is and is reported as unplaced_volume
// with ε below the floor in those cells (clamped at ε_min/10 for the solver, reported).
//
// Rings near the axis. A wedge cell of the first rings is smaller than a particle on the grids a
// rheometer can afford (3 mm disk, 8 × 8 cells, 200 µm spheres: the axis wedge holds 3.3 particle
// volumes), so one particle passing through swings its ε by 0.3 in a few fluid steps and the
// projection answers with a pressure spike that, fed back through the particle forces, grew
// until the solver stopped at φ = 0.1–0.3. Where a ring's wedge holds fewer than
// min_particle_volumes_per_cell mean particle volumes, its solid volume is averaged over the
// ring (per axial layer) before the floor: total volume is unchanged, the ring then behaves like
// one cell of several particle volumes. The merged rings are reported.
//
// YAML:
//   void_fraction: {model: divided, floor: 0.3}
#include <cstddef>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "rheosim/core/registry.hpp"
#include "rheosim/coupling/particles.hpp"
#include "rheosim/fluid/grid.hpp"

namespace rheosim::coupling {

// Finds the cell of a point, mapping points outside the domain back in (see above).
class CellLocator {
 public:
  explicit CellLocator(const fluid::CylindricalGrid& grid);

  struct Location {
    std::size_t cell = 0;       // (i·N_θ + j)·N_z + k
    std::size_t azimuthal = 0;  // j
    bool mapped = false;        // the point was outside and was mirrored/clamped
  };
  [[nodiscard]] Location locate(const Vector3& point) const;
  // The same, for a point near another one in azimuthal cell near_azimuthal (the sub-points of
  // a particle): the sector is found by side tests against the nearby θ faces instead of atan2.
  [[nodiscard]] Location locate_near(const Vector3& point, std::size_t near_azimuthal) const;
  [[nodiscard]] std::size_t cell_index(std::size_t i, std::size_t j, std::size_t k) const {
    return (i * azimuthal_cells_ + j) * axial_cells_ + k;
  }
  [[nodiscard]] const fluid::CylindricalGrid& grid() const { return *grid_; }

 private:
  [[nodiscard]] Location locate(const Vector3& point, std::ptrdiff_t near_azimuthal) const;

  const fluid::CylindricalGrid* grid_;
  std::size_t azimuthal_cells_, axial_cells_;
  double axial_width_, radial_width_;        // uniform Δz; Δr when the radial grid is uniform, else 0
  std::vector<double> face_cos_, face_sin_;  // unit vectors of the θ faces
};

// One particle's volume in one cell.
struct VolumeShare {
  std::size_t cell = 0;
  double volume = 0.0;  // [m³]
};

// The particle → cell split of one step (CSR layout): particle p owns
// shares[offsets[p] .. offsets[p+1]), each cell at most once per particle.
struct ParticleCellMap {
  std::vector<std::size_t> offsets{0};
  std::vector<VolumeShare> shares;
  std::size_t mapped_points = 0;  // sub-points/centres that were outside the domain

  [[nodiscard]] std::size_t particle_count() const { return offsets.size() - 1; }
  [[nodiscard]] std::span<const VolumeShare> of(std::size_t p) const {
    return std::span<const VolumeShare>(shares).subspan(offsets[p], offsets[p + 1] - offsets[p]);
  }
  void clear() {
    offsets.assign(1, 0);
    shares.clear();
    mapped_points = 0;
  }
};

class VoidFractionScheme {
 public:
  virtual ~VoidFractionScheme() = default;
  [[nodiscard]] virtual std::string_view name() const = 0;  // YAML name
  // Splits every particle's volume over cells (replaces out).
  virtual void split(const CellLocator& locator, const ParticleView& particles, ParticleCellMap& out) const = 0;

 protected:
  VoidFractionScheme() = default;
  VoidFractionScheme(const VoidFractionScheme&) = default;
  VoidFractionScheme& operator=(const VoidFractionScheme&) = default;
};

// Implements name() for a Derived scheme with `static constexpr std::string_view name`.
template <class Derived>
class VoidFractionSchemeBase : public VoidFractionScheme {
 public:
  [[nodiscard]] std::string_view name() const final { return Derived::name; }
};

using VoidFractionRegistry = core::Registry<VoidFractionScheme>;
void add_builtin_void_fraction_schemes(VoidFractionRegistry& registry);  // centre, divided
[[nodiscard]] const VoidFractionRegistry& builtin_void_fraction_schemes();
// From a `void_fraction:` section ({model: name}).
[[nodiscard]] std::unique_ptr<const VoidFractionScheme> make_void_fraction_scheme(const core::Section& section);
// By name, e.g. "divided" (throws std::invalid_argument listing the valid names).
[[nodiscard]] std::unique_ptr<const VoidFractionScheme> make_void_fraction_scheme(std::string_view name);

struct VoidFractionReport {
  double particle_volume = 0.0;        // Σ_p V_p [m³]
  double grid_volume = 0.0;            // Σ_c solid volume carried by the grid after the floor [m³]
  double relative_error = 0.0;         // |grid − particle| / particle (0 without particles)
  double min_void_fraction_raw = 1.0;  // smallest ε before the floor
  double min_void_fraction = 1.0;      // smallest ε handed to the fluid
  std::size_t capped_cells = 0;        // cells that hit the floor and gave volume away
  double redistributed_volume = 0.0;   // volume moved by the floor [m³]
  double unplaced_volume = 0.0;        // excess the passes could not place (left below the floor) [m³]
  std::size_t mapped_points = 0;       // points mapped back into the domain
  std::size_t merged_rings = 0;        // rings averaged azimuthally (see "Rings near the axis")
};

// ε per cell, recomputed from the particles by update().
class VoidFractionField {
 public:
  // floor ε_min in (0, 1): throws std::invalid_argument otherwise.
  // min_particle_volumes_per_cell >= 0 (0: never merge rings).
  VoidFractionField(const fluid::CylindricalGrid& grid, double floor, int max_floor_passes = 100,
                    double min_particle_volumes_per_cell = 10.0);

  const VoidFractionReport& update(const VoidFractionScheme& scheme, const ParticleView& particles);

  [[nodiscard]] std::span<const double> void_fraction() const { return void_fraction_; }  // ε per cell
  [[nodiscard]] std::span<const double> solid_volume() const { return solid_volume_; }    // [m³] per cell
  [[nodiscard]] const ParticleCellMap& map() const { return map_; }
  [[nodiscard]] const VoidFractionReport& report() const { return report_; }
  [[nodiscard]] const CellLocator& locator() const { return locator_; }
  [[nodiscard]] double floor() const { return floor_; }

 private:
  void apply_floor();
  void merge_small_rings(double mean_particle_volume);

  const fluid::CylindricalGrid* grid_;
  CellLocator locator_;
  double floor_;
  int max_floor_passes_;
  double min_particle_volumes_per_cell_;
  ParticleCellMap map_;
  std::vector<double> cell_volume_, solid_volume_, void_fraction_;
  VoidFractionReport report_;
};

}  // namespace rheosim::coupling
