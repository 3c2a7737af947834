// The lattice cavity's phases of the LDD step (cavity_solver.hpp, solver.hpp), one method per phase.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "rheosim/ldd/cavity_solver.hpp"

namespace rheosim::ldd {
namespace {

// x = LU⁻¹ b and its residual against `a` (the factorised matrix), as a KrylovResult with one
// iteration; `scratch` holds A x.
numerics::KrylovResult direct_solve(const numerics::SparseLu& lu, const numerics::StencilMatrix& a,
                                    std::span<const double> b, std::span<double> x,
                                    const numerics::KrylovSettings& settings, std::vector<double>& scratch) {
  lu.solve(b, x);
  scratch.resize(b.size());
  a.multiply(x, scratch);
  for (std::size_t i = 0; i < b.size(); ++i) scratch[i] = b[i] - scratch[i];
  numerics::KrylovResult result;
  result.iterations = 1;
  const double b_norm = std::sqrt(numerics::parallel_dot(b, b));
  result.residual = std::sqrt(numerics::parallel_dot(scratch, scratch));
  result.relative_residual = b_norm > 0 ? result.residual / b_norm : result.residual;
  result.converged = result.residual <= std::max(settings.relative_tolerance * b_norm, settings.absolute_tolerance);
  return result;
}

// Relative diagonal shift regularising the closed domain's singular pressure problem.
constexpr double pressure_regularisation = 1e-6;

}  // namespace

// 1. Operators (eqs. 13–16), once: the cloud returns to the same places every step.
void CavitySolver::update_operators(StepStats& stats) {
  if (!operators_valid_) {
    operators_ = build_operators(positions_, 2, neighbours_, OperatorSettings{support_radius_});
    operators_valid_ = true;
  }
  stats.guarded_nodes = operators_.guarded_count();
}

// 2. ∇u (eq. 14), E (eq. 4), γ̇ (eq. 5), μ(γ̇).
void CavitySolver::update_viscosity() {
  const std::size_t n = kinds_.size();
  velocity_gradient_.resize(4 * n);  // per node: ∂u/∂x, ∂u/∂y, ∂v/∂x, ∂v/∂y
  divergence_.resize(n);
  velocity_gradient_of(velocity_, velocity_gradient_);
  const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const double* g = &velocity_gradient_[4 * i];
    const double shear_xy = 0.5 * (g[1] + g[2]);
    shear_rate_[i] = std::sqrt(2.0 * (g[0] * g[0] + g[3] * g[3] + 2.0 * shear_xy * shear_xy));  // eq. 5
  }
  params_.rheology->viscosity(shear_rate_, viscosity_);
}

