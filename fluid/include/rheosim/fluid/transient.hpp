#pragma once
// Transient 3D flow in the gap of a parallel-plate rheometer: the volume-averaged incompressible
// Navier–Stokes equations, CD eqs. 26–27 (set II), in dynamic SI form
//   ∂ε/∂t + ∇·(εu) = 0,
//   ρ[∂(εu)/∂t + ∇·(εuu)] = −ε∇p + ε∇·τ + f − βu + ερg,        τ = 2μ(γ̇)[E − (1/3)(∇·u)I]  (CD eq. 28),
// with a generalized-Newtonian viscosity μ(γ̇), γ̇ = √(2E:E) in cylindrical coordinates (hoop
// strain u_r/r and the θ-derivatives included), on the staggered (r, θ, z) grid of a
// CylindricalGrid with any N_θ >= 1 (N_θ = 1 is the axisymmetric special case). f is the
// caller's momentum source (force per volume on the fluid, i.e. −F^pf of CD eq. 29 times ρ) and
// β >= 0 an optional implicit drag coefficient (f − βu is CD eq. 29 with the drag part implicit).
// This is the solver the CFD-DEM coupling drives step by step: set ε and the source, advance(dt),
// sample the velocity at particle positions.
//
// Unknowns (MAC staggering): u_r on radial faces, u_θ on azimuthal faces (θ = θ_j, at r = r_c),
// u_z on axial faces, p at cell centres. The θ-momentum equation is solved in angular-momentum
// form for ω = u_θ/r_c, r(∇·τ)_θ = ∇·(r τ_θ·), with the same fluxes as the steady SwirlSolver:
// ∫ μ r³ dr ∂_zω over axial faces by 3-point Gauss quadrature in r and r³ μ ∂_rω on radial
// faces. The creeping solution ω = Ωz/H (v_θ = rΩz/H) is therefore an exact discrete steady
// state for every GN law, and the plate torque is the conservative wall flux
//   T = Σ_(i,j) Δθ ∫ μ r³ dr ∂_zω |top  = 2π Σ_i ∫ r² τ_θz dr  (axisymmetric),
// identical to SwirlSolver::torque for N_θ = 1 on the same (r, z) grid when the steady solver
// runs with SwirlParams::one_sided_plate_gradients = false. Its default, with inertia, takes
// the plate fluxes second-order one-sided, not by the half-cell difference used here; on
// coarse grids the torques then differ by about 1e-3 (validate_transient uses false).
//
// Time scheme (per step n → n+1, step Δt, ratio w = Δt/Δt_prev): SBDF2, i.e. variable-step
// BDF2 for ∂(εu)/∂t with every explicit term evaluated at the extrapolated velocity
// u^e = (1+w)u^n − w u^(n−1). The first step after a reset, and any step with w > 2 (variable-step
// BDF2 is zero-stable only for w < 1 + √2), is backward/forward Euler. Second order in time
// (validate_transient: observed 2.0–2.2 on the spin-up series solution).
//   1. μ, γ̇ from u^e (one array call of the rheology law). Shear components of the form
//      r·∂ω + (1/r)∂_θu are evaluated at the radius where μ is wanted (cell centre, edge, or
//      Gauss point), and ∂_zω, ∂_zu_r at the plates by the second-order one-sided formula,
//      both exactly as SwirlSolver evaluates them, so that for N_θ = 1 the discrete steady
//      equations are SwirlSolver's (the transient reaches its torque to ~1e-10).
//   2. Predictor, three decoupled SPD sparse systems (u_r, ω, u_z), viscous term implicit in
//      its Laplacian form for each component's own derivatives: μ∂_ru_r (half of τ_rr), the
//      ∂_θu_r part of τ_rθ, ∂_zu_r of τ_rz and the hoop term μu_r/r² for u_r; r³μ∂_rω, ∫μr³dr ∂_zω
//      and μ∂_θω (half of τ_θθ) for ω; μ∂_zu_z, ∂_ru_z and (1/r)∂_θu_z for u_z. The transposed
//      part ∇·(μ(∇u)ᵀ) — the other halves of the normal stresses and the cross-component terms —
//      with −(2/3)μ∇·u and the axis value of u_r is explicit; for constant μ and ∇·u = 0 it is
//      μ∇(∇·u) = 0, so the split costs nothing for a Newtonian fluid and stays stable with
//      variable μ at viscous Courant numbers νΔt/Δz² of 1000 (test_transient). Convection
//      (central, conservative, ∇·(εuu) with the centrifugal force ρu_θ²/r) is explicit;
//      `inertia = false` drops it (creeping/unsteady-Stokes limit). Small systems are
//      factorised by SimplicialLDLT (refactorised only when their values change, i.e. not at
//      all for a Newtonian fluid at fixed Δt and ε); larger ones are solved by CG with an IC(0)
//      preconditioner in the natural ordering (k fastest: the stiff axial coupling is in the
//      factor), warm-started from u^n.
//   3. Pressure correction in rotational incremental form (Timmermans; Guermond, Minev & Shen
//      2006): ∇·(ε∇φ) = (a₀ρ/Δt)[∇·(εu*) + (BDF2 ∂ε/∂t)], u^(n+1) = u* − (Δt/(a₀ρ))∇φ,
//      p^(n+1) = p^n + φ − μ∇·(u* − u^(n+1)). The last term (zero at a steady state) keeps the
//      pressure converging at large viscous Courant numbers, where φ ∝ ρ/Δt alone would not.
//      The continuity equation including ∂ε/∂t holds to the solver tolerance after every step
//      (relative to the magnitude of the face fluxes).
// A steady state of the scheme satisfies the discrete steady equations exactly, whatever Δt.
//
// Pressure solver: preconditioned conjugate gradients on the 3D variable-coefficient Poisson
// matrix (ε varies in θ in CFD-DEM, so a pure FFT solve is not exact). The preconditioner is
// the exact inverse of the θ-averaged operator: a real DFT in θ (an orthogonal N_θ × N_θ
// transform applied line by line; no FFTW needed for the N_θ <= O(100) used here) splits it
// into ⌊N_θ/2⌋ + 1 two-dimensional (r, z) SPD matrices, each factorised once by SimplicialLDLT.
// For axisymmetric ε (in particular single phase, ε = 1) the preconditioner is the inverse
// and PCG converges in one iteration; for particle-laden ε the iteration count grows only with
// the θ-variation of ε. Factorisations are redone only when ε changes.
//
// Boundaries: bottom plate z = 0 rotating at Ω_b (default 0, at rest), top plate z = H at Ω
// (u_θ = Ωr), no-slip. Rim r = R: the flat, shear-free meniscus of SwirlSolver, u_r = 0,
// τ_rθ = τ_rz = 0. Axis r = 0: the radial faces there have zero area, so no mass, momentum or
// angular-momentum flux crosses the axis (r u_r = 0, r³ → 0); the wedge cells of the first ring
// connect to each other through their θ faces only. The u_r value *on* the axis, which the
// strain rate (∂_ru_r, u_r/r) and the momentum fluxes through the first ring's centres need,
// is the Cartesian velocity (U_x, U_y) on the axis evaluated in each direction θ,
//   u_r(0, θ) = U_x cos θ + U_y sin θ, (U_x, U_y) from the mode-1 DFT of u_r on the first
// interior ring (N_θ >= 3; the average of opposite faces for N_θ = 2; 0 for N_θ = 1). It is
// stored in radial_velocity() at i = 0 and enters the u_r equation explicitly.
//
// Momentum source: f and β are given per cell and averaged to the faces; in the angular-momentum
// equation both act through ∫ r (·) dV with u_θ uniform over the control volume, so f_θ = βu_θ
// balances exactly. Gravity ερg_z acts on u_z.
//
// Failure handling: advance() refuses a step whose convective Courant number (from u^n)
// exceeds max_courant, and rejects a step that produces NaN/inf (including a non-finite μ from
// the rheology law), a velocity blow-up (a speed above blow_up_factor × the reference speed of
// the step) or a failed linear solve; in every case it throws StepError and keeps the last
// good state.
//
// Parameters (SI):
//   grid                     CylindricalGrid::Params, N_r >= 2, N_z >= 2, any N_θ >= 1
//   density                  ρ  [kg/m³]   > 0
//   rheology                 μ(γ̇) law, not null
//   inertia                  true: full equations; false: drop convection (creeping limit)
//   top_angular_velocity     Ω  [rad/s]   finite (also settable between steps)
//   bottom_angular_velocity  Ω_b [rad/s]  finite, default 0 (fixed bottom plate)
//   axial_gravity            g_z [m/s²]   finite, default 0 (−9.80665 for gravity pointing down)
//   max_courant              [-]          > 0, default 0.5: largest Δt Σ|u_d|/Δx_d accepted (the
//                                         first ring's θ-width r_c,0 Δθ is the smallest Δx of a
//                                         polar grid: many θ cells limit Δt there)
//   pressure_tolerance       [-]          > 0, default 1e-10: PCG residual relative to the face fluxes
//   pressure_max_iterations  [-]          >= 1, default 200
//   blow_up_factor           [-]          > 1, default 100: a step whose largest speed exceeds
//                                         this times the reference speed (plates, u^n, source
//                                         and ε change over the step) is rejected as diverged
//   direct_solver_limit      [-]          >= 0, default 1000: predictor systems with at most this
//                                         many unknowns are solved by SimplicialLDLT, larger ones
//                                         by CG with IC(0) (3D Cholesky fill grows too fast: on
//                                         32×16×16 cells CG takes 7–14 ms a step, LDLT 70–290 ms)
//   viscous_tolerance        [-]          > 0, default 1e-14: relative CG residual of those
//   viscous_max_iterations   [-]          >= 1, default 500
//
// Example:
//   TransientParams p;
//   p.grid = {.radius = 0.015, .gap = 0.0005, .radial_cells = 16, .azimuthal_cells = 8, .axial_cells = 8};
//   p.density = 1000; p.rheology = law; p.top_angular_velocity = 0.333;
//   TransientSolver solver(p);
//   while (solver.time() < t_end) {
//     solver.set_void_fraction(eps_next);                  // coupling: ε at the end of the step
//     solver.set_momentum_source({f_r, f_theta, f_z, beta});
//     const StepReport report = solver.advance(1e-5);       // throws StepError on failure
//     use(report.torque, solver.sample_velocity(particle_positions));
//   }
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "rheosim/core/rheology.hpp"
#include "rheosim/fluid/grid.hpp"

