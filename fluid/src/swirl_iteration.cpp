#include "swirl_iteration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rheosim/numerics/gmres.hpp"

namespace rheosim::fluid::swirl_detail {

SwirlSystem::SwirlSystem(const Layout& layout, const Discretisation& discretisation,
                         std::span<const double> torque_density, double angular_velocity, SwirlState scratch)
    : L(layout),
      disc_(discretisation),
      torque_density_(torque_density),
      velocity_scale_(std::abs(angular_velocity) * layout.rf[layout.nr] + 1e-300),
      omega_scale_(std::abs(angular_velocity) + 1e-300),
      scratch_(std::move(scratch)) {}

Eigen::VectorXd SwirlSystem::to_system(const SwirlState& st) const {
  Eigen::VectorXd z(static_cast<Eigen::Index>(L.unknowns()));
  for (std::size_t c = 0; c < L.nc; ++c) {
    z[static_cast<Eigen::Index>(L.omega(c / L.nz, c % L.nz))] = st.angular_velocity[c];
    z[static_cast<Eigen::Index>(L.pressure(c / L.nz, c % L.nz))] = st.pressure[c] - st.pressure[0];
  }
  for (std::size_t i = 1; i < L.nr; ++i)
    for (std::size_t k = 0; k < L.nz; ++k)
      z[static_cast<Eigen::Index>(L.radial(i, k))] = st.radial_velocity[L.ur_index(i, k)];
  for (std::size_t i = 0; i < L.nr; ++i)
    for (std::size_t k = 1; k < L.nz; ++k)
      z[static_cast<Eigen::Index>(L.axial(i, k))] = st.axial_velocity[L.uz_index(i, k)];
  return z;
}

void SwirlSystem::from_system(const Eigen::VectorXd& z, SwirlState& st) const {
  for (std::size_t c = 0; c < L.nc; ++c) {
    st.angular_velocity[c] = z[static_cast<Eigen::Index>(L.omega(c / L.nz, c % L.nz))];
    st.pressure[c] = z[static_cast<Eigen::Index>(L.pressure(c / L.nz, c % L.nz))];
  }
  for (std::size_t i = 1; i < L.nr; ++i)
    for (std::size_t k = 0; k < L.nz; ++k)
      st.radial_velocity[L.ur_index(i, k)] = z[static_cast<Eigen::Index>(L.radial(i, k))];
  for (std::size_t i = 0; i < L.nr; ++i)
    for (std::size_t k = 1; k < L.nz; ++k)
      st.axial_velocity[L.uz_index(i, k)] = z[static_cast<Eigen::Index>(L.axial(i, k))];
}

Eigen::VectorXd SwirlSystem::steady_residual(const Eigen::VectorXd& z) {
  from_system(z, scratch_);
  const ViscosityField m = disc_.viscosity(scratch_);
  disc_.assemble(scratch_, m, torque_density_, std::numeric_limits<double>::infinity(), residual_triplets_,
                 residual_rhs_);
  Eigen::VectorXd f = -residual_rhs_;
  for (const auto& e : residual_triplets_) f[e.row()] += e.value() * z[e.col()];
  return f;
}

Eigen::VectorXd SwirlSystem::newton_krylov_step(const SwirlState& state, const Eigen::VectorXd& x_picard,
                                                double pseudo_time_step, const SparseLu& factor,
                                                const Triplets& linearised) {
  const Eigen::VectorXd y0 = to_system(state);
  const Eigen::VectorXd f0 = steady_residual(y0);
  double p_scale = 0;
  for (std::size_t c = 0; c < L.nc; ++c)
    p_scale = std::max(p_scale, std::abs(x_picard[static_cast<Eigen::Index>(L.nc + c)]));
  Eigen::VectorXd scale = Eigen::VectorXd::Constant(y0.size(), velocity_scale_);
  scale.head(static_cast<Eigen::Index>(L.nc)).setConstant(omega_scale_);
  scale.segment(static_cast<Eigen::Index>(L.nc), static_cast<Eigen::Index>(L.nc))
      .setConstant(p_scale > 0 ? p_scale : 1.0);
  Eigen::VectorXd pseudo = Eigen::VectorXd::Zero(y0.size());
  if (std::isfinite(pseudo_time_step)) {
    Triplets tp;
    Eigen::VectorXd unused = Eigen::VectorXd::Zero(y0.size());
    disc_.add_pseudo_time(state, pseudo_time_step, tp, unused);
    for (const auto& e : tp) pseudo[e.row()] += e.value();
  }
  const Eigen::VectorXd b = (x_picard - y0).cwiseQuotient(scale);
  constexpr double h = 1e-7;  // forward-difference step in the scaled variables (O(1))
  const auto apply = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
    const Eigen::VectorXd w = v.cwiseProduct(scale);
    const Eigen::VectorXd jw = (steady_residual(y0 + h * w) - f0) / h + pseudo.cwiseProduct(w);
    return Eigen::VectorXd(factor.solve(jw)).cwiseQuotient(scale);
  };
  // Inexact Newton: the linear tolerance follows the size of the step (superlinear near the end).
  const double eta = std::clamp(b.lpNorm<Eigen::Infinity>(), 1e-6, 1e-2);
  const Eigen::VectorXd delta = numerics::gmres(apply, b, eta, 30);
  newton_step_size_ = delta.lpNorm<Eigen::Infinity>();
  // Backtracking on the row-scaled residual (rows scaled by Σ|a_rj| of the linearised
  // system): far from the solution the full step can overshoot, as plain Newton does.
  Eigen::VectorXd row_scale = Eigen::VectorXd::Constant(y0.size(), 1e-300);
  for (const auto& e : linearised) row_scale[e.row()] += std::abs(e.value());
  const double merit = f0.cwiseQuotient(row_scale).norm();
  const Eigen::VectorXd step = delta.cwiseProduct(scale);
  double lambda = 1;
  for (int trial = 0; trial < 6; ++trial, lambda *= 0.5) {
    const Eigen::VectorXd f = steady_residual(y0 + lambda * step);
    if (f.allFinite() && f.cwiseQuotient(row_scale).norm() < (1 - 1e-4 * lambda) * merit) break;
  }
  return Eigen::VectorXd(y0 + lambda * step);
}

