// One free-surface step (free_surface.hpp, steps 1–7), one private method per phase.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "free_surface_internal.hpp"
#include "rheosim/ldd/free_surface.hpp"
#include "rheosim/numerics/row_blocks.hpp"
#include "rheosim/numerics/sparse_lu.hpp"

namespace rheosim::ldd {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The preconditioner `choice` of a solve on `matrix`, into settings: the matrix's sparse LU (2D
// only; Jacobi where the factorisation fails), the AMG hierarchy (kept while it fits, amg.hpp), or
// Jacobi (settings left empty). Returns whether an AMG hierarchy was built for this matrix.
bool set_preconditioner(Preconditioner choice, int dimension, const numerics::StencilMatrix& matrix,
                        numerics::SparseLu& lu, numerics::AmgPreconditioner& amg, numerics::KrylovSettings& settings) {
  if (choice == Preconditioner::sparse_lu && dimension == 2 && lu.factorise(matrix))
    settings.preconditioner = lu.as_preconditioner();
  if (choice != Preconditioner::amg) return false;
  const bool fresh = amg.prepare(matrix);
  settings.preconditioner = amg.as_preconditioner();
  return fresh;
}

double norm_of(const std::vector<double>& g) {
  return std::sqrt(std::inner_product(g.begin(), g.end(), g.begin(), 0.0));
}

}  // namespace

// 1. Operators (eqs. 13–16) and the free-surface classification.
void FreeSurfaceSolver::update_operators(StepStats& stats) {
  build_operators(positions_, dimension(), neighbours_,
                  OperatorSettings{support_radius_, params_.min_moment_rcond, params_.centred_gradient}, operators_);
  keep_laplacian_positive();
  last_kinds_ = kinds_;
  classify();
  regradient_for_boundary_values();
  stats.positivity_guarded = laplacian_guarded_;
  for (std::size_t i = 0; i < kinds_.size(); ++i) {
    stats.surface_nodes += kinds_[i] == NodeKind::surface ? 1 : 0;
    stats.splash_nodes += kinds_[i] == NodeKind::splash ? 1 : 0;
  }
}

// 2. ∇u (eq. 14), γ̇ = √(2E:E) (eq. 5), μ(γ̇), and (viscous_stress: full) ∇·(μ(∇u)ᵀ).
void FreeSurfaceSolver::update_viscosity() {
  const auto dim = static_cast<std::size_t>(dimension());
  const std::size_t n = kinds_.size(), dd = dim * dim;
  const numerics::NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  velocity_gradient_.resize(dd * n);  // every entry written
  velocity_gradient_of(velocity_, velocity_gradient_);
  // γ̇ and μ(γ̇) per node, one contiguous block of nodes per thread (the law is stateless).
  numerics::for_blocks(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const double* grad = &velocity_gradient_[dd * i];
      double e2 = 0;  // E:E
      for (std::size_t a = 0; a < dim; ++a)
        for (std::size_t b = 0; b < dim; ++b) {
          const double e = 0.5 * (grad[a * dim + b] + grad[b * dim + a]);
          e2 += e * e;
        }
      shear_rate_[i] = std::sqrt(2.0 * e2);  // eq. 5
    }
    params_.rheology->viscosity(std::span<const double>(shear_rate_).subspan(begin, end - begin),
                                std::span<double>(viscosity_).subspan(begin, end - begin));
  });
  update_surface_pressure();
  // solver.viscous_stress: full (SolverParams::transpose_stress) adds ∇·(μ(∇u)ᵀ) on interior
  // nodes, making the viscous force ∇·(2μE). Explicit alone it is a viscous term far past an
  // explicit limit, δt μ_max/(ρΔ²) up to ~5·10³ (Bingham m = 1000 s at Δ = 2 mm). So the momentum
  // matrix carries the μ-Laplacian twice on those rows (solve_momentum) and the explicit side takes
  // it off once at u_{n−1}: only T − L is explicit, and the implicit 2L bounds it (T ≤ L in energy
  // for the continuous operators). It vanishes for constant μ.
  transpose_stress_.assign(dim * n, 0.0);
  if (!params_.transpose_stress) return;
  transposed_viscous_force(nb, ops, viscosity_, velocity_gradient_, transpose_stress_);
  numerics::for_balanced_rows(nb.offsets, [&](std::size_t i) {
    if (kinds_[i] != NodeKind::interior) {
      for (std::size_t d = 0; d < dim; ++d) transpose_stress_[dim * i + d] = 0.0;
      return;
    }
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
      const std::size_t j = nb.indices[k];
      const double c = face_viscosity(i, j) * ops.laplacian[k];
      for (std::size_t d = 0; d < dim; ++d)
        transpose_stress_[dim * i + d] -= c * (velocity_[dim * j + d] - velocity_[dim * i + d]);
    }
  });
}

