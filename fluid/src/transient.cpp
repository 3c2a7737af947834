#include "rheosim/fluid/transient.hpp"

#include <Eigen/Dense>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include "rheosim/numerics/quadrature.hpp"

namespace rheosim::fluid {

namespace {

constexpr double pi = std::numbers::pi;
constexpr double max_step_ratio = 2.0;  // Δt/Δt_prev above which a step falls back to BDF1

// 3-point Gauss–Legendre on [-1, 1], as in SwirlSolver: ∫ μ r³ dr over an axial face is exact
// for a Newtonian fluid and the torque matches the steady solver's on the same (r, z) grid.
constexpr auto gauss_nodes = numerics::GaussLegendre<3>::nodes;
constexpr auto gauss_weights = numerics::GaussLegendre<3>::weights;

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;
using Factor = Eigen::SimplicialLDLT<SparseMatrix>;

// Geometry of the staggered grid and the index maps of every staggered array.
//   cells and u_θ (faces θ_j at r_c,i):                  (i·N_θ + j)·N_z + k
//   u_r (i = 0..N_r) and rθ-edges (r_i, θ_j, z_c,k):     (i·N_θ + j)·N_z + k
//   u_z (k = 0..N_z) and θz-edges (r_c,i, θ_j, z_k):      (i·N_θ + j)·(N_z + 1) + k
//   rz-edges (r_i, θ_c,j, z_k), i = 0..N_r, k = 0..N_z:   (i·N_θ + j)·(N_z + 1) + k
struct Geometry {
  std::size_t nr, nt, nz, nc;
  double dth;
  std::vector<double> rf, rc, zf, zc, dr, dz;
  std::vector<double> drc;   // [nr+1]: r_c,i − r_c,i−1 for interior radial faces i
  std::vector<double> dzc;   // [nz+1]: z_c,k − z_c,k−1 inside, half cells at the plates
  std::vector<double> a1;    // ∫ r dr over radial cell i (= r_c Δr)
  std::vector<double> r3;    // ∫ r² dr
  std::vector<double> r4;    // ∫ r³ dr
  std::vector<double> reff;  // r_eff = ∫r³dr / (r_c ∫r dr): θ-gradient length of the u_θ correction
  std::vector<double> theta_c, cos_c, sin_c;

  explicit Geometry(const CylindricalGrid& g)
      : nr(g.radial_cells()),
        nt(g.azimuthal_cells()),
        nz(g.axial_cells()),
        nc(g.cell_count()),
        dth(g.azimuthal_width()),
        rf(g.radial_faces().begin(), g.radial_faces().end()),
        rc(g.radial_centres().begin(), g.radial_centres().end()),
        zf(g.axial_faces().begin(), g.axial_faces().end()),
        zc(g.axial_centres().begin(), g.axial_centres().end()) {
    dr.resize(nr);
    a1.resize(nr);
    r3.resize(nr);
    r4.resize(nr);
    reff.resize(nr);
    for (std::size_t i = 0; i < nr; ++i) {
      dr[i] = rf[i + 1] - rf[i];
      a1[i] = rc[i] * dr[i];
      r3[i] = (std::pow(rf[i + 1], 3) - std::pow(rf[i], 3)) / 3.0;
      r4[i] = 0.25 * (std::pow(rf[i + 1], 4) - std::pow(rf[i], 4));
      reff[i] = r4[i] / (rc[i] * a1[i]);
    }
    drc.assign(nr + 1, 0.0);
    for (std::size_t i = 1; i < nr; ++i) drc[i] = rc[i] - rc[i - 1];
    dz.resize(nz);
    for (std::size_t k = 0; k < nz; ++k) dz[k] = zf[k + 1] - zf[k];
    dzc.resize(nz + 1);
    dzc[0] = zc[0] - zf[0];
    dzc[nz] = zf[nz] - zc[nz - 1];
    for (std::size_t k = 1; k < nz; ++k) dzc[k] = zc[k] - zc[k - 1];
    theta_c.assign(g.azimuthal_centres().begin(), g.azimuthal_centres().end());
    for (double t : theta_c) {
      cos_c.push_back(std::cos(t));
      sin_c.push_back(std::sin(t));
    }
  }

  std::size_t cell(std::size_t i, std::size_t j, std::size_t k) const { return (i * nt + j) * nz + k; }
  std::size_t ur(std::size_t i, std::size_t j, std::size_t k) const { return (i * nt + j) * nz + k; }
  std::size_t uz(std::size_t i, std::size_t j, std::size_t k) const { return (i * nt + j) * (nz + 1) + k; }
  std::size_t jm(std::size_t j) const { return (j + nt - 1) % nt; }
  std::size_t jp(std::size_t j) const { return (j + 1) % nt; }
  std::size_t n_ur() const { return (nr + 1) * nt * nz; }
  std::size_t n_uz() const { return nr * nt * (nz + 1); }
  std::size_t n_rz() const { return (nr + 1) * nt * (nz + 1); }
  // Unknowns of the predictor systems: interior u_r faces and interior u_z faces.
  std::size_t row_r(std::size_t i, std::size_t j, std::size_t k) const { return ((i - 1) * nt + j) * nz + k; }
  std::size_t row_z(std::size_t i, std::size_t j, std::size_t k) const { return (i * nt + j) * (nz - 1) + k - 1; }
  std::size_t rows_r() const { return (nr - 1) * nt * nz; }
  std::size_t rows_z() const { return nr * nt * (nz - 1); }
  double volume(std::size_t i, std::size_t k) const { return a1[i] * dth * dz[k]; }
};

struct Velocity {
  std::vector<double> ur, ut, uz;  // u_r (with the axis value at i = 0), u_θ, u_z
};

struct ViscosityField {
  std::vector<double> centre, shear_rate;  // cells
  std::vector<double> rt;                  // rθ-edges, ur(i, j, k) index
  std::vector<double> tz_moment;           // W = ∫ μ r³ dr on θz-edges, uz index
  std::vector<double> tz;                  // W / ∫ r³ dr, a representative μ on θz-edges
  std::vector<double> wall_rz;             // μ on the rz-edges of the plates: (side·(N_r+1) + i)·N_θ + j
};

struct CellFields {  // per-cell ε-like scalar helpers
  static double face_r(const std::vector<double>& e, const Geometry& g, std::size_t i, std::size_t j, std::size_t k) {
    return 0.5 * (e[g.cell(i - 1, j, k)] + e[g.cell(i, j, k)]);
  }
  static double face_t(const std::vector<double>& e, const Geometry& g, std::size_t i, std::size_t j, std::size_t k) {
    return 0.5 * (e[g.cell(i, g.jm(j), k)] + e[g.cell(i, j, k)]);
  }
  static double face_z(const std::vector<double>& e, const Geometry& g, std::size_t i, std::size_t j, std::size_t k) {
    return 0.5 * (e[g.cell(i, j, k - 1)] + e[g.cell(i, j, k)]);
  }
};

// Cartesian velocity (U_x, U_y) on the axis at height z_c,k from the first interior ring of u_r:
// its θ-mode 1 for N_θ >= 3, the half-difference of the two opposite faces for N_θ = 2.
std::pair<double, double> axis_velocity(const Geometry& g, const std::vector<double>& ur, std::size_t k) {
  if (g.nt == 1) return {0.0, 0.0};
  if (g.nt == 2) return {0.0, 0.5 * (ur[g.ur(1, 0, k)] - ur[g.ur(1, 1, k)])};  // θ_c = π/2, 3π/2
  double ux = 0, uy = 0;
  for (std::size_t j = 0; j < g.nt; ++j) {
    ux += ur[g.ur(1, j, k)] * g.cos_c[j];
    uy += ur[g.ur(1, j, k)] * g.sin_c[j];
  }
  const double scale = 2.0 / static_cast<double>(g.nt);
  return {scale * ux, scale * uy};
}

// Imposes the kinematic boundary values: u_r on the axis (Cartesian extrapolation), u_r = 0 on
// the rim, u_z = 0 on the plates.
void impose_boundary_values(const Geometry& g, Velocity& v) {
  for (std::size_t k = 0; k < g.nz; ++k) {
    const auto [ux, uy] = axis_velocity(g, v.ur, k);
    for (std::size_t j = 0; j < g.nt; ++j) {
      v.ur[g.ur(0, j, k)] = ux * g.cos_c[j] + uy * g.sin_c[j];
      v.ur[g.ur(g.nr, j, k)] = 0.0;
    }
  }
  for (std::size_t i = 0; i < g.nr; ++i)
    for (std::size_t j = 0; j < g.nt; ++j) {
      v.uz[g.uz(i, j, 0)] = 0.0;
      v.uz[g.uz(i, j, g.nz)] = 0.0;
    }
}

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

bool all_finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

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

  struct Result {
    int iterations = 0;
    double residual = 0;
    bool converged = false;
  };

  // Solves A φ = b for a right-hand side made compatible (zero sum); φ has zero mean. Converged
  // when ‖r‖ <= tolerance · reference, `reference` >= ‖b‖ being the norm of the same right-hand
  // side built from the magnitudes of its terms (face fluxes, ∂ε/∂t), so that a b that is
  // itself round-off (fluxes cancelling) does not demand an impossible relative reduction.
  Result solve(Eigen::VectorXd b, Eigen::VectorXd& phi, double tolerance, int max_iterations, double reference) const {
    b.array() -= b.mean();
    Result result;
    phi.setZero(b.size());
    const double b_norm = std::max(b.norm(), reference);
    if (b.norm() == 0.0) {
      result.converged = true;
      return result;
    }
    Eigen::VectorXd r = b;
    Eigen::VectorXd z = precondition(r);
    Eigen::VectorXd p = z;
    double rz = r.dot(z);
    for (int it = 1; it <= max_iterations; ++it) {
      const Eigen::VectorXd ap = matrix_ * p;
      const double pap = p.dot(ap);
      if (!(pap > 0)) break;
      const double alpha = rz / pap;
      phi += alpha * p;
      r -= alpha * ap;
      result.iterations = it;
      result.residual = r.norm() / b_norm;
      if (!std::isfinite(result.residual)) break;
      if (result.residual <= tolerance) {
        result.converged = true;
        break;
      }
      z = precondition(r);
      const double rz_next = r.dot(z);
      p = z + (rz_next / rz) * p;
      rz = rz_next;
    }
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
};

}  // namespace

struct TransientSolver::Impl {
  TransientParams params;
  CylindricalGrid grid;
  Geometry g;
  PressureSolver pressure_solver;
  PredictorSystem system_r, system_w, system_z;

