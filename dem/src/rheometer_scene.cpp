// dem::RheometerScene on LIGGGHTS 3.8 (see rheometer_scene.hpp for the scene and its choices).
#include "rheosim/dem/rheometer_scene.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "disk_mesh.hpp"
#include "liggghts_setup.hpp"
#include "portable_random.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/dem/contact.hpp"
#include "rheosim/dem/size_distribution.hpp"

namespace rheosim::dem {
namespace {

namespace fs = std::filesystem;
using core::units::pi;

// LIGGGHTS ids of the scene's fixes and variables.
constexpr const char* top_mesh_id = "rheosim_top";
constexpr const char* torque_average_id = "rheosim_torque";
constexpr const char* omega_variable = "rheosim_omega";
constexpr int particle_type = 1;
constexpr int plate_type = 2;
constexpr int rim_type = 3;
constexpr int material_types = 3;
// Stress module of mesh/surface/stress: global vector [fx fy fz tx ty tz px py pz].
constexpr int torque_z_index = 5;

void check_finite_positive(std::string_view name, double value) {
  if (!(std::isfinite(value) && value > 0.0))
    throw std::invalid_argument(
        fmt::format("RheometerScene::Params::{} = {} is out of range, expected a finite value > 0", name, value));
}

void check_range(std::string_view name, double value, double lower, double upper, std::string_view range) {
  if (!(value >= lower && value <= upper))
    throw std::invalid_argument(
        fmt::format("RheometerScene::Params::{} = {} is out of range, expected {}", name, value, range));
}

void check_params(const RheometerScene::Params& p) {
  const auto& g = p.geometry;
  const auto& q = p.particles;
  check_finite_positive("geometry.radius", g.radius);
  check_finite_positive("geometry.gap", g.gap);
  if (!(g.gap < g.radius))
    throw std::invalid_argument(fmt::format(
        "RheometerScene::Params::geometry.gap = {} m is out of range, expected < radius = {} m", g.gap, g.radius));
  check_finite_positive("particles.diameter", q.diameter);
  if (!(q.diameter < g.gap))
    throw std::invalid_argument(fmt::format(
        "RheometerScene::Params::particles.diameter = {} m is out of range, expected < gap = {} m", q.diameter, g.gap));
  if (q.size_distribution.type != SizeDistribution::Type::none) {
    if (p.positions)
      throw std::invalid_argument(
          "RheometerScene::Params: explicit positions take particles.diameter for every particle; drop "
          "particles.size_distribution");
    const double smallest = smallest_diameter(q);
    const double largest = largest_diameter(q);
    if (!(smallest > 0.0 && smallest <= largest && largest < g.gap))
      throw std::invalid_argument(fmt::format(
          "RheometerScene::Params::particles.size_distribution: diameters in [{}, {}] m, expected 0 < d_min <= "
          "d_max < gap = {} m",
          smallest, largest, g.gap));
  }
  check_range("particles.volume_fraction", q.volume_fraction, 0.0, 0.5, "[0, 0.5]");
  check_finite_positive("particles.density", q.density);
  check_finite_positive("particles.youngs_modulus", q.youngs_modulus);
  check_range("particles.poisson_ratio", q.poisson_ratio, 0.0, 0.5, "[0, 0.5]");
  if (!(q.restitution > 0.0 && q.restitution <= 1.0))
    throw std::invalid_argument(fmt::format(
        "RheometerScene::Params::particles.restitution = {} is out of range, expected (0, 1]", q.restitution));
  if (!(std::isfinite(q.friction) && q.friction >= 0.0))
    throw std::invalid_argument(fmt::format(
        "RheometerScene::Params::particles.friction = {} is out of range, expected a finite value >= 0", q.friction));
  if (!std::isfinite(p.rim_shear_rate))
    throw std::invalid_argument(
        fmt::format("RheometerScene::Params::rim_shear_rate = {} is not finite", p.rim_shear_rate));
  if (!(p.time_step_fraction > 0.0 && p.time_step_fraction <= 1.0))
    throw std::invalid_argument(fmt::format(
        "RheometerScene::Params::time_step_fraction = {} is out of range, expected (0, 1]", p.time_step_fraction));
  if (p.time_step) check_finite_positive("time_step", *p.time_step);
  if (p.gravity)
    for (const double component : *p.gravity)
      if (!std::isfinite(component))
        throw std::invalid_argument(fmt::format("RheometerScene::Params::gravity = ({}, {}, {}) is not finite",
                                                (*p.gravity)[0], (*p.gravity)[1], (*p.gravity)[2]));
  if (p.run_directory.empty())
    throw std::invalid_argument(
        "RheometerScene::Params::run_directory is empty, expected the folder for LIGGGHTS' files");
  if (p.run_directory.string().find_first_of(" \t\r\n\"'") != std::string::npos)
    throw std::invalid_argument(
        fmt::format("RheometerScene::Params::run_directory = '{}' contains whitespace or quotes, which LIGGGHTS' input "
                    "cannot take in file names; choose another folder",
                    p.run_directory.string()));
  if (!(std::isfinite(p.initial_speed) && p.initial_speed >= 0.0))
    throw std::invalid_argument(fmt::format(
        "RheometerScene::Params::initial_speed = {} is out of range, expected a finite value >= 0", p.initial_speed));
  if (p.placement_sweeps < 0)
    throw std::invalid_argument(fmt::format(
        "RheometerScene::Params::placement_sweeps = {} is out of range, expected >= 0", p.placement_sweeps));
  if (p.torque_sample_interval < 1)
    throw std::invalid_argument(
        fmt::format("RheometerScene::Params::torque_sample_interval = {} is out of range, expected >= 1",
                    p.torque_sample_interval));
  if (p.top_plate_rings < 0)
    throw std::invalid_argument(
        fmt::format("RheometerScene::Params::top_plate_rings = {} is out of range, expected >= 0", p.top_plate_rings));
  if (!(p.neighbor_skin_fraction > 0.0 && p.neighbor_skin_fraction <= 1.0))
    throw std::invalid_argument(
        fmt::format("RheometerScene::Params::neighbor_skin_fraction = {} is out of range, expected (0, 1]",
                    p.neighbor_skin_fraction));
  if (p.positions) {
    const auto& x = *p.positions;
    if (x.size() % 3 != 0)
      throw std::invalid_argument(
          fmt::format("RheometerScene::Params::positions has {} values, expected 3 per particle", x.size()));
    const double r = 0.5 * q.diameter;
    for (std::size_t i = 0; i < x.size() / 3; ++i) {
      const double px = x[3 * i];
      const double py = x[3 * i + 1];
      const double pz = x[3 * i + 2];
      const bool inside = std::isfinite(px) && std::isfinite(py) && std::isfinite(pz) && pz >= r && pz <= g.gap - r &&
                          std::hypot(px, py) <= g.radius - r;
      if (!inside)
        throw std::invalid_argument(fmt::format(
            "RheometerScene::Params::positions: particle {} at ({}, {}, {}) m is not inside the gap (centre at "
            "least d/2 = {} m from the plates z = 0, z = {} m and the rim r = {} m)",
            i, px, py, pz, r, g.gap, g.radius));
    }
  }
}

// The smallest sphere: it has the shortest Rayleigh time (t_R ∝ r), which bounds the step.
ElasticSphere sphere_of(const ParticleProperties& q) {
  return {.radius = 0.5 * smallest_diameter(q),
          .density = q.density,
          .youngs_modulus = q.youngs_modulus,
          .poisson_ratio = q.poisson_ratio};
}

RheometerScene::Params checked(RheometerScene::Params p) {
  check_params(p);
  return p;
}

MPI_Comm communicator_of(const RheometerScene::Params& p) {
  return p.communicator_fortran_handle ? MPI_Comm_f2c(*p.communicator_fortran_handle) : MPI_COMM_WORLD;
}

// Sends rank 0's vector to every rank of comm.
void broadcast(std::vector<double>& values, MPI_Comm comm) {
  auto n = static_cast<unsigned long long>(values.size());
  MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
  values.resize(static_cast<std::size_t>(n));
  if (n > 0) MPI_Bcast(values.data(), static_cast<int>(n), MPI_DOUBLE, 0, comm);
}

// Places the particles on rank 0 only and sends the result to the other ranks: the placement
// is done once, and every rank holds the very same one (placement() is the same everywhere).
// An invalid_argument on rank 0 (φ beyond the lattice) is re-thrown on every rank.
Placement place_once(const RheometerScene::Params& params, MPI_Comm comm) {
  const auto& g = params.geometry;
  const auto& q = params.particles;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  Placement placed;
  std::string error;
  if (rank == 0) {
    try {
      PlacementParams pp{.plate_radius = g.radius,
                         .gap = g.gap,
                         .diameter = q.diameter,
                         .volume_fraction = q.volume_fraction,
                         .seed = params.seed,
                         .shake_sweeps = params.placement_sweeps};
      if (q.size_distribution.type != SizeDistribution::Type::none)
        pp.diameters =
            sample_diameters(q.size_distribution, q.diameter, q.volume_fraction * pi * g.radius * g.radius * g.gap,
                             params.seed ^ 0x2545f4914f6cdd1dULL);  // a stream apart from the placement's
      placed = place_particles(pp);
    } catch (const std::exception& e) {  // every rank must learn of it, or the others would wait forever
      error = std::string(dynamic_cast<const std::invalid_argument*>(&e) != nullptr ? "I" : "L") + e.what();
    }
  }
  std::vector<double> text(error.begin(), error.end());
  broadcast(text, comm);
  if (!text.empty()) {
    const std::string message(text.begin() + 1, text.end());
    if (text.front() == 'I') throw std::invalid_argument(message);
    throw std::logic_error(message);
  }
  broadcast(placed.centres, comm);
  broadcast(placed.diameters, comm);
  std::vector<double> scalars{static_cast<double>(placed.count),
                              placed.volume_fraction,
                              static_cast<double>(placed.layers),
                              placed.layer_spacing,
                              placed.capacity_volume_fraction,
                              placed.lattice_spacing,
                              static_cast<double>(placed.lattice_sites),
                              placed.shake_acceptance,
                              placed.shake_step,
                              placed.lattice == "hexagonal" ? 1.0 : 0.0};
  broadcast(scalars, comm);
  if (rank != 0) {
    placed.count = static_cast<std::size_t>(scalars[0]);
    placed.volume_fraction = scalars[1];
    placed.layers = static_cast<int>(scalars[2]);
    placed.layer_spacing = scalars[3];
    placed.capacity_volume_fraction = scalars[4];
    placed.lattice_spacing = scalars[5];
    placed.lattice_sites = static_cast<std::size_t>(scalars[6]);
    placed.shake_acceptance = scalars[7];
    placed.shake_step = scalars[8];
    placed.lattice = scalars[9] == 1.0 ? "hexagonal" : "square";
  }
  return placed;
}

}  // namespace

class RheometerScene::Impl {
 public:
  explicit Impl(Params params);