// The viscosity of the coupling of fluid node i to node j in ∇·(μ∇u): the mean of the two
// nodes' viscosities, or with solver.wall_viscosity: face_shear_rate, between a fluid and a wall
// node, the law at the mean of their shear rates (SolverParams::wall_face_shear_rate).
double FreeSurfaceSolver::face_viscosity(std::size_t i, std::size_t j) const {
  double viscosity = 0.5 * (viscosity_[i] + viscosity_[j]);
  if (params_.wall_face_shear_rate && !is_fluid(j)) {
    const double face_rate = 0.5 * (shear_rate_[i] + shear_rate_[j]);
    params_.rheology->viscosity(std::span<const double>(&face_rate, 1), std::span<double>(&viscosity, 1));
  }
  return viscosity;
}

// 3. Semi-implicit momentum (eq. 19), one solve per component, into new_velocity_. Returns
// whether every component's solve converged.
bool FreeSurfaceSolver::solve_momentum(double next_time, StepStats& stats) {
  LinearSolves& solves = solves_;
  const auto dim = static_cast<std::size_t>(dimension());
  const std::size_t n = kinds_.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  const double dt = params_.time_step, rho = params_.density;
  const std::vector<double>& g = params_.gravity;
  const double g_norm = norm_of(g);
  const numerics::NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  pressure_gradient_.resize(dim * n);
  impose_boundary_pressure();
  gradient(nb, ops, previous_pressure_, pressure_gradient_);
  momentum_matrix_.pattern = &nb;
  momentum_matrix_.diagonal.resize(n);
  momentum_matrix_.off_diagonal.resize(nb.pair_count());
  rhs_.resize(dim * n);  // component-major: rhs_[d·n + i]; every entry written below
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const std::size_t begin = nb.offsets[i], end = nb.offsets[i + 1];
    const NodeKind kind = kinds_[i];
    if (kind == NodeKind::interior || kind == NodeKind::surface) {
      double sum = 0;
      // 2L on interior rows under solver.viscous_stress: full (update_viscosity).
      const double implicit = params_.transpose_stress && kind == NodeKind::interior ? 2.0 : 1.0;
      for (std::size_t k = begin; k < end; ++k) {
        const double c = implicit * dt * face_viscosity(i, nb.indices[k]) * ops.laplacian[k];
        momentum_matrix_.off_diagonal[k] = -c;
        sum += c;
      }
      momentum_matrix_.diagonal[i] = rho + sum;
      for (std::size_t d = 0; d < dim; ++d)
        rhs_[d * n + i] = rho * velocity_[dim * i + d] +
                          dt * (-pressure_gradient_[dim * i + d] + rho * g[d] + transpose_stress_[dim * i + d]);
      continue;
    }
    for (std::size_t k = begin; k < end; ++k) momentum_matrix_.off_diagonal[k] = 0.0;
    if (kind == NodeKind::splash) {  // ballistic: too few neighbours for the operators
      momentum_matrix_.diagonal[i] = rho;
      for (std::size_t d = 0; d < dim; ++d) rhs_[d * n + i] = rho * (velocity_[dim * i + d] + dt * g[d]);
    } else {  // wall: no slip at the wall's velocity (Dirichlet)
      momentum_matrix_.diagonal[i] = 1.0;
      double v[3] = {0, 0, 0};
      const Boundary* boundary =
          boundary_of_[i] >= 0 ? boundaries_[static_cast<std::size_t>(boundary_of_[i])].get() : nullptr;
      if (boundary) boundary->surface_velocity(next_time, std::span<double>(v, dim));
      if (boundary && boundary->slip()) {
        // Free slip: the wall's normal velocity plus the tangential part of the fluid's (Shepard
        // average of the fluid neighbours' u_{n−1}, eq. 12); the fluid's own normal velocity
        // where it leaves the wall (below).
        double mean[3] = {0, 0, 0}, wsum = 0;
        for (std::size_t k = begin; k < end; ++k) {
          const std::size_t j = nb.indices[k];
          if (!is_continuum(j)) continue;
          wsum += ops.weights[k];
          for (std::size_t d = 0; d < dim; ++d) mean[d] += ops.weights[k] * velocity_[dim * j + d];
        }
        if (wsum > 0) {
          const double* normal = &normals_[dim * i];
          double relative_normal = 0;
          for (std::size_t d = 0; d < dim; ++d) {
            mean[d] = mean[d] / wsum - v[d];
            relative_normal += mean[d] * normal[d];
          }
          // Unilateral contact: a wall can push the fluid but not pull it. Where the fluid's
          // normal velocity leaves the wall (relative_normal > 0: the rising mould's slanted side
          // receding from resting concrete, or concrete sinking away from its overhang) the wall
          // node takes the fluid's whole velocity. Imposing the recession (0.0164 m/s on the
          // mould) demanded an expansion of 0.4 /s that only suction could supply, and the
          // no-tension clip turned that into p = 0 in the whole cake (docs/ldd.md).
          const double held = relative_normal > 0 ? 0.0 : relative_normal;
          for (std::size_t d = 0; d < dim; ++d) v[d] += mean[d] - held * normal[d];
        }
      }
      for (std::size_t d = 0; d < dim; ++d) rhs_[d * n + i] = v[d];
    }
  }
  new_velocity_.resize(dim * n);
  component_.resize(n);
  const double sqrt_n = std::sqrt(static_cast<double>(n));
  numerics::KrylovSettings& velocity_settings = solves.velocity;
  velocity_settings = {params_.velocity_tolerance,
                       params_.velocity_tolerance * rho * std::max(g_norm * dt, 1e-12) * sqrt_n,
                       params_.max_iterations,
                       {}};
  const bool velocity_amg = params_.velocity_preconditioner == Preconditioner::amg;
  bool velocity_hierarchy_fresh = set_preconditioner(params_.velocity_preconditioner, dimension(), momentum_matrix_,
                                                     solves.momentum_lu, velocity_amg_, velocity_settings);
  bool velocity_converged = true;
  int most_velocity_iterations = 0;
  const auto copy_component = [&](const std::vector<double>& field, std::size_t d) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      component_[i] = field[dim * i + d];
    }
  };
  for (std::size_t d = 0; d < dim; ++d) {
    copy_component(velocity_, d);
    auto result = numerics::bicgstab(momentum_matrix_, std::span<const double>(&rhs_[d * n], n), component_,
                                     velocity_settings, krylov_);
    if (!result.converged && velocity_amg && !velocity_hierarchy_fresh) {
      // A hierarchy kept from earlier steps no longer fits the matrix: rebuild it, solve again.
      velocity_amg_.setup(momentum_matrix_);
      velocity_hierarchy_fresh = true;
      ++stats.repeated_solves;
      copy_component(velocity_, d);
      stats.velocity_iterations += result.iterations;
      result = numerics::bicgstab(momentum_matrix_, std::span<const double>(&rhs_[d * n], n), component_,
                                  velocity_settings, krylov_);
    }
    most_velocity_iterations = std::max(most_velocity_iterations, result.iterations);
    stats.velocity_iterations += result.iterations;
    stats.velocity_residual = std::max(stats.velocity_residual, result.relative_residual);
    velocity_converged = velocity_converged && result.converged;
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      new_velocity_[dim * i + d] = component_[i];
    }
  }
  if (velocity_amg) velocity_amg_.record_iterations(most_velocity_iterations);
  return velocity_converged;
}

