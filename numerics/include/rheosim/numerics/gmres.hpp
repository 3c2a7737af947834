#pragma once
// GMRES (Saad & Schultz 1986) without restart for M x = b with M given as a callable
// (Eigen::VectorXd apply(column)): modified Gram–Schmidt Arnoldi and Givens rotations. The
// swirl solver's Newton step uses it, with M the exact Jacobian (by finite differences)
// preconditioned by the LU of the linearised system.
#include <cmath>

#include <Eigen/Dense>

namespace rheosim::numerics {

// At most `max_iterations` Krylov vectors; stops when ‖b − M x‖₂ <= tolerance ‖b‖₂ (or on a
// lucky breakdown). Starts from x = 0 and returns x.
template <class Apply>
[[nodiscard]] Eigen::VectorXd gmres(const Apply& apply, const Eigen::VectorXd& b, double tolerance,
                                    int max_iterations) {
  const Eigen::Index n = b.size();
  const double beta = b.norm();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  if (!(beta > 0)) return x;
  const auto m = static_cast<Eigen::Index>(max_iterations);
  Eigen::MatrixXd v(n, m + 1), h = Eigen::MatrixXd::Zero(m + 1, m);
  Eigen::VectorXd cs = Eigen::VectorXd::Zero(m), sn = Eigen::VectorXd::Zero(m), g = Eigen::VectorXd::Zero(m + 1);
  v.col(0) = b / beta;
  g[0] = beta;
  Eigen::Index used = 0;
  for (Eigen::Index j = 0; j < m; ++j) {
    Eigen::VectorXd w = apply(v.col(j));
    for (Eigen::Index i = 0; i <= j; ++i) {  // modified Gram–Schmidt
      h(i, j) = w.dot(v.col(i));
      w -= h(i, j) * v.col(i);
    }
    h(j + 1, j) = w.norm();
    for (Eigen::Index i = 0; i < j; ++i) {  // earlier Givens rotations
      const double a = h(i, j), c = h(i + 1, j);
      h(i, j) = cs[i] * a + sn[i] * c;
      h(i + 1, j) = -sn[i] * a + cs[i] * c;
    }
    const double denom = std::hypot(h(j, j), h(j + 1, j));
    cs[j] = denom > 0 ? h(j, j) / denom : 1.0;
    sn[j] = denom > 0 ? h(j + 1, j) / denom : 0.0;
    const double hj1 = h(j + 1, j);
    h(j, j) = cs[j] * h(j, j) + sn[j] * hj1;
    h(j + 1, j) = 0;
    g[j + 1] = -sn[j] * g[j];
    g[j] = cs[j] * g[j];
    used = j + 1;
    if (std::abs(g[j + 1]) <= tolerance * beta || !(hj1 > 1e-300 * beta)) break;
    v.col(j + 1) = w / hj1;
  }
  const Eigen::VectorXd y = h.topLeftCorner(used, used).triangularView<Eigen::Upper>().solve(g.head(used));
  x = v.leftCols(used) * y;
  return x;
}

}  // namespace rheosim::numerics
