#pragma once
// The Lees–Edwards suspension box: the bulk stress of a sheared non-Brownian suspension from a
// triply periodic box of a few hundred spheres, the standard of suspension simulation
// (Stokesian dynamics, Sierou & Brady 2002; LF_DEM, Mari, Seto, Morris & Denn, J. Rheol. 58
// (2014) 1693). docs/suspension-box.md has the method, the validation and the cost.
//
// Physics, per sphere i (radius a_i) in the simple shear u∞ = γ̇ z e_x (x flow, y vorticity,
// z gradient), Ω∞ = (0, γ̇/2, 0):
//   - isolated-sphere drag −6πμa_i(U_i − u∞(x_i)) and rotation torque −8πμa_i³(Ω_i − Ω∞), and
//     the stresslet (20/3)πμ_S a_i³ E∞ (Einstein's 2.5φ): the far field of the
//     Fast-Lubrication-Dynamics set (Kumar & Higdon 2010);
//   - pair lubrication, leading singular terms of Jeffrey & Onishi (coupling/src/lubrication.hpp),
//     gap regularised by the roughness δ, acting for h < h_c;
//   - optional short-range repulsion F_R0 e^{−h/λ} (Mari et al. 2014);
//   - contacts: linear normal spring k_n and tangential spring k_t with Coulomb friction μ_c
//     (Cundall & Strack 1979), soft enough for a practical step, stiff enough that the overlap
//     stays at a per cent of a radius (measured and reported).
// Momentum, in units a (a reference radius), 1/γ̇, 6πμa²γ̇ for forces:
//   St M (dV'/dt + u'_z e_x) = −R V' − R_lub V∞ + F_contact + F_repulsion,
// with V' = V − V∞ the fluctuating (peculiar) velocities, R the resistance (drag + lubrication),
// St = m γ̇/(6πμa) the Stokes number of the reference sphere. St = 0 is the overdamped
// (inertialess) limit. The resistance is implicit (backward Euler), so neither the stiff
// squeeze term nor the particle relaxation time limits the strain step; the contact springs are
// explicit and set it. The cost of a point is therefore fixed in strain, not in time: flat in γ̇.
// Lees–Edwards images: crossing z = L_z shifts x by the accumulated strain times L_z.
// With wall_gap > 0 the box is walled instead: two plates at z = 0 (at rest) and z = H (moving at
// γ̇H), periodic in x and y, sphere–plate lubrication (the λ → ∞ limit in lubrication.hpp) and
// contacts with the plates' friction. The stress on the top plate is the same virial with the
// plate's contact point as the partner: in the mean-field flow u∞ the liquid passes the force of
// a sphere at height z to the top plate in the share z/H (Couette flow with a body force), so
// σ_xz(H) = μγ̇ + (1/V)[Σ S + Σ_gaps (x_partner − x_i) F_i] (docs/suspension-box.md). With
// mean_flow_coupling the liquid's own profile replaces u∞: μ(1 + 2.5φ(z)) u_f' = τ₀ + ℓ(z)/2 − F(z),
// F(z) = ∫₀^z f, with f and ℓ the drag forces and couples the spheres exert on the liquid and φ(z)
// the solid fraction, each sphere spread over its cross-sections; u_f(0) = 0, u_f(H) = γ̇H fix τ₀,
// and the plate stress is τ₀ less the forces the plates exert through their gaps.
//
// Stress (Batchelor 1970), in units of μ(γ̇)γ̇:
//   σ = 2E∞ + (1/V)[Σ S_p + Σ_pairs (x_j − x_i) ⊗ F_i (lubrication, contact, repulsion)],
// reported as η_r = σ_xz/(μγ̇), N1 = σ_xx − σ_zz, N2 = σ_zz − σ_yy and the particle pressure.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rheosim::coupling {

