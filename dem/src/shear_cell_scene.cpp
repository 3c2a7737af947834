// dem::ShearCellScene on LIGGGHTS 3.8 (see shear_cell_scene.hpp for the scene and its choices).
#include "rheosim/dem/shear_cell_scene.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "liggghts_setup.hpp"
#include "portable_random.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/units.hpp"
#include "rheosim/dem/contact.hpp"

namespace rheosim::dem {
namespace {

namespace fs = std::filesystem;

constexpr const char* top_mesh_id = "rheosim_cell_top";
constexpr const char* bottom_mesh_id = "rheosim_cell_bottom";
constexpr const char* stress_average_id = "rheosim_cell_stress";
constexpr int particle_type = 1;
constexpr int plate_type = 2;
constexpr int material_types = 2;

[[noreturn]] void out_of_range(std::string_view field, double value, std::string_view expected) {
  throw std::invalid_argument(
      fmt::format("ShearCellScene::Params::{} = {} is out of range, expected {}", field, value, expected));
}

void check_params(const ShearCellScene::Params& p) {
  const auto& q = p.particles;
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(q.diameter)) out_of_range("particles.diameter", q.diameter, "a finite value > 0");
  if (!(positive(p.gap) && p.gap > q.diameter)) out_of_range("gap", p.gap, fmt::format("> d = {} m", q.diameter));
  if (!(positive(p.cell_length) && p.cell_length >= 2.0 * q.diameter))
    out_of_range("cell_length", p.cell_length, fmt::format(">= 2 d = {} m", 2.0 * q.diameter));
  if (!(positive(p.cell_width) && p.cell_width >= 2.0 * q.diameter))
    out_of_range("cell_width", p.cell_width, fmt::format(">= 2 d = {} m", 2.0 * q.diameter));
  if (q.size_distribution.type != SizeDistribution::Type::none)
    throw std::invalid_argument(
        "ShearCellScene::Params::particles.size_distribution: the shear cell takes monodisperse particles only; "
        "use model: full_disk for a size distribution");
  if (!(q.volume_fraction >= 0.0 && q.volume_fraction <= 0.45))
    out_of_range("particles.volume_fraction", q.volume_fraction, "[0, 0.45]");
  if (!positive(q.density)) out_of_range("particles.density", q.density, "a finite value > 0");
  if (!positive(q.youngs_modulus)) out_of_range("particles.youngs_modulus", q.youngs_modulus, "a finite value > 0");
  if (!(q.poisson_ratio >= 0.0 && q.poisson_ratio <= 0.5))
    out_of_range("particles.poisson_ratio", q.poisson_ratio, "[0, 0.5]");
  if (!(q.restitution > 0.0 && q.restitution <= 1.0)) out_of_range("particles.restitution", q.restitution, "(0, 1]");
  if (!(std::isfinite(q.friction) && q.friction >= 0.0))
    out_of_range("particles.friction", q.friction, "a finite value >= 0");
  if (!std::isfinite(p.shear_rate)) out_of_range("shear_rate", p.shear_rate, "a finite value");
  if (!(p.time_step_fraction > 0.0 && p.time_step_fraction <= 1.0))
    out_of_range("time_step_fraction", p.time_step_fraction, "(0, 1]");
  if (p.time_step && !positive(*p.time_step)) out_of_range("time_step", *p.time_step, "a finite value > 0");
  if (p.gravity)
    for (const double a : *p.gravity)
      if (!std::isfinite(a)) out_of_range("gravity", a, "finite components");
  if (p.run_directory.empty())
    throw std::invalid_argument(
        "ShearCellScene::Params::run_directory is empty, expected the folder for LIGGGHTS' files");
  if (p.run_directory.string().find_first_of(" \t\r\n\"'") != std::string::npos)
    throw std::invalid_argument(fmt::format(
        "ShearCellScene::Params::run_directory = '{}' contains whitespace or quotes, which LIGGGHTS' input cannot "
        "take in file names; choose another folder",
        p.run_directory.string()));
  if (!(std::isfinite(p.initial_speed) && p.initial_speed >= 0.0))
    out_of_range("initial_speed", p.initial_speed, "a finite value >= 0");
  if (p.stress_sample_interval < 1)
    out_of_range("stress_sample_interval", static_cast<double>(p.stress_sample_interval), ">= 1");
  if (!(p.neighbor_skin_fraction > 0.0 && p.neighbor_skin_fraction <= 1.0))
    out_of_range("neighbor_skin_fraction", p.neighbor_skin_fraction, "(0, 1]");
  if (p.positions) {
    const auto& x = *p.positions;
    if (x.size() % 3 != 0)
      throw std::invalid_argument(
          fmt::format("ShearCellScene::Params::positions has {} values, expected 3 per particle", x.size()));
    const double r = 0.5 * q.diameter;
    for (std::size_t i = 0; i < x.size() / 3; ++i) {
      const double px = x[3 * i], py = x[3 * i + 1], pz = x[3 * i + 2];
      if (!(px >= 0.0 && px < p.cell_length && py >= 0.0 && py < p.cell_width && pz >= r && pz <= p.gap - r))
        throw std::invalid_argument(fmt::format(
            "ShearCellScene::Params::positions: particle {} at ({}, {}, {}) m is not inside the cell (x in [0, {}), "
            "y in [0, {}), z in [{}, {}])",
            i, px, py, pz, p.cell_length, p.cell_width, r, p.gap - r));
    }
  }
}

ShearCellScene::Params checked(ShearCellScene::Params p) {
  check_params(p);
  return p;
}

MPI_Comm communicator_of(const ShearCellScene::Params& p) {
  return p.communicator_fortran_handle ? MPI_Comm_f2c(*p.communicator_fortran_handle) : MPI_COMM_WORLD;
}

// Hard-sphere Monte Carlo shaking in the periodic box, as the disk's placement does
// (placement.cpp: 50 sweeps, step adapted to 40 % acceptance): each move keeps the centre
// d/2 from the plates and d from every other centre (minimum image in x and y).
// Why: the layered lattice alone puts the spheres in two planes d/2 from the plates at
// H = 2.5 d, and a drag-only suspension that follows the flow never leaves them, so its spheres
// never meet; the disk's shaken placement has spheres at every height, which collide. At
// φ = 0.1 the lattice gave 1.000× the liquid against the disk's 1.019 / 1.029× (50 / 100 1/s,
// means of seeds 1–3); shaken, the cell gives 1.023 / 1.024× (docs/shear-cell.md).
void shake_in_cell(const ShearCellScene::Params& p, detail::PortableRandom& random, std::vector<double>& c) {
  constexpr int sweeps = 50;
  constexpr double target_acceptance = 0.4;
  const double d = p.particles.diameter;
  const double lo = 0.5 * d * (1.0 + 1e-9), hi = p.gap - lo;
  const double contact2 = d * d * (1.0 + 2e-9);
  const std::size_t n = c.size() / 3;
  // Columns of at least d in x and y (periodic), all heights in one column.
  const int bx = std::max(1, static_cast<int>(std::floor(p.cell_length / d)));
  const int by = std::max(1, static_cast<int>(std::floor(p.cell_width / d)));
  const auto column_of = [&](double x, double y) {
    const int i = std::min(bx - 1, static_cast<int>(x / p.cell_length * bx));
    const int j = std::min(by - 1, static_cast<int>(y / p.cell_width * by));
    return static_cast<std::size_t>(j * bx + i);
  };
  std::vector<std::vector<std::size_t>> columns(static_cast<std::size_t>(bx * by));
  for (std::size_t i = 0; i < n; ++i) columns[column_of(c[3 * i], c[3 * i + 1])].push_back(i);
  const auto fits = [&](std::size_t self, double x, double y, double z) {
    if (z < lo || z > hi) return false;
    const int ci = static_cast<int>(column_of(x, y) % static_cast<std::size_t>(bx));
    const int cj = static_cast<int>(column_of(x, y) / static_cast<std::size_t>(bx));
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        const int i = ((ci + di) % bx + bx) % bx, j = ((cj + dj) % by + by) % by;
        for (const std::size_t o : columns[static_cast<std::size_t>(j * bx + i)]) {
          if (o == self) continue;
          double dx = x - c[3 * o], dy = y - c[3 * o + 1];
          dx -= std::round(dx / p.cell_length) * p.cell_length;
          dy -= std::round(dy / p.cell_width) * p.cell_width;
          const double dz = z - c[3 * o + 2];
          if (dx * dx + dy * dy + dz * dz < contact2) return false;
        }
      }
    return true;
  };
  double step = 0.1 * d;
  for (int sweep = 0; sweep < sweeps && n > 0; ++sweep) {
    std::size_t accepted = 0;
    for (std::size_t i = 0; i < n; ++i) {
      double x = c[3 * i] + step * random.symmetric(), y = c[3 * i + 1] + step * random.symmetric();
      const double z = c[3 * i + 2] + step * random.symmetric();
      x -= std::floor(x / p.cell_length) * p.cell_length;
      y -= std::floor(y / p.cell_width) * p.cell_width;
      if (!fits(i, x, y, z)) continue;
      auto& from = columns[column_of(c[3 * i], c[3 * i + 1])];
      from.erase(std::find(from.begin(), from.end(), i));
      columns[column_of(x, y)].push_back(i);
      c[3 * i] = x;
      c[3 * i + 1] = y;
      c[3 * i + 2] = z;
      ++accepted;
    }
    const double rate = static_cast<double>(accepted) / static_cast<double>(n);
    step = std::clamp(step * std::clamp(rate / target_acceptance, 0.5, 2.0), 1e-6 * d, d);
  }
}

