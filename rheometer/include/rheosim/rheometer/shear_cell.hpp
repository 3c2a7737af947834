#pragma once
// Suspension rheometry in minutes: the plate torque from a periodic shear cell
// (coupling/shear_cell_point.hpp) instead of CFD-DEM of the whole disk, with the program choosing
// the model, the cell size and the contact stiffness itself and reporting what each choice
// costs in accuracy. docs/shear-cell.md explains the method and its measured errors.
//
//   1. Local flow curve. The cell measures the wall shear stress τ(γ̇) at a uniform shear rate.
//      In a parallel-plate gap the local rate is γ̇(r) = γ̇_R r/R, so the plate torque is
//        T(γ̇_R) = 2π ∫₀ᴿ τ(γ̇_R r/R) r² dr = 2π R³/γ̇_R³ ∫₀^γ̇_R τ(s) s² ds      (CD eq. 5 form)
//      over a fitted local flow curve τ(s): τ = η s (Stokes shortcut, least squares through the
//      origin) or a piecewise power law through the measured points (exact at each point,
//      power-law extrapolation beyond the first and last).
//   2. Similarity. dimensionless_groups() for every point. In the Stokes regime (Re_p, St and
//      the gap Reynolds number at most 1) with a Newtonian matrix the stress is linear in γ̇:
//      the two highest rates are simulated (the cheapest: DEM steps per strain ∝ 1/γ̇) and
//      checked for linearity; the other rates follow from τ = η γ̇. Otherwise every rate is
//      simulated.
//   3. Contact stiffness. Softer spheres allow a larger DEM step (δt ∝ t_R ∝ E^(−1/2)). At the
//      highest rate the cell runs at E·10⁻ᵏ for k = 4, 3, ... and the softest E whose stress
//      differs from the next stiffer one by at most the tolerance (or by at most two combined
//      standard errors, the resolution of the check) is used; the time-step gain is reported.
//   4. Cell size. At the chosen stiffness the cell in-plane size starts at
//      L₀ = max(8 d, 3 H) and doubles until the stress changes by at most the tolerance.
//   5. Estimated error of a point: the root sum of squares of the cell's statistical error,
//      the measured size and stiffness changes, the change with twice the fluid layers (one
//      more run at the highest rate), the linearity deviation (shortcut only), and the
//      liquid's own inertia effect at that rate (the cell is creeping; the disk is not), from the
//      swirl solver.
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "rheosim/coupling/suspension_point.hpp"
#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/sweep.hpp"

namespace rheosim::rheometer {

// Dimensionless groups of one point at rim rate γ̇_R; μ = μ(γ̇_R), a = d/2.
struct DimensionlessGroups {
  double gap_reynolds = 0;       // ρ Ω H² / μ, Ω = γ̇_R H / R: disk inertia, not in the cell
  double particle_reynolds = 0;  // ρ γ̇_R a² / μ
  double stokes = 0;             // (2/9) ρ_p γ̇_R a² / μ: particle relaxation time × γ̇
  double bingham = 0;            // τ_y / (μ γ̇_R); 0 without a yield stress
  double stiffness = 0;          // μ γ̇_R / E*, E* = E / (2(1 − ν²)): viscous stress over contact modulus
  double gap_over_diameter = 0;  // H / d
  [[nodiscard]] bool stokes_regime() const;  // Re_p, St, Re_gap <= 1
};
[[nodiscard]] DimensionlessGroups dimensionless_groups(const RheometerCase& rheometer,
                                                       const core::FluidProperties& fluid,
                                                       const coupling::SuspendedParticles& particles,
                                                       double rim_shear_rate);

// The local flow curve measured by the cell (rates increasing).
struct LocalFlowCurve {
  std::vector<double> shear_rate;                               // [1/s]
  std::vector<double> stress;                                   // [Pa]
  bool linear = false;                                          // τ = η γ̇ (Stokes shortcut)
  double viscosity = std::numeric_limits<double>::quiet_NaN();  // η [Pa·s] when linear
  [[nodiscard]] double stress_at(double shear_rate) const;
};
// T = 2π ∫₀ᴿ τ(γ̇_R r/R) r² dr [N·m] (Gauss–Legendre on each interval between measured rates).
[[nodiscard]] double plate_torque(const LocalFlowCurve& curve, double radius, double rim_shear_rate);

// Which scene computes a suspension point, and why.
struct ModelChoice {
  RheometerCase::SuspensionModel model = RheometerCase::SuspensionModel::shear_cell;
  std::string reason;
  double cell_study_seconds = 0;  // estimated one-core cost of the cell's study of this φ [s]
};
// Estimated one-core wall time [s] of the cell's study of one φ (stiffness pair at E/10³, every
// rate at E/10⁴, cell L₀, to the detector's max strain; ~3e6 particle-steps/s measured with the
// coupling; ×20 with particles.hydrodynamics) — an upper-side estimate used against --point-budget.
[[nodiscard]] double estimate_shear_cell_study_cost(const RheometerCase& rheometer, double volume_fraction);
// The case's `model:`; for auto: the full disk when the cell cannot represent the case (a size
// distribution; R < 10 H, where the rim region matters; gap Reynolds number > 1 at the highest
// rate, where the disk's secondary flow matters) and the disk point fits the budget, or when
// the disk is cheaper; else the cell. The reason carries both cost estimates.
[[nodiscard]] ModelChoice choose_suspension_model(const RheometerCase& rheometer, double volume_fraction,
                                                  double budget_seconds);

struct ShearCellOptions {
  double tolerance = 0.03;        // stress change allowed by each check (relative)
  int softening_decades = 4;      // try E·10⁻ᵏ for k = this … 1
  int max_cell_doublings = 2;     // L₀, 2 L₀, 4 L₀ at most
  int axial_cells = 2;            // fluid layers (the disk's default N_z)
  double fluid_time_step = 1e-5;  // target Δt_CFD [s] (CD §4); the coupling interval follows
  coupling::SteadyStateSettings steady{
      .strain_window = 2.0, .relative_tolerance = 0.02, .min_strain = 4.0, .max_strain = 20.0};
};

// φ > 0 by the shear cell. The first point of each φ measures its local flow curve (stiffness,
// size and linearity checks, cell points; files in work_dir/cell_phi<φ>/...) and is charged
// with that wall time; every point of that φ then gets T from the curve, its estimated error,
// and the cell's choices in PointResult::model_reason.
[[nodiscard]] PointRunner make_shear_cell_suspension_runner(const RheometerCase& rheometer,
                                                            std::filesystem::path work_dir,
                                                            ShearCellOptions options = {});

}  // namespace rheosim::rheometer
