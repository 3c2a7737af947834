// Plate correction of the rim stress and validity flags (rheometer/analysis.hpp §1, §5).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "rheosim/core/units.hpp"
#include "rheosim/rheometer/analysis.hpp"

namespace rheosim::rheometer {

using core::units::pi;

namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

void check_plate(const ParallelPlate& plate) {
  if (!(plate.radius > 0) || !(plate.gap > 0))
    throw std::invalid_argument(fmt::format("plate: radius ({}) and gap ({}) must be > 0", plate.radius, plate.gap));
}
}  // namespace

double apparent_rim_stress(const ParallelPlate& plate, double torque) {
  return 2.0 * torque / (pi * std::pow(plate.radius, 3));
}

double corrected_rim_stress(const ParallelPlate& plate, double torque, double log_slope) {
  return torque / (2.0 * pi * std::pow(plate.radius, 3)) * (3.0 + log_slope);
}

LocalSlopes local_log_slopes(std::span<const double> x, std::span<const double> y,
                             std::span<const double> relative_errors, const LocalSlopeOptions& options) {
  const std::size_t n = x.size();
  if (y.size() != n)
    throw std::invalid_argument(fmt::format("local_log_slopes: {} x values but {} y values", n, y.size()));
  if (!relative_errors.empty() && relative_errors.size() != n)
    throw std::invalid_argument(
        fmt::format("local_log_slopes: {} relative errors for {} points", relative_errors.size(), n));
  if (n < 2) throw std::invalid_argument("local_log_slopes: needs at least 2 points");
  if (options.half_window < 1) throw std::invalid_argument("local_log_slopes: half_window must be >= 1");
  for (std::size_t i = 0; i < n; ++i) {
    if (!(x[i] > 0) || !std::isfinite(x[i]))
      throw std::invalid_argument(fmt::format("local_log_slopes: x[{}] = {} must be positive and finite", i, x[i]));
    if (!(y[i] > 0) || !std::isfinite(y[i]))
      throw std::invalid_argument(fmt::format("local_log_slopes: y[{}] = {} must be positive and finite", i, y[i]));
  }
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return x[a] < x[b]; });
  for (std::size_t k = 1; k < n; ++k)
    if (!(x[order[k]] > x[order[k - 1]]))
      throw std::invalid_argument(
          fmt::format("local_log_slopes: x = {} appears twice; rates must be distinct", x[order[k]]));

  const auto h = static_cast<std::size_t>(options.half_window);
  const std::size_t m = std::min(2 * h + 1, n);
  const int degree = m >= 3 ? 2 : 1;
  const auto cols = static_cast<Eigen::Index>(degree + 1);
  LocalSlopes out;
  out.slope.assign(n, nan);
  out.std_error.assign(n, nan);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t lo = std::min(k > h ? k - h : 0, n - m);
    const double x0 = std::log(x[order[k]]);
    double reach = 0;
    for (std::size_t j = lo; j < lo + m; ++j) reach = std::max(reach, std::abs(std::log(x[order[j]]) - x0));
    Eigen::MatrixXd a(static_cast<Eigen::Index>(m), cols);
    Eigen::VectorXd b(static_cast<Eigen::Index>(m));
    for (std::size_t j = lo; j < lo + m; ++j) {
      const auto row = static_cast<Eigen::Index>(j - lo);
      const std::size_t i = order[j];
      const double s = (std::log(x[i]) - x0) / reach;  // in [−1, 1]
      const double q = std::abs(s) / 2.0;
      double w = std::pow(1.0 - q * q * q, 3);  // tricube with bandwidth 2·reach
      if (!relative_errors.empty() && relative_errors[i] > 0) w /= relative_errors[i] * relative_errors[i];
      const double sw = std::sqrt(w);
      double power = 1.0;
      for (Eigen::Index c = 0; c < cols; ++c) {
        a(row, c) = sw * power;
        power *= s;
      }
      b[row] = sw * std::log(y[i]);
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
    const Eigen::VectorXd coef = qr.solve(b);
    const std::size_t i0 = order[k];
    out.slope[i0] = coef[1] / reach;
    const auto spare = static_cast<Eigen::Index>(m) - cols;
    if (spare > 0) {
      const double s2 = (a * coef - b).squaredNorm() / static_cast<double>(spare);
      const Eigen::MatrixXd inv = (a.transpose() * a).inverse();
      out.std_error[i0] = std::sqrt(s2 * inv(1, 1)) / reach;
    }
  }
  return out;
}