// Jittered layered lattice, periodic in x and y. Layers are at least d apart in z and sites at
// least d apart in the plane, and each site moves by at most half the slack, so no two spheres
// (nor a sphere and a periodic image) overlap. A random subset of the sites gets a particle;
// then shake_in_cell spreads them over every height. Deterministic in the seed, so every MPI
// rank computes the same placement.
std::vector<double> place_in_cell(const ShearCellScene::Params& p) {
  const auto& q = p.particles;
  const double d = q.diameter;
  const double r = 0.5 * d;
  const std::size_t count = shear_cell_particle_count(p.gap, p.cell_length, p.cell_width, d, q.volume_fraction);
  const int layers = 1 + static_cast<int>(std::floor((p.gap - d) / d * (1.0 - 1e-12)));
  const double layer_spacing = layers > 1 ? (p.gap - d) / (layers - 1) : 0.0;
  const double z_slack = layers > 1 ? 0.5 * (layer_spacing - d) : 0.5 * (p.gap - d);
  // In-plane: a hexagonal lattice, n_x sites per row (spacing a_x >= d) and an even number of
  // rows n_y (spacing a_y >= d √3/2), odd rows shifted by a_x/2, so it is periodic in x and y.
  const int nx = std::max(2, static_cast<int>(std::floor(p.cell_length / d + 1e-9)));
  int ny = static_cast<int>(std::floor(p.cell_width / (0.5 * std::sqrt(3.0) * d) + 1e-9));
  ny = std::max(2, ny - ny % 2);
  const double ax = p.cell_length / nx;
  const double ay = p.cell_width / ny;
  // Closest lattice neighbours; each site moves by at most half the slack (|shift| <= jitter).
  const double nearest = std::min({ax, std::hypot(0.5 * ax, ay), 2.0 * ay});
  const double jitter = std::max(0.0, 0.5 * (nearest - d)) * 0.999;
  const std::size_t capacity =
      static_cast<std::size_t>(layers) * static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  if (count > capacity)
    throw std::invalid_argument(fmt::format(
        "ShearCellScene::Params::particles.volume_fraction = {} needs {} particles, but the layered placement of "
        "this cell holds {} ({} layers of {} × {} hexagonal sites), i.e. φ <= {:.3f}; lower φ or change the gap",
        q.volume_fraction, count, capacity, layers, nx, ny,
        static_cast<double>(capacity) * core::units::sphere_volume(d) / (p.cell_length * p.cell_width * p.gap)));

  detail::PortableRandom random(p.seed);
  std::vector<std::size_t> sites(capacity);
  std::iota(sites.begin(), sites.end(), std::size_t{0});
  for (std::size_t i = 0; i < count; ++i) std::swap(sites[i], sites[i + random.below(capacity - i)]);
  sites.resize(count);
  std::sort(sites.begin(), sites.end());

  std::vector<double> centres;
  centres.reserve(3 * count);
  for (const std::size_t s : sites) {
    const auto layer = static_cast<int>(s / (static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny)));
    const std::size_t in_layer = s % (static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
    const auto ix = static_cast<int>(in_layer % static_cast<std::size_t>(nx));
    const auto iy = static_cast<int>(in_layer / static_cast<std::size_t>(nx));
    const double row_shift = (iy % 2 == 1) ? 0.5 : 0.0;
    const double layer_shift = (layer % 2 == 1) ? 0.25 : 0.0;  // stagger alternate layers
    const double angle = 2.0 * core::units::pi * random.uniform();
    const double reach = jitter * random.uniform();
    double x = (ix + 0.25 + row_shift + layer_shift) * ax + reach * std::cos(angle);
    double y = (iy + 0.5) * ay + reach * std::sin(angle);
    x -= std::floor(x / p.cell_length) * p.cell_length;
    y -= std::floor(y / p.cell_width) * p.cell_width;
    const double z0 = layers > 1 ? r + layer * layer_spacing : 0.5 * p.gap;
    const double z = std::clamp(z0 + random.symmetric() * z_slack * 0.999, r, p.gap - r);
    centres.insert(centres.end(), {x, y, z});
  }
  shake_in_cell(p, random, centres);
  return centres;
}

