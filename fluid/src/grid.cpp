#include "rheosim/fluid/grid.hpp"

#include <cmath>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "rheosim/core/units.hpp"

namespace rheosim::fluid {
namespace {

void check_positive(std::string_view name, double value) {
  if (!(std::isfinite(value) && value > 0.0))
    throw std::invalid_argument(
        fmt::format("CylindricalGrid: {} = {} is out of range, expected a finite value > 0", name, value));
}

void check_cell_count(std::string_view name, int value) {
  if (value < 1)
    throw std::invalid_argument(fmt::format("CylindricalGrid: {} = {} is out of range, expected >= 1", name, value));
}

// n + 1 faces over [0, length], evenly spaced; the last is `length` exactly.
std::vector<double> uniform_faces(double length, std::size_t n) {
  std::vector<double> faces(n + 1);
  for (std::size_t i = 0; i <= n; ++i) faces[i] = length * static_cast<double>(i) / static_cast<double>(n);
  faces[n] = length;
  return faces;
}

// Geometric series of widths with last/first = grading: r_i = R (q^i − 1)/(q^n − 1). expm1
// keeps this accurate when q is close to 1.
std::vector<double> graded_faces(double length, std::size_t n, double grading) {
  if (n == 1 || grading == 1.0) return uniform_faces(length, n);
  const double log_q = std::log(grading) / static_cast<double>(n - 1);
  const double denominator = std::expm1(static_cast<double>(n) * log_q);
  std::vector<double> faces(n + 1);
  for (std::size_t i = 0; i <= n; ++i) faces[i] = length * std::expm1(static_cast<double>(i) * log_q) / denominator;
  faces[0] = 0.0;
  faces[n] = length;
  return faces;
}

// Faces clustered towards both ends by z_k = (L/2)[1 + tanh(β(2k/n − 1))/tanh β]; the map is
// odd about mid-gap, so the two plates get mirror-image cells.
std::vector<double> stretched_faces(double length, std::size_t n, double stretching) {
  if (stretching == 0.0) return uniform_faces(length, n);
  const double scale = std::tanh(stretching);
  std::vector<double> faces(n + 1);
  for (std::size_t k = 0; k <= n; ++k) {
    const double xi = 2.0 * static_cast<double>(k) / static_cast<double>(n) - 1.0;
    faces[k] = 0.5 * length * (1.0 + std::tanh(stretching * xi) / scale);
  }
  faces[0] = 0.0;
  faces[n] = length;
  return faces;
}

std::vector<double> midpoints(const std::vector<double>& faces) {
  std::vector<double> centres(faces.size() - 1);
  for (std::size_t i = 0; i < centres.size(); ++i) centres[i] = 0.5 * (faces[i] + faces[i + 1]);
  return centres;
}

}  // namespace

CylindricalGrid::CylindricalGrid(Params params) : params_(params) {
  check_positive("radius", params_.radius);
  check_positive("gap", params_.gap);
  check_cell_count("radial_cells", params_.radial_cells);
  check_cell_count("azimuthal_cells", params_.azimuthal_cells);
  check_cell_count("axial_cells", params_.axial_cells);
  check_positive("radial_grading", params_.radial_grading);
  if (!(std::isfinite(params_.axial_stretching) && params_.axial_stretching >= 0.0))
    throw std::invalid_argument(
        fmt::format("CylindricalGrid: axial_stretching = {} is out of range, expected a finite value >= 0",
                    params_.axial_stretching));

  const auto n_r = static_cast<std::size_t>(params_.radial_cells);
  const auto n_theta = static_cast<std::size_t>(params_.azimuthal_cells);
  const auto n_z = static_cast<std::size_t>(params_.axial_cells);

  radial_faces_ = graded_faces(params_.radius, n_r, params_.radial_grading);
  radial_centres_ = midpoints(radial_faces_);
  azimuthal_faces_ = uniform_faces(2.0 * core::units::pi, n_theta);
  azimuthal_centres_ = midpoints(azimuthal_faces_);
  dtheta_ = 2.0 * core::units::pi / static_cast<double>(n_theta);
  axial_faces_ = stretched_faces(params_.gap, n_z, params_.axial_stretching);
  axial_centres_ = midpoints(axial_faces_);
}

double CylindricalGrid::axial_face_area(std::size_t i) const {
  const double r_in = radial_faces_[i];
  const double r_out = radial_faces_[i + 1];
  // (r_out − r_in)(r_out + r_in) avoids cancelling r_out² − r_in² for thin rings far from the axis.
  return 0.5 * dtheta_ * (r_out - r_in) * (r_out + r_in);
}

double CylindricalGrid::cell_volume(std::size_t i, std::size_t k) const { return axial_face_area(i) * axial_width(k); }

double CylindricalGrid::radial_face_area(std::size_t i, std::size_t k) const {
  return radial_faces_[i] * dtheta_ * axial_width(k);
}

double CylindricalGrid::azimuthal_face_area(std::size_t i, std::size_t k) const {
  return radial_width(i) * axial_width(k);
}

}  // namespace rheosim::fluid