RimStressCurve rim_stress_curve(const ParallelPlate& plate, std::span<const double> rim_shear_rate,
                                std::span<const double> torque, std::span<const double> torque_relative_errors,
                                const LocalSlopeOptions& options) {
  check_plate(plate);
  const auto slopes = local_log_slopes(rim_shear_rate, torque, torque_relative_errors, options);
  RimStressCurve c;
  c.rim_shear_rate.assign(rim_shear_rate.begin(), rim_shear_rate.end());
  c.torque.assign(torque.begin(), torque.end());
  c.log_slope = slopes.slope;
  c.log_slope_std_error = slopes.std_error;
  for (std::size_t i = 0; i < torque.size(); ++i) {
    c.apparent_stress.push_back(apparent_rim_stress(plate, torque[i]));
    c.corrected_stress.push_back(corrected_rim_stress(plate, torque[i], slopes.slope[i]));
    c.apparent_viscosity.push_back(c.apparent_stress.back() / rim_shear_rate[i]);
    c.corrected_viscosity.push_back(c.corrected_stress.back() / rim_shear_rate[i]);
  }
  return c;
}

PointValidity check_validity(const ParallelPlate& plate, const PointConditions& p, const ValidityLimits& limits) {
  check_plate(plate);
  if (!(p.rim_shear_rate >= 0)) throw std::invalid_argument("check_validity: rim_shear_rate must be >= 0");
  if (!(p.density >= 0)) throw std::invalid_argument("check_validity: density must be >= 0");
  if (!(p.viscosity > 0)) throw std::invalid_argument("check_validity: viscosity must be > 0");
  if (!(p.particle_diameter >= 0) || !(p.particle_density >= 0) || !(p.fluid_density >= 0) || !(p.fluid_viscosity >= 0))
    throw std::invalid_argument("check_validity: particle and fluid properties must be >= 0");

  PointValidity v;
  v.gap_reynolds = plate.gap_reynolds_number(p.density, p.rim_shear_rate, p.viscosity);
  v.gap_reynolds_ok = v.gap_reynolds <= limits.max_gap_reynolds;
  if (!v.gap_reynolds_ok)
    v.messages.push_back(
        fmt::format("gap Reynolds number ρΩH²/η = {:.3g} > {:.3g} at γ̇_R = {:.4g} 1/s: secondary "
                    "flow raises the torque above the creeping-flow value",
                    v.gap_reynolds, limits.max_gap_reynolds, p.rim_shear_rate));
  if (p.particle_diameter > 0) {
    const double d2 = p.particle_diameter * p.particle_diameter;
    const double rho_f = p.fluid_density > 0 ? p.fluid_density : p.density;
    const double eta_f = p.fluid_viscosity > 0 ? p.fluid_viscosity : p.viscosity;
    v.particle_reynolds = rho_f * p.rim_shear_rate * d2 / eta_f;
    v.stokes = p.particle_density * p.rim_shear_rate * d2 / eta_f;
    v.gap_to_diameter = plate.gap / p.particle_diameter;
    v.particle_reynolds_ok = v.particle_reynolds <= limits.max_particle_reynolds;
    v.stokes_ok = v.stokes <= limits.max_stokes;
    v.gap_to_diameter_ok = v.gap_to_diameter >= limits.min_gap_to_diameter;
    if (!v.particle_reynolds_ok)
      v.messages.push_back(
          fmt::format("particle Reynolds number ρ_f γ̇ d²/η_f = {:.3g} > {:.3g}: particle-scale "
                      "inertia is not negligible",
                      v.particle_reynolds, limits.max_particle_reynolds));
    if (!v.stokes_ok)
      v.messages.push_back(fmt::format("Stokes number ρ_p γ̇ d²/η_f = {:.3g} > {:.3g}: particles do not follow the flow",
                                       v.stokes, limits.max_stokes));
    if (!v.gap_to_diameter_ok)
      v.messages.push_back(
          fmt::format("gap/diameter H/d = {:.3g} < {:.3g}: the sample is not a continuum across the gap",
                      v.gap_to_diameter, limits.min_gap_to_diameter));
  }
  return v;
}

}  // namespace rheosim::rheometer
