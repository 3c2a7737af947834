#pragma once
// dem::RheometerScene: the particles of a parallel-plate rheometer in LIGGGHTS,
// built from the case file's plate geometry and particle properties.
//
// Scene (SI units, axis along z through x = y = 0)
//   - Bottom plate: fixed, the plane z = 0 (fix wall/gran primitive zplane), material type 2.
//   - Top plate: z = H, a triangulated disk written by the scene into
//     <run_directory>/top_plate.stl (dem/src/disk_mesh.hpp: concentric rings, the outer
//     polygon circumscribes r = R), imported with `fix mesh/surface/stress ... stress on`
//     (material type 2) and rotated about the z axis by `fix move/mesh ... rotate/variable` at
//     Ω = γ̇_R H / R (CD §2.2: rim shear rate γ̇_R = Ω R / H). The angular velocity is an
//     equal-style LIGGGHTS variable, so set_shear_rate() changes Ω without rebuilding anything
//     or setting the run up again.
//   - Rim: frictionless wall at r = R (fix wall/gran primitive zcylinder). It is made
//     frictionless through its material: the rim is material type 3, and the friction
//     coefficient of the pair (particle type 1, rim type 3) is 0 in LIGGGHTS'
//     coefficientFriction matrix. With Coulomb limit μ F_n = 0 the tangential-history model
//     caps the tangential force at 0, so the rim pushes only along the radius, has the same
//     Hertz normal stiffness and restitution as the plates, and takes no torque about the
//     axis. (A separate wall model, e.g. `tangential no_history`, is not an option: wall/gran
//     must use the pair style's models.) One LIGGGHTS detail: when a run sets up (the first
//     advance(), or the first after a command given through engine()), contacts are evaluated
//     once without updating their history, and for a zero history LIGGGHTS applies tangential
//     damping instead of the Coulomb cap, so a rim contact that exists at that moment gets a
//     single step of tangential damping force. set_shear_rate() does not trigger a setup
//     (Engine::set_equal_variable), so in a normal run this happens once, at the start.
//   - Plates (type 2) have the particles' E, ν, e and friction μ_c; the plate material is not
//     given in the case file (CD §4 gives one set of contact parameters).
//   - Contact: `pair_style gran model hertz tangential history` and the same for every wall
//     (CD §3.1, eqs. 12–24; LIGGGHTS derives the damping from e, see contact.hpp). In SI units
//     E > 1e9 Pa needs `hard_particles yes`, which the scene sets.
//   - Particles: type 1, monodisperse (particles.diameter) or with particles.size_distribution (type not none)
//     (diameters drawn to fill φ π R² H by size_distribution.hpp), placed at the requested φ by
//     dem::place_particles (placement.hpp: layered lattice, random subset, hard-sphere Monte
//     Carlo; φ is of the whole gap volume π R² H; no overlaps; within 1 % of the target), or
//     at explicit positions (tests, restarts; monodisperse only). Under MPI the placement runs
//     once, on rank 0, and is broadcast, so every rank's placement() is the same. They enter LIGGGHTS through a data
//     file that the scene writes, <run_directory>/particles.data (read_data), with optional random initial velocities.
//   - Gravity optional (fix gravity), along any direction.
//   - Time step: δt = time_step_fraction · t_R, with the Rayleigh time t_R of the (smallest)
//     particles (contact.hpp), unless time_step overrides it. Default fraction 0.3: the CD §4 particles
//     (r = 100 µm, ρ = 1000 kg/m³, E = 3 GPa, ν = 0.33) have t_R = 3.18e-7 s, and the seed's
//     DEM step of 1e-7 s is 0.31 t_R; 0.3 t_R is that choice, inside the usual 0.1–0.4 t_R,
//     and the cheapest step that resolves a Hertz collision with about 15 steps at 1 m/s
//     (contact.hpp: t_c ∝ v^(−1/5)).
//
// Torque
//   The stress module of the top plate's mesh sums, on every step, the contact forces that the
//   particles exert on the plate and their moments about the origin (LIGGGHTS' f_ID[4..6];
//   reduced over all ranks). The scene reports the z component with the sign of a drive
//   torque: torque = −M_z, positive when the particles resist a plate turning at Ω > 0 (the
//   convention of the fluid torques in rheosim). A `fix ave/time 1 N N` averages it over every
//   block of N = torque_sample_interval steps; advance() stops at each block end and appends
//   one TorqueSample (the mean over the block, not a snapshot, so collisions are not aliased).
//   Blocks are aligned to multiples of N of LIGGGHTS' step counter; a block during which
//   set_shear_rate() was called mixes the two rates. torque() is the instantaneous value of
//   the last step. Contacts with the bottom plate and the rim are not in it (the frictionless
//   rim carries no axial torque anyway).
//
// Files in run_directory: liggghts.log (LIGGGHTS' log, see engine.hpp), top_plate.stl,
// particles.data. Under MPI every rank of the communicator constructs the scene collectively
// with the same Params; rank 0 writes the files.
//
// Example
//   dem::RheometerScene scene({.geometry = c.geometry, .particles = *c.particles,
//                              .rim_shear_rate = 10.0, .gravity = std::nullopt,
//                              .run_directory = out / "dem"});
//   scene.advance(10000);
//   for (const auto& s : scene.torque_series()) ...  // s.step, s.time, s.torque
//   scene.set_shear_rate(50.0);
//   scene.advance(10000);
//
// Not copyable or movable (it owns its Engine).
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "rheosim/core/case.hpp"
#include "rheosim/core/units.hpp"
#include "rheosim/dem/engine.hpp"
#include "rheosim/dem/particles.hpp"
#include "rheosim/dem/placement.hpp"

