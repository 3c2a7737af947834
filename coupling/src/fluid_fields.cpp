#include "rheosim/coupling/fluid_fields.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace rheosim::coupling {

FluidCellFields::FluidCellFields(const fluid::CylindricalGrid& grid)
    : grid_(&grid), n_r_(grid.radial_cells()), n_theta_(grid.azimuthal_cells()), n_z_(grid.axial_cells()) {
  const std::size_t n = grid.cell_count();
  for (CellVectorField* f :
       {&velocity_, &pressure_gradient_, &stress_divergence_, &laplacian_, &grad_a_, &grad_b_, &grad_c_, &grad_mu_})
    f->resize(n);
  viscosity_.assign(n, 0.0);
}

void FluidCellFields::set_pressure_gradient_filter(double time_constant) {
  if (!(std::isfinite(time_constant) && time_constant >= 0.0))
    throw std::invalid_argument(
        "FluidCellFields: the pressure-gradient filter time constant must be finite and >= 0 s");
  filter_time_constant_ = time_constant;
}

void FluidCellFields::gradient(std::span<const double> f, CellVectorField& out) const {
  const auto rc = grid_->radial_centres();
  const auto zc = grid_->axial_centres();
  const double dtheta = grid_->azimuthal_width();
  for (std::size_t i = 0; i < n_r_; ++i)
    for (std::size_t j = 0; j < n_theta_; ++j)
      for (std::size_t k = 0; k < n_z_; ++k) {
        const std::size_t c = index(i, j, k);
        double gr = 0.0, gt = 0.0, gz = 0.0;
        if (n_r_ > 1) {
          const std::size_t lo = i == 0 ? 0 : i - 1, hi = i + 1 == n_r_ ? i : i + 1;
          gr = (f[index(hi, j, k)] - f[index(lo, j, k)]) / (rc[hi] - rc[lo]);
        }
        if (n_theta_ > 2)
          gt = (f[index(i, (j + 1) % n_theta_, k)] - f[index(i, (j + n_theta_ - 1) % n_theta_, k)]) /
               (2.0 * dtheta * rc[i]);
        if (n_z_ > 1) {
          const std::size_t lo = k == 0 ? 0 : k - 1, hi = k + 1 == n_z_ ? k : k + 1;
          gz = (f[index(i, j, hi)] - f[index(i, j, lo)]) / (zc[hi] - zc[lo]);
        }
        out.radial[c] = gr;
        out.azimuthal[c] = gt;
        out.axial[c] = gz;
      }
}

void FluidCellFields::scalar_laplacian(std::span<const double> f, Rim rim, std::span<const double> bottom_wall,
                                       std::span<const double> top_wall, std::vector<double>& out) const {
  const auto rc = grid_->radial_centres();
  const auto zc = grid_->axial_centres();
  const auto zf = grid_->axial_faces();
  const double dtheta = grid_->azimuthal_width();
  out.assign(f.size(), 0.0);
  for (std::size_t i = 0; i < n_r_; ++i)
    for (std::size_t j = 0; j < n_theta_; ++j)
      for (std::size_t k = 0; k < n_z_; ++k) {
        const std::size_t c = index(i, j, k);
        const double fc = f[c];
        double flux = 0.0;
        // Radial faces: the axis face has zero area; the rim face follows the rim condition.
        if (i + 1 < n_r_)
          flux += grid_->radial_face_area(i + 1, k) * (f[index(i + 1, j, k)] - fc) / (rc[i + 1] - rc[i]);
        else if (rim == Rim::zero_value)
          flux += grid_->radial_face_area(i + 1, k) * (0.0 - fc) / (grid_->radial_faces()[i + 1] - rc[i]);
        else if (rim == Rim::rigid_rotation)
          flux += grid_->radial_face_area(i + 1, k) * fc / rc[i];
        if (i > 0) flux += grid_->radial_face_area(i, k) * (f[index(i - 1, j, k)] - fc) / (rc[i] - rc[i - 1]);
        if (n_theta_ > 1) {
          const double a = grid_->azimuthal_face_area(i, k) / (rc[i] * dtheta);
          flux += a * (f[index(i, (j + 1) % n_theta_, k)] - fc);
          flux += a * (f[index(i, (j + n_theta_ - 1) % n_theta_, k)] - fc);
        }
        const double az = grid_->axial_face_area(i);
        flux += k + 1 < n_z_ ? az * (f[index(i, j, k + 1)] - fc) / (zc[k + 1] - zc[k])
                             : az * (top_wall[i] - fc) / (zf[k + 1] - zc[k]);
        flux += k > 0 ? az * (f[index(i, j, k - 1)] - fc) / (zc[k] - zc[k - 1])
                      : az * (bottom_wall[i] - fc) / (zc[k] - zf[k]);
        out[c] = flux / grid_->cell_volume(i, k);
      }
}