// 4. PPE (eq. 17) for φ = p_n − p_{n−1} into increment_.
numerics::KrylovResult FreeSurfaceSolver::solve_pressure(StepStats& stats) {
  LinearSolves& solves = solves_;
  const auto dim = static_cast<std::size_t>(dimension());
  const std::size_t n = kinds_.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  const double dt = params_.time_step, rho = params_.density;
  const std::vector<double>& g = params_.gravity;
  const double g_norm = norm_of(g);
  const double sqrt_n = std::sqrt(static_cast<double>(n));
  const numerics::NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  divergence_.resize(n);
  divergence(nb, ops, new_velocity_, divergence_);
  pressure_matrix_.pattern = &nb;
  pressure_matrix_.diagonal.resize(n);
  pressure_matrix_.off_diagonal.resize(nb.pair_count());
  rhs_.resize(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const std::size_t begin = nb.offsets[i], end = nb.offsets[i + 1];
    double sum = 0;
    switch (kinds_[i]) {
      case NodeKind::interior:
        for (std::size_t k = begin; k < end; ++k) {
          pressure_matrix_.off_diagonal[k] = ops.laplacian[k];
          sum += ops.laplacian[k];
        }
        pressure_matrix_.diagonal[i] = -sum;
        rhs_[i] = rho / dt * divergence_[i];
        break;
      case NodeKind::wall:
      case NodeKind::corner: {
        // Wall pressure extrapolated from the fluid (eq. 12 with the hydrostatic offset):
        //   p_w = Σ_j W_wj (p_j + ρ g·(x_w − x_j)) / Σ_j W_wj over fluid neighbours j,
        // which gives n·∇p = ρ n·g at rest (eq. 17's Neumann condition) and, unlike a Neumann
        // row through the wall node's own gradient, has only positive couplings. As a row for φ:
        //   φ_w − Σ w_j φ_j = Σ w_j (p_j + ρ g·(x_w − x_j)) − p_w.
        // A wall node that sees only surface nodes stands above the fluid: p = p_atm there (the
        // hydrostatic extrapolation would give suction that pulls the fluid up the wall), unless
        // DryWalls::extrapolate keeps the extrapolation as the hydrostatic field's extension.
        double wsum = 0;
        for (std::size_t k = begin; k < end; ++k) {
          const NodeKind kj = kinds_[nb.indices[k]];
          if (kj == NodeKind::interior || kj == NodeKind::surface) wsum += ops.weights[k];
        }
        if (dry_wall_[i] && params_.dry_walls != DryWalls::extrapolate) wsum = 0;
        double source = 0;
        for (std::size_t k = begin; k < end; ++k) {
          const std::size_t j = nb.indices[k];
          const NodeKind kj = kinds_[j];
          const double w =
              (wsum > 0 && (kj == NodeKind::interior || kj == NodeKind::surface)) ? ops.weights[k] / wsum : 0.0;
          pressure_matrix_.off_diagonal[k] = -w;
          if (w == 0) continue;
          double hydrostatic = 0;
          for (std::size_t d = 0; d < dim; ++d)
            hydrostatic += rho * g[d] * (positions_[dim * i + d] - positions_[dim * j + d]);
          source += w * (previous_pressure_[j] + hydrostatic);
        }
        pressure_matrix_.diagonal[i] = 1.0;
        rhs_[i] = source - previous_pressure_[i];
        break;
      }
      default:  // surface, splash, idle wall: p_n = p_atm = 0 (surface: 2μ n·E·n, surface_normal_stress)
        for (std::size_t k = begin; k < end; ++k) pressure_matrix_.off_diagonal[k] = 0.0;
        pressure_matrix_.diagonal[i] = 1.0;
        rhs_[i] = surface_pressure_[i] - previous_pressure_[i];
    }
  }
  increment_.assign(n, 0.0);
  numerics::KrylovSettings& pressure_settings = solves.pressure;
  pressure_settings = {params_.pressure_tolerance,
                       params_.pressure_tolerance * rho * std::max(g_norm, 1e-12) / params_.spacing * sqrt_n,
                       params_.max_iterations,
                       {}};
  const bool pressure_amg = params_.pressure_preconditioner == Preconditioner::amg;
  const bool pressure_hierarchy_fresh =
      set_preconditioner(params_.pressure_preconditioner, dimension(), pressure_matrix_, solves.pressure_lu,
                         pressure_amg_, pressure_settings);
  auto pressure_result = numerics::bicgstab(pressure_matrix_, rhs_, increment_, pressure_settings, krylov_);
  int fresh_hierarchy_iterations = pressure_hierarchy_fresh ? pressure_result.iterations : 0;
  const auto repeat_pressure_solve = [&] {
    ++stats.repeated_solves;
    increment_.assign(n, 0.0);
    const int failed_iterations = pressure_result.iterations;
    pressure_result = numerics::bicgstab(pressure_matrix_, rhs_, increment_, pressure_settings, krylov_);
    pressure_result.iterations += failed_iterations;
  };
  if (!pressure_result.converged && pressure_amg && !pressure_hierarchy_fresh) {
    // As for the velocity: the kept hierarchy was built for an older cloud and classification.
    pressure_amg_.setup(pressure_matrix_);
    const int failed_iterations = pressure_result.iterations;
    repeat_pressure_solve();
    fresh_hierarchy_iterations = pressure_result.iterations - failed_iterations;
  }
  if (!pressure_result.converged && !(pressure_result.relative_residual < 1e3 * params_.pressure_tolerance) &&
      dimension() == 2 && params_.pressure_preconditioner != Preconditioner::sparse_lu &&
      solves.pressure_direct.factorise(pressure_matrix_)) {
    // Last resort in 2D: the exact factors as the preconditioner (seconds at 200 000 nodes).
    pressure_settings.preconditioner = solves.pressure_direct.as_preconditioner();
    ++stats.repeated_with_lu;
    repeat_pressure_solve();
  }
  if (pressure_amg) pressure_amg_.record_iterations(pressure_result.iterations);
  if (pressure_amg && params_.pressure_amg_switch_iterations > 0 && pressure_amg_.smoothed() &&
      stats.repeated_with_lu == 0 && fresh_hierarchy_iterations > params_.pressure_amg_switch_iterations) {
    pressure_amg_.use_plain_aggregation();
    stats.pressure_amg_to_plain = fresh_hierarchy_iterations;
  }
  stats.pressure_iterations = pressure_result.iterations;
  stats.pressure_residual = pressure_result.relative_residual;
  if (params_.stability_probe_iterations > 0) probe_step_map(solves.velocity, solves.pressure, stats);
  solves_ = LinearSolves{};  // the factors are this step's
  return pressure_result;
}

