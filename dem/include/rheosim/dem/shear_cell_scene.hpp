#pragma once
// dem::ShearCellScene: the local equivalent of the rheometer gap at one radius
// — a LIGGGHTS box periodic in x and y between two flat plates, the top one sliding in x.
//
// API in one paragraph (for users such as the lubrication validation):
//   Construct with Params{gap H, cell_length L_x, cell_width L_y, particles (φ, d, ρ_p, E, ν,
//   e, μ_c as in the case file), shear_rate γ̇, run_directory, ...}; the scene places
//   N = round(φ L_x L_y H / V_p) spheres without overlaps (jittered layered lattice, periodic
//   in x and y), writes the plate meshes and the data file, and sets LIGGGHTS up. The top plate
//   (z = H) moves at U = γ̇ H along +x, the bottom plate (z = 0) is at rest; the shear rate of
//   the undisturbed flow is exactly γ̇ everywhere (no radius dependence, unlike the disk).
//   advance(steps) runs DEM steps and appends one WallStressSample per block of
//   stress_sample_interval steps: the block mean of the plates' contact stresses (shear
//   τ_xz = drive force per area, positive when the particles resist the motion; normal σ_zz,
//   positive when the particles push the plates apart). engine() gives the LIGGGHTS instance
//   for particle state and external forces (coupling), exactly as for RheometerScene;
//   box_low()/box_high() give the periodic box (x, y periodic; z from −margin to H + margin),
//   plate_area() = L_x L_y, and plate_velocity() = U. Near-field models describe the same box
//   through coupling::make_near_field_scene(const ShearCellScene&) (coupling/shear_cell_point.hpp).
//   A new shear rate needs a new scene (the plate velocity is fixed at construction; the cell
//   is cheap to rebuild).
//
// Scene (SI units)
//   - Box: `boundary p p f`, x ∈ [0, L_x), y ∈ [0, L_y), z ∈ [−margin, H + margin], margin = d.
//   - Plates: flat rectangles of triangles covering exactly [0, L_x] × [0, L_y], written to
//     <run_directory>/top_plate.stl and bottom_plate.stl, imported with `fix
//     mesh/surface/stress ... stress on` (material type 2, the particles' E, ν, e and μ_c, the
//     same Hertz contact with tangential history as the disk scene: CD §3.1 eqs. 12–24). The
//     top plate is a conveyor (`surface_vel U 0 0`): it stays in place — a moving mesh would
//     leave the periodic box — while its surface carries the velocity U into every contact,
//     which is what a plate sliding over an infinite periodic layer does. Contacts are found for
//     owned particles only (LIGGGHTS' wall/gran), and an owned particle's centre projects
//     inside [0, L_x] × [0, L_y], so each particle–plate contact is counted once; the unit test
//     checks this at the periodic edge (a particle pressed against the plate there gives the
//     plate exactly the pressing force).
//   - Wall stress: the stress module of each mesh sums, every step, the contact forces of the
//     particles on it (f_ID[1..3]); a `fix ave/time 1 N N` averages the four components
//     (top F_x, F_z, bottom F_x, F_z) over each block of N steps. τ_top = −F_x,top / A (the
//     particles drag the plate back), τ_bottom = F_x,bottom / A (they drag the bottom plate
//     forward); in a steady state both equal the contact part of the shear stress.
//   - Particles: type 1, monodisperse (particles.diameter; a size distribution is not supported
//     here), centres in z ∈ [d/2, H − d/2]. Time step δt = time_step_fraction · t_R (default 0.3,
//     the disk scene's choice) unless time_step is given. Gravity optional (default: none — the
//     coupled cell applies buoyancy-reduced gravity itself).
//
// Example
//   dem::ShearCellScene cell({.gap = 5e-4, .cell_length = 2e-3, .cell_width = 2e-3,
//                             .particles = props, .shear_rate = 100.0, .run_directory = out / "cell"});
//   cell.advance(20000);
//   double tau = cell.mean_top_shear_stress(10);  // mean over the last 10 samples [Pa]
//
// Not copyable or movable (it owns its Engine). One MPI rank or several (collective
// construction, like RheometerScene; files written by rank 0).
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "rheosim/dem/engine.hpp"
#include "rheosim/dem/particles.hpp"