// 3. Semi-implicit momentum (eq. 19) with the previous pressure, one solve per component:
//    ρ u* − δt μ⟨∇²u*⟩ = ρ u_{n−1} + δt (−⟨∇p_{n−1}⟩ + F_ext + 2E⟨∇μ⟩); no-slip Dirichlet rows.
//    One pass over the neighbour pairs forms ⟨∇p_{n−1}⟩ (eq. 14, every node: the wall rows of
//    the PPE use it), the explicit ∇·(μ(∇u)ᵀ) and the implicit matrix, each sum in the order
//    of the separate operator passes it replaces (the same bits). Into new_velocity_; returns
//    whether both components' solves converged.
bool CavitySolver::solve_momentum(double /*next_time: the walls' velocities are the cloud's*/, StepStats& stats) {
  const std::size_t n = kinds_.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  const double dt = params_.time_step, rho = params_.density;
  const numerics::NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  pressure_gradient_.resize(2 * n);
  momentum_matrix_.pattern = &nb;
  momentum_matrix_.diagonal.resize(n);
  momentum_matrix_.off_diagonal.resize(nb.pair_count());
  momentum_rhs_.resize(2 * n);  // interleaved x, y like the velocity
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const std::size_t begin = nb.offsets[i], end = nb.offsets[i + 1];
    const double p_i = pressure_[i];
    double px = 0, py = 0;
    if (kinds_[i] != NodeKind::interior) {  // no-slip Dirichlet row
      for (std::size_t k = begin; k < end; ++k) {
        const double dp = pressure_[nb.indices[k]] - p_i;
        px += ops.gradient[2 * k] * dp;
        py += ops.gradient[2 * k + 1] * dp;
        momentum_matrix_.off_diagonal[k] = 0.0;
      }
      pressure_gradient_[2 * i] = px;
      pressure_gradient_[2 * i + 1] = py;
      momentum_matrix_.diagonal[i] = 1.0;
      momentum_rhs_[2 * i] = wall_velocities_[2 * i];
      momentum_rhs_[2 * i + 1] = wall_velocities_[2 * i + 1];
      continue;
    }
    // ∇·(μ(∇u)ᵀ): x row = ∂x(μ ∂u/∂x) + ∂y(μ ∂v/∂x), y row = ∂x(μ ∂u/∂y) + ∂y(μ ∂v/∂y), eq. 14 on
    // the stress components τ_c = μ g_c (g: ∂u/∂x, ∂u/∂y, ∂v/∂x, ∂v/∂y).
    const double mu_i = viscosity_[i];
    const double* g_i = &velocity_gradient_[4 * i];
    const double tau_i[4] = {mu_i * g_i[0], mu_i * g_i[1], mu_i * g_i[2], mu_i * g_i[3]};
    double dx_tau0 = 0, dx_tau1 = 0, dy_tau2 = 0, dy_tau3 = 0, sum = 0;
    for (std::size_t k = begin; k < end; ++k) {
      const std::size_t j = nb.indices[k];
      const double cx = ops.gradient[2 * k], cy = ops.gradient[2 * k + 1];
      const double dp = pressure_[j] - p_i;
      px += cx * dp;
      py += cy * dp;
      const double mu_j = viscosity_[j];
      const double* g_j = &velocity_gradient_[4 * j];
      dx_tau0 += cx * (mu_j * g_j[0] - tau_i[0]);
      dx_tau1 += cx * (mu_j * g_j[1] - tau_i[1]);
      dy_tau2 += cy * (mu_j * g_j[2] - tau_i[2]);
      dy_tau3 += cy * (mu_j * g_j[3] - tau_i[3]);
      // Implicit ∇·(μ∇u) with the pair viscosity ½(μ_i + μ_j) on the eq. 15 coefficients.
      const double coefficient = dt * 0.5 * (mu_i + mu_j) * ops.laplacian[k];
      momentum_matrix_.off_diagonal[k] = -coefficient;
      sum += coefficient;
    }
    pressure_gradient_[2 * i] = px;
    pressure_gradient_[2 * i + 1] = py;
    momentum_matrix_.diagonal[i] = rho + sum;
    // Explicit ∇·(μ(∇u)ᵀ) (eq. 14 on each component): with ∇·u = 0 this is eq. 18's 2E∇μ − μ∇²u
    // + ∇·(μ∇u), i.e. the explicit remainder of ∇·τ. (0.0 + …: the separate passes' sums started at 0.)
    const double fx = 0.0 + dx_tau0 + dy_tau2, fy = 0.0 + dx_tau1 + dy_tau3;
    momentum_rhs_[2 * i] = rho * velocity_[2 * i] + dt * (-px + rho * params_.gravity[0] + fx);
    momentum_rhs_[2 * i + 1] = rho * velocity_[2 * i + 1] + dt * (-py + rho * params_.gravity[1] + fy);
  }
  new_velocity_.resize(2 * n);
  component_.resize(n);
  numerics::KrylovSettings velocity_settings{params_.velocity_tolerance, 1e-300, params_.max_iterations, {}};
  // Jacobi by default: a sparse LU of an earlier step's momentum matrix as preconditioner was
  // measured slower (μ(γ̇) changes too fast early in a run; each LU solve costs ~10 Jacobi
  // iterations). AMG reuses its coarse levels while μ changes slowly (amg.hpp).
  const bool velocity_amg = params_.velocity_preconditioner == Preconditioner::amg;
  if (velocity_amg) {
    velocity_amg_.prepare(momentum_matrix_);
    velocity_settings.preconditioner = velocity_amg_.as_preconditioner();
  }
  double velocity_residual = 0;
  bool velocity_converged = true;
  int most_velocity_iterations = 0;
  const auto record = [&](const numerics::KrylovResult& result) {
    most_velocity_iterations = std::max(most_velocity_iterations, result.iterations);
    stats.velocity_iterations += result.iterations;
    velocity_residual = std::max(velocity_residual, result.relative_residual);
    velocity_converged = velocity_converged && result.converged;
  };
  if (velocity_amg) {
    rhs_.resize(n);  // one component at a time
    for (std::size_t d = 0; d < 2; ++d) {
      for (std::size_t i = 0; i < n; ++i) {
        component_[i] = velocity_[2 * i + d];
        rhs_[i] = momentum_rhs_[2 * i + d];
      }
      record(numerics::bicgstab(momentum_matrix_, rhs_, component_, velocity_settings, krylov_));
      for (std::size_t i = 0; i < n; ++i) new_velocity_[2 * i + d] = component_[i];
    }
  } else {
    // Jacobi: both components in one pass over the stencil (bit-identical to two solves).
    // Initial guess u + 2d₁ − d₂, d the change u* − u of the last two solves: the implicit
    // change varies smoothly from step to step, u itself does not (advection is in u). Cuts the
    // iterations 2.5× over 200 steps (u alone as the guess) and ~20 % from rest.
    momentum_increment_.resize(2 * n, 0.0);
    older_momentum_increment_.resize(2 * n, 0.0);
    for (std::size_t i = 0; i < 2 * n; ++i)
      new_velocity_[i] = velocity_[i] + 2.0 * momentum_increment_[i] - older_momentum_increment_[i];
    for (const numerics::KrylovResult& result : numerics::bicgstab_jacobi_pair(
             momentum_matrix_, momentum_rhs_, new_velocity_, velocity_settings, pair_krylov_))
      record(result);
    next_momentum_increment_.resize(2 * n);  // taken over when the step is committed
    for (std::size_t i = 0; i < 2 * n; ++i) next_momentum_increment_[i] = new_velocity_[i] - velocity_[i];
  }
  if (velocity_amg) velocity_amg_.record_iterations(most_velocity_iterations);
  stats.velocity_residual = velocity_residual;
  return velocity_converged;
}