SwirlState SwirlSystem::picard_state(const Eigen::VectorXd& x, const SwirlState& state) const {
  SwirlState picard = state;
  for (std::size_t c = 0; c < L.nc; ++c) picard.angular_velocity[c] = x[static_cast<Eigen::Index>(c)];
  if (L.inertia) {
    double mean_p = 0;
    for (std::size_t c = 0; c < L.nc; ++c) mean_p += x[static_cast<Eigen::Index>(L.nc + c)];
    mean_p /= static_cast<double>(L.nc);
    for (std::size_t c = 0; c < L.nc; ++c) picard.pressure[c] = x[static_cast<Eigen::Index>(L.nc + c)] - mean_p;
    for (std::size_t i = 1; i < L.nr; ++i)
      for (std::size_t k = 0; k < L.nz; ++k)
        picard.radial_velocity[L.ur_index(i, k)] = x[static_cast<Eigen::Index>(L.radial(i, k))];
    for (std::size_t i = 0; i < L.nr; ++i)
      for (std::size_t k = 1; k < L.nz; ++k)
        picard.axial_velocity[L.uz_index(i, k)] = x[static_cast<Eigen::Index>(L.axial(i, k))];
  }
  return picard;
}

Eigen::VectorXd SwirlSystem::pack(const SwirlState& st) const {
  Eigen::VectorXd v(static_cast<Eigen::Index>(L.inertia ? L.nc + (L.nr - 1) * L.nz + L.nr * (L.nz - 1) : L.nc));
  Eigen::Index j = 0;
  for (double w : st.angular_velocity) v[j++] = w / omega_scale_;
  if (L.inertia) {
    for (std::size_t i = 1; i < L.nr; ++i)
      for (std::size_t k = 0; k < L.nz; ++k) v[j++] = st.radial_velocity[L.ur_index(i, k)] / velocity_scale_;
    for (std::size_t i = 0; i < L.nr; ++i)
      for (std::size_t k = 1; k < L.nz; ++k) v[j++] = st.axial_velocity[L.uz_index(i, k)] / velocity_scale_;
  }
  return v;
}

void SwirlSystem::unpack(const Eigen::VectorXd& v, SwirlState& st) const {
  Eigen::Index j = 0;
  for (double& w : st.angular_velocity) w = v[j++] * omega_scale_;
  if (L.inertia) {
    for (std::size_t i = 1; i < L.nr; ++i)
      for (std::size_t k = 0; k < L.nz; ++k) st.radial_velocity[L.ur_index(i, k)] = v[j++] * velocity_scale_;
    for (std::size_t i = 0; i < L.nr; ++i)
      for (std::size_t k = 1; k < L.nz; ++k) st.axial_velocity[L.uz_index(i, k)] = v[j++] * velocity_scale_;
  }
}

double next_pseudo_time_step(double pseudo_time_step, double residual, double previous_residual,
                             double angular_velocity) {
  if (!std::isfinite(pseudo_time_step)) return pseudo_time_step;
  if (residual < previous_residual)
    pseudo_time_step *= std::min(4.0, 1.5 * previous_residual / residual);
  else
    pseudo_time_step *= 0.5;
  if (pseudo_time_step * std::abs(angular_velocity) > 1e4) return std::numeric_limits<double>::infinity();
  return pseudo_time_step;
}

std::optional<double> newton_floor(const std::vector<double>& changes, int& below_floor) {
  constexpr double floor_limit = 1e-5;
  below_floor = !changes.empty() && changes.back() < floor_limit ? below_floor + 1 : 0;
  if (below_floor < 5) return std::nullopt;
  const auto window = changes.end() - 5;
  const double largest = *std::max_element(window, changes.end());
  const double smallest = *std::min_element(window, changes.end());
  if (largest < 10.0 * smallest || largest < 1e-8) return largest;
  return std::nullopt;
}

}  // namespace rheosim::fluid::swirl_detail
