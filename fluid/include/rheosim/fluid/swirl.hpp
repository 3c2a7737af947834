#pragma once
// Steady axisymmetric swirling flow in the gap of a parallel-plate rheometer: the
// volume-averaged incompressible Navier–Stokes equations (CD eqs. 26–28, set II) with a
// generalized-Newtonian viscosity μ(γ̇), γ̇ = √(2E:E), on the staggered (r, z) grid of a
// CylindricalGrid with N_θ = 1. Unknowns: angular velocity ω = v_θ/r and pressure p at cell
// centres, u_r on radial faces, u_z on axial faces.
//
// Why ω rather than v_θ: torsional flow between plates has ω = Ωz/H exactly in the creeping
// limit for every GN law, and γ̇ = r|∇ω| there. The angular-momentum fluxes are assembled as
// ∫ μ(γ̇(r)) r³ dr ∂_zω over each axial face by 3-point Gauss quadrature in r, so the discrete
// equations hold the creeping solution exactly and the plate torque is the conservative sum of
// the wall fluxes, T = 2π Σ ∫ r² τ_θz dr (CD eq. 7 with dA = r dθ dr).
//
// Boundaries: bottom plate (z = 0) at rest, top plate (z = H) rotating at Ω, both no-slip.
// Rim (r = R): a flat, shear-free meniscus — u_r = 0, τ_rθ = 0, τ_rz = 0. The creeping
// solution has τ_rθ = 0 everywhere, so this rim condition is the one under which the
// closed-form plate torques hold. Axis: u_r = 0 and no angular-momentum flux (r³ → 0).
//
// Two settings of the physics: `inertia = false` solves the creeping (Stokes) limit, where the
// secondary flow vanishes and only ω is solved; `inertia = true` solves the full steady
// equations with centrifugal forcing and the secondary flow it drives (convection by central
// differences). Creeping: Picard/Newton on the viscous flux with Anderson mixing. Inertia:
// Newton–Krylov — each step a GMRES solve with the exact Jacobian (finite differences of the
// residual), preconditioned by the sparse LU of the Newton/Oseen linearisation, with a
// backtracking line search and optional pseudo-time continuation; from no start state the
// solve first runs on half the cells in r and z and starts from that solution (grid
// sequencing), which also gives a Richardson-extrapolated torque.
//
// Plate gradients with inertia: ∂ω/∂z and ∂u_r/∂z at the plates are second-order one-sided
// (quadratic through the wall value and two cells), in the fluxes as in μ(γ̇). With the
// half-cell difference in the flux, a shear-thinning law made the torque first order in N_z.
// The quadratic takes the actual cell centres, so it stays second order when the grid's axial
// cells are clustered towards the plates (grid.axial_stretching > 0), which is what makes the
// torque of a thin shear-thinning plate layer converge at second order from N_z = 8
// (docs/performance.md, "Grid convergence with inertia").
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rheosim/core/rheology.hpp"
#include "rheosim/fluid/grid.hpp"