namespace rheosim::fluid {

struct TransientParams {
  CylindricalGrid::Params grid;                    // N_r >= 2, N_z >= 2, N_θ >= 1
  double density = 0;                              // ρ [kg/m³], > 0
  std::shared_ptr<const core::Rheology> rheology;  // μ(γ̇), not null
  bool inertia = true;                             // false: creeping (unsteady Stokes) limit
  double top_angular_velocity = 0;                 // Ω [rad/s]
  double bottom_angular_velocity = 0;              // Ω_b [rad/s]; 0 = fixed bottom plate
  double axial_gravity = 0;                        // g_z [m/s²]
  double max_courant = 0.5;                        // > 0
  double pressure_tolerance = 1e-10;               // > 0, PCG residual relative to the face fluxes
  int pressure_max_iterations = 200;               // >= 1
  double blow_up_factor = 100;                     // > 1
  int direct_solver_limit = 1000;                  // >= 0: predictor systems up to this size use LDLT
  double viscous_tolerance = 1e-14;                // > 0, relative CG residual of larger predictor systems
  int viscous_max_iterations = 500;                // >= 1
};

struct CylindricalPoint {
  double r = 0;      // [m], 0 <= r <= R
  double theta = 0;  // [rad], any value (periodic)
  double z = 0;      // [m], 0 <= z <= H
};

struct CylindricalVelocity {
  double radial = 0;     // u_r [m/s]
  double azimuthal = 0;  // u_θ [m/s]
  double axial = 0;      // u_z [m/s]
};

// Caller-supplied momentum exchange, one value per cell (cell index (i·N_θ + j)·N_z + k), in the
// cylindrical basis at the cell centre. Every span is either empty (= zero) or of cell_count().
struct MomentumSource {
  std::span<const double> radial;            // f_r [N/m³], force per volume on the fluid
  std::span<const double> azimuthal;         // f_θ [N/m³]
  std::span<const double> axial;             // f_z [N/m³]
  std::span<const double> drag_coefficient;  // β [kg/(m³·s)] >= 0; adds −βu, treated implicitly
};

struct StepReport {
  double time = 0;               // t after the step [s]
  double time_step = 0;          // Δt [s]
  double courant = 0;            // convective Courant number of the new state at this Δt
  int pressure_iterations = 0;   // PCG iterations
  int viscous_iterations = 0;    // largest CG iteration count of the three predictor systems (0: direct)
  double pressure_residual = 0;  // final PCG residual relative to the norm of the face-flux magnitudes
  double max_divergence = 0;     // max |∇·(εu) + ∂ε/∂t| over cells [1/s] after the projection
  double torque = 0;             // on the top plate [N·m], resisting rotation (> 0 for Ω > 0)
  double bottom_torque = 0;      // transmitted to the bottom plate [N·m]
  double wall_time = 0;          // [s]
};

enum class StepFailure {
  courant_exceeded,  // the step was refused before it started
  non_finite,        // NaN or inf in the viscosity, the new velocity or the pressure
  diverged,          // speeds above blow_up_factor × the reference speed
  linear_solver,     // a factorisation failed or PCG did not converge
};

// Thrown by advance(); the solver's state is the one before the failed step.
class StepError : public std::runtime_error {
 public:
  StepError(StepFailure kind, const std::string& message, StepReport report)
      : std::runtime_error(message), kind_(kind), report_(report) {}
  [[nodiscard]] StepFailure kind() const { return kind_; }
  [[nodiscard]] const StepReport& report() const { return report_; }

