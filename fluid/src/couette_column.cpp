// The horizontally averaged liquid of a plane-Couette gap (couette_column.hpp).
#include "rheosim/fluid/couette_column.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rheosim::fluid {

void CouetteColumnParams::check() const {
  const auto fail = [](const char* field, double value, const char* range) {
    throw std::invalid_argument(fmt::format("CouetteColumnParams::{} = {} is not {}", field, value, range));
  };
  if (!(std::isfinite(density) && density > 0.0)) fail("density", density, "> 0");
  if (!rheology) throw std::invalid_argument("CouetteColumnParams::rheology is null");
  if (!(std::isfinite(gap) && gap > 0.0)) fail("gap", gap, "> 0");
  if (layers < 1) fail("layers", layers, ">= 1");
  if (!std::isfinite(plate_speed)) fail("plate_speed", plate_speed, "finite");
  if (!(std::isfinite(area) && area > 0.0)) fail("area", area, "> 0");
}

CouetteColumn::CouetteColumn(CouetteColumnParams params)
    : params_((params.check(), std::move(params))),
      n_(static_cast<std::size_t>(params_.layers)),
      dz_(params_.gap / params_.layers),
      volume_(params_.area * dz_),
      ux_(n_),
      uy_(n_, 0.0),
      eps_(n_, 1.0),
      source_x_(n_, 0.0),
      source_y_(n_, 0.0),
      implicit_(n_, 0.0),
      face_mu_(n_ + 1),
      div_tau_x_(n_),
      div_tau_y_(n_),
      cell_mu_(n_),
      lower_(n_),
      diag_(n_),
      upper_(n_),
      rhs_(n_) {
  for (std::size_t k = 0; k < n_; ++k) ux_[k] = params_.plate_speed * centre(k) / params_.gap;
  update_viscosity();
}

std::array<double, 3> CouetteColumn::velocity_at(double z) const {
  const double gap = params_.gap, top = params_.plate_speed;
  z = std::clamp(z, 0.0, gap);
  const double s = z / dz_ - 0.5;  // position in units of layers from the first centre
  if (s <= 0.0) {
    const double w = z / (0.5 * dz_);
    return {w * ux_[0], w * uy_[0], 0.0};
  }
  if (s >= static_cast<double>(n_) - 1.0) {
    const double w = (gap - z) / (0.5 * dz_);  // weight of the last centre
    return {w * ux_[n_ - 1] + (1.0 - w) * top, w * uy_[n_ - 1], 0.0};
  }
  const auto k = static_cast<std::size_t>(s);
  const double w = s - static_cast<double>(k);
  return {(1.0 - w) * ux_[k] + w * ux_[k + 1], (1.0 - w) * uy_[k] + w * uy_[k + 1], 0.0};
}

std::array<double, 2> CouetteColumn::slope_at(double z) const {
  z = std::clamp(z, 0.0, params_.gap);
  const double s = z / dz_ - 0.5;
  if (s <= 0.0) return {ux_[0] / (0.5 * dz_), uy_[0] / (0.5 * dz_)};
  if (s >= static_cast<double>(n_) - 1.0)
    return {(params_.plate_speed - ux_[n_ - 1]) / (0.5 * dz_), -uy_[n_ - 1] / (0.5 * dz_)};
  const auto k = static_cast<std::size_t>(s);
  return {(ux_[k + 1] - ux_[k]) / dz_, (uy_[k + 1] - uy_[k]) / dz_};
}

double CouetteColumn::mean_fluid_stress() const {
  double sum = 0.0;
  for (std::size_t f = 0; f <= n_; ++f) {
    const double below = f == 0 ? 0.0 : ux_[f - 1];
    const double above = f == n_ ? params_.plate_speed : ux_[f];
    sum += face_mu_[f] * (above - below);
  }
  return sum / params_.gap;
}