// A flat rectangle [0, L_x] × [0, L_y] at height z, cells of about 4 d, two triangles each.
void write_plate_stl(std::ostream& out, const ShearCellScene::Params& p, double z, std::string_view name) {
  const auto cells_along = [&](double length) {
    return std::max(1, static_cast<int>(std::lround(length / (4.0 * p.particles.diameter))));
  };
  const int nx = cells_along(p.cell_length);
  const int ny = cells_along(p.cell_width);
  const double hx = p.cell_length / nx;
  const double hy = p.cell_width / ny;
  fmt::print(out, "solid {}\n", name);
  const auto facet = [&](double x0, double y0, double x1, double y1, double x2, double y2) {
    fmt::print(out, "facet normal 0 0 1\n outer loop\n");
    for (const auto& [x, y] : {std::pair{x0, y0}, std::pair{x1, y1}, std::pair{x2, y2}})
      fmt::print(out, "  vertex {:.17g} {:.17g} {:.17g}\n", x, y, z);
    fmt::print(out, " endloop\nendfacet\n");
  };
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      // Nodes on the far edges are written as L exactly, not i·h, so the plate covers the box.
      const double x0 = i * hx, x1 = (i + 1 == nx) ? p.cell_length : (i + 1) * hx;
      const double y0 = j * hy, y1 = (j + 1 == ny) ? p.cell_width : (j + 1) * hy;
      facet(x0, y0, x1, y0, x1, y1);
      facet(x0, y0, x1, y1, x0, y1);
    }
  fmt::print(out, "endsolid {}\n", name);
}

}  // namespace