  Velocity u, u_old;      // u^n, u^(n−1)
  std::vector<double> p;  // p^n
  std::vector<double> eps_next, eps_now, eps_old;
  std::vector<double> source_r, source_t, source_z, drag;  // empty = none
  double time = 0, dt_old = 0;
  long steps = 0;
  bool have_old = false;  // u^(n−1) valid: the next step is BDF2

  ViscosityField mu_now;         // of the current state
  int predictor_iterations = 0;  // largest CG iteration count of the last predictor (0: direct)
  double torque_top = 0, torque_bottom = 0;

  explicit Impl(TransientParams prm) : params(std::move(prm)), grid(params.grid), g(grid), pressure_solver(g) {
    u.ur.assign(g.n_ur(), 0.0);
    u.ut.assign(g.nc, 0.0);
    u.uz.assign(g.n_uz(), 0.0);
    u_old = u;
    p.assign(g.nc, 0.0);
    eps_next.assign(g.nc, 1.0);
    eps_now = eps_old = eps_next;
    update_diagnostics();
  }

  double omega_top() const { return params.top_angular_velocity; }
  double omega_bottom() const { return params.bottom_angular_velocity; }
  double omega(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    return v.ut[g.cell(i, j, k)] / g.rc[i];
  }

  // ---- strain rates -------------------------------------------------------------------
  double dw_dz(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (k == 0) return (omega(v, i, j, 0) - omega_bottom()) / g.dzc[0];
    if (k == g.nz) return (omega_top() - omega(v, i, j, g.nz - 1)) / g.dzc[g.nz];
    return (omega(v, i, j, k) - omega(v, i, j, k - 1)) / g.dzc[k];
  }
  // The same for evaluating μ: second order at the plates (quadratic through the wall value and
  // the two nearest centres), as SwirlSolver does; the half-cell difference is first order
  // there and would make μ at the wall, and so the torque of a non-Newtonian fluid, first
  // order. Exact, like the half-cell form, for the creeping linear profile.
  double dw_dz_for_viscosity(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (k != 0 && k != g.nz) return dw_dz(v, i, j, k);
    if (k == 0) {
      const double h = g.dz[0], a = omega(v, i, j, 0), b = omega(v, i, j, 1);
      return (9 * a - b - 8 * omega_bottom()) / (3 * h);
    }
    const double h = g.dz[g.nz - 1], a = omega(v, i, j, g.nz - 1), b = omega(v, i, j, g.nz - 2);
    return (8 * omega_top() - 9 * a + b) / (3 * h);
  }
  double duz_dtheta(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (k == 0 || k == g.nz || g.nt == 1) return 0.0;
    return (v.uz[g.uz(i, j, k)] - v.uz[g.uz(i, g.jm(j), k)]) / g.dth;
  }
  double dur_dz(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (k == 0) return v.ur[g.ur(i, j, 0)] / g.dzc[0];
    if (k == g.nz) return -v.ur[g.ur(i, j, g.nz - 1)] / g.dzc[g.nz];
    return (v.ur[g.ur(i, j, k)] - v.ur[g.ur(i, j, k - 1)]) / g.dzc[k];
  }
  double duz_dr(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (k == 0 || k == g.nz) return 0.0;
    return (v.uz[g.uz(i, j, k)] - v.uz[g.uz(i - 1, j, k)]) / g.drc[i];
  }
  // 2E_rz on the rz-edge (r_i, θ_c,j, z_k) for evaluating μ (second order at the plates, where
  // ∂_ru_z = 0); zero on the axis and the shear-free rim.
  double strain_rz_for_viscosity(const Velocity& v, std::size_t i, std::size_t j, std::size_t k) const {
    if (i == 0 || i == g.nr) return 0.0;
    if (k == 0) return (9 * v.ur[g.ur(i, j, 0)] - v.ur[g.ur(i, j, 1)]) / (3 * g.dz[0]);
    if (k == g.nz) return -(9 * v.ur[g.ur(i, j, g.nz - 1)] - v.ur[g.ur(i, j, g.nz - 2)]) / (3 * g.dz[g.nz - 1]);
    return dur_dz(v, i, j, k) + duz_dr(v, i, j, k);
  }
  // ∇·u per cell [1/s] (not ε-weighted): the −(2/3)μ∇·u part of CD eq. 28.
  std::vector<double> velocity_divergence(const Velocity& v) const {
    std::vector<double> div(g.nc);
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          double flux = (g.rf[i + 1] * v.ur[g.ur(i + 1, j, k)] - g.rf[i] * v.ur[g.ur(i, j, k)]) * g.dth * g.dz[k];
          if (g.nt > 1) flux += (v.ut[g.cell(i, g.jp(j), k)] - v.ut[g.cell(i, j, k)]) * g.dr[i] * g.dz[k];
          flux += (v.uz[g.uz(i, j, k + 1)] - v.uz[g.uz(i, j, k)]) * g.a1[i] * g.dth;
          div[g.cell(i, j, k)] = flux / g.volume(i, k);
        }
    return div;
  }

  // μ and γ̇ = √(2E:E) of a velocity field, with
  //   2E:E = 2(E_rr² + E_θθ² + E_zz²) + (2E_rθ)² + (2E_θz)² + (2E_rz)²,
  //   E_rr = ∂_ru_r, E_θθ = ∂_θω + u_r/r, E_zz = ∂_zu_z,
  //   2E_rθ = r∂_rω + (1/r)∂_θu_r, 2E_θz = r∂_zω + (1/r)∂_θu_z, 2E_rz = ∂_zu_r + ∂_ru_z.
  // Normal parts live at cell centres, shear parts on their edges. A shear part of the form
  // r·g + h (g a gradient of ω, h = (1/r)∂_θu at the edge's own radius) is evaluated at the
  // radius where μ is wanted: a cell keeps the means of g², g·h and h² over its four edges of
  // that kind, giving r²⟨g²⟩ + 2r⟨gh⟩ + ⟨h²⟩ at any r. On an edge, its own shear component is
  // exact and the rest is the mean over the adjacent cells at the edge's radius; on θz-edges
  // μ is taken at the three Gauss radii. For N_θ = 1 this is SwirlSolver's evaluation exactly.
  ViscosityField evaluate_viscosity(const Velocity& v) const {
    const std::size_t nr = g.nr, nt = g.nt, nz = g.nz, nc = g.nc;
    // Edge values: rθ-edges g_rt = ∂_rω, h_rt = ∂_θu_r/r_i (zero on axis and rim); θz-edges
    // g_tz = ∂_zω, h_tz = ∂_θu_z/r_c; rz-edges the full 2E_rz.
    std::vector<double> g_rt(g.n_ur(), 0.0), h_rt(g.n_ur(), 0.0), srz(g.n_rz()), g_tz(g.n_uz()), h_tz(g.n_uz());
    for (std::size_t i = 0; i <= nr; ++i)
      for (std::size_t j = 0; j < nt; ++j) {
        if (i > 0 && i < nr)
          for (std::size_t k = 0; k < nz; ++k) {
            g_rt[g.ur(i, j, k)] = (omega(v, i, j, k) - omega(v, i - 1, j, k)) / g.drc[i];
            if (nt > 1) h_rt[g.ur(i, j, k)] = (v.ur[g.ur(i, j, k)] - v.ur[g.ur(i, g.jm(j), k)]) / (g.rf[i] * g.dth);
          }
        for (std::size_t k = 0; k <= nz; ++k) {
          srz[g.uz(i, j, k)] = strain_rz_for_viscosity(v, i, j, k);  // same index formula, i up to nr
          if (i < nr) {
            g_tz[g.uz(i, j, k)] = dw_dz_for_viscosity(v, i, j, k);
            h_tz[g.uz(i, j, k)] = duz_dtheta(v, i, j, k) / g.rc[i];
          }
        }
      }
    struct Moments {  // ⟨g²⟩, ⟨gh⟩, ⟨h²⟩ over a cell's four edges of one kind
      double gg = 0, gh = 0, hh = 0;
      double at(double r) const { return r * r * gg + 2 * r * gh + hh; }
    };
    std::vector<double> normal(nc), a_rz(nc);
    std::vector<Moments> m_rt(nc), m_tz(nc);
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k) {
          const std::size_t c = g.cell(i, j, k), jj = g.jp(j);
          const double err = (v.ur[g.ur(i + 1, j, k)] - v.ur[g.ur(i, j, k)]) / g.dr[i];
          double ett = 0.5 * (v.ur[g.ur(i, j, k)] + v.ur[g.ur(i + 1, j, k)]) / g.rc[i];
          if (nt > 1) ett += (omega(v, i, jj, k) - omega(v, i, j, k)) / g.dth;
          const double ezz = (v.uz[g.uz(i, j, k + 1)] - v.uz[g.uz(i, j, k)]) / g.dz[k];
          normal[c] = 2.0 * (err * err + ett * ett + ezz * ezz);
          Moments rt, tz;
          for (std::size_t b : {j, jj}) {
            for (std::size_t a : {i, i + 1}) {
              const std::size_t e = g.ur(a, b, k);
              rt.gg += 0.25 * g_rt[e] * g_rt[e];
              rt.gh += 0.25 * g_rt[e] * h_rt[e];
              rt.hh += 0.25 * h_rt[e] * h_rt[e];
            }
            for (std::size_t f : {k, k + 1}) {
              const std::size_t e = g.uz(i, b, f);
              tz.gg += 0.25 * g_tz[e] * g_tz[e];
              tz.gh += 0.25 * g_tz[e] * h_tz[e];
              tz.hh += 0.25 * h_tz[e] * h_tz[e];
            }
          }
          m_rt[c] = rt;
          m_tz[c] = tz;
          double s = 0;
          for (std::size_t a : {i, i + 1})
            for (std::size_t f : {k, k + 1}) s += srz[g.uz(a, j, f)] * srz[g.uz(a, j, f)];
          a_rz[c] = 0.25 * s;
        }