 private:
  StepFailure kind_;
  StepReport report_;
};

class TransientSolver {
 public:
  explicit TransientSolver(TransientParams params);  // validates; throws std::invalid_argument
  ~TransientSolver();
  TransientSolver(TransientSolver&&) noexcept;
  TransientSolver& operator=(TransientSolver&&) noexcept;
  TransientSolver(const TransientSolver&) = delete;
  TransientSolver& operator=(const TransientSolver&) = delete;

  // Advances the state by dt [s] > 0. @pre the Courant number of the current state at dt is at
  // most max_courant. @post the new state satisfies the discrete continuity equation to the
  // pressure tolerance. Throws StepError (state unchanged) on any failure.
  StepReport advance(double dt);

  // Void fraction ε^(n+1) in (0, 1] per cell at the end of the next step (kept until changed);
  // its change from the current field drives ∇·(εu) = −∂ε/∂t.
  void set_void_fraction(std::span<const double> void_fraction);
  // Sets the current field, and the next one, to ε with no change in time (∂ε/∂t = 0): the
  // initial condition, or a restart.
  void reset_void_fraction(std::span<const double> void_fraction);
  // Momentum source for the following steps (kept until changed); an empty source clears it.
  void set_momentum_source(const MomentumSource& source);
  void set_top_angular_velocity(double angular_velocity);  // Ω [rad/s] from the next step on