namespace rheosim::fluid {

struct SwirlParams {
  CylindricalGrid::Params grid;                    // azimuthal_cells must be 1
  double density = 0;                              // ρ [kg/m³], > 0
  std::shared_ptr<const core::Rheology> rheology;  // μ(γ̇), not null
  bool inertia = true;                             // false: creeping (Stokes) limit
  double tolerance = 1e-10;                        // relative change of ω, u and torque per iteration
  int max_iterations = 500;                        // Picard iterations
  double viscosity_relaxation = 1.0;               // (0, 1]: μ ← μ_old + α(μ_new − μ_old)
  double velocity_relaxation = 1.0;                // (0, 1]: the iterate moves by β of each Picard step
  int anderson_depth = 5;                          // Anderson acceleration history; 0 = plain Picard
  double pseudo_time_step = 0;                     // first pseudo-time step [rad of plate rotation]; 0 = off
  bool newton_krylov = true;                       // inertia: Newton steps by GMRES on the full Jacobian
  bool grid_sequencing = true;                     // inertia: start from the solution on half the cells
  bool one_sided_plate_gradients = true;           // inertia: second-order plate fluxes (false: half-cell,
                                                   // as the transient solver's)
};

// Fields of one converged (or last) iterate. Index cell (i, k) as i * N_z + k.
struct SwirlState {
  std::vector<double> angular_velocity;  // ω [rad/s], cell centres
  std::vector<double> pressure;          // p [Pa], cell centres (zero mean)
  std::vector<double> radial_velocity;   // u_r [m/s], radial faces i = 0..N_r (i * N_z + k)
  std::vector<double> axial_velocity;    // u_z [m/s], axial faces k = 0..N_z (i * (N_z + 1) + k)
  std::vector<double> viscosity;         // μ [Pa·s], cell centres
  std::vector<double> shear_rate;        // γ̇ [1/s], cell centres
};

struct SwirlResult {
  SwirlState state;
  double torque = 0;         // on the top plate [N·m], resisting the rotation (> 0)
  double bottom_torque = 0;  // transmitted to the bottom plate [N·m]; equals torque when steady
  int iterations = 0;
  bool converged = false;
  std::string failure;                   // why it did not converge (empty when converged)
  std::vector<double> residual_history;  // relative change per iteration
  // Converged at the iteration's floor rather than at the tolerance: the largest relative change
  // of the last iterations, which stopped gaining (0 when the tolerance itself was met).
  double accepted_change = 0;
  double wall_time = 0;  // [s]
  // Grid sequencing only (else 0): the torque on the grid with half the cells in r and z, and
  // the Richardson extrapolation of the pair assuming second order, T + (T − T_2h)/3, with
  // its estimated relative error |T − T_2h|/(3 T_ext).
  double coarse_torque = 0;
  double extrapolated_torque = 0;
  double extrapolation_error = 0;
};

// External fields for the volume-averaged (CD eq. 27) form; both optional (empty = single phase).
struct SwirlCoupling {
  std::span<const double> void_fraction;   // ε [-] per cell, in (0, 1]
  std::span<const double> torque_density;  // particle → fluid azimuthal force × r per volume [N/m²]
};

class SwirlSolver {
 public:
  explicit SwirlSolver(SwirlParams params);  // validates; throws std::invalid_argument

  // Solves for the top plate rotating at Ω [rad/s]. `initial` (optional) warm-starts from a
  // previous state on the same grid (e.g. the last shear rate of a sweep); otherwise, with
  // inertia, single phase and even cell counts >= 8, the solution on half the cells is the
  // start (grid sequencing; coarse_torque and extrapolated_torque are then set), else the
  // creeping profile ω = Ωz/H. Picard steps are damped automatically when the change grows;
  // if the direct attempt still fails, Ω is reached by continuation from lower speeds. A
  // result that did not converge says why in `failure` and holds the last iterate.
  [[nodiscard]] SwirlResult solve(double angular_velocity, const SwirlState* initial = nullptr,
                                  const SwirlCoupling& coupling = {}) const;

  // Starts from rest (ω = 0 inside): a harder start for robustness tests.
  [[nodiscard]] SwirlState rest_state() const;

  [[nodiscard]] const CylindricalGrid& grid() const { return grid_; }
  [[nodiscard]] const SwirlParams& params() const { return params_; }

 private:
  SwirlResult solve_from(double angular_velocity, const SwirlState* initial, const SwirlCoupling& coupling) const;
  // `initial` checked against the grid, or the creeping profile ω = Ωz/H; no secondary flow
  // without inertia.
  SwirlState start_state(double angular_velocity, const SwirlState* initial) const;
  SwirlResult attempt(double angular_velocity, const SwirlState* initial, const SwirlCoupling& coupling,
                      double relaxation, int max_iterations) const;

  SwirlParams params_;
  CylindricalGrid grid_;
};

}  // namespace rheosim::fluid