// The pressure n into new_pressure_ and the projection of new_velocity_.
Solver::Correction FreeSurfaceSolver::correct_velocity() {
  const auto dim = static_cast<std::size_t>(dimension());
  const std::size_t n = kinds_.size();
  const double dt = params_.time_step, rho = params_.density;
  const numerics::NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  // No tension: p_n = max(p_{n−1} + φ, p_atm). A free-surface fluid cannot pull on the void, and
  // without the clip the suction at a stretching toe (ρ/δt ∇·u* > 0 on a torn cloud) grew without
  // bound; the velocity is corrected with the increment actually applied.
  const auto count = static_cast<std::ptrdiff_t>(n);
  new_pressure_.resize(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    new_pressure_[i] = std::max(previous_pressure_[i] + increment_[i], 0.0);
  }
  if (params_.dry_walls == DryWalls::extrapolate) {
    // Wall pressures unclipped, as the PPE's wall rows but from the clipped fluid pressures: they
    // only extend the fluid's field into its gradients (−ρg·height above the surface). Taken from
    // the unclipped fluid values they would carry the suction the clip removes: the water dam
    // break's back wall then runs away to −1.8·10⁴ Pa within 0.024 s.
    const auto fluid = [&](std::size_t j) { return is_continuum(j); };
    // Each wall node reads fluid values only, so the nodes are independent.
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      if (kinds_[i] == NodeKind::wall || kinds_[i] == NodeKind::corner)
        new_pressure_[i] = extrapolated_pressure(i, new_pressure_, fluid, false);
    }
  }
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    increment_[i] = new_pressure_[i] - previous_pressure_[i];
  }
  increment_gradient_.resize(dim * n);
  gradient(nb, ops, increment_, increment_gradient_);
  // The correction per node in parallel; the fastest continuum node per thread block, combined
  // in block order (the first of equal speeds, as the serial loop): splash nodes fall
  // ballistically (no operators) and do not limit the Courant number.
  const int threads = omp_get_max_threads();
  std::vector<double> block_speed2(static_cast<std::size_t>(threads), 0.0);
  std::vector<std::size_t> block_fastest(static_cast<std::size_t>(threads), 0);
  std::vector<char> block_finite(static_cast<std::size_t>(threads), 1);
  numerics::for_blocks(n, [&](std::size_t begin, std::size_t end) {
    const auto t = static_cast<std::size_t>(omp_get_thread_num());
    double most = 0;
    std::size_t fastest = 0;
    bool finite = true;
    for (std::size_t i = begin; i < end; ++i) {
      if (is_continuum(i))
        for (std::size_t d = 0; d < dim; ++d) new_velocity_[dim * i + d] -= dt / rho * increment_gradient_[dim * i + d];
      double speed2 = 0;
      for (std::size_t d = 0; d < dim; ++d) {
        speed2 += new_velocity_[dim * i + d] * new_velocity_[dim * i + d];
        if (!std::isfinite(new_velocity_[dim * i + d])) finite = false;
      }
      if (!std::isfinite(new_pressure_[i])) finite = false;
      if (is_continuum(i) && speed2 > most) {
        most = speed2;
        fastest = i;
      }
    }
    block_speed2[t] = most;
    block_fastest[t] = fastest;
    block_finite[t] = finite ? 1 : 0;
  });
  Correction c;
  double max_speed_squared = 0;
  for (std::size_t t = 0; t < block_speed2.size(); ++t) {
    if (!block_finite[t]) c.finite = false;
    if (block_speed2[t] > max_speed_squared) {
      max_speed_squared = block_speed2[t];
      c.fastest = block_fastest[t];
    }
  }
  c.max_speed = std::sqrt(max_speed_squared);
  if (probe_divergence_) {  // divergence_ still holds ⟨∇·u*⟩ (solve_pressure)
    std::vector<double> projected(n);
    divergence(nb, ops, new_velocity_, projected);
    bulk_divergence_predicted_ = bulk_mean([&](std::size_t i) { return divergence_[i]; }, 0.0);
    bulk_divergence_ = bulk_mean([&](std::size_t i) { return projected[i]; }, 0.0);
  }
  return c;
}

