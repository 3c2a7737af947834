// LIGGGHTS input shared by the DEM scenes (see liggghts_setup.hpp).
#include "liggghts_setup.hpp"

#include <cmath>

#include <fmt/format.h>

namespace rheosim::dem::detail {

std::string repeated(double value, int times) {
  std::string s;
  for (int i = 0; i < times; ++i) s += fmt::format(" {:.17g}", value);
  return s;
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

}  // namespace rheosim::dem::detail
