// CylindricalGrid: exact annular-sector geometry. Volumes tile the gap cylinder πR²H, face
// areas satisfy the divergence theorem for fields whose fluxes are exact on these faces,
// grading does what it says, and invalid parameters are rejected by name.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>

#include "rheosim/fluid/grid.hpp"

namespace rheosim::fluid {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double pi = std::numbers::pi;
constexpr double plate_radius = 0.015;  // CD §2.3 rheometer: R = 15 mm
constexpr double plate_gap = 0.0005;    // H = 0.5 mm

CylindricalGrid make_grid(int n_r, int n_theta, int n_z, double grading = 1.0) {
  return CylindricalGrid({.radius = plate_radius,
                          .gap = plate_gap,
                          .radial_cells = n_r,
                          .azimuthal_cells = n_theta,
                          .axial_cells = n_z,
                          .radial_grading = grading});
}

// (N_r, N_θ, N_z, grading)
class GridResolutions : public ::testing::TestWithParam<std::tuple<int, int, int, double>> {
 protected:
  CylindricalGrid grid() const {
    const auto [n_r, n_theta, n_z, grading] = GetParam();
    return make_grid(n_r, n_theta, n_z, grading);
  }
};

INSTANTIATE_TEST_SUITE_P(Grid, GridResolutions,
                         ::testing::Values(std::tuple{1, 1, 1, 1.0}, std::tuple{8, 1, 4, 1.0},
                                           std::tuple{40, 1, 10, 0.2}, std::tuple{17, 16, 5, 1.0},
                                           std::tuple{33, 32, 7, 0.05}, std::tuple{25, 3, 9, 5.0},
                                           std::tuple{200, 1, 20, 1.0 + 1e-12}));

TEST_P(GridResolutions, VolumesSumToTheGapCylinder) {
  const CylindricalGrid g = grid();
  double total = 0.0;
  for (std::size_t i = 0; i < g.radial_cells(); ++i)
    for (std::size_t k = 0; k < g.axial_cells(); ++k) total += g.cell_volume(i, k) * double(g.azimuthal_cells());
  const double exact = pi * plate_radius * plate_radius * plate_gap;
  EXPECT_NEAR(total, exact, 1e-13 * exact);
}

TEST_P(GridResolutions, FacesSpanTheDomainAndCentresAreMidpoints) {
  const CylindricalGrid g = grid();
  const auto r = g.radial_faces();
  const auto z = g.axial_faces();
  const auto theta = g.azimuthal_faces();
  ASSERT_EQ(r.size(), g.radial_cells() + 1);
  ASSERT_EQ(z.size(), g.axial_cells() + 1);
  ASSERT_EQ(theta.size(), g.azimuthal_cells() + 1);
  EXPECT_EQ(r.front(), 0.0);
  EXPECT_EQ(r.back(), plate_radius);
  EXPECT_EQ(z.front(), 0.0);
  EXPECT_EQ(z.back(), plate_gap);
  EXPECT_EQ(theta.front(), 0.0);
  EXPECT_DOUBLE_EQ(theta.back(), 2.0 * pi);
  EXPECT_DOUBLE_EQ(g.azimuthal_width(), 2.0 * pi / double(g.azimuthal_cells()));
  for (std::size_t i = 0; i < g.radial_cells(); ++i) {
    EXPECT_GT(g.radial_width(i), 0.0) << i;
    EXPECT_DOUBLE_EQ(g.radial_centres()[i], 0.5 * (r[i] + r[i + 1]));
  }
  for (std::size_t k = 0; k < g.axial_cells(); ++k) {
    EXPECT_NEAR(g.axial_width(k), plate_gap / double(g.axial_cells()), 1e-12 * plate_gap);
    EXPECT_DOUBLE_EQ(g.axial_centres()[k], 0.5 * (z[k] + z[k + 1]));
  }
}

TEST_P(GridResolutions, FaceAreasMatchTheSectorGeometry) {
  const CylindricalGrid g = grid();
  const auto r = g.radial_faces();
  const double dtheta = g.azimuthal_width();
  for (std::size_t i = 0; i < g.radial_cells(); ++i) {
    // Top and bottom faces are the cell's base: V = A_z Δz.
    const double base = 0.5 * dtheta * (r[i + 1] * r[i + 1] - r[i] * r[i]);
    EXPECT_NEAR(g.axial_face_area(i), base, 1e-12 * base) << i;
    for (std::size_t k = 0; k < g.axial_cells(); ++k) {
      const double dz = g.axial_width(k);
      EXPECT_NEAR(g.cell_volume(i, k), g.axial_face_area(i) * dz, 1e-14 * g.cell_volume(i, k));
      EXPECT_DOUBLE_EQ(g.radial_face_area(i + 1, k), r[i + 1] * dtheta * dz);  // outer face
      EXPECT_DOUBLE_EQ(g.azimuthal_face_area(i, k), (r[i + 1] - r[i]) * dz);
    }
  }
}

TEST_P(GridResolutions, AxisIsADegenerateFace) {
  const CylindricalGrid g = grid();
  EXPECT_TRUE(CylindricalGrid::is_axis_face(0));
  EXPECT_FALSE(CylindricalGrid::is_axis_face(1));
  for (std::size_t k = 0; k < g.axial_cells(); ++k) EXPECT_EQ(g.radial_face_area(0, k), 0.0);
}

TEST_P(GridResolutions, PlateAndRimAreasAddUp) {
  const CylindricalGrid g = grid();
  const double n_theta = double(g.azimuthal_cells());
  double plate = 0.0;
  for (std::size_t i = 0; i < g.radial_cells(); ++i) plate += g.axial_face_area(i) * n_theta;
  EXPECT_NEAR(plate, pi * plate_radius * plate_radius, 1e-13 * plate);
  double rim = 0.0;
  for (std::size_t k = 0; k < g.axial_cells(); ++k) rim += g.radial_face_area(g.radial_cells(), k) * n_theta;
  EXPECT_NEAR(rim, 2.0 * pi * plate_radius * plate_gap, 1e-13 * rim);
}

// Divergence theorem, cell by cell, for linear fields whose face fluxes are exact:
// F = r e_r = (x, y, 0) has ∇·F = 2 and F·n = ±r on radial faces, 0 elsewhere;
// F = z e_z has ∇·F = 1 and F·n = ±z on axial faces, 0 elsewhere.
TEST_P(GridResolutions, DivergenceTheoremForLinearFields) {
  const CylindricalGrid g = grid();
  const auto r = g.radial_faces();
  const auto z = g.axial_faces();
  for (std::size_t i = 0; i < g.radial_cells(); ++i) {
    for (std::size_t k = 0; k < g.axial_cells(); ++k) {
      const double volume = g.cell_volume(i, k);
      const double radial_flux = r[i + 1] * g.radial_face_area(i + 1, k) - r[i] * g.radial_face_area(i, k);
      EXPECT_NEAR(radial_flux, 2.0 * volume, 1e-12 * volume) << i << ", " << k;
      const double axial_flux = (z[k + 1] - z[k]) * g.axial_face_area(i);
      EXPECT_NEAR(axial_flux, volume, 1e-12 * volume) << i << ", " << k;
    }
  }
}

// A constant Cartesian field c has zero net flux. On the curved faces
// ∫ c·e_r dA = (A_r/Δθ)[c_x (sin θ₂ − sin θ₁) − c_y (cos θ₂ − cos θ₁)]; on the flat θ faces
// c·(±e_θ) A_θ. Checks that radial and azimuthal face areas are mutually consistent. (With
// N_θ = 1 the two θ faces coincide and cancel, and the curved terms vanish over 2π.)
TEST_P(GridResolutions, ConstantCartesianFieldHasZeroNetFlux) {
  const CylindricalGrid g = grid();
  const double c_x = 0.7, c_y = -1.3;
  const auto theta = g.azimuthal_faces();
  const double dtheta = g.azimuthal_width();
  for (std::size_t i = 0; i < g.radial_cells(); ++i) {
    for (std::size_t j = 0; j < g.azimuthal_cells(); ++j) {
      const double t1 = theta[j], t2 = theta[j + 1];
      const double curved = c_x * (std::sin(t2) - std::sin(t1)) - c_y * (std::cos(t2) - std::cos(t1));
      const std::size_t k = 0;
      const double outer = g.radial_face_area(i + 1, k) / dtheta * curved;
      const double inner = -g.radial_face_area(i, k) / dtheta * curved;
      const double flat_area = g.azimuthal_face_area(i, k);
      const double side2 = flat_area * (-c_x * std::sin(t2) + c_y * std::cos(t2));  // n = +e_θ(θ₂)
      const double side1 = flat_area * (c_x * std::sin(t1) - c_y * std::cos(t1));   // n = −e_θ(θ₁)
      const double scale = g.radial_face_area(i + 1, k) * std::hypot(c_x, c_y);
      EXPECT_NEAR(outer + inner + side1 + side2, 0.0, 1e-12 * scale) << i << ", " << j;
    }
  }
}

TEST(Grid, GradingIsTheRatioOfLastToFirstRadialWidth) {
  for (const double grading : {0.1, 0.5, 2.0, 10.0}) {
    const CylindricalGrid g = make_grid(30, 1, 4, grading);
    const double ratio = g.radial_width(29) / g.radial_width(0);
    EXPECT_NEAR(ratio, grading, 1e-10 * grading) << grading;
    // Constant growth factor between neighbouring cells.
    const double q = std::pow(grading, 1.0 / 29.0);
    for (std::size_t i = 1; i < 30; ++i) EXPECT_NEAR(g.radial_width(i) / g.radial_width(i - 1), q, 1e-10);
  }
}

TEST(Grid, UniformGridHasEqualRadialWidths) {
  const CylindricalGrid g = make_grid(12, 1, 3);
  for (std::size_t i = 0; i < 12; ++i) EXPECT_NEAR(g.radial_width(i), plate_radius / 12.0, 1e-15);
  EXPECT_TRUE(g.is_axisymmetric());
  EXPECT_EQ(g.cell_count(), 36u);
  EXPECT_DOUBLE_EQ(g.azimuthal_width(), 2.0 * pi);
}

// Axial stretching (tanh map towards both plates): mirror-symmetric about mid-gap, cells grow
// away from each plate, volumes still tile the cylinder, and the grid with half the cells has
// every other face (so grid sequencing and Richardson pairs refine by exactly 2).
TEST(Grid, AxialStretchingClustersSymmetricallyTowardsBothPlates) {
  const auto stretched = [](int n_z, double beta) {
    return CylindricalGrid({.radius = plate_radius,
                            .gap = plate_gap,
                            .radial_cells = 6,
                            .axial_cells = n_z,
                            .radial_grading = 0.5,
                            .axial_stretching = beta});
  };
  const double beta = 1.5;
  const CylindricalGrid g = stretched(16, beta), half = stretched(8, beta);
  EXPECT_FALSE(g.is_axially_uniform());
  const auto z = g.axial_faces();
  EXPECT_EQ(z.front(), 0.0);
  EXPECT_EQ(z.back(), plate_gap);
  for (std::size_t k = 0; k <= 16; ++k) EXPECT_NEAR(z[k] + z[16 - k], plate_gap, 1e-15 * plate_gap) << k;
  for (std::size_t k = 1; k < 8; ++k) EXPECT_GT(g.axial_width(k), g.axial_width(k - 1)) << k;
  // Δz_mid/Δz_plate tends to cosh²β = 5.5 as N_z grows; on 16 cells it is already above 4.
  EXPECT_GT(g.axial_width(7) / g.axial_width(0), 4.0);
  EXPECT_LT(g.axial_width(7) / g.axial_width(0), std::cosh(beta) * std::cosh(beta));
  for (std::size_t k = 0; k <= 8; ++k) EXPECT_NEAR(half.axial_faces()[k], z[2 * k], 1e-15 * plate_gap) << k;
  for (std::size_t k = 0; k < 16; ++k) EXPECT_DOUBLE_EQ(g.axial_centres()[k], 0.5 * (z[k] + z[k + 1]));
  double total = 0.0;
  for (std::size_t i = 0; i < g.radial_cells(); ++i)
    for (std::size_t k = 0; k < g.axial_cells(); ++k) total += g.cell_volume(i, k);
  EXPECT_NEAR(total, pi * plate_radius * plate_radius * plate_gap, 1e-13 * plate_gap * plate_radius * plate_radius);
  const CylindricalGrid uniform = stretched(10, 0.0);
  EXPECT_TRUE(uniform.is_axially_uniform());
  for (std::size_t k = 0; k < 10; ++k) EXPECT_NEAR(uniform.axial_width(k), plate_gap / 10, 1e-15);
}

TEST(Grid, InvalidParametersAreRejectedByName) {
  const auto message = [](CylindricalGrid::Params p) -> std::string {
    try {
      (void)CylindricalGrid(p);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no exception";
  };
  const CylindricalGrid::Params ok{.radius = 0.01, .gap = 1e-3, .radial_cells = 4, .axial_cells = 2};
  EXPECT_NO_THROW((void)CylindricalGrid(ok));

  auto p = ok;
  p.radius = 0.0;
  EXPECT_THAT(message(p), AllOf(HasSubstr("radius"), HasSubstr("> 0")));
  p = ok;
  p.gap = -1e-3;
  EXPECT_THAT(message(p), AllOf(HasSubstr("gap"), HasSubstr("> 0")));
  p = ok;
  p.gap = std::nan("");
  EXPECT_THAT(message(p), HasSubstr("gap"));
  p = ok;
  p.radial_cells = 0;
  EXPECT_THAT(message(p), AllOf(HasSubstr("radial_cells"), HasSubstr(">= 1")));
  p = ok;
  p.azimuthal_cells = 0;
  EXPECT_THAT(message(p), AllOf(HasSubstr("azimuthal_cells"), HasSubstr(">= 1")));
  p = ok;
  p.axial_cells = -3;
  EXPECT_THAT(message(p), AllOf(HasSubstr("axial_cells"), HasSubstr(">= 1")));
  p = ok;
  p.radial_grading = 0.0;
  EXPECT_THAT(message(p), AllOf(HasSubstr("radial_grading"), HasSubstr("> 0")));
  p = ok;
  p.radial_grading = std::numeric_limits<double>::infinity();
  EXPECT_THAT(message(p), HasSubstr("radial_grading"));
  p = ok;
  p.axial_stretching = -0.5;
  EXPECT_THAT(message(p), AllOf(HasSubstr("axial_stretching"), HasSubstr(">= 0")));
  p = ok;
  p.axial_stretching = std::nan("");
  EXPECT_THAT(message(p), HasSubstr("axial_stretching"));
}

}  // namespace
}  // namespace rheosim::fluid