namespace rheosim::dem {

struct WallStressSample {
  std::int64_t step = 0;       // LIGGGHTS step at the end of the block
  double time = 0.0;           // simulated time at the end of the block [s]
  double top_shear = 0.0;      // −F_x / A on the top plate, block mean [Pa]
  double top_normal = 0.0;     // F_z / A on the top plate (particles push it up: > 0) [Pa]
  double bottom_shear = 0.0;   // +F_x / A on the bottom plate [Pa]
  double bottom_normal = 0.0;  // −F_z / A on the bottom plate (pushed down: > 0) [Pa]
};

class ShearCellScene {
 public:
  struct Params {
    double gap = 0.0;                 // H [m] > d
    double cell_length = 0.0;         // L_x [m] (shear direction), >= 2 d (periodic images must not touch themselves)
    double cell_width = 0.0;          // L_y [m] (vorticity direction), >= 2 d
    ParticleProperties particles{};   // φ in [0, 0.45], d, ρ_p, E, ν, e, μ_c; monodisperse
    double shear_rate = 0.0;          // γ̇ [1/s], finite: top plate at U = γ̇ H along +x
    double time_step_fraction = 0.3;  // δt / t_R, in (0, 1]
    std::optional<double> time_step = std::nullopt;               // δt [s] > 0, overrides the fraction
    std::optional<std::array<double, 3>> gravity = std::nullopt;  // [m/s²]; nullopt: none
    std::uint64_t seed = 1;                                       // placement jitter, subset, initial velocities
    std::filesystem::path run_directory{};                        // required; no whitespace or quotes
    // Start velocities: the undisturbed shear profile u_x = γ̇ z (true) or rest (false), plus
    // a random isotropic part of magnitude initial_speed [m/s] >= 0.
    bool start_in_shear_profile = true;
    double initial_speed = 0.0;
    std::int64_t stress_sample_interval = 100;  // N: steps per WallStressSample, >= 1
    double neighbor_skin_fraction = 0.25;       // LIGGGHTS neighbour skin / d, in (0, 1]
    // Particle centres [x0 y0 z0 ...] [m] instead of the placement (tests); inside the box and
    // at least d/2 from the plates; overlaps are not checked.
    std::optional<std::vector<double>> positions = std::nullopt;
    std::optional<int> communicator_fortran_handle = std::nullopt;  // see Engine::Params
  };

  // Checks params (std::invalid_argument naming the field and its range, also when φ is
  // beyond what the layered placement can hold), places, writes files, sets LIGGGHTS up.
  explicit ShearCellScene(Params params);
  ~ShearCellScene();
  ShearCellScene(const ShearCellScene&) = delete;
  ShearCellScene& operator=(const ShearCellScene&) = delete;
  ShearCellScene(ShearCellScene&&) = delete;
  ShearCellScene& operator=(ShearCellScene&&) = delete;

  // Runs steps >= 0 DEM steps, appending a WallStressSample at every block end passed.
  void advance(std::int64_t steps);

  [[nodiscard]] std::span<const WallStressSample> stress_series() const;
  // Mean top-plate contact shear stress over the last `samples` samples (all if fewer) [Pa];
  // 0 before the first sample.
  [[nodiscard]] double mean_top_shear_stress(std::size_t samples) const;

  [[nodiscard]] double shear_rate() const;      // γ̇ [1/s]
  [[nodiscard]] double plate_velocity() const;  // U = γ̇ H [m/s]
  [[nodiscard]] double plate_area() const;      // A = L_x L_y [m²]
  [[nodiscard]] double time_step() const;       // δt [s]
  [[nodiscard]] double rayleigh_time() const;   // t_R [s]
  [[nodiscard]] std::int64_t total_particle_count() const;
  // Achieved φ = N V_p / (L_x L_y H).
  [[nodiscard]] double volume_fraction() const;
  [[nodiscard]] std::array<double, 3> box_low() const;   // (0, 0, −margin)
  [[nodiscard]] std::array<double, 3> box_high() const;  // (L_x, L_y, H + margin)
  // The initial centres [x0 y0 z0 ...] [m] (placement or the given positions).
  [[nodiscard]] const std::vector<double>& initial_positions() const;
  [[nodiscard]] const Params& params() const;

  [[nodiscard]] Engine& engine();
  [[nodiscard]] const Engine& engine() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// Particles a shear cell of this size holds at φ: round(φ L_x L_y H / V_p).
[[nodiscard]] std::size_t shear_cell_particle_count(double gap, double cell_length, double cell_width, double diameter,
                                                    double volume_fraction);

}  // namespace rheosim::dem
