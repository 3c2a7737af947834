#pragma once
// lubrication: near-contact hydrodynamic resistance between two spheres and between a sphere
// and a plate. Leading singular terms of the exact two-sphere resistance
// functions (Jeffrey & Onishi, J. Fluid Mech. 139 (1984) 261; Kim & Karrila, Microhydrodynamics
// (1991) §9.3, §11.3), sphere–plane limits of Cox & Brenner (1967) and Goldman, Cox & Brenner
// (1967), which are the λ → ∞ limits of the same functions.
//
// Two spheres a_i, a_j = λ a_i, centres x_i, x_j, n = (x_j − x_i)/|x_j − x_i|, surface gap
// h = |x_j − x_i| − a_i − a_j, regularised h_eff = max(h, 0) + δ with δ = roughness · ā,
// ā = (a_i + a_j)/2, dimensionless gap ξ = h_eff/ā = 2h_eff/(a_i + a_j), ℓ = ln(1/ξ), and
// P = I − nn. With ΔU = U_i − U_j (the ambient flow does not enter: the singular terms depend
// on the relative motion of the two surfaces only):
//   squeeze      F_i,n = −6πμa_i (g1/ξ + g2 ℓ) (n·ΔU) n,    g1 = 2λ²/(1+λ)³,
//                                                          g2 = λ(1+7λ+λ²)/(5(1+λ)³)
//   shear        F_i,t = −6πμa_i g4 ℓ P ΔU,                 g4 = 4λ(2+λ+2λ²)/(15(1+λ)³)
//   pump/roll    F_i  += −4πμa_i² ℓ [b_s Ω_i×n + b_o Ω_j×n], b_s = λ(4+λ)/(5(1+λ)²),
//                                                          b_o = λ²(1+4λ)/(5(1+λ)²)
//   torques      T_i = −4πμa_i² b_s ℓ n×ΔU − 8πμa_i³ ℓ [c_s PΩ_i + c_o PΩ_j],
//                                                          c_s = 2λ/(5(1+λ)), c_o = λ²/(10(1+λ))
//   and F_j = −F_i, T_j by exchanging i and j (n → −n).
// b_o and c_o follow from b_s(1/λ), c_s by reciprocity (R symmetric) and from rigid-body
// invariance (a rotating rigid pair feels no singular force: b_s + b_o = (3/2)(1+λ) g4 and
// c_s + c_o = (1+λ) b_s/2), which these coefficients satisfy identically. Equal spheres:
// g1 = 1/4, g2 = 9/40, g4 = 1/6, b_s = b_o = 1/4, c_s = 1/5, c_o = 1/20; the tangential
// force is then −πμaℓ times the relative surface velocity ΔU + a(Ω_i + Ω_j)×n.
// Plate (λ → ∞, ξ = h_eff/a, a plate moving with U_w and not rotating): g1/ξ → a/h,
// g2 → 1/5, g4 → 8/15, b_s → 1/5, c_s → 2/5 (Cox & Brenner; Goldman, Cox & Brenner).
// Twisting about n (X^C) has no singular term and is left out; so are the O(1) parts, which
// the single-particle terms and the cutoff stand in for.
//
// Matrix viscosity: μ(γ̇_gap) with γ̇_gap = |v_s|/h_eff, v_s the relative velocity of the two
// surfaces at the gap (the Reynolds-lubrication shear rate), but not below the ambient shear
// rate at the pair; a generalized-Newtonian law is thereby evaluated where it acts.
#include <array>
#include <cstddef>
#include <limits>
#include <span>

#include "rheosim/coupling/near_field.hpp"

namespace rheosim::coupling::lubrication {

inline constexpr std::size_t no_partner = std::numeric_limits<std::size_t>::max();

// One lubricated gap, its dimensional coefficients frozen for this step (the resistance is
// linear in the velocities): particle i and either particle j or a plate (j == no_partner).
struct Gap {
  std::size_t i = 0, j = no_partner, plate = 0;
  Vector3 n{};                                // unit normal from i towards j (or the plate)
  Vector3 separation{};                       // x_j − x_i (minimum image), or the plate point under i minus x_i
  Vector3 plate_velocity{};                   // U_w (plates only)
  double gap_ratio = 0.0;                     // h/ā before regularisation
  double k_squeeze = 0.0;                     // 6πμa_i (g1/ξ + g2 ℓ)          [N·s/m]
  double k_shear = 0.0;                       // 6πμa_i g4 ℓ                    [N·s/m]
  double b_i = 0.0, b_j = 0.0;                // 4πμa_i² b_s ℓ, 4πμa_i² b_o ℓ [N·s]
  double c_ii = 0.0, c_ij = 0.0, c_jj = 0.0;  // 8πμa_i³ c_s ℓ, 8πμa_i³ c_o ℓ, 8πμa_j³ c_s(1/λ) ℓ [N·m·s]
};

// Fills the coefficients of a sphere–sphere gap (radii a_i, a_j; gap h; viscosity μ; δ/ā).
void set_pair_coefficients(Gap& gap, double radius_i, double radius_j, double gap_width, double viscosity,
                           double roughness);
// Fills the coefficients of a sphere–plate gap.
void set_plate_coefficients(Gap& gap, double radius, double gap_width, double viscosity, double roughness);

// Forces and torques of one gap for generalized velocities V (6 per particle: U then Ω,
// interleaved as [Ux Uy Uz Ωx Ωy Ωz] per particle); adds −R_gap V (and, for plates, the plate
// velocity term) to out (same layout).
void add_gap_forces(const Gap& gap, std::span<const double> velocities, std::span<double> out,
                    bool include_plate_drive);
// The force on particle i from this gap for generalized velocities V (with the plate drive).
[[nodiscard]] Vector3 gap_force_on_i(const Gap& gap, std::span<const double> velocities);
// The particles' own 6×6 blocks of R_gap (row-major, 36 per particle, order U then Ω) added
// to blocks, for the block-Jacobi preconditioner and the stability estimate.
void add_gap_self_blocks(const Gap& gap, std::span<double> blocks);
// Relative surface velocity magnitude at the gap.
[[nodiscard]] double surface_slip_speed(const Gap& gap, double radius_i, double radius_j,
                                        std::span<const double> velocities);

}  // namespace rheosim::coupling::lubrication
