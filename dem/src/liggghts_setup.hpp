// LIGGGHTS input shared by the DEM scenes (rheometer disk, shear cell): the particles' data file,
// the granular atom set-up, Hertz contacts with per-material properties, gravity, the integrator,
// and the run in blocks that end where the scene's plate averages are sampled.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "rheosim/dem/engine.hpp"
#include "rheosim/dem/particles.hpp"

namespace rheosim::dem::detail {

// " v v v …": `times` copies of value, for LIGGGHTS' peratomtype / peratomtypepair lists.
[[nodiscard]] std::string repeated(double value, int times);

// What a LIGGGHTS data file (atom_style granular) holds: spheres of one material type and density.
struct ParticleData {
  std::string title;                            // the first line
  int atom_types = 1;                           // material types the scene declares
  int particle_type = 1;                        // the spheres' type
  std::array<double, 3> box_low{}, box_high{};  // [m]
  std::span<const double> centres;              // 3 per sphere [m]
  std::span<const double> diameters;            // 1 per sphere [m]
  double density = 0;                           // [kg/m³]
  std::span<const double> velocities;           // empty, or 6 per sphere: vx vy vz [m/s], ωx ωy ωz [rad/s]
};
// Writes `data` to `file` atomically (core::write_atomically), every number to 17 digits.
void write_particle_data(const std::filesystem::path& file, const ParticleData& data);

// atom_style granular in SI units, `boundary` ("p p f", "f f f"), atoms from a LIGGGHTS data file.
void read_granular_atoms(Engine& engine, std::string_view boundary, const std::filesystem::path& data_file);

// Hertz contacts with tangential history for `material_types` materials sharing the particles'
// E, ν and e; `friction_pairs` is the peratomtypepair list of μ_c (types × types values).
// LIGGGHTS checks E in SI units against [5e6, 1e9] Pa unless told otherwise: softened particles
// (contact-stiffness scaling) need soft_particles, the CD §4 ones hard_particles.
void set_hertz_contacts(Engine& engine, const ParticleProperties& particles, int material_types,
                        std::string_view friction_pairs, double neighbor_skin, double time_step);

// fix gravity along `acceleration` (nothing for nullopt or a zero vector).
void add_gravity(Engine& engine, const std::optional<std::array<double, 3>>& acceleration);

// Velocity-Verlet for spheres, then `average_fix` (the scene's fix ave/time on its plates) and a
// thermo line only at the start and end of each run.
void integrate_spheres(Engine& engine, std::string_view average_fix);

// Runs `steps` steps (>= 0) in chunks that end on multiples of `block` (the scene's fix ave/time
// period) and calls at_block_end(step) whenever a chunk ends on one, when the average is fresh.
void advance_in_blocks(Engine& engine, std::int64_t steps, std::int64_t block,
                       const std::function<void(std::int64_t block_end)>& at_block_end);

}  // namespace rheosim::dem::detail