    // All shear rates in one array: one rheology call for the whole field.
    const std::size_t off_rt = nc, off_tz = nc + g.n_ur(), off_wall = off_tz + 3 * g.n_uz();
    std::vector<double> rates(off_wall + 2 * (nr + 1) * nt, 0.0);
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k) {
          const std::size_t c = g.cell(i, j, k);
          rates[c] = std::sqrt(normal[c] + m_rt[c].at(g.rc[i]) + m_tz[c].at(g.rc[i]) + a_rz[c]);
        }
    for (std::size_t i = 1; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k) {
          double rest = 0;
          for (std::size_t a : {i - 1, i})
            for (std::size_t b : {g.jm(j), j}) {
              const std::size_t c = g.cell(a, b, k);
              rest += 0.25 * (normal[c] + m_tz[c].at(g.rf[i]) + a_rz[c]);
            }
          const std::size_t e = g.ur(i, j, k);
          const double s = g.rf[i] * g_rt[e] + h_rt[e];
          rates[off_rt + e] = std::sqrt(s * s + rest);
        }
    for (std::size_t i = 0; i < nr; ++i) {
      const double mid = 0.5 * (g.rf[i] + g.rf[i + 1]), half = 0.5 * g.dr[i];
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k <= nz; ++k) {
          const std::size_t e = g.uz(i, j, k);
          for (std::size_t q = 0; q < 3; ++q) {
            const double r = mid + half * gauss_nodes[q];
            double rest = 0, n = 0;
            for (std::size_t b : {g.jm(j), j})
              for (std::size_t f : {k - 1, k}) {
                if (f >= nz) continue;  // k − 1 wraps at k = 0
                const std::size_t c = g.cell(i, b, f);
                rest += m_rt[c].at(r) + ((k == 0 || k == nz) ? 0.0 : normal[c] + a_rz[c]);
                n += 1;
              }
            rest /= n;
            if (k == 0 || k == nz) {  // on a plate the rest is the wall shear ∂_zu_r alone (u = 0, ∂_zu_z = 0)
              for (std::size_t a : {i, i + 1})
                for (std::size_t b : {g.jm(j), j}) rest += 0.25 * srz[g.uz(a, b, k)] * srz[g.uz(a, b, k)];
            }
            const double s = r * g_tz[e] + h_tz[e];
            rates[off_tz + 3 * e + q] = std::sqrt(s * s + rest);
          }
        }
    }
    // rz-edges on the plates, for τ_rz there: γ̇² = (r ∂_zω)² + (∂_zu_r)², ∂_zω averaged over the
    // adjacent θz-edges.
    for (std::size_t side = 0; side < 2; ++side) {
      const std::size_t k = side == 0 ? 0 : nz;
      for (std::size_t i = 0; i <= nr; ++i)
        for (std::size_t j = 0; j < nt; ++j) {
          double gz_mean = 0, n = 0;
          for (std::size_t a : {i - 1, i})
            for (std::size_t b : {j, g.jp(j)})
              if (a < nr) {
                gz_mean += g_tz[g.uz(a, b, k)];
                n += 1;
              }
          gz_mean /= n;
          const double shear = srz[g.uz(i, j, k)];
          rates[off_wall + (side * (nr + 1) + i) * nt + j] =
              std::sqrt(g.rf[i] * g.rf[i] * gz_mean * gz_mean + shear * shear);
        }
    }
    std::vector<double> mu(rates.size());
    params.rheology->viscosity(rates, mu);

    ViscosityField out;
    out.centre.assign(mu.begin(), mu.begin() + static_cast<std::ptrdiff_t>(nc));
    out.shear_rate.assign(rates.begin(), rates.begin() + static_cast<std::ptrdiff_t>(nc));
    out.rt.assign(mu.begin() + static_cast<std::ptrdiff_t>(off_rt), mu.begin() + static_cast<std::ptrdiff_t>(off_tz));
    out.wall_rz.assign(mu.begin() + static_cast<std::ptrdiff_t>(off_wall), mu.end());
    out.tz_moment.assign(g.n_uz(), 0.0);
    out.tz.assign(g.n_uz(), 0.0);
    for (std::size_t i = 0; i < nr; ++i) {
      const double mid = 0.5 * (g.rf[i] + g.rf[i + 1]), half = 0.5 * g.dr[i];
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k <= nz; ++k) {
          const std::size_t e = g.uz(i, j, k);
          double w = 0;
          for (std::size_t q = 0; q < 3; ++q) {
            const double r = mid + half * gauss_nodes[q];
            w += gauss_weights[q] * mu[off_tz + 3 * e + q] * r * r * r;
          }
          out.tz_moment[e] = w * half;
          out.tz[e] = out.tz_moment[e] / g.r4[i];
        }
    }
    return out;
  }

  // μ on the rz-edge (r_i, θ_c,j, z_k): from the wall shear rate on the plates, else the mean of
  // the adjacent cells (SwirlSolver's corner value).
  double mu_rz(const ViscosityField& mu, std::size_t i, std::size_t j, std::size_t k) const {
    if (k == 0) return mu.wall_rz[i * g.nt + j];
    if (k == g.nz) return mu.wall_rz[((g.nr + 1) + i) * g.nt + j];
    double sum = 0, n = 0;
    for (std::size_t a : {i - 1, i})
      for (std::size_t f : {k - 1, k})
        if (a < g.nr && f < g.nz) {
          sum += mu.centre[g.cell(a, j, f)];
          n += 1;
        }
    return sum / n;
  }

  // Torque transmitted through the top (or bottom) plate: Σ Δθ W ∂_zω [N·m].
  double wall_torque(const Velocity& v, const ViscosityField& mu, bool top) const {
    const std::size_t k = top ? g.nz : 0;
    double sum = 0;
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j) sum += mu.tz_moment[g.uz(i, j, k)] * dw_dz(v, i, j, k);
    return g.dth * sum;
  }

  void update_diagnostics() {
    mu_now = evaluate_viscosity(u);
    torque_top = wall_torque(u, mu_now, true);
    torque_bottom = wall_torque(u, mu_now, false);
  }

  // ---- Courant number ---------------------------------------------------------------------
  struct CourantResult {
    double value = 0;
    std::size_t i = 0, j = 0, k = 0;
  };
  CourantResult courant(const Velocity& v, double dt) const {
    CourantResult out;
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          double rate = std::abs(0.5 * (v.ur[g.ur(i, j, k)] + v.ur[g.ur(i + 1, j, k)])) / g.dr[i] +
                        std::abs(0.5 * (v.uz[g.uz(i, j, k)] + v.uz[g.uz(i, j, k + 1)])) / g.dz[k];
          if (g.nt > 1)
            rate += std::abs(0.5 * (v.ut[g.cell(i, j, k)] + v.ut[g.cell(i, g.jp(j), k)])) / (g.rc[i] * g.dth);
          if (!std::isfinite(rate)) return {std::numeric_limits<double>::infinity(), i, j, k};
          if (rate * dt > out.value) out = {rate * dt, i, j, k};
        }
    return out;
  }

  // ---- explicit terms ----------------------------------------------------------------------
  // Integrated explicit forces (u_r, u_z: N) and torques (ω: N·m) per unknown, before the
  // division by ε^(n+1): convection (with the centrifugal force), then viscous cross terms.
  struct Explicit {
    std::vector<double> r, w, z;
  };

  // −∇·(ρεuu) (+ ρεu_θ²/r for u_r), central and conservative; ε = ε^(n+1).
  Explicit convection(const Velocity& v, const std::vector<double>& e) const {
    Explicit out{std::vector<double>(g.rows_r(), 0.0), std::vector<double>(g.nc, 0.0),
                 std::vector<double>(g.rows_z(), 0.0)};
    if (!params.inertia) return out;
    const double rho = params.density;
    const std::size_t nr = g.nr, nt = g.nt, nz = g.nz;
    const auto eps_corner_rz = [&](std::size_t i, std::size_t j, std::size_t k) {  // rz-edge, interior
      return 0.25 * (e[g.cell(i - 1, j, k - 1)] + e[g.cell(i, j, k - 1)] + e[g.cell(i - 1, j, k)] + e[g.cell(i, j, k)]);
    };
    const auto eps_corner_rt = [&](std::size_t i, std::size_t j, std::size_t k) {  // rθ-edge, interior i
      const std::size_t b = g.jm(j);
      return 0.25 * (e[g.cell(i - 1, b, k)] + e[g.cell(i, b, k)] + e[g.cell(i - 1, j, k)] + e[g.cell(i, j, k)]);
    };
    const auto eps_corner_tz = [&](std::size_t i, std::size_t j, std::size_t k) {  // θz-edge, interior k
      const std::size_t b = g.jm(j);
      return 0.25 * (e[g.cell(i, b, k - 1)] + e[g.cell(i, j, k - 1)] + e[g.cell(i, b, k)] + e[g.cell(i, j, k)]);
    };
    // u_r control volumes.
    for (std::size_t i = 1; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k) {
          double outflow = 0;
          for (std::size_t c : {i - 1, i}) {  // faces at the cell centres r_c
            const double sign = c == i ? 1.0 : -1.0;
            const double un = 0.5 * (v.ur[g.ur(c, j, k)] + v.ur[g.ur(c + 1, j, k)]);
            outflow += sign * e[g.cell(c, j, k)] * g.rc[c] * g.dth * g.dz[k] * un * un;
          }
          const double wr = (g.rf[i] - g.rc[i - 1]) / g.drc[i];
          if (nt > 1)
            for (std::size_t b : {j, g.jp(j)}) {  // θ faces on rθ-edges
              const double sign = b == j ? -1.0 : 1.0;
              const double ut = (1 - wr) * v.ut[g.cell(i - 1, b, k)] + wr * v.ut[g.cell(i, b, k)];
              const double phi = 0.5 * (v.ur[g.ur(i, g.jm(b), k)] + v.ur[g.ur(i, b, k)]);
              outflow += sign * eps_corner_rt(i, b, k) * g.drc[i] * g.dz[k] * ut * phi;
            }
          for (std::size_t f : {k, k + 1}) {  // axial faces on rz-edges (none through the plates)
            if (f == 0 || f == nz) continue;
            const double sign = f == k + 1 ? 1.0 : -1.0;
            const double uzc = (1 - wr) * v.uz[g.uz(i - 1, j, f)] + wr * v.uz[g.uz(i, j, f)];
            const double phi = 0.5 * (v.ur[g.ur(i, j, f - 1)] + v.ur[g.ur(i, j, f)]);
            outflow += sign * eps_corner_rz(i, j, f) * g.rf[i] * g.drc[i] * g.dth * uzc * phi;
          }
          // Centrifugal force ρε u_θ²/r with u_θ = r_i ω̄, ω̄ the mean of the four nearest ω.
          const double wbar = 0.25 * (omega(v, i - 1, j, k) + omega(v, i, j, k) + omega(v, i - 1, g.jp(j), k) +
                                      omega(v, i, g.jp(j), k));
          const double volume = g.rf[i] * g.drc[i] * g.dth * g.dz[k];
          const double centrifugal = CellFields::face_r(e, g, i, j, k) * wbar * wbar * g.rf[i] * volume;
          out.r[g.row_r(i, j, k)] = rho * (centrifugal - outflow);
        }
    // ω control volumes: angular momentum L = r²ω transported.
    for (std::size_t i = 0; i < nr; ++i) {
      const double r2_mean = 0.5 * (g.rf[i] * g.rf[i] + g.rf[i + 1] * g.rf[i + 1]);
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k) {
          double outflow = 0;
          for (std::size_t f : {i, i + 1}) {
            if (f == 0 || f == nr) continue;
            const double sign = f == i + 1 ? 1.0 : -1.0;
            const double urf = 0.5 * (v.ur[g.ur(f, g.jm(j), k)] + v.ur[g.ur(f, j, k)]);
            const double wr = (g.rf[f] - g.rc[f - 1]) / g.drc[f];
            const double l = g.rf[f] * g.rf[f] * ((1 - wr) * omega(v, f - 1, j, k) + wr * omega(v, f, j, k));
            outflow += sign * eps_corner_rt(f, j, k) * g.rf[f] * g.dth * g.dz[k] * urf * l;
          }
          for (std::size_t f : {k, k + 1}) {
            if (f == 0 || f == nz) continue;
            const double sign = f == k + 1 ? 1.0 : -1.0;
            const double uzf = 0.5 * (v.uz[g.uz(i, g.jm(j), f)] + v.uz[g.uz(i, j, f)]);
            const double wz = (g.zf[f] - g.zc[f - 1]) / g.dzc[f];
            const double l = r2_mean * ((1 - wz) * omega(v, i, j, f - 1) + wz * omega(v, i, j, f));
            outflow += sign * eps_corner_tz(i, j, f) * g.a1[i] * g.dth * uzf * l;
          }
          if (nt > 1)
            for (std::size_t c : {g.jm(j), j}) {  // θ faces at the cell centres
              const double sign = c == j ? 1.0 : -1.0;
              const double utc = 0.5 * (v.ut[g.cell(i, c, k)] + v.ut[g.cell(i, g.jp(c), k)]);
              const double l = r2_mean * 0.5 * (omega(v, i, c, k) + omega(v, i, g.jp(c), k));
              outflow += sign * e[g.cell(i, c, k)] * g.dr[i] * g.dz[k] * utc * l;
            }
          out.w[g.cell(i, j, k)] = -rho * outflow;
        }
    }
    // u_z control volumes.
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 1; k < nz; ++k) {
          double outflow = 0;
          for (std::size_t c : {k - 1, k}) {
            const double sign = c == k ? 1.0 : -1.0;
            const double un = 0.5 * (v.uz[g.uz(i, j, c)] + v.uz[g.uz(i, j, c + 1)]);
            outflow += sign * e[g.cell(i, j, c)] * g.a1[i] * g.dth * un * un;
          }
          const double wz = (g.zf[k] - g.zc[k - 1]) / g.dzc[k];
          for (std::size_t f : {i, i + 1}) {
            if (f == 0 || f == nr) continue;
            const double sign = f == i + 1 ? 1.0 : -1.0;
            const double urc = (1 - wz) * v.ur[g.ur(f, j, k - 1)] + wz * v.ur[g.ur(f, j, k)];
            const double phi = 0.5 * (v.uz[g.uz(f - 1, j, k)] + v.uz[g.uz(f, j, k)]);
            outflow += sign * eps_corner_rz(f, j, k) * g.rf[f] * g.dth * g.dzc[k] * urc * phi;
          }
          if (nt > 1)
            for (std::size_t b : {j, g.jp(j)}) {
              const double sign = b == j ? -1.0 : 1.0;
              const double ut = (1 - wz) * v.ut[g.cell(i, b, k - 1)] + wz * v.ut[g.cell(i, b, k)];
              const double phi = 0.5 * (v.uz[g.uz(i, g.jm(b), k)] + v.uz[g.uz(i, b, k)]);
              outflow += sign * eps_corner_tz(i, b, k) * g.dr[i] * g.dzc[k] * ut * phi;
            }
          out.z[g.row_z(i, j, k)] = -rho * outflow;
        }
    return out;
  }

  // The viscous terms left explicit: the transposed-gradient part ∇·(μ(∇u)ᵀ) — cross-component
  // terms and half of each normal stress (the implicit operator is the Laplacian form) — plus
  // −(2/3)μ∇·u and the axis value of u_r in τ_rr of the first ring (the axis is not an unknown).
  // For constant μ and ∇·u = 0 this part is μ∇(∇·u) = 0 in the continuum.
  Explicit viscous_cross(const Velocity& v, const ViscosityField& mu) const {
    Explicit out{std::vector<double>(g.rows_r(), 0.0), std::vector<double>(g.nc, 0.0),
                 std::vector<double>(g.rows_z(), 0.0)};
    const std::size_t nr = g.nr, nt = g.nt, nz = g.nz;
    const std::vector<double> div = velocity_divergence(v);
    const auto mu_c = [&](std::size_t i, std::size_t j, std::size_t k) { return mu.centre[g.cell(i, j, k)]; };
    for (std::size_t i = 1; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k) {
          double force = 0;
          for (std::size_t c : {i - 1, i}) {  // τ_rr ⊃ μ∂_ru_r − (2/3)μ∇·u
            const double sign = c == i ? 1.0 : -1.0;
            const double dur = (v.ur[g.ur(c + 1, j, k)] - v.ur[g.ur(c, j, k)]) / g.dr[c];
            force += sign * g.rc[c] * g.dth * g.dz[k] * mu_c(c, j, k) * (dur - (2.0 / 3.0) * div[g.cell(c, j, k)]);
          }
          if (i == 1) {  // the implicit μ∂_ru_r at the first centre takes the axis value u_r(0, θ) from here
            const double coef = mu_c(0, j, k) * g.rc[0] * g.dth * g.dz[k] / g.dr[0];
            force += coef * v.ur[g.ur(0, j, k)];
          }
          if (nt > 1)
            for (std::size_t b : {j, g.jp(j)}) {  // τ_rθ ⊃ μ r ∂_rω
              const double sign = b == j ? -1.0 : 1.0;
              const double tau =
                  mu.rt[g.ur(i, b, k)] * g.rf[i] * (omega(v, i, b, k) - omega(v, i - 1, b, k)) / g.drc[i];
              force += sign * tau * g.drc[i] * g.dz[k];
            }
          for (std::size_t f : {k, k + 1}) {  // τ_rz ⊃ μ ∂_ru_z
            const double sign = f == k + 1 ? 1.0 : -1.0;
            force += sign * mu_rz(mu, i, j, f) * duz_dr(v, i, j, f) * g.rf[i] * g.drc[i] * g.dth;
          }
          // Hoop term −τ_θθ/r ⊃ −[μu_r/r + 2μ∂_θω − (2/3)μ∇·u]/r at the face.
          const double mu_f = 0.5 * (mu_c(i - 1, j, k) + mu_c(i, j, k));
          double dtheta_w = 0;
          if (nt > 1)
            for (std::size_t c : {i - 1, i}) dtheta_w += 0.5 * (omega(v, c, g.jp(j), k) - omega(v, c, j, k)) / g.dth;
          const double div_f = 0.5 * (div[g.cell(i - 1, j, k)] + div[g.cell(i, j, k)]);
          force -= mu_f * (v.ur[g.ur(i, j, k)] / g.rf[i] + 2.0 * dtheta_w - (2.0 / 3.0) * div_f) * g.drc[i] * g.dth *
                   g.dz[k];
          out.r[g.row_r(i, j, k)] = force;
        }
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 0; k < nz; ++k) {
          double torque = 0;
          if (nt > 1) {
            for (std::size_t f : {i, i + 1}) {  // r²τ_rθ ⊃ r μ ∂_θu_r
              if (f == 0 || f == nr) continue;
              const double sign = f == i + 1 ? 1.0 : -1.0;
              torque +=
                  sign * g.rf[f] * g.dz[k] * mu.rt[g.ur(f, j, k)] * (v.ur[g.ur(f, j, k)] - v.ur[g.ur(f, g.jm(j), k)]);
            }
            for (std::size_t f : {k, k + 1}) {  // r τ_θz ⊃ μ ∂_θu_z, ∫ r dr
              if (f == 0 || f == nz) continue;
              const double sign = f == k + 1 ? 1.0 : -1.0;
              torque += sign * mu.tz[g.uz(i, j, f)] * g.a1[i] * (v.uz[g.uz(i, j, f)] - v.uz[g.uz(i, g.jm(j), f)]);
            }
          }
          for (std::size_t c : {g.jm(j), j}) {  // r τ_θθ ⊃ μ r∂_θω + 2μu_r − (2/3)μ r ∇·u
            if (nt == 1) break;
            const double sign = c == j ? 1.0 : -1.0;
            const double ur_mean = 0.5 * (v.ur[g.ur(i, c, k)] + v.ur[g.ur(i + 1, c, k)]);
            const double dtheta_w = (omega(v, i, g.jp(c), k) - omega(v, i, c, k)) / g.dth;
            torque += sign * g.dz[k] * mu_c(i, c, k) *
                      (dtheta_w * g.a1[i] + 2.0 * ur_mean * g.dr[i] - (2.0 / 3.0) * div[g.cell(i, c, k)] * g.a1[i]);
          }
          out.w[g.cell(i, j, k)] = torque;
        }
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t j = 0; j < nt; ++j)
        for (std::size_t k = 1; k < nz; ++k) {
          double force = 0;
          for (std::size_t c : {k - 1, k}) {  // τ_zz ⊃ μ∂_zu_z − (2/3)μ∇·u
            const double sign = c == k ? 1.0 : -1.0;
            const double duz = (v.uz[g.uz(i, j, c + 1)] - v.uz[g.uz(i, j, c)]) / g.dz[c];
            force += sign * g.a1[i] * g.dth * mu_c(i, j, c) * (duz - (2.0 / 3.0) * div[g.cell(i, j, c)]);
          }
          for (std::size_t f : {i, i + 1}) {  // τ_rz ⊃ μ ∂_zu_r
            if (f == 0 || f == nr) continue;
            const double sign = f == i + 1 ? 1.0 : -1.0;
            force += sign * mu_rz(mu, f, j, k) * dur_dz(v, f, j, k) * g.rf[f] * g.dth * g.dzc[k];
          }
          if (nt > 1)
            for (std::size_t b : {j, g.jp(j)}) {  // τ_θz ⊃ μ ∂_zu_θ
              const double sign = b == j ? -1.0 : 1.0;
              const double duz = (v.ut[g.cell(i, b, k)] - v.ut[g.cell(i, b, k - 1)]) / g.dzc[k];
              force += sign * mu.tz[g.uz(i, b, k)] * duz * g.dr[i] * g.dzc[k];
            }
          out.z[g.row_z(i, j, k)] = force;
        }
    return out;
  }

  // ---- the step ---------------------------------------------------------------------------
  struct Candidate {
    Velocity u;
    std::vector<double> p;
    PressureSolver::Result pressure;
    double max_divergence = 0;
  };

  double source_value(const std::vector<double>& s, std::size_t c) const { return s.empty() ? 0.0 : s[c]; }

  // Integrated Σ_faces ε_f u_n A_f per cell with the pressure solver's face ε (or, with
  // `magnitude`, Σ_faces |ε_f u_n A_f|: the scale against which continuity is judged).
  std::vector<double> flux_divergence(const Velocity& v, const std::vector<double>& e, bool magnitude = false) const {
    std::vector<double> d(g.nc);
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          double flux = 0;
          const auto add = [&](double sign, double value) { flux += magnitude ? std::abs(value) : sign * value; };
          if (i + 1 < g.nr)
            add(1, CellFields::face_r(e, g, i + 1, j, k) * g.rf[i + 1] * g.dth * g.dz[k] * v.ur[g.ur(i + 1, j, k)]);
          if (i > 0) add(-1, CellFields::face_r(e, g, i, j, k) * g.rf[i] * g.dth * g.dz[k] * v.ur[g.ur(i, j, k)]);
          if (g.nt > 1) {
            add(1, CellFields::face_t(e, g, i, g.jp(j), k) * g.dr[i] * g.dz[k] * v.ut[g.cell(i, g.jp(j), k)]);
            add(-1, CellFields::face_t(e, g, i, j, k) * g.dr[i] * g.dz[k] * v.ut[g.cell(i, j, k)]);
          }
          if (k + 1 < g.nz) add(1, CellFields::face_z(e, g, i, j, k + 1) * g.a1[i] * g.dth * v.uz[g.uz(i, j, k + 1)]);
          if (k > 0) add(-1, CellFields::face_z(e, g, i, j, k) * g.a1[i] * g.dth * v.uz[g.uz(i, j, k)]);
          d[g.cell(i, j, k)] = flux;
        }
    return d;
  }

  // v ← v − scale ∇φ with the gradients of the Poisson operator.
  void correct(Velocity& v, const Eigen::VectorXd& phi, double scale) const {
    const auto ph = [&](std::size_t i, std::size_t j, std::size_t k) {
      return phi[static_cast<Eigen::Index>(g.cell(i, j, k))];
    };
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          if (i > 0) v.ur[g.ur(i, j, k)] -= scale * (ph(i, j, k) - ph(i - 1, j, k)) / g.drc[i];
          if (g.nt > 1) v.ut[g.cell(i, j, k)] -= scale * (ph(i, j, k) - ph(i, g.jm(j), k)) / (g.reff[i] * g.dth);
          if (k > 0) v.uz[g.uz(i, j, k)] -= scale * (ph(i, j, k) - ph(i, j, k - 1)) / g.dzc[k];
        }
    impose_boundary_values(g, v);
  }

  [[noreturn]] void fail(StepFailure kind, const std::string& message, StepReport report) const {
    throw StepError(kind, "TransientSolver: " + message, report);
  }

  StepReport advance(double dt) {
    const auto start = std::chrono::steady_clock::now();
    StepReport report;
    report.time_step = dt;
    report.time = time;
    if (!(dt > 0) || !std::isfinite(dt))
      throw std::invalid_argument(fmt::format("TransientSolver::advance: dt = {} s, expected a finite value > 0", dt));
    const CourantResult before = courant(u, dt);
    report.courant = before.value;
    if (!(before.value <= params.max_courant))
      fail(StepFailure::courant_exceeded,
           fmt::format(
               "Courant number {:.4g} at cell (i={}, j={}, k={}) exceeds max_courant = {:.4g} for dt = {:.4g} s; "
               "use dt <= {:.4g} s",
               before.value, before.i, before.j, before.k, params.max_courant, dt,
               dt * params.max_courant / before.value),
           report);

    // SBDF2 coefficients (variable step); BDF1 after a reset and when the step grows by more
    // than max_step_ratio (variable-step BDF2 is zero-stable only for ratios below 1 + √2).
    double a0 = 1, a1 = -1, a2 = 0, w = 0;
    const bool second_order = have_old && dt <= max_step_ratio * dt_old;
    if (second_order) {
      w = dt / dt_old;
      a0 = (1 + 2 * w) / (1 + w);
      a1 = -(1 + w);
      a2 = w * w / (1 + w);
    }
    Velocity ue = u;
    if (second_order) {
      const auto extrapolate = [w](std::vector<double>& out, const std::vector<double>& now,
                                   const std::vector<double>& old) {
        for (std::size_t n = 0; n < out.size(); ++n) out[n] = (1 + w) * now[n] - w * old[n];
      };
      extrapolate(ue.ur, u.ur, u_old.ur);
      extrapolate(ue.ut, u.ut, u_old.ut);
      extrapolate(ue.uz, u.uz, u_old.uz);
      impose_boundary_values(g, ue);
    }
    const ViscosityField mu = evaluate_viscosity(ue);
    for (const std::vector<double>* field : {&mu.centre, &mu.rt, &mu.tz_moment, &mu.wall_rz})
      if (!all_finite(*field))
        fail(
            StepFailure::non_finite,
            fmt::format("the rheology law '{}' returned a non-finite viscosity (NaN or inf) at t = {:.6g} s (step {}); "
                        "the state before the step is kept",
                        params.rheology->name(), time, steps + 1),
            report);
    const Explicit conv = convection(ue, eps_next);
    const Explicit cross = viscous_cross(ue, mu);

    Candidate next;
    next.u = u;
    try {
      solve_predictor(dt, a0, a1, a2, mu, conv, cross, next.u);
    } catch (const std::runtime_error& e) {
      fail(StepFailure::linear_solver, e.what(), report);
    }

    if (!all_finite(next.u.ur) || !all_finite(next.u.ut) || !all_finite(next.u.uz))
      fail(
          StepFailure::non_finite,
          fmt::format("NaN or inf in the predicted velocity at t = {:.6g} s (step {}, dt = {:.4g} s); the state before "
                      "the step is kept",
                      time + dt, steps + 1, dt),
          report);

    // Projection.
    try {
      pressure_solver.set_void_fraction(eps_next);
    } catch (const std::runtime_error& e) {
      fail(StepFailure::linear_solver, e.what(), report);
    }
    const std::vector<double> flux = flux_divergence(next.u, eps_next);
    const std::vector<double> flux_magnitude = flux_divergence(next.u, eps_next, true);
    Eigen::VectorXd b(static_cast<Eigen::Index>(g.nc));
    const double scale = dt / (a0 * params.density);
    double flux_scale = 0;
    // BDF2 ∂ε/∂t with a₁ = −a₀ − a₂ substituted: exactly zero where ε does not change.
    const auto eps_rate = [&](std::size_t c) {
      return (a0 * (eps_next[c] - eps_now[c]) + a2 * (eps_old[c] - eps_now[c])) / dt;
    };
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          const std::size_t c = g.cell(i, j, k);
          const double rate = g.volume(i, k) * eps_rate(c);
          b[static_cast<Eigen::Index>(c)] = -(flux[c] + rate) / scale;
          const double magnitude = (flux_magnitude[c] + std::abs(rate)) / scale;
          flux_scale += magnitude * magnitude;
        }
    Eigen::VectorXd phi;
    next.pressure =
        pressure_solver.solve(b, phi, params.pressure_tolerance, params.pressure_max_iterations, std::sqrt(flux_scale));
    report.pressure_iterations = next.pressure.iterations;
    report.viscous_iterations = predictor_iterations;
    report.pressure_residual = next.pressure.residual;
    if (!next.pressure.converged)
      fail(StepFailure::linear_solver,
           fmt::format("pressure PCG did not reach the relative residual {:.3g} in {} iterations (last {:.3g})",
                       params.pressure_tolerance, next.pressure.iterations, next.pressure.residual),
           report);
    const std::vector<double> div_star = velocity_divergence(next.u);
    correct(next.u, phi, scale);
    // Rotational pressure update: p += φ − μ∇·(u* − u^(n+1)), the viscous stress of the
    // gradient the projection removed. Without it the pressure update φ ∝ ρ/Δt vanishes at
    // large viscous Courant numbers and the pressure converges like an Uzawa iteration with a
    // tiny step; the term is zero at a steady state.
    const std::vector<double> div_new = velocity_divergence(next.u);
    next.p = p;
    for (std::size_t c = 0; c < g.nc; ++c)
      next.p[c] += phi[static_cast<Eigen::Index>(c)] - mu.centre[c] * (div_star[c] - div_new[c]);
    remove_volume_mean(next.p);

    // Continuity residual after the projection.
    const std::vector<double> flux_after = flux_divergence(next.u, eps_next);
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          const std::size_t c = g.cell(i, j, k);
          next.max_divergence = std::max(next.max_divergence, std::abs(flux_after[c] / g.volume(i, k) + eps_rate(c)));
        }
    report.max_divergence = next.max_divergence;

    // Health of the candidate: finite, and no blow-up.
    if (!all_finite(next.u.ur) || !all_finite(next.u.ut) || !all_finite(next.u.uz) || !all_finite(next.p))
      fail(StepFailure::non_finite,
           fmt::format("NaN or inf in the velocity or pressure at t = {:.6g} s (step {}, dt = {:.4g} s); "
                       "the state before the step is kept",
                       time + dt, steps + 1, dt),
           report);
    const double speed = std::max({max_abs(next.u.ur), max_abs(next.u.ut), max_abs(next.u.uz)});
    const double reference = reference_speed(dt);
    if (speed > params.blow_up_factor * reference)
      fail(StepFailure::diverged,
           fmt::format(
               "velocity {:.4g} m/s at t = {:.6g} s exceeds blow_up_factor × reference speed ({:.4g} × {:.4g} m/s); "
               "reduce dt (was {:.4g} s) — the state before the step is kept",
               speed, time + dt, params.blow_up_factor, reference, dt),
           report);

    // Commit.
    u_old = std::move(u);
    u = std::move(next.u);
    p = std::move(next.p);
    eps_old = eps_now;
    eps_now = eps_next;
    time += dt;
    dt_old = dt;
    ++steps;
    have_old = true;
    update_diagnostics();
    report.time = time;
    report.courant = courant(u, dt).value;
    report.torque = torque_top;
    report.bottom_torque = torque_bottom;
    report.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
  }

  // Speed scale against which a blow-up is judged: plates, current flow, what the source, the
  // gravity and the change of ε can drive within one step.
  double reference_speed(double dt) const {
    const double radius = g.rf[g.nr], gap = g.zf[g.nz];
    double ref = std::max(std::abs(omega_top()), std::abs(omega_bottom())) * radius;
    ref += std::max({max_abs(u.ur), max_abs(u.ut), max_abs(u.uz)});
    const double eps_min = *std::min_element(eps_next.begin(), eps_next.end());
    const double force = std::max({max_abs(source_r), max_abs(source_t), max_abs(source_z)});
    ref += dt * (force / (params.density * eps_min) + std::abs(params.axial_gravity));
    double deps = 0;
    for (std::size_t c = 0; c < g.nc; ++c) deps = std::max(deps, std::abs(eps_next[c] - eps_now[c]));
    ref += std::max(radius, gap) * deps / (dt * eps_min);
    return std::max(ref, 1e-30);
  }

  void remove_volume_mean(std::vector<double>& field) const {
    double sum = 0, volume = 0;
    for (std::size_t i = 0; i < g.nr; ++i)
      for (std::size_t j = 0; j < g.nt; ++j)
        for (std::size_t k = 0; k < g.nz; ++k) {
          sum += field[g.cell(i, j, k)] * g.volume(i, k);
          volume += g.volume(i, k);
        }
    const double mean = sum / volume;
    for (double& x : field) x -= mean;
  }

  // Assembles and solves the three implicit viscous systems (divided by ε^(n+1) of the control
  // volume, which makes each symmetric positive definite); writes u* into `star`.
  void solve_predictor(double dt, double a0, double a1, double a2, const ViscosityField& mu, const Explicit& conv,
                       const Explicit& cross, Velocity& star) {
    const std::size_t nr = g.nr, nt = g.nt, nz = g.nz;
    const double rho = params.density;
    const auto mu_c = [&](std::size_t i, std::size_t j, std::size_t k) { return mu.centre[g.cell(i, j, k)]; };
    Triplets t;
    predictor_iterations = 0;
    const auto run = [&](PredictorSystem& system, std::string_view name, std::size_t n, const Triplets& triplets,
                         const Eigen::VectorXd& rhs, const Eigen::VectorXd& guess, Eigen::VectorXd& x) {
      const auto outcome = system.solve(n, triplets, rhs, guess, static_cast<std::size_t>(params.direct_solver_limit),
                                        params.viscous_tolerance, params.viscous_max_iterations, x);
      if (!outcome.ok) throw std::runtime_error(fmt::format("{} predictor: {}", name, outcome.failure));
      predictor_iterations = std::max(predictor_iterations, outcome.iterations);
    };

    // ---- u_r --------------------------------------------------------------------------------
    {
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(g.rows_r()));
      t.clear();
      for (std::size_t i = 1; i < nr; ++i)
        for (std::size_t j = 0; j < nt; ++j)
          for (std::size_t k = 0; k < nz; ++k) {
            const std::size_t row = g.row_r(i, j, k), face = g.ur(i, j, k);
            const auto add = [&](std::size_t col, double value) {
              t.emplace_back(static_cast<int>(row), static_cast<int>(col), value);
            };
            const double volume = g.rf[i] * g.drc[i] * g.dth * g.dz[k];
            const double en = CellFields::face_r(eps_next, g, i, j, k);
            const double e0 = CellFields::face_r(eps_now, g, i, j, k);
            const double e1 = CellFields::face_r(eps_old, g, i, j, k);
            double diag = rho * a0 * volume / dt;
            double b = -rho * volume / dt * (a1 * e0 * u.ur[face] + a2 * e1 * u_old.ur[face]) / en;
            if (!drag.empty()) diag += 0.5 * (drag[g.cell(i - 1, j, k)] + drag[g.cell(i, j, k)]) * volume / en;
            b -= g.rf[i] * g.dth * g.dz[k] * (p[g.cell(i, j, k)] - p[g.cell(i - 1, j, k)]);
            for (std::size_t c : {i - 1, i}) {  // τ_rr ⊃ μ∂_ru_r at the centres (the other μ∂_ru_r explicit)
              const double k_rr = mu_c(c, j, k) * g.rc[c] * g.dth * g.dz[k] / g.dr[c];
              diag += k_rr;
              const std::size_t other = c == i ? i + 1 : i - 1;
              if (other != 0 && other != nr) add(g.row_r(other, j, k), -k_rr);  // axis: explicit; rim: u_r = 0
            }
            if (nt > 1)
              for (std::size_t b_edge : {j, g.jp(j)}) {  // τ_rθ ⊃ μ(1/r)∂_θu_r
                const double k_rt = mu.rt[g.ur(i, b_edge, k)] * g.drc[i] * g.dz[k] / (g.rf[i] * g.dth);
                diag += k_rt;
                add(g.row_r(i, b_edge == j ? g.jm(j) : g.jp(j), k), -k_rt);
              }
            for (std::size_t f : {k, k + 1}) {  // τ_rz ⊃ μ∂_zu_r (u_r = 0 on the plates)
              const double k_rz = mu_rz(mu, i, j, f) * g.rf[i] * g.drc[i] * g.dth / g.dzc[f];
              diag += k_rz;
              if (f != 0 && f != nz) add(g.row_r(i, j, f == k ? k - 1 : k + 1), -k_rz);
            }
            diag += 0.5 * (mu_c(i - 1, j, k) + mu_c(i, j, k)) * g.drc[i] * g.dth * g.dz[k] / g.rf[i];  // hoop ⊃ μu_r/r²
            const double source =
                0.5 * (source_value(source_r, g.cell(i - 1, j, k)) + source_value(source_r, g.cell(i, j, k))) * volume;
            b += cross.r[row] + (conv.r[row] + source) / en;
            add(row, diag);
            rhs[static_cast<Eigen::Index>(row)] = b;
          }
      Eigen::VectorXd guess(static_cast<Eigen::Index>(g.rows_r())), x;
      for (std::size_t i = 1; i < nr; ++i)
        for (std::size_t j = 0; j < nt; ++j)
          for (std::size_t k = 0; k < nz; ++k) guess[static_cast<Eigen::Index>(g.row_r(i, j, k))] = u.ur[g.ur(i, j, k)];
      run(system_r, "u_r", g.rows_r(), t, rhs, guess, x);
      for (std::size_t i = 1; i < nr; ++i)
        for (std::size_t j = 0; j < nt; ++j)
          for (std::size_t k = 0; k < nz; ++k) star.ur[g.ur(i, j, k)] = x[static_cast<Eigen::Index>(g.row_r(i, j, k))];
    }

    // ---- ω = u_θ/r_c, angular-momentum form -------------------------------------------------
    {
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(g.nc));
      t.clear();
      for (std::size_t i = 0; i < nr; ++i)
        for (std::size_t j = 0; j < nt; ++j)
          for (std::size_t k = 0; k < nz; ++k) {
            const std::size_t row = g.cell(i, j, k);
            const auto add = [&](std::size_t col, double value) {
              t.emplace_back(static_cast<int>(row), static_cast<int>(col), value);
            };
            const double inertia_moment = g.dth * g.dz[k] * g.r4[i];  // ∫ r · r dV per unit ω
            const double en = CellFields::face_t(eps_next, g, i, j, k);
            const double e0 = CellFields::face_t(eps_now, g, i, j, k);
            const double e1 = CellFields::face_t(eps_old, g, i, j, k);
            double diag = rho * a0 * inertia_moment / dt;
            double b =
                -rho * inertia_moment / dt * (a1 * e0 * omega(u, i, j, k) + a2 * e1 * omega(u_old, i, j, k)) / en;
            // Drag torque ∫ r βu_θ dV with the stored u_θ = r_c ω over the control volume, like the
            // source torque below, so that f_θ = βu_θ balances exactly.
            if (!drag.empty())
              diag += 0.5 * (drag[g.cell(i, g.jm(j), k)] + drag[g.cell(i, j, k)]) * g.rc[i] * g.dth * g.dz[k] *
                      g.r3[i] / en;
            if (nt > 1) b -= g.dz[k] * g.a1[i] * (p[g.cell(i, j, k)] - p[g.cell(i, g.jm(j), k)]);
            for (std::size_t f : {i, i + 1}) {  // r³μ∂_rω (none through axis and rim)
              if (f == 0 || f == nr) continue;
              const double k_r = g.dth * g.dz[k] * std::pow(g.rf[f], 3) * mu.rt[g.ur(f, j, k)] / g.drc[f];
              diag += k_r;
              add(g.cell(f == i ? i - 1 : i + 1, j, k), -k_r);
            }
            for (std::size_t f : {k, k + 1}) {  // ∫μr³dr ∂_zω; plates give ω_bottom, ω_top
              const double k_z = g.dth * mu.tz_moment[g.uz(i, j, f)] / g.dzc[f];
              diag += k_z;
              if (f == 0)
                b += k_z * omega_bottom();
              else if (f == nz)
                b += k_z * omega_top();
              else
                add(g.cell(i, j, f == k ? k - 1 : k + 1), -k_z);
            }
            if (nt > 1)
              for (std::size_t c :
                   {g.jm(j), j}) {  // r τ_θθ ⊃ μ r ∂_θω through the cell centres (the other half explicit)
                const double k_t = mu_c(i, c, k) * g.dz[k] * g.a1[i] / g.dth;
                diag += k_t;
                add(g.cell(i, c == j ? g.jp(j) : g.jm(j), k), -k_t);
              }
            const double source =
                0.5 * (source_value(source_t, g.cell(i, g.jm(j), k)) + source_value(source_t, g.cell(i, j, k))) *
                g.dth * g.dz[k] * g.r3[i];
            b += cross.w[row] + (conv.w[row] + source) / en;
            add(row, diag);
            rhs[static_cast<Eigen::Index>(row)] = b;
          }
      Eigen::VectorXd guess(static_cast<Eigen::Index>(g.nc)), x;
      for (std::size_t c = 0; c < g.nc; ++c) guess[static_cast<Eigen::Index>(c)] = u.ut[c] / g.rc[c / (nt * nz)];
      run(system_w, "ω", g.nc, t, rhs, guess, x);
      for (std::size_t i = 0; i < nr; ++i)
        for (std::size_t j = 0; j < nt; ++j)
          for (std::size_t k = 0; k < nz; ++k)
            star.ut[g.cell(i, j, k)] = g.rc[i] * x[static_cast<Eigen::Index>(g.cell(i, j, k))];
    }

    // ---- u_z --------------------------------------------------------------------------------
    {
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(g.rows_z()));
      t.clear();
      for (std::size_t i = 0; i < nr; ++i)
        for (std::size_t j = 0; j < nt; ++j)
          for (std::size_t k = 1; k < nz; ++k) {
            const std::size_t row = g.row_z(i, j, k), face = g.uz(i, j, k);
            const auto add = [&](std::size_t col, double value) {
              t.emplace_back(static_cast<int>(row), static_cast<int>(col), value);
            };
            const double volume = g.a1[i] * g.dth * g.dzc[k];
            const double en = CellFields::face_z(eps_next, g, i, j, k);
            const double e0 = CellFields::face_z(eps_now, g, i, j, k);
            const double e1 = CellFields::face_z(eps_old, g, i, j, k);
            double diag = rho * a0 * volume / dt;
            double b = -rho * volume / dt * (a1 * e0 * u.uz[face] + a2 * e1 * u_old.uz[face]) / en;
            if (!drag.empty()) diag += 0.5 * (drag[g.cell(i, j, k - 1)] + drag[g.cell(i, j, k)]) * volume / en;
            b -= g.a1[i] * g.dth * (p[g.cell(i, j, k)] - p[g.cell(i, j, k - 1)]);
            for (std::size_t c : {k - 1, k}) {  // τ_zz ⊃ μ∂_zu_z (the other μ∂_zu_z explicit)
              const double k_zz = mu_c(i, j, c) * g.a1[i] * g.dth / g.dz[c];
              diag += k_zz;
              const std::size_t other = c == k ? k + 1 : k - 1;
              if (other != 0 && other != nz) add(g.row_z(i, j, other), -k_zz);
            }
            for (std::size_t f : {i, i + 1}) {  // τ_rz ⊃ μ∂_ru_z (none through axis and rim)
              if (f == 0 || f == nr) continue;
              const double k_rz = mu_rz(mu, f, j, k) * g.rf[f] * g.dth * g.dzc[k] / g.drc[f];
              diag += k_rz;
              add(g.row_z(f == i ? i - 1 : i + 1, j, k), -k_rz);
            }
            if (nt > 1)
              for (std::size_t b_edge : {j, g.jp(j)}) {  // τ_θz ⊃ μ(1/r)∂_θu_z
                const double k_tz = mu.tz[g.uz(i, b_edge, k)] * g.dr[i] * g.dzc[k] / (g.rc[i] * g.dth);
                diag += k_tz;
                add(g.row_z(i, b_edge == j ? g.jm(j) : g.jp(j), k), -k_tz);
              }
            const double source =
                0.5 * (source_value(source_z, g.cell(i, j, k - 1)) + source_value(source_z, g.cell(i, j, k))) * volume;
            b += cross.z[row] + (conv.z[row] + source) / en + rho * params.axial_gravity * volume;
            add(row, diag);
            rhs[static_cast<Eigen::Index>(row)] = b;
          }
      Eigen::VectorXd guess(static_cast<Eigen::Index>(g.rows_z())), x;
      for (std::size_t i = 0; i < nr; ++i)
        for (std::size_t j = 0; j < nt; ++j)
          for (std::size_t k = 1; k < nz; ++k) guess[static_cast<Eigen::Index>(g.row_z(i, j, k))] = u.uz[g.uz(i, j, k)];
      run(system_z, "u_z", g.rows_z(), t, rhs, guess, x);
      for (std::size_t i = 0; i < nr; ++i)
        for (std::size_t j = 0; j < nt; ++j)
          for (std::size_t k = 1; k < nz; ++k) star.uz[g.uz(i, j, k)] = x[static_cast<Eigen::Index>(g.row_z(i, j, k))];
    }
    impose_boundary_values(g, star);
  }

  // ---- sampling ---------------------------------------------------------------------------
  // Bracket x in sorted nodes: index a and weight t of nodes[a + 1].
  static std::pair<std::size_t, double> bracket(const std::vector<double>& nodes, double x) {
    if (x <= nodes.front()) return {0, 0.0};
    if (x >= nodes.back()) return {nodes.size() - 2, 1.0};
    const auto it = std::upper_bound(nodes.begin(), nodes.end(), x);
    const auto a = static_cast<std::size_t>(it - nodes.begin()) - 1;
    return {a, (x - nodes[a]) / (nodes[a + 1] - nodes[a])};
  }
  // Periodic bracket on θ_j = offset + jΔθ.
  std::tuple<std::size_t, std::size_t, double> bracket_theta(double theta, double offset) const {
    double s = (theta - offset) / g.dth;
    const double fl = std::floor(s);
    const double t = s - fl;
    const auto n = static_cast<long>(g.nt);
    long j0 = static_cast<long>(fl) % n;
    if (j0 < 0) j0 += n;
    return {static_cast<std::size_t>(j0), static_cast<std::size_t>((j0 + 1) % n), t};
  }

  template <class Value>
  double trilinear(const std::vector<double>& rn, double theta_offset, const std::vector<double>& zn,
                   const CylindricalPoint& pt, Value value) const {
    const auto [a, tr] = bracket(rn, pt.r);
    const auto [j0, j1, tt] = bracket_theta(pt.theta, theta_offset);
    const auto [c, tz] = bracket(zn, pt.z);
    double sum = 0;
    for (int da = 0; da < 2; ++da)
      for (int db = 0; db < 2; ++db)
        for (int dc = 0; dc < 2; ++dc) {
          const double weight = (da ? tr : 1 - tr) * (db ? tt : 1 - tt) * (dc ? tz : 1 - tz);
          if (weight == 0.0) continue;
          sum += weight * value(a + static_cast<std::size_t>(da), db ? j1 : j0, c + static_cast<std::size_t>(dc));
        }
    return sum;
  }

  std::vector<CylindricalVelocity> sample(std::span<const CylindricalPoint> points) const {
    const double radius = g.rf[g.nr], gap = g.zf[g.nz];
    std::vector<double> r_ext{0.0}, z_ext{0.0};  // centres extended by the boundaries
    r_ext.insert(r_ext.end(), g.rc.begin(), g.rc.end());
    r_ext.push_back(radius);
    z_ext.insert(z_ext.end(), g.zc.begin(), g.zc.end());
    z_ext.push_back(gap);
    std::vector<std::pair<double, double>> axis(g.nz);
    for (std::size_t k = 0; k < g.nz; ++k) axis[k] = axis_velocity(g, u.ur, k);
    std::vector<CylindricalVelocity> out;
    out.reserve(points.size());
    for (const CylindricalPoint& raw : points) {
      CylindricalPoint pt = raw;
      pt.r = std::clamp(pt.r, 0.0, radius);
      pt.z = std::clamp(pt.z, 0.0, gap);
      CylindricalVelocity vel;
      vel.radial = trilinear(g.rf, 0.5 * g.dth, z_ext, pt, [&](std::size_t a, std::size_t j, std::size_t c) {
        if (c == 0 || c == g.nz + 1) return 0.0;
        return u.ur[g.ur(a, j, c - 1)];
      });
      vel.azimuthal = trilinear(r_ext, 0.0, z_ext, pt, [&](std::size_t a, std::size_t j, std::size_t c) {
        const double r = r_ext[a];
        if (c == 0) return omega_bottom() * r;
        if (c == g.nz + 1) return omega_top() * r;
        if (a == 0) {  // Cartesian axis velocity seen in direction θ_j
          const double th = static_cast<double>(j) * g.dth;
          return -axis[c - 1].first * std::sin(th) + axis[c - 1].second * std::cos(th);
        }
        if (a == g.nr + 1) return omega(u, g.nr - 1, j, c - 1) * radius;  // shear-free rim: ∂_rω = 0
        return u.ut[g.cell(a - 1, j, c - 1)];
      });
      vel.axial = trilinear(r_ext, 0.5 * g.dth, g.zf, pt, [&](std::size_t a, std::size_t j, std::size_t c) {
        if (a == 0) {
          double mean = 0;
          for (std::size_t b = 0; b < g.nt; ++b) mean += u.uz[g.uz(0, b, c)];
          return mean / static_cast<double>(g.nt);
        }
        if (a == g.nr + 1) return u.uz[g.uz(g.nr - 1, j, c)];
        return u.uz[g.uz(a - 1, j, c)];
      });
      out.push_back(vel);
    }
    return out;
  }
};

