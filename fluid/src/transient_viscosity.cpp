// μ and γ̇ of a velocity field on the staggered grid (TransientSolver::Impl).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "transient_impl.hpp"

namespace rheosim::fluid {

ViscosityField TransientSolver::Impl::evaluate_viscosity(const Velocity& v) const {
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

}  // namespace rheosim::fluid
