// LIGGGHTS input shared by the DEM scenes (rheometer disk, shear cell): the granular atom set-up,
// Hertz contacts with per-material properties, gravity and the integrator.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "rheosim/dem/engine.hpp"
#include "rheosim/dem/particles.hpp"

namespace rheosim::dem::detail {

// " v v v …": `times` copies of value, for LIGGGHTS' peratomtype / peratomtypepair lists.
[[nodiscard]] std::string repeated(double value, int times);

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

}  // namespace rheosim::dem::detail
