#include "rheosim/ldd/operators.hpp"

#include <fmt/format.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "rheosim/numerics/row_blocks.hpp"

namespace rheosim::ldd {
namespace {

// Below this fraction of Σ W r² the Laplacian's offset-corrected denominator is treated as
// cancelled and the offset correction is dropped for the node.
constexpr double min_laplacian_denominator_fraction = 0.05;

// (Σ W x xᵀ)⁻¹ (eq. 13); near-singular (λ_min/λ_max < rcond): the pseudo-inverse on the
// well-determined directions only, so a gradient stays exact along the directions the neighbours
// span and is zero across them.
template <int D>
struct GuardedInverse {
  Eigen::Matrix<double, D, D> inverse;
  double conditioning = 0;  // λ_min/λ_max (0 for a zero matrix)
  bool pseudo = false;      // pseudo-inverted
};

template <int D>
GuardedInverse<D> guarded_inverse(const Eigen::Matrix<double, D, D>& moment, double rcond) {
  using Vec = Eigen::Matrix<double, D, 1>;
  // Eigenvalues first, in closed form (they only decide the guard and the conditioning); the
  // eigenvectors only for the (few) near-singular moments.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> values;
  values.computeDirect(moment, Eigen::EigenvaluesOnly);
  const double lambda_max = values.eigenvalues().maxCoeff();
  const double lambda_min = values.eigenvalues().minCoeff();
  GuardedInverse<D> r;
  r.pseudo = !(lambda_max > 0 && lambda_min >= rcond * lambda_max);
  r.conditioning = lambda_max > 0 ? std::max(lambda_min, 0.0) / lambda_max : 0.0;
  if (!r.pseudo) {
    r.inverse = moment.inverse();
    return r;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> eigen(moment);
  Vec inverse_eigenvalues = Vec::Zero();
  for (int d = 0; d < D; ++d)
    if (lambda_max > 0 && eigen.eigenvalues()[d] >= rcond * lambda_max)
      inverse_eigenvalues[d] = 1.0 / eigen.eigenvalues()[d];
  r.inverse = eigen.eigenvectors() * inverse_eigenvalues.asDiagonal() * eigen.eigenvectors().transpose();
  return r;
}

template <int D>
void build_node(std::size_t i, std::span<const double> x, const numerics::NeighbourList& nb,
                const OperatorSettings& settings, Operators& ops) {
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  const double h = settings.support_radius;
  const Vec xi = Eigen::Map<const Vec>(&x[i * D]);
  const std::size_t begin = nb.offsets[i];
  const std::size_t end = nb.offsets[i + 1];

  Mat moment = Mat::Zero();
  Vec offset = Vec::Zero();
  double weight_sum = 0;
  for (std::size_t k = begin; k < end; ++k) {
    const Vec xij = Eigen::Map<const Vec>(&x[nb.indices[k] * D]) - xi;
    const double w = weight(xij.norm(), h);
    ops.weights[k] = w;
    moment.noalias() += w * xij * xij.transpose();  // eq. 13 (before inversion)
    offset += w * xij;                              // eq. 16
    weight_sum += w;
  }
  std::uint8_t guard = 0;
  const GuardedInverse<D> moment_inverse = guarded_inverse<D>(moment, settings.min_moment_rcond);
  const Mat& b = moment_inverse.inverse;  // eq. 13
  if (moment_inverse.pseudo) guard |= 1U;
  const Vec b_offset = b * offset;
  // Gradient coefficients W_ij G_i (x_ij − c_i): eq. 14 about the node itself (c_i = 0, G_i = B_i)
  // or, centred, the least-squares plane through the neighbours with a free intercept (c_i their
  // weighted centroid o_i/Σ W_ij, G_i the inverse of the moment about it), whose coefficients sum
  // to zero: the node's own value does not enter its gradient.
  Vec centre = Vec::Zero();
  Mat gradient_b = b;
  if (settings.centred_gradient && weight_sum > 0) {
    centre = offset / weight_sum;
    const GuardedInverse<D> centred =
        guarded_inverse<D>(moment - weight_sum * centre * centre.transpose(), settings.min_moment_rcond);
    gradient_b = centred.inverse;
    if (centred.pseudo) guard |= 1U;
  }

  double denominator = 0, plain_denominator = 0;
  for (std::size_t k = begin; k < end; ++k) {
    const Vec xij = Eigen::Map<const Vec>(&x[nb.indices[k] * D]) - xi;
    const double w = ops.weights[k];
    Eigen::Map<Vec>(&ops.gradient[k * D]) = w * (gradient_b * (xij - centre));  // eq. 14 coefficient
    const double r2 = xij.squaredNorm();
    denominator += w * r2 * (1.0 - xij.dot(b_offset));
    plain_denominator += w * r2;
  }
  const bool use_offset = denominator > min_laplacian_denominator_fraction * plain_denominator;
  if (!use_offset && plain_denominator > 0) guard |= 2U;
  const double scale_denominator = use_offset ? denominator : plain_denominator;
  const double scale = scale_denominator > 0 ? 2.0 * D / scale_denominator : 0.0;
  for (std::size_t k = begin; k < end; ++k) {
    const Vec xij = Eigen::Map<const Vec>(&x[nb.indices[k] * D]) - xi;
    const double factor = use_offset ? 1.0 - xij.dot(b_offset) : 1.0;
    ops.laplacian[k] = scale * ops.weights[k] * factor;  // eq. 15 coefficient of f_ij
  }
  Eigen::Map<Vec>(&ops.offset[i * D]) = offset;
  ops.guarded[i] = guard;
  ops.conditioning[i] = moment_inverse.conditioning;  // of eq. 13's moment (free-surface detection reads it)
}

// Gradient coefficients of node i from its pair weights, neighbours j with skip[j] != 0 left out
// (skip empty: none), about the node (eq. 14) or, centred, about the kept neighbours' centroid.
template <int D>
void rebuild_node_gradient(std::size_t i, std::span<const double> x, const numerics::NeighbourList& nb,
                           const OperatorSettings& settings, std::span<const std::uint8_t> skip, Operators& ops) {
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  const Vec xi = Eigen::Map<const Vec>(&x[i * D]);
  const auto kept_weight = [&](std::size_t k) { return !skip.empty() && skip[nb.indices[k]] ? 0.0 : ops.weights[k]; };
  Mat moment = Mat::Zero();
  Vec offset = Vec::Zero();
  double weight_sum = 0;
  for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
    const Vec xij = Eigen::Map<const Vec>(&x[nb.indices[k] * D]) - xi;
    const double w = kept_weight(k);
    moment.noalias() += w * xij * xij.transpose();  // eq. 13
    offset += w * xij;
    weight_sum += w;
  }
  Vec centre = Vec::Zero();
  if (settings.centred_gradient && weight_sum > 0) {
    centre = offset / weight_sum;
    moment -= weight_sum * centre * centre.transpose();
  }
  const GuardedInverse<D> inverse = guarded_inverse<D>(moment, settings.min_moment_rcond);
  const Mat& b = inverse.inverse;
  for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
    const Vec xij = Eigen::Map<const Vec>(&x[nb.indices[k] * D]) - xi;
    Eigen::Map<Vec>(&ops.gradient[k * D]) = kept_weight(k) * (b * (xij - centre));  // eq. 14
  }
  // Bit 0 now tells whether this gradient's moment was pseudo-inverted.
  ops.guarded[i] = static_cast<std::uint8_t>((ops.guarded[i] & ~1U) | (inverse.pseudo ? 1U : 0U));
}

void check_sizes(const numerics::NeighbourList& nb, const Operators& ops, std::size_t f_size, std::size_t f_stride,
                 std::size_t out_size, std::size_t out_stride, const char* what) {
  const std::size_t n = nb.node_count();
  if (ops.node_count() != n || f_size != n * f_stride || out_size != n * out_stride)
    throw std::invalid_argument(fmt::format("{}: sizes do not match the {} nodes of the neighbour list", what, n));
}

}  // namespace