namespace {

void check_params(const TransientParams& p) {
  const auto bad = [](const std::string& what) { throw std::invalid_argument("TransientSolver: " + what); };
  if (p.grid.radial_cells < 2)
    bad(fmt::format("grid.radial_cells = {} is out of range, expected >= 2", p.grid.radial_cells));
  if (p.grid.axial_cells < 2)
    bad(fmt::format("grid.axial_cells = {} is out of range, expected >= 2", p.grid.axial_cells));
  // The plate stencils here assume equal wall cells; only the steady swirl solver stretches z.
  if (p.grid.axial_stretching != 0.0)
    bad(fmt::format("grid.axial_stretching = {} is not supported, expected 0 (uniform axial cells)",
                    p.grid.axial_stretching));
  if (!(p.density > 0) || !std::isfinite(p.density))
    bad(fmt::format("density = {} kg/m³ is out of range, expected > 0", p.density));
  if (!p.rheology) bad("rheology must be set");
  if (!std::isfinite(p.top_angular_velocity)) bad("top_angular_velocity must be finite");
  if (!std::isfinite(p.bottom_angular_velocity)) bad("bottom_angular_velocity must be finite");
  if (!std::isfinite(p.axial_gravity)) bad("axial_gravity must be finite");
  if (!(p.max_courant > 0)) bad(fmt::format("max_courant = {} is out of range, expected > 0", p.max_courant));
  if (!(p.pressure_tolerance > 0))
    bad(fmt::format("pressure_tolerance = {} is out of range, expected > 0", p.pressure_tolerance));
  if (p.pressure_max_iterations < 1)
    bad(fmt::format("pressure_max_iterations = {} is out of range, expected >= 1", p.pressure_max_iterations));
  if (p.direct_solver_limit < 0)
    bad(fmt::format("direct_solver_limit = {} is out of range, expected >= 0", p.direct_solver_limit));
  if (!(p.viscous_tolerance > 0))
    bad(fmt::format("viscous_tolerance = {} is out of range, expected > 0", p.viscous_tolerance));
  if (p.viscous_max_iterations < 1)
    bad(fmt::format("viscous_max_iterations = {} is out of range, expected >= 1", p.viscous_max_iterations));
  if (!(p.blow_up_factor > 1)) bad(fmt::format("blow_up_factor = {} is out of range, expected > 1", p.blow_up_factor));
}

TransientParams checked(TransientParams p) {
  check_params(p);
  return p;
}

void check_size(std::string_view name, std::size_t got, std::size_t expected) {
  if (got != expected)
    throw std::invalid_argument(fmt::format("TransientSolver: {} has {} values, expected {}", name, got, expected));
}

}  // namespace

