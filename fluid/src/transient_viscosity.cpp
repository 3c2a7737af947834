// μ and γ̇ of a velocity field on the staggered grid (TransientSolver::Impl).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "transient_impl.hpp"

namespace rheosim::fluid {

struct TransientSolver::Impl::EdgeGradients {
  // rθ-edges g_rt = ∂_rω, h_rt = ∂_θu_r/r_i (zero on axis and rim); θz-edges g_tz = ∂_zω,
  // h_tz = ∂_θu_z/r_c; rz-edges the full 2E_rz.
  std::vector<double> g_rt, h_rt, srz, g_tz, h_tz;
};

namespace {
struct Moments {  // ⟨g²⟩, ⟨gh⟩, ⟨h²⟩ over a cell's four edges of one kind
  double gg = 0, gh = 0, hh = 0;
  [[nodiscard]] double at(double r) const { return r * r * gg + 2 * r * gh + hh; }
};
}  // namespace

struct TransientSolver::Impl::CellStrain {
  std::vector<double> normal, a_rz;  // 2(e_rr² + e_θθ² + e_zz²); ⟨(2E_rz)²⟩ over the cell's rz-edges
  std::vector<Moments> m_rt, m_tz;
};

struct TransientSolver::Impl::ShearRates {
  std::size_t off_rt = 0, off_tz = 0, off_wall = 0;  // cells, rθ-edges, θz-edges × 3 Gauss points, plate rz-edges
  std::vector<double> rates;
};

TransientSolver::Impl::EdgeGradients TransientSolver::Impl::edge_gradients(const Velocity& v) const {
  const std::size_t nr = g.nr, nt = g.nt, nz = g.nz;
  EdgeGradients e{std::vector<double>(g.n_ur(), 0.0), std::vector<double>(g.n_ur(), 0.0), std::vector<double>(g.n_rz()),
                  std::vector<double>(g.n_uz()), std::vector<double>(g.n_uz())};
  for (std::size_t i = 0; i <= nr; ++i)
    for (std::size_t j = 0; j < nt; ++j) {
      if (i > 0 && i < nr)
        for (std::size_t k = 0; k < nz; ++k) {
          e.g_rt[g.ur(i, j, k)] = (omega(v, i, j, k) - omega(v, i - 1, j, k)) / g.drc[i];
          if (nt > 1) e.h_rt[g.ur(i, j, k)] = (v.ur[g.ur(i, j, k)] - v.ur[g.ur(i, g.jm(j), k)]) / (g.rf[i] * g.dth);
        }
      for (std::size_t k = 0; k <= nz; ++k) {
        e.srz[g.uz(i, j, k)] = strain_rz_for_viscosity(v, i, j, k);  // same index formula, i up to nr
        if (i < nr) {
          e.g_tz[g.uz(i, j, k)] = dw_dz_for_viscosity(v, i, j, k);
          e.h_tz[g.uz(i, j, k)] = duz_dtheta(v, i, j, k) / g.rc[i];
        }
      }
    }
  return e;
}

TransientSolver::Impl::CellStrain TransientSolver::Impl::cell_strain(const Velocity& v, const EdgeGradients& e) const {
  const std::size_t nr = g.nr, nt = g.nt, nz = g.nz, nc = g.nc;
  CellStrain out{std::vector<double>(nc), std::vector<double>(nc), std::vector<Moments>(nc), std::vector<Moments>(nc)};
  for (std::size_t i = 0; i < nr; ++i)
    for (std::size_t j = 0; j < nt; ++j)
      for (std::size_t k = 0; k < nz; ++k) {
        const std::size_t c = g.cell(i, j, k), jj = g.jp(j);
        const double err = (v.ur[g.ur(i + 1, j, k)] - v.ur[g.ur(i, j, k)]) / g.dr[i];
        double ett = 0.5 * (v.ur[g.ur(i, j, k)] + v.ur[g.ur(i + 1, j, k)]) / g.rc[i];
        if (nt > 1) ett += (omega(v, i, jj, k) - omega(v, i, j, k)) / g.dth;
        const double ezz = (v.uz[g.uz(i, j, k + 1)] - v.uz[g.uz(i, j, k)]) / g.dz[k];
        out.normal[c] = 2.0 * (err * err + ett * ett + ezz * ezz);
        Moments rt, tz;
        for (std::size_t b : {j, jj}) {
          for (std::size_t a : {i, i + 1}) {
            const std::size_t edge = g.ur(a, b, k);
            rt.gg += 0.25 * e.g_rt[edge] * e.g_rt[edge];
            rt.gh += 0.25 * e.g_rt[edge] * e.h_rt[edge];
            rt.hh += 0.25 * e.h_rt[edge] * e.h_rt[edge];
          }
          for (std::size_t f : {k, k + 1}) {
            const std::size_t edge = g.uz(i, b, f);
            tz.gg += 0.25 * e.g_tz[edge] * e.g_tz[edge];
            tz.gh += 0.25 * e.g_tz[edge] * e.h_tz[edge];
            tz.hh += 0.25 * e.h_tz[edge] * e.h_tz[edge];
          }
        }
        out.m_rt[c] = rt;
        out.m_tz[c] = tz;
        double s = 0;
        for (std::size_t a : {i, i + 1})
          for (std::size_t f : {k, k + 1}) s += e.srz[g.uz(a, j, f)] * e.srz[g.uz(a, j, f)];
        out.a_rz[c] = 0.25 * s;
      }
  return out;
}

// All shear rates in one array: one rheology call for the whole field.
TransientSolver::Impl::ShearRates TransientSolver::Impl::shear_rates(const EdgeGradients& e,
                                                                     const CellStrain& cs) const {
  const std::size_t nr = g.nr, nt = g.nt, nz = g.nz, nc = g.nc;
  ShearRates out;
  out.off_rt = nc;
  out.off_tz = nc + g.n_ur();
  out.off_wall = out.off_tz + 3 * g.n_uz();
  std::vector<double>& rates = out.rates;
  rates.assign(out.off_wall + 2 * (nr + 1) * nt, 0.0);
  const auto& normal = cs.normal;
  const auto& a_rz = cs.a_rz;
  const auto& m_rt = cs.m_rt;
  const auto& m_tz = cs.m_tz;
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
        const std::size_t edge = g.ur(i, j, k);
        const double s = g.rf[i] * e.g_rt[edge] + e.h_rt[edge];
        rates[out.off_rt + edge] = std::sqrt(s * s + rest);
      }
  for (std::size_t i = 0; i < nr; ++i) {
    const double mid = 0.5 * (g.rf[i] + g.rf[i + 1]), half = 0.5 * g.dr[i];
    for (std::size_t j = 0; j < nt; ++j)
      for (std::size_t k = 0; k <= nz; ++k) {
        const std::size_t edge = g.uz(i, j, k);
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
              for (std::size_t b : {g.jm(j), j}) rest += 0.25 * e.srz[g.uz(a, b, k)] * e.srz[g.uz(a, b, k)];
          }
          const double s = r * e.g_tz[edge] + e.h_tz[edge];
          rates[out.off_tz + 3 * edge + q] = std::sqrt(s * s + rest);
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
              gz_mean += e.g_tz[g.uz(a, b, k)];
              n += 1;
            }
        gz_mean /= n;
        const double shear = e.srz[g.uz(i, j, k)];
        rates[out.off_wall + (side * (nr + 1) + i) * nt + j] =
            std::sqrt(g.rf[i] * g.rf[i] * gz_mean * gz_mean + shear * shear);
      }
  }
  return out;
}

