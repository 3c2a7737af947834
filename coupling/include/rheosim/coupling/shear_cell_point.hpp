#pragma once
// One suspension point in the periodic shear cell: a dem::ShearCellScene
// coupled to the horizontally averaged fluid column of the same gap, run until the wall shear
// stress is steady. rheometer/ turns τ(γ̇) at a few rates into a plate torque (shear_cell.hpp
// there).
//
// Fluid: the mean-flow equation of a periodic cell. In a box periodic in x and y the
// horizontally averaged volume-averaged momentum equation (CD eq. 27, set II / form A) has no
// horizontal pressure gradient, no mean convection (mean u_z = 0, ∂/∂x = ∂/∂y = 0 of the mean),
// and reads, for u(z, t) = (u_x, u_y):
//     ρ ∂(ε u)/∂t = ε ∂/∂z (μ(γ̇) ∂u/∂z) − f_drag,    γ̇ = |∂u/∂z|,
// with u = 0 at z = 0 and u = (U, 0) at z = H (U = γ̇ H). An unresolved CFD-DEM grid has cells
// several particle diameters wide, so it resolves no particle-scale flow; in the cell its
// horizontal cells would only carry the noise of ε between them, and averaging them is exactly
// this column. It is therefore the faithful fluid for the disk model's physics (not an extra
// approximation), on N_z layers — the same axial cells as the disk's grid, so both have the same
// resolution in the one direction that matters. Buoyancy: the hydrostatic pressure acts on the
// particles as −V_p ∇p_h (CD eq. 34); here it is applied as the reduced gravity
// (1 − ρ/ρ_p) g on the particles, which is the same force. The dynamic vertical pressure
// (which balances the mean vertical drag reaction) is not applied (it is zero on average).
//
// Coupling (as coupling::Coupler, with the layer as the cell):
//   - void fraction: the particle volume split of the chosen scheme (centre | divided, reused
//     from void_fraction.hpp on a one-cell-wide cylindrical grid, so the sub-points and the
//     plate mirroring are the disk's), ε_k = 1 − V_s,k / (A Δz), floored at void_fraction_floor;
//   - forces on each particle, the disk's force models (forces.hpp) by name: the drag law of
//     particles.drag (di_felice, CD eqs. 30–33, ε and μ in Re_p) and the viscous force V_p ∂z τ of
//     CD eq. 35 (with the layer's discrete ∂z τ; no pressure-gradient force, the buoyancy being in
//     the reduced gravity): u_f is the column
//     velocity interpolated linearly in z between layer centres and the plate values; ε, μ and
//     ∂z τ are the layer values weighted by the particle's volume shares;
//   - fluid step: implicit in u (Thomas algorithm), drag reaction −Σ w β (ũ − u_p)/V with an
//     implicit K = Σ w β / V on the change of u over the step (CD eq. 29; unlike the disk's
//     exchange, which applies β(u_p − u_cell), the reaction here equals the particles' drag with
//     the velocity ũ they sampled, so momentum is exchanged exactly at steady state), μ from
//     the previous step's γ̇ (lagged, as the transient disk solver's explicit μ update);
//   - wall stress on the top plate: fluid μ ∂u_x/∂z at z = H plus the plate's contact stress
//     (ShearCellScene, mean over the coupling step); the bottom plate the same at z = 0.
// Momentum: ε∂zτ on the fluid plus (1−ε)∂zτ on the particles (CD eq. 35) is ∂zτ, which
// telescopes, so in a steady state the top and bottom plates carry the same total stress; the
// validation checks this (tests/coupling/validate_shear_cell_point.cpp).
//
// Near-field hydrodynamics (`near_field`): the model runs on every DEM step through
// NearFieldStepHook (implicit update) in the column's flow (u(z) and ∂u/∂z of the layers), with
// make_near_field_scene()'s plates and periodic box. The wall stress is then fluid + contact +
// plate lubrication + the stresslets' Σ S_xz / V + the rotation couples' ½ Σ T_y / V (near_field.hpp):
// a force dipole and a couple that the column does not carry, added as the stress they transmit
// (for a Newtonian column this is exact, since (1/H)∫μ∂u/∂z dz = μU/H whatever the profile).
//
// Stress cross-check: every step also gives the bulk (Batchelor) stress of the
// cell contents, (1/H)∫μ∂u/∂z dz + (1/V)[pair contact virial (LIGGGHTS) + plate contacts +
// near-field virial (pairs and plates: force x times lever z, not symmetrised) + Σ −(z_p − z_layer)
// F_p of the fluid forces] + the same stresslet and couple parts. Summing each body's x-momentum
// balance times its height shows that at a steady state this equals the top-plate stress exactly
// (LIGGGHTS' contact virial is the symmetric one, so tangential contact forces leave a small
// difference); the validation compares the two.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rheosim/core/case.hpp"
#include "rheosim/coupling/coupler.hpp"
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/coupling/suspension_point.hpp"
#include "rheosim/dem/shear_cell_scene.hpp"