void CouetteColumn::clear_sources() {
  std::fill(source_x_.begin(), source_x_.end(), 0.0);
  std::fill(source_y_.begin(), source_y_.end(), 0.0);
  std::fill(implicit_.begin(), implicit_.end(), 0.0);
}

void CouetteColumn::add_reaction(std::size_t k, double weighted_beta,
                                 const std::array<double, 3>& sampled_fluid_velocity,
                                 const std::array<double, 3>& particle_velocity) {
  source_x_[k] += weighted_beta * (particle_velocity[0] - sampled_fluid_velocity[0]) / volume_;
  source_y_[k] += weighted_beta * (particle_velocity[1] - sampled_fluid_velocity[1]) / volume_;
  implicit_[k] += weighted_beta / volume_;
}

void CouetteColumn::advance(double dt) {
  solve(ux_, source_x_, params_.plate_speed, dt);
  solve(uy_, source_y_, 0.0, dt);
  wall_top_ = face_mu_[n_] * (params_.plate_speed - ux_[n_ - 1]) / (0.5 * dz_);
  wall_bottom_ = face_mu_[0] * ux_[0] / (0.5 * dz_);
  update_viscosity();
}

void CouetteColumn::update_viscosity() {
  const double top = params_.plate_speed;
  std::vector<double> rate(n_ + 1);
  for (std::size_t f = 0; f <= n_; ++f) {
    const double below_x = f == 0 ? 0.0 : ux_[f - 1], below_y = f == 0 ? 0.0 : uy_[f - 1];
    const double above_x = f == n_ ? top : ux_[f], above_y = f == n_ ? 0.0 : uy_[f];
    rate[f] = std::hypot(above_x - below_x, above_y - below_y) / face_spacing(f);
    face_mu_[f] = params_.rheology->viscosity(rate[f]);
  }
  for (std::size_t k = 0; k < n_; ++k) {
    cell_mu_[k] = params_.rheology->viscosity(0.5 * (rate[k] + rate[k + 1]));
    const auto flux = [&](const std::vector<double>& u, double top_value, std::size_t f) {
      const double below = f == 0 ? 0.0 : u[f - 1];
      const double above = f == n_ ? top_value : u[f];
      return face_mu_[f] * (above - below) / face_spacing(f);
    };
    div_tau_x_[k] = (flux(ux_, top, k + 1) - flux(ux_, top, k)) / dz_;
    div_tau_y_[k] = (flux(uy_, 0.0, k + 1) - flux(uy_, 0.0, k)) / dz_;
  }
}

// Thomas algorithm on a_k u_{k-1} + b_k u_k + c_k u_{k+1} = d_k (bottom plate at rest).
void CouetteColumn::solve(std::vector<double>& u, const std::vector<double>& source, double top_value, double dt) {
  for (std::size_t k = 0; k < n_; ++k) {
    const double g_below = eps_[k] * face_mu_[k] / (face_spacing(k) * dz_);
    const double g_above = eps_[k] * face_mu_[k + 1] / (face_spacing(k + 1) * dz_);
    const double inertia = params_.density * eps_[k] / dt;
    diag_[k] = inertia + g_below + g_above + implicit_[k];
    lower_[k] = k == 0 ? 0.0 : -g_below;
    upper_[k] = k + 1 == n_ ? 0.0 : -g_above;
    rhs_[k] = (inertia + implicit_[k]) * u[k] + source[k] + (k + 1 == n_ ? g_above * top_value : 0.0);
  }
  for (std::size_t k = 1; k < n_; ++k) {
    const double m = lower_[k] / diag_[k - 1];
    diag_[k] -= m * upper_[k - 1];
    rhs_[k] -= m * rhs_[k - 1];
  }
  u[n_ - 1] = rhs_[n_ - 1] / diag_[n_ - 1];
  for (std::size_t k = n_ - 1; k-- > 0;) u[k] = (rhs_[k] - upper_[k] * u[k + 1]) / diag_[k];
}

}  // namespace rheosim::fluid
