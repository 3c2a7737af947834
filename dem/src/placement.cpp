// Particle placement in the plate gap (see placement.hpp for the method).
#include "rheosim/dem/placement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "portable_random.hpp"
#include "rheosim/core/units.hpp"

namespace rheosim::dem {
namespace {

using core::units::pi;

constexpr double clearance = 1e-9;  // relative to d, see placement.hpp
constexpr double target_acceptance = 0.4;
constexpr double spare = 1.05;  // lattice sites per particle after stretching

void check_positive(std::string_view name, double value) {
  if (!(std::isfinite(value) && value > 0.0))
    throw std::invalid_argument(fmt::format("{} = {} is out of range, expected a finite value > 0", name, value));
}

void check_geometry(double plate_radius, double gap, double diameter, double volume_fraction) {
  check_positive("plate_radius", plate_radius);
  check_positive("gap", gap);
  check_positive("diameter", diameter);
  if (!(diameter < gap))
    throw std::invalid_argument(
        fmt::format("diameter = {} m is out of range, expected < gap = {} m (a particle must fit between the plates)",
                    diameter, gap));
  if (!(diameter < plate_radius))
    throw std::invalid_argument(
        fmt::format("diameter = {} m is out of range, expected < plate_radius = {} m", diameter, plate_radius));
  if (!(volume_fraction >= 0.0 && volume_fraction <= 0.5))
    throw std::invalid_argument(
        fmt::format("volume_fraction = {} is out of range, expected [0, 0.5]", volume_fraction));
}

using Random = detail::PortableRandom;

struct Lattice {
  bool hexagonal = true;
  int layers = 1;
  double layer_spacing = 0.0;   // s
  double spacing = 0.0;         // a
  double sites_per_area = 0.0;  // all layers together
};

// The densest layered lattice for a centre slab of thickness w (see placement.hpp).
Lattice choose_lattice(double w, double d) {
  Lattice best;
  best.spacing = d;
  best.sites_per_area = 2.0 / (std::sqrt(3.0) * d * d);  // one hexagonal layer
  const int max_layers = static_cast<int>(std::floor(3.0 * w / d)) + 1;
  for (int layers = 2; layers <= max_layers; ++layers) {
    const double s = w / (layers - 1);
    const double deficit = std::max(0.0, d * d - s * s);
    if (layers <= 3 || 3.0 * s >= d) {
      const double a = std::max(d, std::sqrt(3.0 * deficit));
      const double density = layers * 2.0 / (std::sqrt(3.0) * a * a);
      if (density > best.sites_per_area) best = {true, layers, s, a, density};
    }
    if (layers <= 2 || 2.0 * s >= d) {
      const double a = std::max(d, std::sqrt(2.0 * deficit));
      const double density = layers / (a * a);
      if (density > best.sites_per_area) best = {false, layers, s, a, density};
    }
  }
  return best;
}

// Sites of the lattice with centres in r <= r_max, z_lo <= z <= z_lo + (L−1) s.
std::vector<std::array<double, 3>> lattice_sites(const Lattice& lattice, double r_max, double z_lo, double gap,
                                                 double angle) {
  const double a = lattice.spacing;
  // In-plane basis and per-layer offsets.
  std::array<double, 2> e1{a, 0.0};
  std::array<double, 2> e2{};
  std::array<std::array<double, 2>, 3> offsets{};
  int period = 1;
  if (lattice.hexagonal) {
    e2 = {0.5 * a, 0.5 * std::sqrt(3.0) * a};
    const std::array<double, 2> hollow{(e1[0] + e2[0]) / 3.0, (e1[1] + e2[1]) / 3.0};
    offsets = {{{0.0, 0.0}, hollow, {2.0 * hollow[0], 2.0 * hollow[1]}}};
    period = 3;
  } else {
    e2 = {0.0, a};
    offsets = {{{0.0, 0.0}, {0.5 * a, 0.5 * a}, {0.0, 0.0}}};
    period = 2;
  }
  const double c = std::cos(angle);
  const double sn = std::sin(angle);
  const int n = static_cast<int>(std::ceil(2.0 * r_max / a)) + 3;  // e2 has |e2| = a; the skew needs 2x
  std::vector<std::array<double, 3>> sites;
  for (int layer = 0; layer < lattice.layers; ++layer) {
    const double z = lattice.layers == 1 ? 0.5 * gap : z_lo + layer * lattice.layer_spacing;
    const auto& off = offsets[static_cast<std::size_t>(layer % period)];
    for (int i = -n; i <= n; ++i) {
      for (int j = -n; j <= n; ++j) {
        const double u = off[0] + i * e1[0] + j * e2[0];
        const double v = off[1] + i * e1[1] + j * e2[1];
        const double x = c * u - sn * v;
        const double y = sn * u + c * v;
        if (x * x + y * y <= r_max * r_max) sites.push_back({x, y, z});
      }
    }
  }
  return sites;
}

// Uniform cell list over [-R, R]² × [0, H] with cells no smaller than the contact distance.
class CellList {
 public:
  CellList(double plate_radius, double gap, double min_cell) : radius_(plate_radius) {
    nxy_ = std::max(1, static_cast<int>(std::floor(2.0 * plate_radius / min_cell)));
    nz_ = std::max(1, static_cast<int>(std::floor(gap / min_cell)));
    // Cap the number of cells for very wide plates (memory); cells only get larger.
    while (static_cast<double>(nxy_) * nxy_ * nz_ > 5e7) nxy_ /= 2;
    hxy_ = 2.0 * plate_radius / nxy_;
    hz_ = gap / nz_;
    cells_.resize(static_cast<std::size_t>(nxy_) * nxy_ * nz_);
  }

