#pragma once
// Suspension points from the suspension box (coupling/suspension_box.hpp): the predictive
// default. The Lees–Edwards box gives the bulk stress of the suspension at a uniform shear rate,
// the walled box the stress on plates at the case's gap H (for H/d < walled_box_gap_limit); the
// parallel-plate gap is locally that simple shear at γ̇(r) = γ̇_R r/R, so
//   torque        T = 2π ∫₀ᴿ τ(γ̇_R r/R) r² dr                          (shear_cell.hpp plate_torque)
//   normal force  F = (πR²/γ̇_R²) ∫₀^γ̇_R (N1 − N2)(s) s ds,
// the inverse of the parallel-plate relation N1 − N2 = (F/πR²)(2 + d ln F/d ln γ̇_R).
// The case's scales fix the box (box_settings): St = (2/9)ρ_p a²γ̇/μ decides the integrator
// (overdamped at St <= overdamped_stokes_limit), the friction is the case's, the near field is
// the case's `particles.hydrodynamics` or, absent, lubrication with roughness 1e-3 and cutoff
// 0.25ā, no repulsion. Where the dimensionless problem is the same at every rate (Newtonian
// liquid, overdamped, no fixed-force repulsion) one box serves every rate of a φ.
// docs/suspension-box.md has the method, its validation and its cost.
#include <filesystem>
#include <string>
#include <vector>

#include "rheosim/coupling/suspension_box.hpp"
#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/sweep.hpp"

namespace rheosim::rheometer {

// St at or below this: the overdamped integrator (inertia changes η_r by less than the box's
// statistical error there; measured in docs/suspension-box.md).
inline constexpr double overdamped_stokes_limit = 0.01;
// Re_p = ρ γ̇ a²/μ above this: the box (Stokes flow around each sphere) warns that fluid
// inertia at the particle scale is not modelled.
inline constexpr double particle_reynolds_limit = 0.1;
// H/d below this: `auto` simulates the plates (walled box); at and above it the bulk stress of the
// Lees–Edwards box (the walled box's excess over the bulk at φ = 0.3 falls from +190 % at H/d = 2.5
// to about +15 % at 10, docs/suspension-box.md).
inline constexpr double walled_box_gap_limit = 10.0;

// The box for one φ and rate of the case, in its units (a = d/2, 1/γ̇, μ(γ̇)).
[[nodiscard]] coupling::SuspensionBoxSettings box_settings(const RheometerCase& rheometer, double volume_fraction,
                                                           double shear_rate);
// Whether the case's box has the plates (model: walled_box, or auto with H/d < walled_box_gap_limit).
[[nodiscard]] bool box_has_walls(const RheometerCase& rheometer);
// Whether box_settings gives the same dimensionless problem at every rate of the case.
[[nodiscard]] bool box_is_rate_independent(const RheometerCase& rheometer);
// One line that states the box's settings for this case (for `rheosim validate`, the log and
// summary.json): integrator and why, near field, friction, stiffness, particles.
[[nodiscard]] std::string describe_box(const RheometerCase& rheometer, double volume_fraction);

// Plate normal force [N] of a local normal-stress curve: n12[k] = (N1 − N2) at rates[k] (increasing),
// linear in each interval and ∝ s below the first rate, constant ratio to s beyond the last.
[[nodiscard]] double plate_normal_force(const std::vector<double>& rates, const std::vector<double>& n12, double radius,
                                        double rim_shear_rate);

// φ > 0 by the box. The first point of each φ runs the boxes it needs (one, or one per rate)
// and is charged with their wall time; every point of that φ gets T, F, N1, N2 from them.
// volume_fractions (the sweep's, increasing): the first point of a φ also queues the boxes of
// every later φ, which run on the machine's other cores meanwhile (each box is deterministic,
// so the results do not depend on the order; a resumed sweep queues only from its first missing
// point on).
[[nodiscard]] PointRunner make_box_suspension_runner(const RheometerCase& rheometer,
                                                     std::vector<double> volume_fractions = {});

}  // namespace rheosim::rheometer