  // Replaces the velocity (sizes as the accessors below; the axis, rim and wall values are
  // imposed) and restarts the time history (the next step is BDF1). The field is used as given:
  // call project_velocity() to make an arbitrary initial field divergence-free.
  void set_velocity(std::span<const double> radial, std::span<const double> azimuthal, std::span<const double> axial);
  // Replaces the pressure [Pa] (cell centres), e.g. on a restart; the predictor of the next step
  // starts from it. Its volume mean is removed.
  void set_pressure(std::span<const double> pressure);
  // Removes the divergent part of the current velocity: ∇·(εu) = 0 to the pressure tolerance
  // (with the current ε); the pressure is unchanged. Returns the PCG iteration count.
  int project_velocity();

  // Fields of the current state (index formulas: cell (i·N_θ + j)·N_z + k).
  [[nodiscard]] std::span<const double> radial_velocity() const;     // u_r [m/s], (N_r+1)·N_θ·N_z, i = 0 axis value
  [[nodiscard]] std::span<const double> azimuthal_velocity() const;  // u_θ [m/s], N_r·N_θ·N_z, at (r_c,i, θ_j, z_c,k)
  [[nodiscard]] std::span<const double> axial_velocity() const;  // u_z [m/s], N_r·N_θ·(N_z+1): (i·N_θ+j)·(N_z+1)+k
  [[nodiscard]] std::span<const double> pressure() const;        // p [Pa], cell centres, volume mean 0
  [[nodiscard]] std::span<const double> viscosity() const;       // μ [Pa·s], cell centres
  [[nodiscard]] std::span<const double> shear_rate() const;      // γ̇ [1/s], cell centres
  [[nodiscard]] std::span<const double> void_fraction() const;   // ε [-], cell centres (current)
  // ∇·(εu) per cell [1/s] of the current state (equals −∂ε/∂t of the last step).
  [[nodiscard]] std::vector<double> divergence() const;
  // Velocity interpolated (trilinear on each staggered component, walls/axis/rim included).
  [[nodiscard]] std::vector<CylindricalVelocity> sample_velocity(std::span<const CylindricalPoint> points) const;

  [[nodiscard]] double torque() const;         // top plate [N·m], current state
  [[nodiscard]] double bottom_torque() const;  // bottom plate [N·m], current state
  [[nodiscard]] double time() const;           // [s]
  [[nodiscard]] long step_count() const;
  // Convective Courant number Δt max_cells(|u_r|/Δr + |u_θ|/(r Δθ) + |u_z|/Δz) of the current
  // state (the θ term only for N_θ > 1).
  [[nodiscard]] double courant_number(double dt) const;

  [[nodiscard]] const CylindricalGrid& grid() const;
  [[nodiscard]] const TransientParams& params() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rheosim::fluid