  [[nodiscard]] std::array<int, 3> coords(const std::array<double, 3>& p) const {
    const auto clamp = [](int v, int n) { return std::min(std::max(v, 0), n - 1); };
    return {clamp(static_cast<int>(std::floor((p[0] + radius_) / hxy_)), nxy_),
            clamp(static_cast<int>(std::floor((p[1] + radius_) / hxy_)), nxy_),
            clamp(static_cast<int>(std::floor(p[2] / hz_)), nz_)};
  }
  [[nodiscard]] std::size_t index(const std::array<int, 3>& c) const {
    return (static_cast<std::size_t>(c[2]) * nxy_ + c[1]) * nxy_ + c[0];
  }
  void insert(std::uint32_t id, const std::array<double, 3>& p) { cells_[index(coords(p))].push_back(id); }
  void erase(std::uint32_t id, const std::array<double, 3>& p) {
    auto& cell = cells_[index(coords(p))];
    const auto it = std::find(cell.begin(), cell.end(), id);
    if (it != cell.end()) {
      *it = cell.back();
      cell.pop_back();
    }
  }
  // Calls f(other_id) for every particle in the 27 cells around p.
  template <class F>
  void for_neighbours(const std::array<double, 3>& p, F&& f) const {
    const auto c = coords(p);
    for (int dz = -1; dz <= 1; ++dz) {
      const int z = c[2] + dz;
      if (z < 0 || z >= nz_) continue;
      for (int dy = -1; dy <= 1; ++dy) {
        const int y = c[1] + dy;
        if (y < 0 || y >= nxy_) continue;
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = c[0] + dx;
          if (x < 0 || x >= nxy_) continue;
          for (const std::uint32_t other : cells_[index({x, y, z})]) f(other);
        }
      }
    }
  }

 private:
  double radius_;
  int nxy_ = 1;
  int nz_ = 1;
  double hxy_ = 0.0;
  double hz_ = 0.0;
  std::vector<std::vector<std::uint32_t>> cells_;
};

double squared_distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  const double dx = a[0] - b[0];
  const double dy = a[1] - b[1];
  const double dz = a[2] - b[2];
  return dx * dx + dy * dy + dz * dz;
}

}  // namespace