// 4. Pressure Poisson equation (eq. 17) for the increment φ = p_n − p_{n−1} into increment_:
//    interior ⟨∇²φ⟩ = ρ/δt ⟨∇·u*⟩, walls n·⟨∇φ⟩ = ρ n·F_ext − n·⟨∇p_{n−1}⟩, corners Shepard.
numerics::KrylovResult CavitySolver::solve_pressure(StepStats& stats) {
  const std::size_t n = kinds_.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  const double dt = params_.time_step, rho = params_.density;
  const numerics::NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  divergence(nb, ops, new_velocity_, divergence_);
  // The matrix depends on the operators, normals and node kinds only: it is built once (and factorised once, below);
  // each step then only forms the right-hand side.
  const bool build_pressure_matrix = pressure_matrix_.pattern != &nb;
  if (build_pressure_matrix) {
    pressure_matrix_.pattern = &nb;
    pressure_matrix_.diagonal.resize(n);
    pressure_matrix_.off_diagonal.resize(nb.pair_count());
  }
  rhs_.resize(n);
  double max_divergence = 0;
#pragma omp parallel for schedule(static) reduction(max : max_divergence)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const std::size_t begin = nb.offsets[i], end = nb.offsets[i + 1];
    if (kinds_[i] == NodeKind::interior) {
      rhs_[i] = rho / dt * divergence_[i];
      max_divergence = std::max(max_divergence, std::abs(divergence_[i]));
    } else if (kinds_[i] == NodeKind::wall) {
      const double nx = normals_[2 * i], ny = normals_[2 * i + 1];
      rhs_[i] = rho * (nx * params_.gravity[0] + ny * params_.gravity[1]) -
                (nx * pressure_gradient_[2 * i] + ny * pressure_gradient_[2 * i + 1]);
    } else {
      rhs_[i] = 0.0;
    }
    if (!build_pressure_matrix) continue;
    double sum = 0;
    if (kinds_[i] == NodeKind::interior) {
      for (std::size_t k = begin; k < end; ++k) {
        pressure_matrix_.off_diagonal[k] = ops.laplacian[k];
        sum += ops.laplacian[k];
      }
      pressure_matrix_.diagonal[i] = -sum;
    } else if (kinds_[i] == NodeKind::wall) {
      const double nx = normals_[2 * i], ny = normals_[2 * i + 1];
      for (std::size_t k = begin; k < end; ++k) {
        const double c = nx * ops.gradient[2 * k] + ny * ops.gradient[2 * k + 1];
        pressure_matrix_.off_diagonal[k] = c;
        sum += c;
      }
      pressure_matrix_.diagonal[i] = -sum;
    } else {  // corner: Shepard average of the neighbours (eq. 12)
      double wsum = 0;
      for (std::size_t k = begin; k < end; ++k) wsum += ops.weights[k];
      for (std::size_t k = begin; k < end; ++k)
        pressure_matrix_.off_diagonal[k] = wsum > 0 ? -ops.weights[k] / wsum : 0.0;
      pressure_matrix_.diagonal[i] = 1.0;
    }
    // The closed domain's Neumann problem is singular (constants). A relative diagonal shift
    // makes it regular without pinning a node (a pinned node acts as a point sink for the
    // discrete compatibility mismatch and destabilises its neighbourhood); the constant part
    // of φ, which no gradient sees, absorbs the mismatch.
    pressure_matrix_.diagonal[i] *= 1.0 + pressure_regularisation;
  }
  stats.max_divergence = max_divergence;
  increment_.assign(n, 0.0);
  // Converged when the residual is small relative to the source, or when the divergence it
  // leaves is below pressure_tolerance · U/L in the RMS sense (near steady state ‖b‖ → 0).
  const double divergence_scale = rho / dt * params_.velocity_scale / params_.length_scale;
  const numerics::KrylovSettings pressure_settings{
      params_.pressure_tolerance,
      params_.pressure_tolerance * divergence_scale * std::sqrt(static_cast<double>(n)),
      params_.max_iterations,
      {}};
  numerics::KrylovSettings settings_with_preconditioner = pressure_settings;
  if (params_.pressure_preconditioner == Preconditioner::sparse_lu) {
    // The matrix never changes (its operators are built once and do not depend on μ): factorised once, every step
    // solves with the factors.
    if (!pressure_lu_.ready() &&
        !pressure_lu_.factorise(pressure_matrix_, numerics::SparseLu::Method::nested_dissection, positions_))
      params_.pressure_preconditioner = Preconditioner::jacobi;  // fall back to Jacobi
    if (pressure_lu_.ready()) settings_with_preconditioner.preconditioner = pressure_lu_.as_preconditioner();
  }
  // AMG: the matrix is constant, so the first set-up serves the whole run.
  const bool pressure_amg = params_.pressure_preconditioner == Preconditioner::amg;
  if (pressure_amg) {
    if (!pressure_amg_.ready()) pressure_amg_.setup(pressure_matrix_);
    settings_with_preconditioner.preconditioner = pressure_amg_.as_preconditioner();
  }
  numerics::KrylovResult pressure_result;
  if (pressure_lu_.ready()) {
    // The LU factorises this very matrix, so one direct solve is the answer to rounding (as a
    // BiCGStab preconditioner it cost a further matrix product and seven vector passes). Kept
    // when its residual meets the tolerance; otherwise BiCGStab continues from it.
    pressure_result = direct_solve(pressure_lu_, pressure_matrix_, rhs_, increment_, pressure_settings, krylov_.r);
  }
  if (!pressure_result.converged) {
    if (!std::isfinite(pressure_result.residual)) increment_.assign(n, 0.0);
    const numerics::KrylovResult krylov =
        numerics::bicgstab(pressure_matrix_, rhs_, increment_, settings_with_preconditioner, krylov_);
    pressure_result = numerics::KrylovResult{pressure_result.iterations + krylov.iterations, krylov.residual,
                                             krylov.relative_residual, krylov.converged};
  }
  if (pressure_amg) pressure_amg_.record_iterations(pressure_result.iterations);
  stats.pressure_iterations = pressure_result.iterations;
  stats.pressure_residual = pressure_result.relative_residual;
  return pressure_result;
}