TransientSolver::TransientSolver(TransientParams params) : impl_(std::make_unique<Impl>(checked(std::move(params)))) {}
TransientSolver::~TransientSolver() = default;
TransientSolver::TransientSolver(TransientSolver&&) noexcept = default;
TransientSolver& TransientSolver::operator=(TransientSolver&&) noexcept = default;

StepReport TransientSolver::advance(double dt) { return impl_->advance(dt); }

namespace {
void check_void_fraction(std::span<const double> void_fraction, std::size_t cells) {
  check_size("void_fraction", void_fraction.size(), cells);
  for (std::size_t c = 0; c < void_fraction.size(); ++c)
    if (!(void_fraction[c] > 0 && void_fraction[c] <= 1))
      throw std::invalid_argument(fmt::format(
          "TransientSolver: void_fraction[{}] = {} is out of range, expected 0 < ε <= 1", c, void_fraction[c]));
}
}  // namespace

void TransientSolver::set_void_fraction(std::span<const double> void_fraction) {
  Impl& m = *impl_;
  check_void_fraction(void_fraction, m.g.nc);
  m.eps_next.assign(void_fraction.begin(), void_fraction.end());
}

void TransientSolver::reset_void_fraction(std::span<const double> void_fraction) {
  Impl& m = *impl_;
  check_void_fraction(void_fraction, m.g.nc);
  m.eps_next.assign(void_fraction.begin(), void_fraction.end());
  m.eps_now = m.eps_old = m.eps_next;
}