std::size_t target_particle_count(double plate_radius, double gap, double diameter, double volume_fraction) {
  check_geometry(plate_radius, gap, diameter, volume_fraction);
  const double particle_volume = core::units::sphere_volume(diameter);
  return static_cast<std::size_t>(
      std::llround(volume_fraction * pi * plate_radius * plate_radius * gap / particle_volume));
}

namespace {

// The diameters to place (params.diameters, checked, or N equal ones) and the lattice diameter,
// the largest of them.
std::pair<std::vector<double>, double> diameters_to_place(const PlacementParams& params) {
  const bool sized = !params.diameters.empty();
  double d = params.diameter;
  if (sized) {
    d = 0.0;
    for (std::size_t i = 0; i < params.diameters.size(); ++i) {
      const double di = params.diameters[i];
      if (!(std::isfinite(di) && di > 0.0))
        throw std::invalid_argument(
            fmt::format("diameters[{}] = {} is out of range, expected a finite value > 0", i, di));
      d = std::max(d, di);
    }
    check_geometry(params.plate_radius, params.gap, d, 0.0);
  }
  const std::size_t count = sized ? params.diameters.size()
                                  : target_particle_count(params.plate_radius, params.gap, d, params.volume_fraction);
  if (params.shake_sweeps < 0)
    throw std::invalid_argument(fmt::format("shake_sweeps = {} is out of range, expected >= 0", params.shake_sweeps));
  if (count > std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument(fmt::format("{} particles are too many for the placement", count));
  return {sized ? params.diameters : std::vector<double>(count, d), d};
}

// Spreads the layers in-plane so that they hold about `spare` · N sites: every particle then has
// room to move (in the densest lattice, neighbours touch and the Monte Carlo step would
// collapse). Returns the sites of the spacing chosen (kept in lattice.spacing).
std::vector<std::array<double, 3>> spread_lattice(Lattice& lattice, std::vector<std::array<double, 3>> sites,
                                                  std::size_t count, double site_radius, double site_z, double gap,
                                                  double angle) {
  const double wanted = std::ceil(spare * static_cast<double>(count));
  if (count == 0 || static_cast<double>(sites.size()) <= wanted) return sites;
  const double densest = lattice.spacing;
  double stretch = std::sqrt(static_cast<double>(sites.size()) / wanted);
  for (;;) {
    lattice.spacing = densest * stretch;
    auto stretched = lattice_sites(lattice, site_radius, site_z, gap, angle);
    if (static_cast<double>(stretched.size()) >= wanted || stretch <= 1.0) {
      if (stretched.size() >= count)
        sites = std::move(stretched);
      else
        lattice.spacing = densest;  // cannot happen for stretch <= 1; keep the densest
      return sites;
    }
    stretch = std::max(1.0, stretch * 0.99);
  }
}

// Hard-sphere Monte Carlo shaking of the centres `sites` (particle i of diameter diameters[i]),
// each keeping r_i (1 + clearance) from the plates and the rim and pairs (r_i + r_j)(1 +
// clearance); the step adapts towards target_acceptance. Checks the invariant at the end.
void shake(std::vector<std::array<double, 3>>& sites, const std::vector<double>& diameters, double d,
           const PlacementParams& params, Random& random, Placement& result) {
  const double R = params.plate_radius, H = params.gap;
  const auto count = static_cast<std::uint32_t>(sites.size());
  const auto half = [&](std::uint32_t i) { return 0.5 * diameters[i] * (1.0 + clearance); };
  CellList cells(R, H, d * (1.0 + clearance));
  for (std::uint32_t i = 0; i < count; ++i) cells.insert(i, sites[i]);
  const auto fits = [&](std::uint32_t self, const std::array<double, 3>& p) {
    const double h = half(self);
    if (p[2] < h || p[2] > H - h || p[0] * p[0] + p[1] * p[1] > (R - h) * (R - h)) return false;
    bool free = true;
    cells.for_neighbours(p, [&](std::uint32_t other) {
      const double contact = h + half(other);
      if (other != self && squared_distance(p, sites[other]) < contact * contact) free = false;
    });
    return free;
  };
  double step = 0.1 * d;
  std::size_t proposed = 0;
  std::size_t accepted = 0;
  for (int sweep = 0; sweep < params.shake_sweeps && count > 0; ++sweep) {
    std::size_t sweep_accepted = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::array<double, 3> trial{sites[i][0] + step * random.symmetric(),
                                        sites[i][1] + step * random.symmetric(),
                                        sites[i][2] + step * random.symmetric()};
      if (!fits(i, trial)) continue;
      cells.erase(i, sites[i]);
      sites[i] = trial;
      cells.insert(i, trial);
      ++sweep_accepted;
    }
    proposed += count;
    accepted += sweep_accepted;
    const double rate = static_cast<double>(sweep_accepted) / static_cast<double>(count);
    step = std::clamp(step * std::clamp(rate / target_acceptance, 0.5, 2.0), 1e-6 * d, d);
  }
  result.shake_acceptance = proposed > 0 ? static_cast<double>(accepted) / static_cast<double>(proposed) : 0.0;
  result.shake_step = step;
  for (std::uint32_t i = 0; i < count; ++i)
    if (!fits(i, sites[i]))
      throw std::logic_error(fmt::format("place_particles: particle {} at ({}, {}, {}) overlaps a neighbour or a wall",
                                         i, sites[i][0], sites[i][1], sites[i][2]));
}

}  // namespace

