#include "rheosim/coupling/exchange.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace rheosim::coupling {

MomentumExchange::MomentumExchange(const fluid::CylindricalGrid& grid) : grid_(&grid) {
  const std::size_t n = grid.cell_count(), n_theta = grid.azimuthal_cells(), n_z = grid.axial_cells();
  for (std::vector<double>* v : {&radial_, &azimuthal_, &axial_, &drag_coefficient_, &cell_volume_, &cell_theta_})
    v->assign(n, 0.0);
  for (std::size_t i = 0; i < grid.radial_cells(); ++i)
    for (std::size_t j = 0; j < n_theta; ++j)
      for (std::size_t k = 0; k < n_z; ++k) {
        const std::size_t c = (i * n_theta + j) * n_z + k;
        cell_volume_[c] = grid.cell_volume(i, k);
        cell_theta_[c] = grid.azimuthal_centres()[j];
      }
}

double MomentumExchange::basis_angle(std::size_t cell, const ParticleSample& particle) const {
  return grid_->azimuthal_cells() > 1 ? cell_theta_[cell] : particle.theta;
}

void MomentumExchange::build(const ParticleCellMap& map, std::span<const ParticleSample> samples,
                             std::span<const ParticleForce> forces, const CellVectorField* cell_velocity) {
  if (cell_velocity &&
      (cell_velocity->radial.size() != radial_.size() || cell_velocity->azimuthal.size() != radial_.size() ||
       cell_velocity->axial.size() != radial_.size()))
    throw std::invalid_argument("MomentumExchange: the cell velocity field does not match the grid");
  if (cell_velocity)
    cell_velocity_ = *cell_velocity;
  else
    cell_velocity_ = {};
  if (map.particle_count() != samples.size() || samples.size() != forces.size())
    throw std::invalid_argument(fmt::format("MomentumExchange: {} mapped particles, {} samples, {} forces",
                                            map.particle_count(), samples.size(), forces.size()));
  std::fill(radial_.begin(), radial_.end(), 0.0);
  std::fill(azimuthal_.begin(), azimuthal_.end(), 0.0);
  std::fill(axial_.begin(), axial_.end(), 0.0);
  std::fill(drag_coefficient_.begin(), drag_coefficient_.end(), 0.0);
  for (std::size_t p = 0; p < samples.size(); ++p) {
    const double beta = forces[p].drag_coefficient;
    if (beta == 0.0) continue;
    Vector3 v = samples[p].velocity;
    // With ũ_c: explicit β(u_p − u_f(x_p)) + β ũ_c (header comment).
    if (cell_velocity)
      for (std::size_t d = 0; d < 3; ++d) v[d] -= samples[p].fluid_velocity[d];
    for (const VolumeShare& share : map.of(p)) {
      const std::size_t c = share.cell;
      const double w = share.volume / samples[p].volume;
      const double theta = basis_angle(c, samples[p]);
      const double cs = std::cos(theta), sn = std::sin(theta);
      // −f_d = β u_p − β u_f: explicit β u_p, implicit β (CD eq. 29).
      const double per_volume = w * beta / cell_volume_[c];
      radial_[c] += per_volume * (v[0] * cs + v[1] * sn);
      azimuthal_[c] += per_volume * (-v[0] * sn + v[1] * cs);
      axial_[c] += per_volume * v[2];
      drag_coefficient_[c] += per_volume;
      if (cell_velocity) {
        radial_[c] += per_volume * cell_velocity->radial[c];
        azimuthal_[c] += per_volume * cell_velocity->azimuthal[c];
        axial_[c] += per_volume * cell_velocity->axial[c];
      }
    }
  }
}

fluid::MomentumSource MomentumExchange::source() const {
  return {.radial = radial_, .azimuthal = azimuthal_, .axial = axial_, .drag_coefficient = drag_coefficient_};
}

ExchangeBalance MomentumExchange::balance(const ParticleCellMap& map, std::span<const ParticleSample> samples,
                                          std::span<const ParticleForce> forces) const {
  ExchangeBalance out;
  out.axial_only = grid_->azimuthal_cells() == 1;
  double scale = 0.0;
  for (std::size_t p = 0; p < samples.size(); ++p) {
    const ParticleForce& f = forces[p];
    for (std::size_t d = 0; d < 3; ++d) {
      out.drag_on_particles[d] += f.drag[d];
      out.pressure_on_particles[d] += f.pressure_gradient[d];
      out.viscous_on_particles[d] += f.viscous[d];
    }
    scale += std::hypot(f.drag[0], f.drag[1], f.drag[2]);
    // The implicit part −K_c ũ_c V_c: at the velocity particle p sampled (plain split), or at the
    // cell velocity of the build (added below, per cell).
    if (!cell_velocity_.radial.empty()) continue;
    for (const VolumeShare& share : map.of(p)) {
      const double wb = share.volume / samples[p].volume * f.drag_coefficient;
      for (std::size_t d = 0; d < 3; ++d) out.drag_to_fluid[d] -= wb * samples[p].fluid_velocity[d];
    }
  }
  // The explicit part (minus K_c ũ_c with the cell velocities), rebuilt from the solver's
  // cylindrical arrays.
  const bool per_cell = !cell_velocity_.radial.empty();
  for (std::size_t c = 0; c < radial_.size(); ++c) {
    const double theta = cell_theta_[c];
    const double cs = std::cos(theta), sn = std::sin(theta);
    const double k = per_cell ? drag_coefficient_[c] : 0.0;
    const double fr = radial_[c] - (per_cell ? k * cell_velocity_.radial[c] : 0.0);
    const double ft = azimuthal_[c] - (per_cell ? k * cell_velocity_.azimuthal[c] : 0.0);
    const double fz = axial_[c] - (per_cell ? k * cell_velocity_.axial[c] : 0.0);
    if (!out.axial_only) {
      out.drag_to_fluid[0] += (fr * cs - ft * sn) * cell_volume_[c];
      out.drag_to_fluid[1] += (fr * sn + ft * cs) * cell_volume_[c];
    }
    out.drag_to_fluid[2] += fz * cell_volume_[c];
  }
  if (out.axial_only) out.drag_to_fluid[0] = out.drag_to_fluid[1] = 0.0;  // not representable
  double mismatch = 0.0;
  for (std::size_t d = out.axial_only ? 2 : 0; d < 3; ++d) {
    const double e = out.drag_on_particles[d] + out.drag_to_fluid[d];
    mismatch += e * e;
  }
  out.relative_error = scale > 0.0 ? std::sqrt(mismatch) / scale : 0.0;
  return out;
}

}  // namespace rheosim::coupling