// p_n (relative to its mean) into new_pressure_, u_n = u* − δt/ρ ⟨∇φ⟩ on fluid nodes; the
// largest speed over every node (the lid's included) and whether all values are finite.
Solver::Correction CavitySolver::correct_velocity() {
  const std::size_t n = kinds_.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  const double dt = params_.time_step, rho = params_.density;
  const numerics::NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  gradient(nb, ops, increment_, pressure_gradient_);
  new_pressure_.resize(n);
  double mean = 0;
  for (std::size_t i = 0; i < n; ++i) mean += pressure_[i] + increment_[i];
  mean /= static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) new_pressure_[i] = pressure_[i] + increment_[i] - mean;  // p relative to its mean
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (kinds_[i] != NodeKind::interior) continue;
    new_velocity_[2 * i] -= dt / rho * pressure_gradient_[2 * i];
    new_velocity_[2 * i + 1] -= dt / rho * pressure_gradient_[2 * i + 1];
  }
  Correction c;
  double max_speed_squared = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double u = new_velocity_[2 * i], v = new_velocity_[2 * i + 1];
    if (!std::isfinite(u) || !std::isfinite(v) || !std::isfinite(new_pressure_[i])) c.finite = false;
    if (u * u + v * v > max_speed_squared) {
      max_speed_squared = u * u + v * v;
      c.fastest = i;
    }
  }
  c.max_speed = std::sqrt(max_speed_squared);
  return c;
}

std::string CavitySolver::pressure_failure(const StepStats& /*stats*/) const {
  return fmt::format("(tolerance {:.3g})", params_.pressure_tolerance);
}