void FluidCellFields::vector_laplacian(const CellVectorField& u, double bottom_angular_velocity,
                                       double top_angular_velocity, CellVectorField& out) const {
  const auto rc = grid_->radial_centres();
  std::vector<double> zero(n_r_, 0.0), bottom(n_r_), top(n_r_);
  for (std::size_t i = 0; i < n_r_; ++i) {
    bottom[i] = bottom_angular_velocity * rc[i];
    top[i] = top_angular_velocity * rc[i];
  }
  std::vector<double> lr, lt, lz;
  scalar_laplacian(u.radial, Rim::zero_value, zero, zero, lr);
  scalar_laplacian(u.azimuthal, Rim::rigid_rotation, bottom, top, lt);
  scalar_laplacian(u.axial, Rim::zero_gradient, zero, zero, lz);
  const double dtheta = grid_->azimuthal_width();
  for (std::size_t i = 0; i < n_r_; ++i) {
    const double r2 = rc[i] * rc[i];
    for (std::size_t j = 0; j < n_theta_; ++j)
      for (std::size_t k = 0; k < n_z_; ++k) {
        const std::size_t c = index(i, j, k);
        double dur = 0.0, dut = 0.0;  // ∂_θ u_r, ∂_θ u_θ
        if (n_theta_ > 2) {
          const std::size_t jp = index(i, (j + 1) % n_theta_, k), jm = index(i, (j + n_theta_ - 1) % n_theta_, k);
          dur = (u.radial[jp] - u.radial[jm]) / (2.0 * dtheta);
          dut = (u.azimuthal[jp] - u.azimuthal[jm]) / (2.0 * dtheta);
        }
        out.radial[c] = lr[c] - u.radial[c] / r2 - 2.0 * dut / r2;
        out.azimuthal[c] = lt[c] - u.azimuthal[c] / r2 + 2.0 * dur / r2;
        out.axial[c] = lz[c];
      }
  }
}

void FluidCellFields::update(const fluid::TransientSolver& solver) {
  const auto ur = solver.radial_velocity();
  const auto ut = solver.azimuthal_velocity();
  const auto uz = solver.axial_velocity();
  const auto mu = solver.viscosity();
  std::copy(mu.begin(), mu.end(), viscosity_.begin());
  // Staggered → centre: u_r on radial faces (i = 0 is the axis value), u_θ on θ faces, u_z on z faces.
  for (std::size_t i = 0; i < n_r_; ++i)
    for (std::size_t j = 0; j < n_theta_; ++j)
      for (std::size_t k = 0; k < n_z_; ++k) {
        const std::size_t c = index(i, j, k);
        velocity_.radial[c] = 0.5 * (ur[(i * n_theta_ + j) * n_z_ + k] + ur[((i + 1) * n_theta_ + j) * n_z_ + k]);
        velocity_.azimuthal[c] = 0.5 * (ut[c] + ut[index(i, (j + 1) % n_theta_, k)]);
        const std::size_t zi = (i * n_theta_ + j) * (n_z_ + 1) + k;
        velocity_.axial[c] = 0.5 * (uz[zi] + uz[zi + 1]);
      }
  if (filter_time_constant_ > 0.0 && has_pressure_gradient_) {
    gradient(solver.pressure(), grad_c_);
    const double weight = -std::expm1(-(solver.time() - last_update_time_) / filter_time_constant_);
    for (auto [filtered, raw] : {std::pair{&pressure_gradient_.radial, &grad_c_.radial},
                                 std::pair{&pressure_gradient_.azimuthal, &grad_c_.azimuthal},
                                 std::pair{&pressure_gradient_.axial, &grad_c_.axial}})
      for (std::size_t c = 0; c < filtered->size(); ++c) (*filtered)[c] += weight * ((*raw)[c] - (*filtered)[c]);
  } else {
    gradient(solver.pressure(), pressure_gradient_);
  }
  has_pressure_gradient_ = true;
  last_update_time_ = solver.time();

  const fluid::TransientParams& params = solver.params();
  vector_laplacian(velocity_, params.bottom_angular_velocity, params.top_angular_velocity, laplacian_);
  const auto [mu_min, mu_max] = std::minmax_element(viscosity_.begin(), viscosity_.end());
  const bool uniform = *mu_max - *mu_min <= 1e-12 * *mu_max;
  for (std::size_t c = 0; c < viscosity_.size(); ++c) {
    stress_divergence_.radial[c] = viscosity_[c] * laplacian_.radial[c];
    stress_divergence_.azimuthal[c] = viscosity_[c] * laplacian_.azimuthal[c];
    stress_divergence_.axial[c] = viscosity_[c] * laplacian_.axial[c];
  }
  if (uniform) return;
  // Generalized Newtonian: + 2 E·∇μ, E from centred differences of the centre velocities.
  gradient(viscosity_, grad_mu_);
  gradient(velocity_.radial, grad_a_);
  gradient(velocity_.azimuthal, grad_b_);
  gradient(velocity_.axial, grad_c_);
  const auto rc = grid_->radial_centres();
  for (std::size_t i = 0; i < n_r_; ++i)
    for (std::size_t j = 0; j < n_theta_; ++j)
      for (std::size_t k = 0; k < n_z_; ++k) {
        const std::size_t c = index(i, j, k);
        const double r = rc[i];
        const double err = grad_a_.radial[c];
        const double ett = grad_b_.azimuthal[c] + velocity_.radial[c] / r;
        const double ezz = grad_c_.axial[c];
        const double ert = 0.5 * (grad_b_.radial[c] - velocity_.azimuthal[c] / r + grad_a_.azimuthal[c]);
        const double erz = 0.5 * (grad_a_.axial[c] + grad_c_.radial[c]);
        const double etz = 0.5 * (grad_b_.axial[c] + grad_c_.azimuthal[c]);
        const double gr = grad_mu_.radial[c], gt = grad_mu_.azimuthal[c], gz = grad_mu_.axial[c];
        stress_divergence_.radial[c] += 2.0 * (err * gr + ert * gt + erz * gz);
        stress_divergence_.azimuthal[c] += 2.0 * (ert * gr + ett * gt + etz * gz);
        stress_divergence_.axial[c] += 2.0 * (erz * gr + etz * gt + ezz * gz);
      }
}

}  // namespace rheosim::coupling
