#include "rheosim/ldd/lattice_interpolation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "rheosim/ldd/operators.hpp"

namespace rheosim::ldd {

namespace {

// Below this λ_min/λ_max the normal matrix of a fit is treated as singular.
constexpr double min_fit_rcond = 1e-8;

bool is_fluid(NodeKind k) { return k == NodeKind::interior; }

// Solves the weighted least-squares fit of `Size` terms at one node in coordinates scaled by h
// (entries O(1)); writes coefficients for the first Size terms of every pair. False if singular.
template <int Size>
bool fit_node(std::span<const double> positions, const numerics::NeighbourList& nb, std::size_t i, double h,
              std::span<double> coefficients) {
  using Mat = Eigen::Matrix<double, Size, Size>;
  using Vec = Eigen::Matrix<double, Size, 1>;
  const auto scaled_basis = [&](std::size_t j) {
    const auto b =
        taylor_basis((positions[2 * j] - positions[2 * i]) / h, (positions[2 * j + 1] - positions[2 * i + 1]) / h);
    Vec v;
    for (int t = 0; t < Size; ++t) v[t] = b[static_cast<std::size_t>(t)];
    return v;
  };
  Mat normal = Mat::Zero();
  for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
    const std::size_t j = nb.indices[k];
    const double w =
        weight(std::hypot(positions[2 * j] - positions[2 * i], positions[2 * j + 1] - positions[2 * i + 1]), h);
    if (w <= 0) continue;
    const Vec b = scaled_basis(j);
    normal += w * b * b.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Mat> eigen(normal);
  const auto& lambda = eigen.eigenvalues();
  if (!(lambda[Size - 1] > 0) || lambda[0] < min_fit_rcond * lambda[Size - 1]) return false;
  const Mat inverse = eigen.eigenvectors() * lambda.cwiseInverse().asDiagonal() * eigen.eigenvectors().transpose();
  for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
    const std::size_t j = nb.indices[k];
    const double w =
        weight(std::hypot(positions[2 * j] - positions[2 * i], positions[2 * j + 1] - positions[2 * i + 1]), h);
    if (w <= 0) continue;
    const Vec c = inverse * (w * scaled_basis(j));
    for (int t = 0; t < Size; ++t) {
      const double unscale = t < 2 ? h : h * h;  // first / second derivatives in scaled coordinates
      coefficients[QuadraticFit::terms * k + static_cast<std::size_t>(t)] = c[t] / unscale;
    }
  }
  return true;
}

}  // namespace

std::array<double, QuadraticFit::terms> taylor_basis(double rx, double ry) {
  return {rx, ry, 0.5 * rx * rx, rx * ry, 0.5 * ry * ry};
}

QuadraticFit::QuadraticFit(std::span<const double> positions, const numerics::NeighbourList& neighbours,
                           double support_radius)
    : support_radius_(support_radius),
      coefficients_(terms * neighbours.pair_count(), 0.0),
      linear_only_(neighbours.node_count(), 0) {
  const auto count = static_cast<std::ptrdiff_t>(neighbours.node_count());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (fit_node<5>(positions, neighbours, i, support_radius, coefficients_)) continue;
    linear_only_[i] = 1;
    std::fill(coefficients_.begin() + static_cast<std::ptrdiff_t>(terms * neighbours.offsets[i]),
              coefficients_.begin() + static_cast<std::ptrdiff_t>(terms * neighbours.offsets[i + 1]), 0.0);
    if (!fit_node<2>(positions, neighbours, i, support_radius, coefficients_))
      std::fill(coefficients_.begin() + static_cast<std::ptrdiff_t>(terms * neighbours.offsets[i]),
                coefficients_.begin() + static_cast<std::ptrdiff_t>(terms * neighbours.offsets[i + 1]), 0.0);
  }
}

std::array<double, QuadraticFit::terms> QuadraticFit::derivatives(const numerics::NeighbourList& neighbours,
                                                                  std::span<const double> field, std::size_t stride,
                                                                  std::size_t component, std::size_t node) const {
  std::array<double, terms> d{};
  const double own = field[stride * node + component];
  for (std::size_t k = neighbours.offsets[node]; k < neighbours.offsets[node + 1]; ++k) {
    const double difference = field[stride * neighbours.indices[k] + component] - own;
    for (std::size_t t = 0; t < terms; ++t) d[t] += coefficients_[terms * k + t] * difference;
  }
  return d;
}

std::size_t QuadraticFit::linear_only_count() const {
  return static_cast<std::size_t>(std::count(linear_only_.begin(), linear_only_.end(), std::uint8_t{1}));
}

void return_to_lattice(std::span<const double> positions, std::span<const NodeKind> kinds,
                       const numerics::NeighbourList& nb, const QuadraticFit& fit, std::span<const double> velocity,
                       std::span<const double> advection, double time_step, bool limit, std::vector<double>& out) {
  out.resize(velocity.size());
  const auto count = static_cast<std::ptrdiff_t>(kinds.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (!is_fluid(kinds[i])) {
      out[2 * i] = velocity[2 * i];
      out[2 * i + 1] = velocity[2 * i + 1];
      continue;
    }
    // Departure offset by the midpoint rule: r = δt a(X_i − ½ δt a_i) ≈ δt (a_i − ½ δt (a·∇)a_i).
    const auto ax = fit.derivatives(nb, advection, 2, 0, i), ay = fit.derivatives(nb, advection, 2, 1, i);
    const double a0 = advection[2 * i], a1 = advection[2 * i + 1];
    const double rx = time_step * (a0 - 0.5 * time_step * (ax[0] * a0 + ax[1] * a1));
    const double ry = time_step * (a1 - 0.5 * time_step * (ay[0] * a0 + ay[1] * a1));
    const auto b = taylor_basis(-rx, -ry);
    for (std::size_t c = 0; c < 2; ++c) {
      const auto d = fit.derivatives(nb, velocity, 2, c, i);
      double value = velocity[2 * i + c];
      for (std::size_t t = 0; t < QuadraticFit::terms; ++t) value += d[t] * b[t];
      if (limit) {
        double low = velocity[2 * i + c], high = low;
        for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
          const std::size_t j = nb.indices[k];
          const double upwind =
              (positions[2 * j] - positions[2 * i]) * rx + (positions[2 * j + 1] - positions[2 * i + 1]) * ry;
          if (!(upwind < 0) || !(nb.distances[k] < fit.support_radius())) continue;
          low = std::min(low, velocity[2 * j + c]);
          high = std::max(high, velocity[2 * j + c]);
        }
        value = std::clamp(value, low, high);
      }
      out[2 * i + c] = value;
    }
  }
}

}  // namespace rheosim::ldd