struct SuspensionBoxSettings {
  double volume_fraction = 0.3;  // φ, in (0, 0.6]
  int particles = 500;           // spheres in the box, >= 20
  // Radii in units of the reference radius a and their shares of the solid volume (sum 1);
  // {1}, {1}: monodisperse.
  std::vector<double> radii{1.0};
  std::vector<double> volume_shares{1.0};
  double friction = 0.3;       // μ_c, Coulomb coefficient of the contacts, >= 0
  double stokes_number = 0.0;  // St = m γ̇/(6πμa) = (2/9)ρ_p a² γ̇/μ of the reference sphere; 0: overdamped
  double roughness = 1.0e-3;   // δ/ā, regularises the lubrication gap
  // h_c/ā: beyond about 0.25ā the leading singular terms overestimate the pair resistance
  // (their O(1) remainder is negative there); 0.5 raises η_r by 2 % at φ = 0.1 and 11–17 % at 0.3–0.4.
  double lubrication_cutoff = 0.25;
  double contact_stiffness = 0.0;                 // k_n/(6πμaγ̇); 0: default_contact_stiffness(φ)
  double tangential_stiffness_ratio = 2.0 / 7.0;  // k_t/k_n
  double repulsion_force = 0.0;                   // F_R0/(6πμa²γ̇); 0: no repulsion
  double repulsion_length = 0.05;                 // λ/ā
  double stresslet_viscosity_ratio = 1.0;         // μ_S/μ(γ̇) in the stresslet
  // μ(s γ̇)/μ(γ̇) at the local rate s γ̇ of a lubricated gap (s = γ̇_gap/γ̇), for a
  // generalized-Newtonian matrix; empty: Newtonian (ratio 1).
  std::function<double(double)> viscosity_ratio;
  double strain_step = 0.0;  // Δγ; 0: from the contact stiffness and St (default_strain_step)
  // Left out of the averages: the random placement relaxes over a few strain units (η_r at
  // φ = 0.3 falls by 1–2 % from the window after strain 3 to the one after 10).
  double warmup_strain = 5.0;
  double min_averaging_strain = 10.0;
  double max_strain = 40.0;          // total, warm-up included
  double relative_tolerance = 0.02;  // stop once the standard error of η_r is below this (relative)
  double block_strain = 1.0;         // averaging block length (strain) for the error bar
  double solver_tolerance = 1.0e-4;  // residual / |rhs| of the implicit solve (η_r moves by 3e-4 against 1e-6)
  int max_solver_iterations = 400;
  std::uint64_t seed = 1;
  // H/a, plate surface to plate surface, for a walled box; 0: the triply periodic Lees–Edwards box.
  double wall_gap = 0.0;
  // Walled box: the liquid's mean velocity u_f(z) carries the spheres' drag and couples (two-way,
  // solved from the plane-Couette momentum balance, so a particle-poor layer at a plate shears
  // faster: the apparent slip of a real gap) and the stress is read on the plates; false: the
  // liquid keeps the linear profile u∞ and the stress is the virial (one-way).
  bool mean_flow_coupling = true;
  double mean_flow_relaxation = 1.0;  // strain over which the drag that shapes u_f(z) is averaged
  // Called every block with the strain reached (progress); may be empty.
  std::function<void(double)> on_block;
};

// Throws std::invalid_argument naming the setting out of range and its valid range.
void check_suspension_box_settings(const SuspensionBoxSettings& settings);

// The normal contact stiffness [6πμaγ̇] at volume fraction φ: 2000 (see
// suspension_box_settings.cpp for the measured overlaps and the stress's sensitivity to it).
[[nodiscard]] double default_contact_stiffness(double volume_fraction);
// Δγ: 5e-3 (the springs are implicit, so accuracy sets it); with inertia at most half the
// particle relaxation time St, and a tenth of the contact oscillation period where the squeeze
// at contact does not overdamp it.
[[nodiscard]] double default_strain_step(const SuspensionBoxSettings& settings);

// Mean ± standard error over the averaging window (blocks).
struct BoxMean {
  double mean = 0.0, error = 0.0;
};

struct SuspensionBoxResult {
  int particles = 0;
  double box_length = 0.0;       // side in x and y [a] (the cube's side for Lees–Edwards)
  double box_height = 0.0;       // extent in z [a]: the cube's side, or the plates' gap H
  double volume_fraction = 0.0;  // as placed
  // Stresses in units of μ(γ̇)γ̇ (η_r = σ_xz/(μγ̇)).
  BoxMean relative_viscosity;
  BoxMean n1, n2;             // N1 = σ_xx − σ_zz, N2 = σ_zz − σ_yy
  BoxMean particle_pressure;  // Π = −tr σ_p/3
  // Parts of σ_xz: liquid (1), stresslets, lubrication, contacts, repulsion.
  double part_fluid = 1.0, part_stresslet = 0.0, part_lubrication = 0.0, part_contact = 0.0, part_repulsion = 0.0;
  // σ_xz over the first and second halves of the averaging window (steady-state check).
  double first_half = 0.0, second_half = 0.0;
  double strain = 0.0, averaged_strain = 0.0, strain_step = 0.0;
  double contact_stiffness = 0.0;
  long steps = 0;
  double mean_solver_iterations = 0.0;
  long solves_at_iteration_cap = 0;    // implicit solves that stopped at max_solver_iterations
  double worst_solver_residual = 0.0;  // largest relative residual accepted
  double mean_contacts_per_particle = 0.0;
  double sliding_fraction = 0.0;                 // share of contacts at the Coulomb limit
  double mean_overlap = 0.0, max_overlap = 0.0;  // over contacts, in units of ā
  // Walled box: how far the spheres whose centres lie within 2ā of a plate lag the affine flow
  // towards that plate's velocity, mean of (u∞(z_i) − U_i,x)·(±1) [āγ̇] (0: they follow u∞).
  double wall_slip = 0.0;
  // Walled box with mean_flow_coupling: the liquid's mean shear rate in the middle third of the
  // gap and next to the plates (the bins within ā of them), in units of γ̇ (1 for a linear profile).
  double core_shear_rate = 1.0, plate_shear_rate = 1.0;
  bool converged = false;             // standard error below the tolerance within max_strain
  double wall_time = 0.0;             // [s]
  std::vector<std::string> warnings;  // every rule the run bent, for the log and summary.json
};

// Places the spheres (random, overlaps relaxed away), shears the box and averages the stress.
// Throws std::invalid_argument for settings out of range and std::runtime_error when the run
// diverges (a non-finite velocity or an overlap beyond a radius), naming the strain reached.
[[nodiscard]] SuspensionBoxResult run_suspension_box(const SuspensionBoxSettings& settings);

}  // namespace rheosim::coupling