  void set_shear_rate(double rim_shear_rate);
  void advance(std::int64_t steps);

  Params params;
  Engine engine;
  std::optional<Placement> placement;
  std::vector<TorqueSample> series;
  double rim_shear_rate = 0.0;
  double time_step = 0.0;
  double rayleigh_time = 0.0;
  int triangles = 0;

 private:
  [[nodiscard]] double omega_of(double rate) const { return rate * params.geometry.gap / params.geometry.radius; }
  void write_files(const std::vector<double>& centres, const std::vector<double>& diameters,
                   const detail::DiskMesh& mesh);
  void set_up_liggghts();
};

RheometerScene::Impl::Impl(Params p)
    : params(checked(std::move(p))),
      engine(Engine::Params{.run_directory = params.run_directory,
                            .communicator_fortran_handle = params.communicator_fortran_handle}) {
  const auto& g = params.geometry;
  const auto& q = params.particles;
  rim_shear_rate = params.rim_shear_rate;
  rayleigh_time = dem::rayleigh_time(sphere_of(q));
  time_step = params.time_step ? *params.time_step : params.time_step_fraction * rayleigh_time;

  std::vector<double> centres;
  std::vector<double> diameters;
  if (params.positions) {
    centres = *params.positions;
    diameters.assign(centres.size() / 3, q.diameter);
  } else {
    placement = place_once(params, communicator_of(params));
    centres = placement->centres;
    diameters = placement->diameters;
  }
  const int rings = params.top_plate_rings > 0
                        ? params.top_plate_rings
                        : std::max(1, static_cast<int>(std::ceil(g.radius / (10.0 * q.diameter))));
  const auto mesh = detail::make_disk_mesh(g.radius, g.gap, rings);
  triangles = static_cast<int>(mesh.triangles.size());
  write_files(centres, diameters, mesh);
  set_up_liggghts();
}

// Rank 0 writes, everybody waits: LIGGGHTS reads the files in the next commands.
void RheometerScene::Impl::write_files(const std::vector<double>& centres, const std::vector<double>& diameters,
                                       const detail::DiskMesh& mesh) {
  const MPI_Comm comm = communicator_of(params);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) {
    core::write_atomically(params.run_directory / "top_plate.stl",
                           [&](std::ostream& out) { detail::write_ascii_stl(out, mesh, "top_plate"); });

    const auto& g = params.geometry;
    const auto& q = params.particles;
    const std::size_t n = centres.size() / 3;
    // Velocities: isotropic directions from the seed, no spin.
    std::vector<double> velocities;
    if (params.initial_speed > 0.0) {
      detail::PortableRandom random(params.seed ^ 0x9e3779b97f4a7c15ULL);
      velocities.reserve(6 * n);
      for (std::size_t i = 0; i < n; ++i) {
        for (const double c : random.direction()) velocities.push_back(params.initial_speed * c);
        velocities.insert(velocities.end(), 3, 0.0);
      }
    }
    // The box holds the whole mesh (LIGGGHTS warns about mesh nodes outside it) with a margin.
    const double margin = largest_diameter(q);
    const double half_width = mesh.outer_radius + margin;
    detail::write_particle_data(
        params.run_directory / "particles.data",
        {.title = fmt::format("LIGGGHTS data file written by rheosim: parallel-plate gap R = {} m, H = {} m", g.radius,
                              g.gap),
         .atom_types = material_types,
         .particle_type = particle_type,
         .box_low = {-half_width, -half_width, -margin},
         .box_high = {half_width, half_width, g.gap + margin},
         .centres = centres,
         .diameters = diameters,
         .density = q.density,
         .velocities = velocities});
  }
  MPI_Barrier(comm);
}