std::size_t Operators::guarded_count() const {
  return static_cast<std::size_t>(std::count_if(guarded.begin(), guarded.end(), [](std::uint8_t g) { return g != 0; }));
}

Operators build_operators(std::span<const double> positions, int dimension, const numerics::NeighbourList& neighbours,
                          const OperatorSettings& settings) {
  Operators ops;
  build_operators(positions, dimension, neighbours, settings, ops);
  return ops;
}

void build_operators(std::span<const double> positions, int dimension, const numerics::NeighbourList& neighbours,
                     const OperatorSettings& settings, Operators& ops) {
  if (dimension != 2 && dimension != 3)
    throw std::invalid_argument(fmt::format("build_operators: dimension = {}, expected 2 or 3", dimension));
  if (!(settings.support_radius > 0))
    throw std::invalid_argument(fmt::format("build_operators: support radius {} is not > 0", settings.support_radius));
  const auto dim = static_cast<std::size_t>(dimension);
  const std::size_t n = neighbours.node_count();
  if (positions.size() != n * dim)
    throw std::invalid_argument(
        fmt::format("build_operators: {} coordinates for {} nodes in {}D", positions.size(), n, dimension));
  // Every entry is written below (build_node), so resizing without clearing is enough.
  ops.dimension = dimension;
  ops.weights.resize(neighbours.pair_count());
  ops.gradient.resize(neighbours.pair_count() * dim);
  ops.laplacian.resize(neighbours.pair_count());
  ops.offset.resize(n * dim);
  ops.guarded.resize(n);
  ops.conditioning.resize(n);
  numerics::for_balanced_rows(neighbours.offsets, [&](std::size_t i) {
    if (dimension == 2)
      build_node<2>(i, positions, neighbours, settings, ops);
    else
      build_node<3>(i, positions, neighbours, settings, ops);
  });
}

