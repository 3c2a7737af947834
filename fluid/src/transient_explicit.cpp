// The explicit terms of a transient step: convection and the viscous cross terms.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "transient_impl.hpp"

namespace rheosim::fluid {

TransientSolver::Impl::Explicit TransientSolver::Impl::convection(const Velocity& v,
                                                                  const std::vector<double>& e) const {
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
        const double wbar =
            0.25 * (omega(v, i - 1, j, k) + omega(v, i, j, k) + omega(v, i - 1, g.jp(j), k) + omega(v, i, g.jp(j), k));
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

TransientSolver::Impl::Explicit TransientSolver::Impl::viscous_cross(const Velocity& v,
                                                                     const ViscosityField& mu) const {
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
            const double tau = mu.rt[g.ur(i, b, k)] * g.rf[i] * (omega(v, i, b, k) - omega(v, i - 1, b, k)) / g.drc[i];
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
        force -=
            mu_f * (v.ur[g.ur(i, j, k)] / g.rf[i] + 2.0 * dtheta_w - (2.0 / 3.0) * div_f) * g.drc[i] * g.dth * g.dz[k];
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

}  // namespace rheosim::fluid
