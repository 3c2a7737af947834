#pragma once
// The pieces of one steady swirl solve (SwirlSolver::attempt): the maps between the state and
// the linear system's vector, the steady residual, the Newton–Krylov step, the fixed-point
// variable, and the stopping rules. swirl.cpp strings them into the iteration.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>

#include <optional>
#include <span>
#include <vector>

#include "swirl_discretisation.hpp"

namespace rheosim::fluid::swirl_detail {

using SparseLu = Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>>;

class SwirlSystem {
 public:
  // `layout`, `discretisation` and `torque_density` must outlive the system.
  SwirlSystem(const Layout& layout, const Discretisation& discretisation, std::span<const double> torque_density,
              double angular_velocity, SwirlState scratch);

  // System vector (ω, p, interior u_r, u_z) ↔ state; pressure pinned to 0 at cell (0, 0) as in
  // the assembled continuity rows.
  [[nodiscard]] Eigen::VectorXd to_system(const SwirlState& state) const;
  void from_system(const Eigen::VectorXd& z, SwirlState& state) const;

  // Steady residual A(z) z − b(z) of the discrete equations (the Newton terms of the
  // linearisation cancel at its own expansion point, so this is the nonlinear residual).
  [[nodiscard]] Eigen::VectorXd steady_residual(const Eigen::VectorXd& z);

  // One inexact Newton step from `state`: solves (J + D) δ = −F by GMRES, left-preconditioned
  // with the Picard LU `factor` (whose solution x_picard gives the first Krylov vector), in
  // variables scaled by Ω, ΩR and the pressure's magnitude; J·v by a forward difference of F.
  // D is the pseudo-time term Δτ (infinite: none), so with it each step is one implicit
  // pseudo-time step. `linearised` is the Picard matrix, whose row sums scale the line search.
  [[nodiscard]] Eigen::VectorXd newton_krylov_step(const SwirlState& state, const Eigen::VectorXd& x_picard,
                                                   double pseudo_time_step, const SparseLu& factor,
                                                   const Triplets& linearised);
  // ‖δ‖∞ of the last full Newton step (scaled), for the stopping test.
  [[nodiscard]] double newton_step_size() const { return newton_step_size_; }

  // The Picard map's output: `state` with ω (and with inertia p, u_r, u_z) from the solution x.
  [[nodiscard]] SwirlState picard_state(const Eigen::VectorXd& x, const SwirlState& state) const;

  // The fixed-point variable: ω/Ω and (with inertia) interior u_r, u_z over ΩR, so that one
  // tolerance fits all components. Pressure follows from each linear solve.
  [[nodiscard]] Eigen::VectorXd pack(const SwirlState& state) const;
  void unpack(const Eigen::VectorXd& v, SwirlState& state) const;

 private:
  const Layout& L;
  const Discretisation& disc_;
  std::span<const double> torque_density_;
  double velocity_scale_, omega_scale_;
  SwirlState scratch_;
  Triplets residual_triplets_;
  Eigen::VectorXd residual_rhs_;
  double newton_step_size_ = 0;
};

// Switched evolution relaxation: Δτ follows the residual's fall, and is dropped (steady
// Picard/Newton, infinity) once it exceeds 10⁴ revolutions.
[[nodiscard]] double next_pseudo_time_step(double pseudo_time_step, double residual, double previous_residual,
                                           double angular_velocity);

// Newton reaches a floor that may sit above a tight tolerance: the rounding of the residual's
// cancelling terms at large Re (~1e-9 of their size), or the stiff regularised viscosity of a
// yield-stress liquid at low Bingham numbers (~1e-7). Five changes in a row below 1e-5 that gain
// less than a decade together, where a working Newton step would have gained orders, count as
// converged at that floor. Counts in `below_floor`; returns the floor (the window's largest
// change) when reached.
[[nodiscard]] std::optional<double> newton_floor(const std::vector<double>& changes, int& below_floor);

}  // namespace rheosim::fluid::swirl_detail