// 5. (the checks are Solver's) Why a pressure solve may have failed: the repeated solves and
// whether a block of nodes reaches no free-surface node.
std::string FreeSurfaceSolver::pressure_failure(const StepStats& stats) const {
  const numerics::FloatingGroups floating = numerics::floating_groups(pressure_matrix_);
  const std::size_t at = floating.largest_member;
  return fmt::format(
      "({} repeated solve(s)); {}", stats.repeated_solves,
      floating.groups == 0
          ? std::string("every node reaches a free-surface node through the pressure matrix")
          : fmt::format("{} node group(s), {} nodes, reach no free-surface node (a singular Neumann block); the "
                        "largest, {} nodes, includes {} node at {}",
                        floating.groups, floating.nodes, floating.largest, a_kind(kinds_[at]), place(at)));
}

// 6. Commit, advect (eq. 20), move the walls, keep fluid off the boundaries.
void FreeSurfaceSolver::commit_and_advect(double next_time) {
  const auto dim = static_cast<std::size_t>(dimension());
  const auto count = static_cast<std::ptrdiff_t>(kinds_.size());
  const double dt = params_.time_step;
  pressure_.swap(new_pressure_);
  velocity_gradient_of(new_velocity_, velocity_gradient_);  // ∇u_n, to carry velocities along PBD shifts
  const double older = first_step_ ? 0.0 : 0.5;
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (is_fluid(i)) {
      for (std::size_t d = 0; d < dim; ++d)
        positions_[dim * i + d] += ((1.0 + older) * new_velocity_[dim * i + d] - older * velocity_[dim * i + d]) * dt;
      keep_off_boundaries(i, next_time, new_velocity_);
    } else if (boundary_of_[i] >= 0) {  // wall nodes move with their boundary (slip or not)
      double v[3] = {0, 0, 0};
      boundaries_[static_cast<std::size_t>(boundary_of_[i])]->velocity(next_time, std::span<double>(v, dim));
      for (std::size_t d = 0; d < dim; ++d) positions_[dim * i + d] += v[d] * dt;
    }
  }
  previous_velocity_.swap(velocity_);
  velocity_.swap(new_velocity_);
  first_step_ = false;
}

// 7. The neighbour search on the advected cloud and the volume-keeping PBD.
void FreeSurfaceSolver::reorder(StepStats& stats) {
  auto t0 = Clock::now();
  rebuild_neighbours();
  times_.neighbours += seconds_since(t0);

  t0 = Clock::now();
  apply_pbd(velocity_gradient_);
  stats.max_pbd_shift = largest_pbd_shift();
  if (probe_divergence_) {  // measured on the cloud before advection (solve_pressure, correct_velocity)
    stats.bulk_divergence_predicted = bulk_divergence_predicted_;
    stats.bulk_divergence = bulk_divergence_;
  }
  times_.reordering += seconds_since(t0);
}

// 7. (after reorder) the largest PBD displacement of this step, in units of Δ.
double FreeSurfaceSolver::largest_pbd_shift() const {
  const auto dim = static_cast<std::size_t>(dimension());
  const std::size_t n = kinds_.size();
  double max_shift = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double s2 = 0;
    for (std::size_t d = 0; d < dim; ++d) s2 += shift_[dim * i + d] * shift_[dim * i + d];
    max_shift = std::max(max_shift, s2);
  }
  return std::sqrt(max_shift) / params_.spacing;
}

}  // namespace rheosim::ldd
