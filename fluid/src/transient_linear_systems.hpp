#pragma once
// The transient solver's linear systems: the SPD viscous predictor systems and the pressure
// Poisson solve. Private to fluid/src/transient*.cpp.
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include <memory>

#include <fmt/format.h>

#include "rheosim/numerics/conjugate_gradient.hpp"
#include "transient_grid.hpp"

namespace rheosim::fluid::transient_detail {

// One SPD predictor system. Up to `direct_limit` unknowns: SimplicialLDLT, pattern analysed
// once, refactorised only when the values change. Above: conjugate gradients preconditioned by
// IC(0) in the natural ordering (k fastest, so the stiff axial coupling Δz ≪ Δr, rΔθ sits in
// the factor), warm-started from the current field; 3D Cholesky fill grows too fast for
// refactorising every step (a non-Newtonian μ changes the values every step).
class PredictorSystem {
 public:
  struct Outcome {
    bool ok = false;
    int iterations = 0;  // 0 for the direct solve
    std::string failure;
  };

  Outcome solve(std::size_t n, const Triplets& triplets, const Eigen::VectorXd& rhs, const Eigen::VectorXd& guess,
                std::size_t direct_limit, double tolerance, int max_iterations, Eigen::VectorXd& x) {
    SparseMatrix assembled(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    assembled.setFromTriplets(triplets.begin(), triplets.end());
    assembled.makeCompressed();
    const auto nnz = static_cast<std::size_t>(assembled.nonZeros());
    const bool direct = n <= direct_limit;
    const bool same = factorized_ && direct == direct_ && values_.size() == nnz &&
                      std::equal(values_.begin(), values_.end(), assembled.valuePtr());
    Outcome out;
    if (!same) {
      // The CG solver keeps a reference to matrix_: replace it only together with compute().
      matrix_ = std::move(assembled);
      factorized_ = false;
      direct_ = direct;
      if (direct) {
        if (!analysed_ || values_.size() != nnz) {
          factor_.analyzePattern(matrix_);
          analysed_ = true;
        }
        factor_.factorize(matrix_);
        if (factor_.info() != Eigen::Success) {
          out.failure = "sparse LDLT factorisation failed";
          return out;
        }
      } else {
        iterative_.compute(matrix_);
        if (iterative_.info() != Eigen::Success) {
          out.failure = "incomplete Cholesky factorisation failed";
          return out;
        }
      }
      values_.assign(matrix_.valuePtr(), matrix_.valuePtr() + nnz);
      factorized_ = true;
    }
    if (direct) {
      x = factor_.solve(rhs);
      out.ok = true;
      return out;
    }
    iterative_.setTolerance(tolerance);
    iterative_.setMaxIterations(max_iterations);
    x = iterative_.solveWithGuess(rhs, guess);
    out.iterations = static_cast<int>(iterative_.iterations());
    out.ok = iterative_.info() == Eigen::Success;
    if (!out.ok)
      out.failure = fmt::format("conjugate gradients did not reach {:.3g} in {} iterations (last {:.3g})", tolerance,
                                out.iterations, iterative_.error());
    return out;
  }

 private:
  SparseMatrix matrix_;
  Factor factor_;
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper,
                           Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::NaturalOrdering<int>>>
      iterative_;
  std::vector<double> values_;
  bool analysed_ = false, factorized_ = false, direct_ = true;
};

// The pressure Poisson operator A φ = Σ_faces c_f (φ_c − φ_nb), c_f = ε_f A_f / h_f, and its PCG
// solver preconditioned by the exact inverse of the θ-averaged operator (real DFT in θ, one
// (r, z) LDLT per distinct θ-wavenumber).
class PressureSolver {
 public:
  explicit PressureSolver(const Geometry& geometry) : g_(geometry) {
    const std::size_t n = g_.nt;
    q_.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    mode_.assign(n, 0);
    const auto N = static_cast<double>(n);
    for (std::size_t j = 0; j < n; ++j) {
      const auto J = static_cast<Eigen::Index>(j);
      const auto jd = static_cast<double>(j);
      q_(J, 0) = 1.0 / std::sqrt(N);
      for (std::size_t m = 1; 2 * m < n; ++m) {
        q_(J, static_cast<Eigen::Index>(2 * m - 1)) =
            std::sqrt(2.0 / N) * std::cos(2 * pi * static_cast<double>(m) * jd / N);
        q_(J, static_cast<Eigen::Index>(2 * m)) =
            std::sqrt(2.0 / N) * std::sin(2 * pi * static_cast<double>(m) * jd / N);
      }
      if (n % 2 == 0 && n > 1) q_(J, static_cast<Eigen::Index>(n - 1)) = (j % 2 == 0 ? 1.0 : -1.0) / std::sqrt(N);
    }
    for (std::size_t m = 1; 2 * m < n; ++m) mode_[2 * m - 1] = mode_[2 * m] = m;
    if (n % 2 == 0 && n > 1) mode_[n - 1] = n / 2;
  }