void RheometerScene::Impl::set_up_liggghts() {
  const auto& g = params.geometry;
  const auto& q = params.particles;
  const std::string mesh_file = (params.run_directory / "top_plate.stl").string();
  const std::string data_file = (params.run_directory / "particles.data").string();

  // Friction of each material pair: particle–particle and particle–plate μ_c, particle–rim 0.
  // Pairs without a particle never meet; they get μ_c (LIGGGHTS wants the full matrix).
  std::string friction;
  for (int i = 1; i <= material_types; ++i)
    for (int j = 1; j <= material_types; ++j) {
      const bool rim_contact = (i == rim_type || j == rim_type);
      friction += fmt::format(" {:.17g}", rim_contact ? 0.0 : q.friction);
    }

  detail::read_granular_atoms(engine, "f f f", data_file);
  detail::set_hertz_contacts(engine, q, material_types, friction, params.neighbor_skin_fraction * largest_diameter(q),
                             time_step);
  engine.commands({
      // Top plate: the stress module sums force and torque (about the origin) on the mesh.
      fmt::format("fix {} all mesh/surface/stress file {} type {} stress on", top_mesh_id, mesh_file, plate_type),
      fmt::format("variable {} equal {:.17g}", omega_variable, omega_of(rim_shear_rate)),
      fmt::format("fix rheosim_top_rotation all move/mesh mesh {} rotate/variable origin 0 0 0 axis 0 0 1 omega v_{}",
                  top_mesh_id, omega_variable),
      fmt::format("fix rheosim_top_wall all wall/gran model hertz tangential history mesh n_meshes 1 meshes {}",
                  top_mesh_id),
      fmt::format("fix rheosim_bottom_wall all wall/gran model hertz tangential history primitive type {} zplane 0.0",
                  plate_type),
      fmt::format(
          "fix rheosim_rim_wall all wall/gran model hertz tangential history primitive type {} zcylinder {:.17g} 0 0",
          rim_type, g.radius),
  });
  detail::add_gravity(engine, params.gravity);
  detail::integrate_spheres(
      engine, fmt::format("fix {} all ave/time 1 {} {} f_{}[{}]", torque_average_id, params.torque_sample_interval,
                          params.torque_sample_interval, top_mesh_id, torque_z_index + 1));
}