Placement place_particles(const PlacementParams& params) {
  const double R = params.plate_radius;
  const double H = params.gap;
  auto [diameters, d] = diameters_to_place(params);  // d: the lattice diameter, the largest particle
  const std::size_t count = diameters.size();
  const double gap_volume = pi * R * R * H;

  // The lattice keeps twice the clearance, so rounding cannot bring its sites closer than
  // the contact distance to each other or to the walls.
  Random random(params.seed);
  const double lattice_contact = d * (1.0 + 2.0 * clearance);
  Lattice lattice = choose_lattice(H - lattice_contact, lattice_contact);
  const double angle = 2.0 * pi * random.uniform();
  const double site_radius = R - 0.5 * lattice_contact;
  const double site_z = 0.5 * lattice_contact;
  auto sites = lattice_sites(lattice, site_radius, site_z, H, angle);

  Placement result;
  result.count = count;
  double solid_volume = 0.0;
  for (const double di : diameters) solid_volume += core::units::sphere_volume(di);
  result.volume_fraction = solid_volume / gap_volume;
  result.lattice = lattice.hexagonal ? "hexagonal" : "square";
  result.layers = lattice.layers;
  result.layer_spacing = lattice.layers > 1 ? lattice.layer_spacing : 0.0;
  result.capacity_volume_fraction = static_cast<double>(sites.size()) * core::units::sphere_volume(d) / gap_volume;
  if (sites.size() < count)
    throw std::invalid_argument(fmt::format(
        "volume_fraction = {:.4g} needs {} particles, but the placement lattice holds only {} (φ = {:.3f} of "
        "spheres of {} m) for R = {} m, H = {} m, d = {} m ({} {} layers); use a lower volume fraction, a wider gap{}",
        result.volume_fraction, count, sites.size(), result.capacity_volume_fraction, d, R, H, d, lattice.layers,
        result.lattice,
        params.diameters.empty() ? ""
                                 : " or a narrower size distribution (sites are spaced for the largest particle)"));
  sites = spread_lattice(lattice, std::move(sites), count, site_radius, site_z, H, angle);
  result.lattice_spacing = lattice.spacing;
  result.lattice_sites = sites.size();

  // Random subset: the first `count` entries of a partial Fisher–Yates shuffle. Particle i
  // (diameter diameters[i]) gets site i.
  for (std::size_t i = 0; i < count; ++i) std::swap(sites[i], sites[i + random.below(sites.size() - i)]);
  sites.resize(count);
  shake(sites, diameters, d, params, random, result);

  result.centres.reserve(3 * count);
  for (const auto& p : sites) result.centres.insert(result.centres.end(), p.begin(), p.end());
  result.diameters = std::move(diameters);
  return result;
}

}  // namespace rheosim::dem