namespace rheosim::dem {

struct TorqueSample {
  std::int64_t step = 0;  // LIGGGHTS step at the end of the block
  double time = 0.0;      // simulated time at the end of the block [s]
  double torque = 0.0;    // mean contact torque on the top plate over the block, −M_z [N·m]
};

class RheometerScene {
 public:
  struct Params {
    core::PlateGeometry geometry{};                  // R, H [m]: R > 0, 0 < H < R
    ParticleProperties particles{};                  // φ in [0, 0.5], d in (0, H), ρ_p, E, ν, e, μ_c
    double rim_shear_rate = 0.0;                     // γ̇_R [1/s] at the start (finite; < 0 turns backwards)
    double time_step_fraction = 0.3;                 // δt / t_R, in (0, 1]
    std::optional<double> time_step = std::nullopt;  // δt [s] > 0; overrides time_step_fraction
    // Gravitational acceleration [m/s²]; std::nullopt: no gravity.
    std::optional<std::array<double, 3>> gravity = std::array<double, 3>{0.0, 0.0, -core::units::standard_gravity};
    std::uint64_t seed = 1;                 // placement, lattice angle, initial velocities
    std::filesystem::path run_directory{};  // required; no whitespace or quotes (LIGGGHTS input)
    // Particle centres [x0 y0 z0 x1 y1 z1 ...] [m] instead of the placement at φ; each must lie
    // inside the gap (centre at least d/2 from the plates and the rim), overlaps are not checked.
    std::optional<std::vector<double>> positions = std::nullopt;
    double initial_speed = 0.0;                 // [m/s] >= 0: random isotropic initial velocity of this magnitude
    int placement_sweeps = 50;                  // Monte Carlo sweeps of the placement (placement.hpp), >= 0
    std::int64_t torque_sample_interval = 100;  // N: steps per TorqueSample, >= 1
    int top_plate_rings = 0;               // rings of the disk mesh (disk_mesh.hpp), >= 0; 0: max(1, ⌈R/(10 d)⌉)
    double neighbor_skin_fraction = 0.25;  // LIGGGHTS neighbour skin / d, in (0, 1]
    // Fortran handle of the communicator (see Engine::Params); empty: MPI_COMM_WORLD.
    std::optional<int> communicator_fortran_handle = std::nullopt;
  };

  // Checks params (std::invalid_argument naming the field and its range), places the
  // particles, writes the mesh and data files and sets up LIGGGHTS. Throws EngineError if
  // LIGGGHTS rejects the scene.
  explicit RheometerScene(Params params);
  ~RheometerScene();
  RheometerScene(const RheometerScene&) = delete;
  RheometerScene& operator=(const RheometerScene&) = delete;
  RheometerScene(RheometerScene&&) = delete;
  RheometerScene& operator=(RheometerScene&&) = delete;

  // Sets γ̇_R [1/s] (finite): Ω = γ̇_R H / R from the next step on.
  void set_shear_rate(double rim_shear_rate);
  // Runs steps >= 0 DEM steps, appending a TorqueSample at every block end passed.
  void advance(std::int64_t steps);

  [[nodiscard]] double rim_shear_rate() const;    // γ̇_R [1/s]
  [[nodiscard]] double angular_velocity() const;  // Ω [rad/s]
  [[nodiscard]] double time_step() const;         // δt [s]
  [[nodiscard]] double rayleigh_time() const;     // t_R of the (smallest) particles [s]
  [[nodiscard]] std::int64_t total_particle_count() const;

  // Torque samples so far, oldest first (see "Torque").
  [[nodiscard]] std::span<const TorqueSample> torque_series() const;
  // Contact torque −M_z on the top plate at the last step [N·m] (0 before the first step).
  [[nodiscard]] double torque() const;

  // The placement, unless explicit positions were given.
  [[nodiscard]] const std::optional<Placement>& placement() const;
  [[nodiscard]] const Params& params() const;
  [[nodiscard]] std::filesystem::path top_plate_mesh_path() const;
  [[nodiscard]] std::filesystem::path particle_data_path() const;
  [[nodiscard]] int top_plate_triangles() const;

  // The LIGGGHTS instance, for particle state, external forces and extra commands.
  [[nodiscard]] Engine& engine();
  [[nodiscard]] const Engine& engine() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rheosim::dem