void TransientSolver::set_pressure(std::span<const double> pressure) {
  Impl& m = *impl_;
  check_size("pressure", pressure.size(), m.g.nc);
  if (!std::all_of(pressure.begin(), pressure.end(), [](double x) { return std::isfinite(x); }))
    throw std::invalid_argument("TransientSolver: pressure contains a non-finite value");
  m.p.assign(pressure.begin(), pressure.end());
  m.remove_volume_mean(m.p);
}

void TransientSolver::set_momentum_source(const MomentumSource& source) {
  Impl& m = *impl_;
  const auto copy = [&](std::string_view name, std::span<const double> in, std::vector<double>& out) {
    if (in.empty()) {
      out.clear();
      return;
    }
    check_size(name, in.size(), m.g.nc);
    for (double x : in)
      if (!std::isfinite(x))
        throw std::invalid_argument(fmt::format("TransientSolver: {} contains a non-finite value", name));
    out.assign(in.begin(), in.end());
  };
  copy("momentum source radial", source.radial, m.source_r);
  copy("momentum source azimuthal", source.azimuthal, m.source_t);
  copy("momentum source axial", source.axial, m.source_z);
  copy("drag_coefficient", source.drag_coefficient, m.drag);
  for (double b : m.drag)
    if (b < 0) throw std::invalid_argument("TransientSolver: drag_coefficient must be >= 0 kg/(m³·s)");
}

