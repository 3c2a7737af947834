// LIGGGHTS input shared by the DEM scenes (see liggghts_setup.hpp).
#include "liggghts_setup.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "rheosim/core/output.hpp"

namespace rheosim::dem::detail {

std::string repeated(double value, int times) {
  std::string s;
  for (int i = 0; i < times; ++i) s += fmt::format(" {:.17g}", value);
  return s;
}

void write_particle_data(const std::filesystem::path& file, const ParticleData& data) {
  const std::size_t n = data.diameters.size();
  core::write_atomically(file, [&](std::ostream& out) {
    fmt::print(out, "{}\n\n", data.title);
    fmt::print(out, "{} atoms\n{} atom types\n\n", n, data.atom_types);
    fmt::print(out, "{:.17g} {:.17g} xlo xhi\n{:.17g} {:.17g} ylo yhi\n{:.17g} {:.17g} zlo zhi\n", data.box_low[0],
               data.box_high[0], data.box_low[1], data.box_high[1], data.box_low[2], data.box_high[2]);
    if (n == 0) return;
    fmt::print(out, "\nAtoms\n\n");  // atom-ID atom-type diameter density x y z
    for (std::size_t i = 0; i < n; ++i)
      fmt::print(out, "{} {} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", i + 1, data.particle_type, data.diameters[i],
                 data.density, data.centres[3 * i], data.centres[3 * i + 1], data.centres[3 * i + 2]);
    if (data.velocities.empty()) return;
    fmt::print(out, "\nVelocities\n\n");  // atom-ID vx vy vz ωx ωy ωz
    for (std::size_t i = 0; i < n; ++i) {
      const double* v = &data.velocities[6 * i];
      fmt::print(out, "{} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", i + 1, v[0], v[1], v[2], v[3], v[4],
                 v[5]);
    }
  });
}

void read_granular_atoms(Engine& engine, std::string_view boundary, const std::filesystem::path& data_file) {
  engine.commands({
      "atom_style granular",
      "atom_modify map array",
      fmt::format("boundary {}", boundary),
      "newton off",
      "communicate single vel yes",
      "units si",
  });
  engine.command(fmt::format("read_data {}", data_file.string()));
}

void set_hertz_contacts(Engine& engine, const ParticleProperties& particles, int material_types,
                        std::string_view friction_pairs, double neighbor_skin, double time_step) {
  const auto& q = particles;
  engine.commands({
      fmt::format("neighbor {:.17g} bin", neighbor_skin),
      "neigh_modify delay 0",
      q.youngs_modulus < 5e6 ? "soft_particles yes" : "hard_particles yes",
      fmt::format("fix rheosim_m1 all property/global youngsModulus peratomtype{}",
                  repeated(q.youngs_modulus, material_types)),
      fmt::format("fix rheosim_m2 all property/global poissonsRatio peratomtype{}",
                  repeated(q.poisson_ratio, material_types)),
      fmt::format("fix rheosim_m3 all property/global coefficientRestitution peratomtypepair {}{}", material_types,
                  repeated(q.restitution, material_types * material_types)),
      fmt::format("fix rheosim_m4 all property/global coefficientFriction peratomtypepair {}{}", material_types,
                  friction_pairs),
      "pair_style gran model hertz tangential history",
      "pair_coeff * *",
      fmt::format("timestep {:.17g}", time_step),
  });
}

void add_gravity(Engine& engine, const std::optional<std::array<double, 3>>& acceleration) {
  if (!acceleration) return;
  const auto& a = *acceleration;
  const double magnitude = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (magnitude > 0.0)
    engine.command(fmt::format("fix rheosim_gravity all gravity {:.17g} vector {:.17g} {:.17g} {:.17g}", magnitude,
                               a[0] / magnitude, a[1] / magnitude, a[2] / magnitude));
}

void integrate_spheres(Engine& engine, std::string_view average_fix) {
  engine.commands({
      "fix rheosim_integrate all nve/sphere", average_fix, "thermo_style custom step atoms ke",
      "thermo 0",  // one line at the start and end of each run
  });
}

void advance_in_blocks(Engine& engine, std::int64_t steps, std::int64_t block,
                       const std::function<void(std::int64_t block_end)>& at_block_end) {
  while (steps > 0) {
    const std::int64_t now = engine.step();
    const std::int64_t block_end = (now / block + 1) * block;
    const std::int64_t chunk = std::min(steps, block_end - now);
    engine.run(chunk);
    steps -= chunk;
    if (engine.step() == block_end) at_block_end(block_end);
  }
}

}  // namespace rheosim::dem::detail