// 6. Commit and advect (eq. 20). The first step has no u_{n−1}: plain Euler. The nodes return to
// their lattice places with the velocity arriving there (step 7 of the header comment).
void CavitySolver::commit_and_advect(double /*next_time*/) {
  const std::size_t n = kinds_.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  const double dt = params_.time_step;
  const numerics::NeighbourList& nb = neighbours_;
  pressure_.swap(new_pressure_);
  if (!next_momentum_increment_.empty()) {
    older_momentum_increment_.swap(momentum_increment_);
    momentum_increment_.swap(next_momentum_increment_);
  }
  // ∇u_n for the gradient-corrected interpolation; the quadratic interpolation fits its own.
  if (params_.interpolation == LatticeInterpolation::gradient_corrected)
    velocity_gradient_of(new_velocity_, velocity_gradient_);
  const double older_weight = first_step_ ? 0.0 : 0.5;
  // Displacement of every node over the step (eq. 20); walls stay.
  const auto displacement = [&](std::size_t j, std::size_t d) {
    if (!is_fluid(j)) return 0.0;
    return ((1.0 + older_weight) * new_velocity_[2 * j + d] - older_weight * velocity_[2 * j + d]) * dt;
  };
  if (params_.interpolation == LatticeInterpolation::quadratic) {
    // Advect (eq. 20) and return to the lattice in one: each lattice place takes the velocity
    // arriving from its departure point (lattice_interpolation.hpp). Walls advect with their
    // own velocity (the lid's material moves along it).
    if (lattice_fit_.empty()) lattice_fit_ = QuadraticFit(positions_, nb, support_radius_);
    advection_velocity_.resize(2 * n);
    for (std::size_t i = 0; i < 2 * n; ++i)
      advection_velocity_[i] = (1.0 + older_weight) * new_velocity_[i] - older_weight * velocity_[i];
    return_to_lattice(positions_, kinds_, nb, lattice_fit_, new_velocity_, advection_velocity_, dt, true, component_);
    previous_velocity_.swap(velocity_);
    velocity_.swap(component_);
    first_step_ = false;
  } else {
    // Advect (eq. 20), then reorder every node back onto its lattice place, interpolating the
    // velocity there from the advected cloud (eq. 12, optionally with a gradient correction):
    //   u(X_i) = Σ_j W(|X_i − x'_j|) (u_j + c ⟨∇u⟩_j·(X_i − x'_j)) / Σ_j W,  x'_j = X_j + d_j,
    // over j ∈ {i} ∪ N(i). The node spacing is kept exactly and the operators stay valid.
    component_.resize(2 * n);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      if (!is_fluid(i)) {
        component_[2 * i] = new_velocity_[2 * i];
        component_[2 * i + 1] = new_velocity_[2 * i + 1];
        continue;
      }
      double wsum = 0, su = 0, sv = 0;
      double u_min = std::numeric_limits<double>::infinity(), u_max = -u_min, v_min = u_min, v_max = -u_min;
      const auto add = [&](std::size_t j) {
        const double rx = positions_[2 * i] - (positions_[2 * j] + displacement(j, 0));
        const double ry = positions_[2 * i + 1] - (positions_[2 * j + 1] + displacement(j, 1));
        const double w = weight(std::hypot(rx, ry), support_radius_);
        if (w <= 0) return;
        const double c = params_.interpolation == LatticeInterpolation::gradient_corrected ? 1.0 : 0.0;
        const double g[4] = {c * velocity_gradient_[4 * j], c * velocity_gradient_[4 * j + 1],
                             c * velocity_gradient_[4 * j + 2], c * velocity_gradient_[4 * j + 3]};
        wsum += w;
        su += w * (new_velocity_[2 * j] + g[0] * rx + g[1] * ry);
        sv += w * (new_velocity_[2 * j + 1] + g[2] * rx + g[3] * ry);
        u_min = std::min(u_min, new_velocity_[2 * j]);
        u_max = std::max(u_max, new_velocity_[2 * j]);
        v_min = std::min(v_min, new_velocity_[2 * j + 1]);
        v_max = std::max(v_max, new_velocity_[2 * j + 1]);
      };
      add(i);
      for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) add(nb.indices[k]);
      // Clipped to the range of the contributing values (Bermejo & Staniforth 1992): the
      // gradient correction is second order but not monotone, and at high Re its overshoots grow.
      component_[2 * i] = std::clamp(su / wsum, u_min, u_max);
      component_[2 * i + 1] = std::clamp(sv / wsum, v_min, v_max);
    }
    previous_velocity_.swap(velocity_);
    velocity_.swap(component_);
    first_step_ = false;
  }
}

}  // namespace rheosim::ldd