void TransientSolver::set_top_angular_velocity(double angular_velocity) {
  if (!std::isfinite(angular_velocity))
    throw std::invalid_argument("TransientSolver: top angular velocity must be finite");
  impl_->params.top_angular_velocity = angular_velocity;
}

void TransientSolver::set_velocity(std::span<const double> radial, std::span<const double> azimuthal,
                                   std::span<const double> axial) {
  Impl& m = *impl_;
  check_size("radial velocity", radial.size(), m.g.n_ur());
  check_size("azimuthal velocity", azimuthal.size(), m.g.nc);
  check_size("axial velocity", axial.size(), m.g.n_uz());
  m.u.ur.assign(radial.begin(), radial.end());
  m.u.ut.assign(azimuthal.begin(), azimuthal.end());
  m.u.uz.assign(axial.begin(), axial.end());
  impose_boundary_values(m.g, m.u);
  m.u_old = m.u;
  m.have_old = false;
  m.update_diagnostics();
}

int TransientSolver::project_velocity() {
  Impl& m = *impl_;
  m.pressure_solver.set_void_fraction(m.eps_now);
  const std::vector<double> flux = m.flux_divergence(m.u, m.eps_now);
  const std::vector<double> magnitude = m.flux_divergence(m.u, m.eps_now, true);
  Eigen::VectorXd b(static_cast<Eigen::Index>(m.g.nc));
  double reference = 0;
  for (std::size_t c = 0; c < m.g.nc; ++c) {
    b[static_cast<Eigen::Index>(c)] = -flux[c];
    reference += magnitude[c] * magnitude[c];
  }
  Eigen::VectorXd phi;
  const auto result = m.pressure_solver.solve(b, phi, m.params.pressure_tolerance, m.params.pressure_max_iterations,
                                              std::sqrt(reference));
  if (!result.converged)
    throw StepError(
        StepFailure::linear_solver,
        fmt::format("TransientSolver::project_velocity: PCG did not converge ({} iterations, residual {:.3g})",
                    result.iterations, result.residual),
        StepReport{});
  m.correct(m.u, phi, 1.0);
  m.u_old = m.u;
  m.have_old = false;
  m.update_diagnostics();
  return result.iterations;
}

