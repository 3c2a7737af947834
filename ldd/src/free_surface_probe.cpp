// Diagnostic: the growth per step of the linearised free-surface step map (free_surface.hpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "rheosim/ldd/free_surface.hpp"

namespace rheosim::ldd {

// The step is linear in (u_{n−1}, p_{n−1}) once its matrices are fixed (operators,
// classification, μ): u* = M⁻¹(ρu − δt⟨∇p⟩), φ = P⁻¹ rhs(u*, p), u' = u* − δt/ρ ⟨∇φ⟩, p' = p + φ,
// with wall and splash rows homogeneous. Power iteration from a pseudo-random start finds its
// largest growth factor; pressure is measured in velocity units δt p/(ρΔ).
void FreeSurfaceSolver::probe_step_map(const numerics::KrylovSettings& velocity_settings,
                                       const numerics::KrylovSettings& pressure_settings, StepStats& stats) {
  const auto dim = static_cast<std::size_t>(dimension());
  const std::size_t n = kinds_.size();
  const numerics::NeighbourList& nb = neighbours_;
  const Operators& ops = operators_;
  const double dt = params_.time_step, rho = params_.density;
  const double pressure_scale = dt / (rho * params_.spacing);
  std::vector<double> u(dim * n, 0.0), p(n, 0.0), predicted(dim * n), rhs(n), component(n), phi(n), grad(dim * n),
      div(n);
  std::uint64_t state = 0x9E3779B97F4A7C15ULL;
  const auto random = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_continuum(i)) continue;
    for (std::size_t d = 0; d < dim; ++d) u[dim * i + d] = random();
    if (kinds_[i] == NodeKind::interior) p[i] = random() / pressure_scale;
  }
  const auto normalise = [&] {
    double sum = 0;
    for (double v : u) sum += v * v;
    for (double v : p) sum += pressure_scale * pressure_scale * v * v;
    const double norm = std::sqrt(sum);
    for (double& v : u) v /= norm;
    for (double& v : p) v /= norm;
    return norm;
  };
  normalise();
  numerics::KrylovSettings velocity = velocity_settings, pressure = pressure_settings;
  velocity.relative_tolerance = pressure.relative_tolerance = 1e-10;
  velocity.absolute_tolerance = pressure.absolute_tolerance = 0.0;
  const int iterations = params_.stability_probe_iterations;
  double log_growth = 0;
  int counted = 0;
  for (int it = 0; it < iterations; ++it) {
    gradient(nb, ops, p, grad);
    for (std::size_t d = 0; d < dim; ++d) {
      for (std::size_t i = 0; i < n; ++i) {
        rhs[i] = is_continuum(i) ? rho * u[dim * i + d] - dt * grad[dim * i + d] : 0.0;
        component[i] = u[dim * i + d];
      }
      numerics::bicgstab(momentum_matrix_, rhs, component, velocity, krylov_);
      for (std::size_t i = 0; i < n; ++i) predicted[dim * i + d] = is_continuum(i) ? component[i] : 0.0;
    }
    divergence(nb, ops, predicted, div);
    for (std::size_t i = 0; i < n; ++i) {
      if (kinds_[i] == NodeKind::interior) {
        rhs[i] = rho / dt * div[i];
      } else if (kinds_[i] == NodeKind::wall || kinds_[i] == NodeKind::corner) {
        double source = 0;  // Σ w_j p_j of the wall row (its off-diagonal is −w_j)
        for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k)
          source -= pressure_matrix_.off_diagonal[k] * p[nb.indices[k]];
        rhs[i] = source - p[i];
      } else {
        rhs[i] = -p[i];
      }
    }
    std::fill(phi.begin(), phi.end(), 0.0);
    numerics::bicgstab(pressure_matrix_, rhs, phi, pressure, krylov_);
    gradient(nb, ops, phi, grad);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t d = 0; d < dim; ++d)
        u[dim * i + d] = is_continuum(i) ? predicted[dim * i + d] - dt / rho * grad[dim * i + d] : 0.0;
      p[i] += phi[i];
    }
    const double growth = normalise();
    if (2 * it >= iterations) {
      log_growth += std::log(growth);
      ++counted;
    }
  }
  stats.step_map_growth = std::exp(log_growth / std::max(counted, 1));
  double largest = -1;
  for (std::size_t i = 0; i < n; ++i) {
    double a = pressure_scale * pressure_scale * p[i] * p[i];
    for (std::size_t d = 0; d < dim; ++d) a += u[dim * i + d] * u[dim * i + d];
    if (a > largest) {
      largest = a;
      stats.step_map_node = i;
    }
  }
}

}  // namespace rheosim::ldd