std::size_t shear_cell_particle_count(double gap, double cell_length, double cell_width, double diameter,
                                      double volume_fraction) {
  return static_cast<std::size_t>(
      std::llround(volume_fraction * cell_length * cell_width * gap / core::units::sphere_volume(diameter)));
}

class ShearCellScene::Impl {
 public:
  explicit Impl(Params p);
  void advance(std::int64_t steps);

  Params params;
  Engine engine;
  std::vector<double> centres;
  std::vector<WallStressSample> series;
  double time_step = 0.0;
  double rayleigh_time = 0.0;

  [[nodiscard]] double margin() const { return params.particles.diameter; }
  [[nodiscard]] double area() const { return params.cell_length * params.cell_width; }

 private:
  void write_files();
  void set_up_liggghts();
};

ShearCellScene::Impl::Impl(Params p)
    : params(checked(std::move(p))),
      engine(Engine::Params{.run_directory = params.run_directory,
                            .communicator_fortran_handle = params.communicator_fortran_handle}) {
  const auto& q = params.particles;
  rayleigh_time = dem::rayleigh_time({.radius = 0.5 * q.diameter,
                                      .density = q.density,
                                      .youngs_modulus = q.youngs_modulus,
                                      .poisson_ratio = q.poisson_ratio});
  time_step = params.time_step ? *params.time_step : params.time_step_fraction * rayleigh_time;
  centres = params.positions ? *params.positions : place_in_cell(params);
  write_files();
  set_up_liggghts();
}