std::span<const double> TransientSolver::radial_velocity() const { return impl_->u.ur; }
std::span<const double> TransientSolver::azimuthal_velocity() const { return impl_->u.ut; }
std::span<const double> TransientSolver::axial_velocity() const { return impl_->u.uz; }
std::span<const double> TransientSolver::pressure() const { return impl_->p; }
std::span<const double> TransientSolver::viscosity() const { return impl_->mu_now.centre; }
std::span<const double> TransientSolver::shear_rate() const { return impl_->mu_now.shear_rate; }
std::span<const double> TransientSolver::void_fraction() const { return impl_->eps_now; }

std::vector<double> TransientSolver::divergence() const {
  const Impl& m = *impl_;
  std::vector<double> d = m.flux_divergence(m.u, m.eps_now);
  for (std::size_t i = 0; i < m.g.nr; ++i)
    for (std::size_t j = 0; j < m.g.nt; ++j)
      for (std::size_t k = 0; k < m.g.nz; ++k) d[m.g.cell(i, j, k)] /= m.g.volume(i, k);
  return d;
}

std::vector<CylindricalVelocity> TransientSolver::sample_velocity(std::span<const CylindricalPoint> points) const {
  return impl_->sample(points);
}

double TransientSolver::torque() const { return impl_->torque_top; }
double TransientSolver::bottom_torque() const { return impl_->torque_bottom; }
double TransientSolver::time() const { return impl_->time; }
long TransientSolver::step_count() const { return impl_->steps; }
double TransientSolver::courant_number(double dt) const { return impl_->courant(impl_->u, dt).value; }
const CylindricalGrid& TransientSolver::grid() const { return impl_->grid; }
const TransientParams& TransientSolver::params() const { return impl_->params; }

}  // namespace rheosim::fluid