void RheometerScene::Impl::set_shear_rate(double rate) {
  if (!std::isfinite(rate))
    throw std::invalid_argument(fmt::format("RheometerScene::set_shear_rate: rim_shear_rate = {} is not finite", rate));
  engine.set_equal_variable(omega_variable, omega_of(rate));  // no new run setup (see header, "Rim")
  rim_shear_rate = rate;
}

void RheometerScene::Impl::advance(std::int64_t steps) {
  if (steps < 0) throw std::invalid_argument(fmt::format("RheometerScene::advance: steps = {}, expected >= 0", steps));
  detail::advance_in_blocks(engine, steps, params.torque_sample_interval, [&](std::int64_t block_end) {
    series.push_back({.step = block_end, .time = engine.time(), .torque = -engine.fix_scalar(torque_average_id)});
  });
}

// ---------------------------------------------------------------------------------------------

RheometerScene::RheometerScene(Params params) : impl_(std::make_unique<Impl>(std::move(params))) {}
RheometerScene::~RheometerScene() = default;

void RheometerScene::set_shear_rate(double rim_shear_rate) { impl_->set_shear_rate(rim_shear_rate); }
void RheometerScene::advance(std::int64_t steps) { impl_->advance(steps); }

double RheometerScene::rim_shear_rate() const { return impl_->rim_shear_rate; }
double RheometerScene::angular_velocity() const {
  return impl_->rim_shear_rate * impl_->params.geometry.gap / impl_->params.geometry.radius;
}
double RheometerScene::time_step() const { return impl_->time_step; }
double RheometerScene::rayleigh_time() const { return impl_->rayleigh_time; }
std::int64_t RheometerScene::total_particle_count() const { return impl_->engine.total_particle_count(); }

std::span<const TorqueSample> RheometerScene::torque_series() const { return impl_->series; }
double RheometerScene::torque() const { return -impl_->engine.fix_vector(top_mesh_id, torque_z_index); }

const std::optional<Placement>& RheometerScene::placement() const { return impl_->placement; }
const RheometerScene::Params& RheometerScene::params() const { return impl_->params; }
std::filesystem::path RheometerScene::top_plate_mesh_path() const {
  return impl_->params.run_directory / "top_plate.stl";
}
std::filesystem::path RheometerScene::particle_data_path() const {
  return impl_->params.run_directory / "particles.data";
}
int RheometerScene::top_plate_triangles() const { return impl_->triangles; }

Engine& RheometerScene::engine() { return impl_->engine; }
const Engine& RheometerScene::engine() const { return impl_->engine; }

}  // namespace rheosim::dem