void ShearCellScene::Impl::write_files() {
  const MPI_Comm comm = communicator_of(params);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) {
    core::write_atomically(params.run_directory / "top_plate.stl",
                           [&](std::ostream& out) { write_plate_stl(out, params, params.gap, "top_plate"); });
    core::write_atomically(params.run_directory / "bottom_plate.stl",
                           [&](std::ostream& out) { write_plate_stl(out, params, 0.0, "bottom_plate"); });
    const auto& q = params.particles;
    const std::size_t n = centres.size() / 3;
    detail::PortableRandom random(params.seed ^ 0x9e3779b97f4a7c15ULL);
    std::vector<double> velocities;
    velocities.reserve(6 * n);
    for (std::size_t i = 0; i < n; ++i) {
      std::array<double, 3> v{params.start_in_shear_profile ? params.shear_rate * centres[3 * i + 2] : 0.0, 0.0, 0.0};
      if (params.initial_speed > 0.0) {
        const std::array<double, 3> direction = random.direction();
        for (int k = 0; k < 3; ++k) v[k] += params.initial_speed * direction[k];
      }
      // Spin of the undisturbed shear flow, ω_y = γ̇/2, when starting in the profile.
      const double spin = params.start_in_shear_profile ? 0.5 * params.shear_rate : 0.0;
      velocities.insert(velocities.end(), {v[0], v[1], v[2], 0.0, spin, 0.0});
    }
    const std::vector<double> diameters(n, q.diameter);
    detail::write_particle_data(
        params.run_directory / "particles.data",
        {.title =
             fmt::format("LIGGGHTS data file written by rheosim: periodic shear cell L_x = {} m, L_y = {} m, H = {} m",
                         params.cell_length, params.cell_width, params.gap),
         .atom_types = material_types,
         .particle_type = particle_type,
         .box_low = {0.0, 0.0, -margin()},
         .box_high = {params.cell_length, params.cell_width, params.gap + margin()},
         .centres = centres,
         .diameters = diameters,
         .density = q.density,
         .velocities = velocities});
  }
  MPI_Barrier(comm);
}