void rebuild_gradients(std::span<const double> positions, const numerics::NeighbourList& neighbours,
                       const OperatorSettings& settings, std::span<const std::size_t> nodes,
                       std::span<const std::uint8_t> skip, Operators& ops) {
  const auto dim = static_cast<std::size_t>(ops.dimension);
  check_sizes(neighbours, ops, positions.size(), dim, positions.size(), dim, "rebuild_gradients");
  if (!skip.empty() && skip.size() != neighbours.node_count())
    throw std::invalid_argument(
        fmt::format("rebuild_gradients: {} skip flags for {} nodes", skip.size(), neighbours.node_count()));
  const auto count = static_cast<std::ptrdiff_t>(nodes.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const std::size_t i = nodes[static_cast<std::size_t>(s)];
    if (dim == 2)
      rebuild_node_gradient<2>(i, positions, neighbours, settings, skip, ops);
    else
      rebuild_node_gradient<3>(i, positions, neighbours, settings, skip, ops);
  }
}

void gradient(const numerics::NeighbourList& nb, const Operators& ops, std::span<const double> f,
              std::span<double> out) {
  const auto dim = static_cast<std::size_t>(ops.dimension);
  check_sizes(nb, ops, f.size(), 1, out.size(), dim, "gradient");
  numerics::for_balanced_rows(nb.offsets, [&](std::size_t i) {
    double g[3] = {0, 0, 0};
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
      const double fij = f[nb.indices[k]] - f[i];
      for (std::size_t d = 0; d < dim; ++d) g[d] += ops.gradient[k * dim + d] * fij;
    }
    for (std::size_t d = 0; d < dim; ++d) out[i * dim + d] = g[d];
  });
}

void transposed_viscous_force(const numerics::NeighbourList& nb, const Operators& ops,
                              std::span<const double> viscosity, std::span<const double> velocity_gradient,
                              std::span<double> out) {
  const auto dim = static_cast<std::size_t>(ops.dimension);
  const std::size_t dd = dim * dim;
  check_sizes(nb, ops, viscosity.size(), 1, out.size(), dim, "transposed_viscous_force");
  check_sizes(nb, ops, velocity_gradient.size(), dd, out.size(), dim, "transposed_viscous_force");
  numerics::for_balanced_rows(nb.offsets, [&](std::size_t i) {
    double force[3] = {0, 0, 0};
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
      const std::size_t j = nb.indices[k];
      const double* grad_i = &velocity_gradient[dd * i];
      const double* grad_j = &velocity_gradient[dd * j];
      for (std::size_t a = 0; a < dim; ++a)
        for (std::size_t b = 0; b < dim; ++b)  // ∂_b of μ ∂u_b/∂x_a
          force[a] +=
              ops.gradient[k * dim + b] * (viscosity[j] * grad_j[b * dim + a] - viscosity[i] * grad_i[b * dim + a]);
    }
    for (std::size_t a = 0; a < dim; ++a) out[i * dim + a] = force[a];
  });
}

void divergence(const numerics::NeighbourList& nb, const Operators& ops, std::span<const double> v,
                std::span<double> out) {
  const auto dim = static_cast<std::size_t>(ops.dimension);
  check_sizes(nb, ops, v.size(), dim, out.size(), 1, "divergence");
  numerics::for_balanced_rows(nb.offsets, [&](std::size_t i) {
    double sum = 0;
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) {
      const std::size_t j = nb.indices[k];
      for (std::size_t d = 0; d < dim; ++d) sum += ops.gradient[k * dim + d] * (v[j * dim + d] - v[i * dim + d]);
    }
    out[i] = sum;
  });
}

void laplacian(const numerics::NeighbourList& nb, const Operators& ops, std::span<const double> f,
               std::span<double> out) {
  check_sizes(nb, ops, f.size(), 1, out.size(), 1, "laplacian");
  numerics::for_balanced_rows(nb.offsets, [&](std::size_t i) {
    double sum = 0;
    for (std::size_t k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k) sum += ops.laplacian[k] * (f[nb.indices[k]] - f[i]);
    out[i] = sum;
  });
}

}  // namespace rheosim::ldd