  // Face coefficients and factorisations for the void fraction `eps`; a no-op if unchanged.
  void set_void_fraction(const std::vector<double>& eps) {
    if (ready_ && eps == eps_) return;
    ready_ = false;
    eps_ = eps;
    const Geometry& g = g_;
    cr_.assign(g.n_ur(), 0.0);
    ct_.assign(g.nc, 0.0);
    cz_.assign(g.n_uz(), 0.0);
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          if (i > 0) cr_[g.ur(i, j, k)] = CellFields::face_r(eps, g, i, j, k) * g.rf[i] * g.dth * g.dz[k] / g.drc[i];
          if (g.nt > 1)
            ct_[g.cell(i, j, k)] = CellFields::face_t(eps, g, i, j, k) * g.dr[i] * g.dz[k] / (g.reff[i] * g.dth);
          if (k > 0) cz_[g.uz(i, j, k)] = CellFields::face_z(eps, g, i, j, k) * g.a1[i] * g.dth / g.dzc[k];
        }
    Triplets t;
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          const auto row = static_cast<int>(g.cell(i, j, k));
          double diag = 0;
          const auto link = [&](std::size_t other, double c) {
            diag += c;
            t.emplace_back(row, static_cast<int>(other), -c);
          };
          if (i > 0) link(g.cell(i - 1, j, k), cr_[g.ur(i, j, k)]);
          if (i + 1 < g.nr) link(g.cell(i + 1, j, k), cr_[g.ur(i + 1, j, k)]);
          if (g.nt > 1) {
            link(g.cell(i, g.jm(j), k), ct_[g.cell(i, j, k)]);
            link(g.cell(i, g.jp(j), k), ct_[g.cell(i, g.jp(j), k)]);
          }
          if (k > 0) link(g.cell(i, j, k - 1), cz_[g.uz(i, j, k)]);
          if (k + 1 < g.nz) link(g.cell(i, j, k + 1), cz_[g.uz(i, j, k + 1)]);
          t.emplace_back(row, row, diag);
        }
    matrix_.resize(static_cast<Eigen::Index>(g.nc), static_cast<Eigen::Index>(g.nc));
    matrix_.setFromTriplets(t.begin(), t.end());

    // θ-averaged coefficients, then one (r, z) matrix per wavenumber m: A_rz + λ_m diag(c̄_θ),
    // λ_m = 4 sin²(πm/N_θ) the eigenvalue of the periodic second difference.
    const std::size_t n2 = g.nr * g.nz;
    std::vector<double> cr_bar((g.nr + 1) * g.nz, 0.0), ct_bar(n2, 0.0), cz_bar(g.nr * (g.nz + 1), 0.0);
    const double inv_nt = 1.0 / static_cast<double>(g.nt);
    for (std::size_t i = 0; i <= g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k <= g.nz; ++k) {
          if (k < g.nz) cr_bar[i * g.nz + k] += inv_nt * cr_[g.ur(i, j, k)];
          if (i < g.nr && k < g.nz) ct_bar[i * g.nz + k] += inv_nt * ct_[g.cell(i, j, k)];
          if (i < g.nr) cz_bar[i * (g.nz + 1) + k] += inv_nt * cz_[g.uz(i, j, k)];
        }
    const std::size_t modes = g.nt / 2 + 1;
    factors_.clear();
    for (std::size_t m = 0; m < modes; ++m) {
      const double s = std::sin(pi * static_cast<double>(m) / static_cast<double>(g.nt));
      const double lambda = 4.0 * s * s;
      Triplets t2;
      double pin = 0;
      for (std::size_t i = 0; i < g.nr; ++i)
        for (std::size_t k = 0; k < g.nz; ++k) {
          const auto row = static_cast<int>(i * g.nz + k);
          double diag = lambda * ct_bar[i * g.nz + k];
          const auto link = [&](std::size_t other, double c) {
            diag += c;
            t2.emplace_back(row, static_cast<int>(other), -c);
          };
          if (i > 0) link((i - 1) * g.nz + k, cr_bar[i * g.nz + k]);
          if (i + 1 < g.nr) link((i + 1) * g.nz + k, cr_bar[(i + 1) * g.nz + k]);
          if (k > 0) link(i * g.nz + k - 1, cz_bar[i * (g.nz + 1) + k]);
          if (k + 1 < g.nz) link(i * g.nz + k + 1, cz_bar[i * (g.nz + 1) + k + 1]);
          if (row == 0) pin = diag;
          t2.emplace_back(row, row, diag);
        }
      // m = 0 is the singular Neumann operator: an extra diagonal entry at one cell gives an SPD
      // matrix whose solution for a compatible (zero-sum) right-hand side is the singular
      // system's solution with φ = 0 at that cell (summing all rows forces the pin to vanish).
      if (lambda == 0.0) t2.emplace_back(0, 0, pin);
      SparseMatrix a2(static_cast<Eigen::Index>(n2), static_cast<Eigen::Index>(n2));
      a2.setFromTriplets(t2.begin(), t2.end());
      auto factor = std::make_unique<Factor>();
      factor->compute(a2);
      if (factor->info() != Eigen::Success)
        throw std::runtime_error("TransientSolver: pressure preconditioner factorisation failed");
      factors_.push_back(std::move(factor));
    }
    ready_ = true;
  }

