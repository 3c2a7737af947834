#pragma once
// The lattice cavity's scheme of the LDD step (solver.hpp) for closed 2D domains (LDD §3.2), one
// call to Solver::step():
//
//   1. operators (eqs. 13–16), built once: the cloud returns to the same places every step;
//   2. explicit velocity gradient (eq. 14), strain rate E (eq. 4), shear rate γ̇ (eq. 5),
//      viscosity μ(γ̇) from the rheology law, and the explicit stress term ∇·(μ(∇u)ᵀ);
//   3. semi-implicit momentum (eq. 19) with the previous pressure, matrix-free BiCGStab (Jacobi:
//      both components in one fused solve, krylov.hpp; initial guess u + 2d₁ − d₂ from the last
//      two solves' changes d = u* − u), no-slip Dirichlet rows on wall nodes (the lid moves):
//        ρ u* − δt ∇·(μ∇u*) = ρ u_{n−1} + δt (−⟨∇p_{n−1}⟩ + F_ext + ∇·(μ(∇u)ᵀ)_{n−1}).
//      For ∇·u = 0, ∇·(μ∇u) + ∇·(μ(∇u)ᵀ) = μ∇²u + 2E∇μ (eq. 18); the implicit part uses the pair
//      viscosity ½(μ_i + μ_j) on the eq. 15 coefficients. Identical to eq. 19 for a Newtonian
//      fluid; for viscosity contrasts of 10⁴ (Bn = 10) the explicit 2E∇μ of eq. 19 blew up at the
//      first step, this split does not (docs/ldd.md);
//   4. pressure Poisson equation (eq. 17) for the increment φ = p_n − p_{n−1} (incremental
//      pressure correction): one direct solve with the sparse LU of the constant matrix, BiCGStab
//      only if its residual is above tolerance (or BiCGStab with AMG or Jacobi):
//        fluid     ⟨∇²φ⟩ = ρ/δt ⟨∇·u*⟩   (eq. 17's −ρ∇·(Du/Dt) with ∇·∇·τ dropped, as in the seed)
//        walls     n·⟨∇φ⟩ = ρ n·F_ext − n·⟨∇p_{n−1}⟩ (eq. 17's Neumann condition for p; walls at
//                  rest or moving steadily, so ∂U/∂t = 0; the ν n·∇×∇×u term is dropped)
//        corners   φ = Shepard average of the neighbours (eq. 12), the normal being undefined;
//      the closed domain's singular Neumann problem is regularised by a 1e-6 relative diagonal
//      shift (a pinned node destabilised its neighbourhood); p is reported relative to its mean;
//      then u_n = u* − δt/ρ ⟨∇φ⟩ on fluid nodes;
//   5. divergence checks: NaN, Courant number max|u|δt/Δ, solver residuals; on failure step()
//      throws DivergenceError and leaves the state of the last good step untouched;
//   6. Lagrangian advection (eq. 20): x' = x + (3/2 u_n − 1/2 u_{n−1}) δt;
//   7. reordering: every node returns to its lattice place and takes the velocity arriving there
//      (LatticeInterpolation; the default is second order).
//
// OpenMP parallelises every loop over nodes; reductions add per-thread blocks in order, so a
// run is bit-identical for a given thread count.
#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "rheosim/core/rheology.hpp"
#include "rheosim/ldd/domain.hpp"
#include "rheosim/ldd/lattice_interpolation.hpp"
#include "rheosim/ldd/node_reordering.hpp"
#include "rheosim/ldd/operators.hpp"
#include "rheosim/ldd/preconditioner.hpp"
#include "rheosim/ldd/solver.hpp"
#include "rheosim/ldd/step.hpp"
#include "rheosim/numerics/amg.hpp"
#include "rheosim/numerics/krylov.hpp"
#include "rheosim/numerics/neighbours.hpp"
#include "rheosim/numerics/sparse_lu.hpp"

namespace rheosim::ldd {

// The cavity's parameters are SolverParams::for_cavity() (step.hpp): eq. 19 with Jacobi (both
// components in one fused solve) or AMG, no sparse LU; the PPE's sparse LU factorised once.
class CavitySolver final : public Solver {
 public:
  // `walls`: the boundaries the cloud's wall nodes name (Cavity::walls()).
  CavitySolver(SolverParams params, std::vector<std::shared_ptr<const Boundary>> walls, NodeCloud cloud);
  ~CavitySolver() override;
  CavitySolver(CavitySolver&&) noexcept;
  CavitySolver& operator=(CavitySolver&&) noexcept;

  // The state a checkpoint keeps (solver.hpp), with the momentum solves' initial-guess
  // increments. After restore() the constant operators, the lattice fit and the PPE's factors or
  // AMG set-up are rebuilt from the same cloud.
  [[nodiscard]] SolverState state() const override;
  void restore(SolverState state) override;

  // Velocity at arbitrary points (interleaved x, y) by Shepard interpolation (eq. 12) with a
  // first-order gradient correction: ⟨u(x)⟩ = Σ W_j (u_j + ⟨∇u⟩_j·(x − x_j)) / Σ W_j over the
  // nodes within h of x. Points without a node within h get NaN.
  [[nodiscard]] std::vector<double> sample_velocity(std::span<const double> points) const;

 private:
  // The phases of step(), in order (cavity_step.cpp).
  void update_operators(StepStats& stats) override;
  void update_viscosity() override;
  bool solve_momentum(double next_time, StepStats& stats) override;
  numerics::KrylovResult solve_pressure(StepStats& stats) override;
  Correction correct_velocity() override;
  void commit_and_advect(double next_time) override;
  [[nodiscard]] std::string pressure_failure(const StepStats& stats) const override;

  std::vector<double> wall_velocities_;  // each wall node's surface velocity (constant walls)
  bool operators_valid_ = false;
  numerics::SparseLu pressure_lu_;
  QuadraticFit lattice_fit_;                // quadratic interpolation
  std::vector<double> advection_velocity_;  // a of eq. 20 on every node
  numerics::PairKrylovWorkspace pair_krylov_;
  std::vector<double> momentum_rhs_;
  // u* − u of the last two committed momentum solves (Jacobi: the next initial guess), and this step's.
  std::vector<double> momentum_increment_, older_momentum_increment_, next_momentum_increment_;
};

}  // namespace rheosim::ldd
