// Closed-form plate torques against direct quadrature of T = 2π ∫₀ᴿ τ(γ̇_R r/R) r² dr.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"
#include "rheosim/core/units.hpp"
#include "rheosim/rheometer/plate.hpp"

namespace rheosim::rheometer {
namespace {

const ParallelPlate cd_plate{0.015, 0.0005};  // CD §2.3

std::shared_ptr<const core::Rheology> law(const std::string& yaml) {
  const auto doc = core::Document::from_string(yaml, "test.yaml");
  return core::make_rheology(doc.root());
}

TEST(Plate, KinematicsAndReynoldsNumber) {
  EXPECT_DOUBLE_EQ(cd_plate.angular_velocity(100), 100 * 0.0005 / 0.015);
  EXPECT_DOUBLE_EQ(cd_plate.rim_shear_rate(cd_plate.angular_velocity(37)), 37);
  // Water between the CD plates at 100 1/s: ρΩH²/μ = 1000 · 3.33 · 2.5e-7 / 1e-3.
  EXPECT_NEAR(cd_plate.gap_reynolds_number(1000, 100, 1e-3), 0.8333333333, 1e-9);
}

TEST(Plate, NewtonianClosedFormMatchesQuadrature) {
  const auto water = law("model: newtonian\nviscosity: 1.0e-3\n");
  for (double rate : {1.0, 10.0, 50.0, 100.0}) {
    const double exact = newtonian_torque(cd_plate, 1e-3, rate);
    // CD eq. 8 in terms of Ω: T = πηΩR⁴/(2H).
    EXPECT_NEAR(exact, core::units::pi * 1e-3 * cd_plate.angular_velocity(rate) * std::pow(0.015, 4) / (2 * 0.0005),
                1e-15 * exact);
    EXPECT_NEAR(creeping_torque(cd_plate, *water, rate), exact, 1e-12 * exact);
    EXPECT_DOUBLE_EQ(*closed_form_torque(cd_plate, *water, rate), exact);
  }
}

TEST(Plate, PowerLawClosedFormMatchesQuadrature) {
  for (double n : {0.3, 0.6, 0.9, 1.5}) {
    const auto fluid = law("model: power_law\nconsistency: 1.0e-3\nindex: " + std::to_string(n) + "\n");
    for (double rate : {1.0, 10.0, 100.0}) {
      const double exact = power_law_torque(cd_plate, 1e-3, n, rate);
      // The low-rate plateau (γ̇ < 1e-6 1/s) only touches r < 1e-6 R/γ̇_R: invisible here.
      EXPECT_NEAR(creeping_torque(cd_plate, *fluid, rate), exact, 1e-9 * exact) << "n=" << n;
    }
  }
}

TEST(Plate, PowerLawWithIndexOneIsNewtonian) {
  EXPECT_NEAR(power_law_torque(cd_plate, 2e-3, 1.0, 30), newtonian_torque(cd_plate, 2e-3, 30), 1e-18);
}

TEST(Plate, YieldStressClosedFormsMatchQuadratureAsRegularisationVanishes) {
  // The Papanastasiou law differs from the exact one only where m γ̇ = O(1), a core of radius
  // ~ R/(m γ̇_R); weighted by r², its torque share shrinks like (m γ̇_R)⁻³.
  const double rate = 10.0;
  const std::string bingham = "model: bingham\nplastic_viscosity: 0.1\nyield_stress: 5.0\nregularization: ";
  const std::string casson = "model: casson\nplastic_viscosity: 0.1\nyield_stress: 5.0\nregularization: ";
  const std::string hb = "model: herschel_bulkley\nconsistency: 0.1\nindex: 0.5\nyield_stress: 5.0\nregularization: ";
  for (const auto& [yaml, exact] : {std::pair{bingham, bingham_torque(cd_plate, 0.1, 5.0, rate)},
                                    std::pair{casson, casson_torque(cd_plate, 0.1, 5.0, rate)},
                                    std::pair{hb, herschel_bulkley_torque(cd_plate, 0.1, 0.5, 5.0, rate)}}) {
    double previous_error = 0;
    for (double m : {1e2, 1e3, 1e4}) {
      const auto fluid = law(yaml + std::to_string(m) + "\n");
      const double error = std::abs(creeping_torque(cd_plate, *fluid, rate) - exact) / exact;
      EXPECT_LT(error, 5.0 / m) << yaml << m;
      if (previous_error > 0) {
        EXPECT_LT(error, previous_error / 100) << "error must fall ~m^-3";
      }
      previous_error = error;
      EXPECT_DOUBLE_EQ(*closed_form_torque(cd_plate, *fluid, rate), exact);
    }
  }
}

TEST(Plate, LawsWithoutClosedFormSayNothing) {
  const auto fluid =
      law("model: cross\nzero_shear_viscosity: 1.0\ninfinite_shear_viscosity: 0.01\n"
          "time_constant: 0.1\nexponent: 0.7\n");
  EXPECT_FALSE(closed_form_torque(cd_plate, *fluid, 10).has_value());
  EXPECT_GT(creeping_torque(cd_plate, *fluid, 10), 0);
}

}  // namespace
}  // namespace rheosim::rheometer