void ShearCellScene::Impl::set_up_liggghts() {
  const auto& q = params.particles;
  const std::string top_file = (params.run_directory / "top_plate.stl").string();
  const std::string bottom_file = (params.run_directory / "bottom_plate.stl").string();
  const std::string data_file = (params.run_directory / "particles.data").string();
  detail::read_granular_atoms(engine, "p p f", data_file);
  detail::set_hertz_contacts(engine, q, material_types, detail::repeated(q.friction, material_types * material_types),
                             params.neighbor_skin_fraction * q.diameter, time_step);
  engine.commands({
      // Top plate: a conveyor surface at U along x (see the header), stress module on.
      fmt::format("fix {} all mesh/surface/stress file {} type {} surface_vel {:.17g} 0 0 stress on", top_mesh_id,
                  top_file, plate_type, params.shear_rate * params.gap),
      fmt::format("fix {} all mesh/surface/stress file {} type {} stress on", bottom_mesh_id, bottom_file, plate_type),
      fmt::format("fix rheosim_cell_walls all wall/gran model hertz tangential history mesh n_meshes 2 meshes {} {}",
                  top_mesh_id, bottom_mesh_id),
  });
  detail::add_gravity(engine, params.gravity);
  const auto n = params.stress_sample_interval;
  detail::integrate_spheres(
      engine, fmt::format("fix {} all ave/time 1 {} {} f_{}[1] f_{}[3] f_{}[1] f_{}[3]", stress_average_id, n, n,
                          top_mesh_id, top_mesh_id, bottom_mesh_id, bottom_mesh_id));
}

void ShearCellScene::Impl::advance(std::int64_t steps) {
  if (steps < 0) throw std::invalid_argument(fmt::format("ShearCellScene::advance: steps = {}, expected >= 0", steps));
  const double a = area();
  detail::advance_in_blocks(engine, steps, params.stress_sample_interval, [&](std::int64_t block_end) {
    series.push_back({.step = block_end,
                      .time = engine.time(),
                      .top_shear = -engine.fix_vector(stress_average_id, 0) / a,
                      .top_normal = engine.fix_vector(stress_average_id, 1) / a,
                      .bottom_shear = engine.fix_vector(stress_average_id, 2) / a,
                      .bottom_normal = -engine.fix_vector(stress_average_id, 3) / a});
  });
}

// ---------------------------------------------------------------------------------------------

ShearCellScene::ShearCellScene(Params params) : impl_(std::make_unique<Impl>(std::move(params))) {}
ShearCellScene::~ShearCellScene() = default;

void ShearCellScene::advance(std::int64_t steps) { impl_->advance(steps); }
std::span<const WallStressSample> ShearCellScene::stress_series() const { return impl_->series; }
double ShearCellScene::mean_top_shear_stress(std::size_t samples) const {
  const auto& s = impl_->series;
  const std::size_t n = std::min(samples, s.size());
  if (n == 0) return 0.0;
  double sum = 0.0;
  for (std::size_t i = s.size() - n; i < s.size(); ++i) sum += s[i].top_shear;
  return sum / static_cast<double>(n);
}
double ShearCellScene::shear_rate() const { return impl_->params.shear_rate; }
double ShearCellScene::plate_velocity() const { return impl_->params.shear_rate * impl_->params.gap; }
double ShearCellScene::plate_area() const { return impl_->area(); }
double ShearCellScene::time_step() const { return impl_->time_step; }
double ShearCellScene::rayleigh_time() const { return impl_->rayleigh_time; }
std::int64_t ShearCellScene::total_particle_count() const { return impl_->engine.total_particle_count(); }
double ShearCellScene::volume_fraction() const {
  const auto& p = impl_->params;
  return static_cast<double>(impl_->centres.size() / 3) * core::units::sphere_volume(p.particles.diameter) /
         (p.cell_length * p.cell_width * p.gap);
}
std::array<double, 3> ShearCellScene::box_low() const { return {0.0, 0.0, -impl_->margin()}; }
std::array<double, 3> ShearCellScene::box_high() const {
  const auto& p = impl_->params;
  return {p.cell_length, p.cell_width, p.gap + impl_->margin()};
}
const std::vector<double>& ShearCellScene::initial_positions() const { return impl_->centres; }
const ShearCellScene::Params& ShearCellScene::params() const { return impl_->params; }
Engine& ShearCellScene::engine() { return impl_->engine; }
const Engine& ShearCellScene::engine() const { return impl_->engine; }

}  // namespace rheosim::dem