// μ(γ̇) at every rate, into the field's arrays; the θz-edges' flux moment ∫ μ r³ dr by the
// three Gauss points.
ViscosityField TransientSolver::Impl::viscosity_field(const ShearRates& sr) const {
  const std::size_t nr = g.nr, nt = g.nt, nz = g.nz, nc = g.nc;
  std::vector<double> mu(sr.rates.size());
  params.rheology->viscosity(sr.rates, mu);
  ViscosityField out;
  out.centre.assign(mu.begin(), mu.begin() + static_cast<std::ptrdiff_t>(nc));
  out.shear_rate.assign(sr.rates.begin(), sr.rates.begin() + static_cast<std::ptrdiff_t>(nc));
  out.rt.assign(mu.begin() + static_cast<std::ptrdiff_t>(sr.off_rt),
                mu.begin() + static_cast<std::ptrdiff_t>(sr.off_tz));
  out.wall_rz.assign(mu.begin() + static_cast<std::ptrdiff_t>(sr.off_wall), mu.end());
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
          w += gauss_weights[q] * mu[sr.off_tz + 3 * e + q] * r * r * r;
        }
        out.tz_moment[e] = w * half;
        out.tz[e] = out.tz_moment[e] / g.r4[i];
      }
  }
  return out;
}

ViscosityField TransientSolver::Impl::evaluate_viscosity(const Velocity& v) const {
  const EdgeGradients edges = edge_gradients(v);
  return viscosity_field(shear_rates(edges, cell_strain(v, edges)));
}

}  // namespace rheosim::fluid
