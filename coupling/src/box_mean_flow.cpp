// The walled box's mean liquid profile (see box_mean_flow.hpp).
#include "box_mean_flow.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rheosim::coupling {

BoxMeanFlow::BoxMeanFlow(double height, double area, double viscosity, double stresslet_ratio)
    : height_(height),
      area_(area),
      viscosity_(viscosity),
      stresslet_ratio_(stresslet_ratio),
      bins_(static_cast<std::size_t>(std::max(8.0, std::round(4.0 * height)))),
      width_(height / static_cast<double>(bins_)),
      force_(bins_),
      couple_(bins_),
      fraction_(bins_),
      sample_force_(bins_),
      sample_couple_(bins_),
      sample_fraction_(bins_),
      shear_(bins_, 1.0),
      velocity_(bins_ + 1),
      tau0_(viscosity) {
  for (std::size_t k = 0; k <= bins_; ++k) velocity_[k] = width_ * static_cast<double>(k);
}

std::size_t BoxMeanFlow::bin(double z) const {
  return static_cast<std::size_t>(std::clamp(std::floor(z / width_), 0.0, static_cast<double>(bins_ - 1)));
}

void BoxMeanFlow::add_sphere(double z, double a, double force, double couple) {
  const std::size_t first = bin(z - a), last = bin(z + a);
  const auto primitive = [&](double y) {  // ∫ (a² − (ζ − z)²) dζ up to y, clipped to the sphere
    const double t = std::clamp(y - z, -a, a);
    return a * a * t - t * t * t / 3.0;
  };
  const double whole = 4.0 * a * a * a / 3.0;
  for (std::size_t k = first; k <= last; ++k) {
    const double share =
        (primitive(width_ * static_cast<double>(k + 1)) - primitive(width_ * static_cast<double>(k))) / whole;
    const double per_volume = share / (area_ * width_);
    sample_force_[k] += force * per_volume;
    sample_couple_[k] += couple * per_volume;
    sample_fraction_[k] += std::numbers::pi * whole * per_volume;  // the sphere's volume in the bin / bin volume
  }
}

void BoxMeanFlow::relax(double weight) {
  for (std::size_t k = 0; k < bins_; ++k) {
    force_[k] += weight * (sample_force_[k] - force_[k]);
    couple_[k] += weight * (sample_couple_[k] - couple_[k]);
    fraction_[k] += weight * (sample_fraction_[k] - fraction_[k]);
    sample_force_[k] = sample_couple_[k] = sample_fraction_[k] = 0.0;
  }
  // u_f' = (τ₀ + drive)/resistance per bin; ∫ u_f' = H fixes τ₀.
  double running = 0.0, compliance = 0.0, offset = 0.0;
  std::vector<double> drive(bins_), resistance(bins_);
  for (std::size_t k = 0; k < bins_; ++k) {
    const double mid = running + 0.5 * force_[k] * width_;
    running += force_[k] * width_;
    resistance[k] = viscosity_ * (1.0 + 2.5 * stresslet_ratio_ * fraction_[k]);
    drive[k] = 0.5 * couple_[k] - mid;
    compliance += width_ / resistance[k];
    offset += drive[k] * width_ / resistance[k];
  }
  total_force_ = running;
  tau0_ = (height_ - offset) / compliance;
  for (std::size_t k = 0; k < bins_; ++k) {
    shear_[k] = (tau0_ + drive[k]) / resistance[k];
    velocity_[k + 1] = velocity_[k] + shear_[k] * width_;
  }
}

double BoxMeanFlow::velocity(double z) const {
  const std::size_t k = bin(z);
  return velocity_[k] + shear_[k] * (z - width_ * static_cast<double>(k));
}

double BoxMeanFlow::shear_rate(double z) const { return shear_[bin(z)]; }

}  // namespace rheosim::coupling