namespace rheosim::coupling {

struct ShearCellPointSettings {
  double gap = 0.0;          // H [m]
  double cell_length = 0.0;  // L_x [m], >= 2 d
  double cell_width = 0.0;   // L_y [m], >= 2 d
  core::FluidProperties fluid{};
  dem::ParticleProperties particles{};  // φ = 0 runs the column alone (no LIGGGHTS)
  DragLaw drag = DragLaw::di_felice;    // particles.drag
  double shear_rate = 0.0;              // γ̇ [1/s] > 0
  int axial_cells = 2;                  // N_z fluid layers, >= 1
  bool gravity = true;                  // standard gravity along −z (reduced by buoyancy)
  std::optional<double> dem_time_step = std::nullopt;
  double time_step_fraction = 0.3;        // δt / t_R
  int coupling_interval = 100;            // DEM steps per fluid step
  std::string void_fraction = "divided";  // centre | divided
  double void_fraction_floor = 0.3;
  bool viscous_force = true;  // CD eq. 35
  SteadyStateSettings steady{};
  std::uint64_t seed = 1;
  std::filesystem::path run_directory{};
  // Near-field hydrodynamics (nullptr: the seed's drag-only model). See the header comment.
  std::shared_ptr<const NearFieldModel> near_field = nullptr;
};

// The bulk (virial) stress split into its parts [Pa] (xz; docs/hydrodynamics.md, "the coupled
// cell against the imposed one"). bulk = fluid + stresslet + couple + pair_lubrication +
// pair_lubrication_antisymmetric + plate_lubrication + pair_contact + plate_contact + drag;
// imposed_cell_definition() is what the imposed-flow cell calls its bulk stress (symmetric pair
// virials, no plates, no couple, no drag offsets).
struct ShearCellBulkParts {
  double fluid = 0.0;  // (1/H) ∫ μ ∂u_x/∂z dz
  double stresslet = 0.0, couple = 0.0;
  double pair_lubrication = 0.0;                // symmetric pair virial of lubrication + repulsion
  double pair_lubrication_antisymmetric = 0.0;  // force x lever z minus the symmetric part
  double plate_lubrication = 0.0;               // plate gaps, force x lever z
  double pair_contact = 0.0, plate_contact = 0.0;
  double drag = 0.0;  // Σ −(z_p − z_layer) F_x / V
  [[nodiscard]] double imposed_cell_definition() const { return fluid + stresslet + pair_lubrication + pair_contact; }
};

struct ShearCellStepRecord {
  double time = 0.0;          // after the fluid step [s]
  double fluid_top = 0.0;     // fluid shear stress on the top plate [Pa]
  double contact_top = 0.0;   // contact shear stress on the top plate (mean over the step) [Pa]
  double fluid_bottom = 0.0;  // on the bottom plate [Pa]
  double contact_bottom = 0.0;
  double lubrication_top = 0.0;  // plate lubrication on the top plate [Pa] (near field)
  double lubrication_bottom = 0.0;
  double stresslet = 0.0;    // Σ S_xz / V [Pa] (near field)
  double couple = 0.0;       // ½ Σ T_y / V of the rotation torques [Pa] (near field)
  double bulk = 0.0;         // bulk stress from the virial [Pa] (see the header)
  ShearCellBulkParts parts;  // bulk's parts
  [[nodiscard]] double total_top() const { return fluid_top + contact_top + lubrication_top + stresslet + couple; }
};

struct ShearCellPoint {
  double shear_rate = 0.0;  // γ̇ [1/s]
  // Top-plate total shear stress [Pa]: mean over the detector's last window when steady, else
  // over the second half of the run (5 batch means give the error); the parts use the same span.
  double stress = 0.0;
  double stress_error = 0.0;        // its standard error [Pa]
  double stress_fluid = 0.0;        // fluid part [Pa]
  double stress_contact = 0.0;      // contact part [Pa]
  double stress_lubrication = 0.0;  // plate lubrication part [Pa]
  double stress_stresslet = 0.0;    // stresslet part [Pa]
  double stress_couple = 0.0;       // rotation-couple part [Pa]
  double bottom_stress = 0.0;       // bottom plate total, same window [Pa]
  double bulk_stress = 0.0;         // bulk stress from the particle virial, same window [Pa]
  ShearCellBulkParts bulk_parts;    // its parts, same window
  int max_near_field_iterations = 0;
  bool converged = false;
  double strain = 0.0;
  std::int64_t particles = 0;
  double volume_fraction = 0.0;  // achieved
  double cell_length = 0.0, cell_width = 0.0;
  double dem_time_step = 0.0, fluid_time_step = 0.0;
  std::vector<ShearCellStepRecord> series;
  CostSplit cost;
  double min_void_fraction = 1.0;  // smallest layer ε seen (after the floor)
  double wall_time = 0.0;          // [s]
};

// Runs one point. Throws std::invalid_argument for bad settings, dem::EngineError from LIGGGHTS.
[[nodiscard]] ShearCellPoint run_shear_cell_point(const ShearCellPointSettings& settings);

// The box of a shear cell as the near-field models see it (plates at z = 0 at rest and z = H
// moving at (U, 0, 0); periodic in x and y).
[[nodiscard]] NearFieldScene make_near_field_scene(const dem::ShearCellScene& scene);

// Steady 1D column without particles at ε = 1: the exact Couette stress μ(γ̇) γ̇ (a check).
[[nodiscard]] double couette_stress(const core::FluidProperties& fluid, double shear_rate);

}  // namespace rheosim::coupling