  // Solves A φ = b for a right-hand side made compatible (zero sum); φ has zero mean. Converged
  // when ‖r‖ <= tolerance · reference, `reference` >= ‖b‖ being the norm of the same right-hand
  // side built from the magnitudes of its terms (face fluxes, ∂ε/∂t), so that a b that is
  // itself round-off (fluxes cancelling) does not demand an impossible relative reduction.
  numerics::KrylovResult solve(Eigen::VectorXd b, Eigen::VectorXd& phi, double tolerance, int max_iterations,
                               double reference) const {
    b.array() -= b.mean();
    phi.setZero(b.size());
    const auto as_vector = [](std::span<const double> v) {
      return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
    };
    const auto apply = [&](std::span<const double> x, std::span<double> out) {
      Eigen::Map<Eigen::VectorXd>(out.data(), static_cast<Eigen::Index>(out.size())) = matrix_ * as_vector(x);
    };
    const auto apply_preconditioner = [&](std::span<const double> r, std::span<double> z) {
      Eigen::Map<Eigen::VectorXd>(z.data(), static_cast<Eigen::Index>(z.size())) = precondition(as_vector(r));
    };
    numerics::ConjugateGradientSettings settings;
    settings.relative_tolerance = tolerance;
    settings.max_iterations = max_iterations;
    settings.reference_norm = reference;
    settings.min_iterations = 1;
    const auto result = numerics::conjugate_gradient(
        apply, apply_preconditioner, std::span<const double>(b.data(), static_cast<std::size_t>(b.size())),
        std::span<double>(phi.data(), static_cast<std::size_t>(phi.size())), settings, work_);
    phi.array() -= phi.mean();
    return result;
  }

  const std::vector<double>& cr() const { return cr_; }
  const std::vector<double>& ct() const { return ct_; }
  const std::vector<double>& cz() const { return cz_; }

 private:
  // z = M⁻¹ r: DFT in θ line by line, one (r, z) solve per mode, inverse DFT.
  Eigen::VectorXd precondition(const Eigen::VectorXd& r) const {
    const Geometry& g = g_;
    const auto n2 = static_cast<Eigen::Index>(g.nr * g.nz);
    const auto nt = static_cast<Eigen::Index>(g.nt);
    Eigen::MatrixXd lines(n2, nt);
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k)
          lines(static_cast<Eigen::Index>(i * g.nz + k), static_cast<Eigen::Index>(j)) =
              r[static_cast<Eigen::Index>(g.cell(i, j, k))];
    Eigen::MatrixXd spectral = lines * q_;
    for (Eigen::Index q = 0; q < nt; ++q) {
      const Eigen::VectorXd column = spectral.col(q);
      spectral.col(q) = factors_[mode_[static_cast<std::size_t>(q)]]->solve(column);
    }
    lines.noalias() = spectral * q_.transpose();
    Eigen::VectorXd z(r.size());
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k)
          z[static_cast<Eigen::Index>(g.cell(i, j, k))] =
              lines(static_cast<Eigen::Index>(i * g.nz + k), static_cast<Eigen::Index>(j));
    z.array() -= z.mean();
    return z;
  }

  const Geometry& g_;
  Eigen::MatrixXd q_;              // orthonormal real DFT basis (columns = modes)
  std::vector<std::size_t> mode_;  // wavenumber of each column
  std::vector<std::unique_ptr<Factor>> factors_;
  Eigen::SparseMatrix<double, Eigen::RowMajor> matrix_;
  std::vector<double> cr_, ct_, cz_;
  std::vector<double> eps_;
  bool ready_ = false;
  mutable numerics::ConjugateGradientWorkspace work_;  // reused by every solve
};

}  // namespace rheosim::fluid::transient_detail
