// CouetteColumn (fluid/couette_column.hpp) against closed forms: plane Couette flow of a
// generalized-Newtonian liquid (a linear profile whatever μ(γ̇), wall stress μ(γ̇)γ̇), and the
// steady profile under a uniform implicit drag towards particles at rest, μu'' = Ku:
// u = U sinh(λz)/sinh(λH), λ = √(K/μ), wall stress μUλ coth(λH).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"
#include "rheosim/fluid/couette_column.hpp"

namespace rheosim::fluid {
namespace {

std::shared_ptr<const core::Rheology> law(const std::string& yaml) {
  return core::make_rheology(core::Document::from_string(yaml, "test.yaml").root());
}

constexpr double gap = 1e-3;  // H [m]

CouetteColumnParams params(std::shared_ptr<const core::Rheology> rheology, int layers, double plate_speed) {
  return {.density = 1000,
          .rheology = std::move(rheology),
          .gap = gap,
          .layers = layers,
          .plate_speed = plate_speed,
          .area = 1e-6};
}

TEST(CouetteColumn, PowerLawCouetteStaysLinearWithTheExactWallStress) {
  const auto power_law = law("{model: power_law, consistency: 0.5, index: 0.4}");
  const double speed = 0.1, rate = speed / gap;  // γ̇ = 100 1/s
  CouetteColumn column(params(power_law, 8, speed));
  for (int step = 0; step < 20; ++step) {
    column.clear_sources();
    column.advance(1e-3);
  }
  const double stress = power_law->stress(rate);
  EXPECT_NEAR(column.wall_stress_top(), stress, 1e-12 * stress);
  EXPECT_NEAR(column.wall_stress_bottom(), stress, 1e-12 * stress);
  EXPECT_NEAR(column.mean_fluid_stress(), stress, 1e-12 * stress);
  for (std::size_t k = 0; k < column.layers(); ++k) {
    const double z = column.centre(k);
    EXPECT_NEAR(column.velocity_at(z)[0], speed * z / gap, 1e-12 * speed);
    EXPECT_NEAR(column.slope_at(z)[0], rate, 1e-9 * rate);
    EXPECT_NEAR(column.div_tau_x(k), 0.0, 1e-9 * stress / gap);
    EXPECT_NEAR(column.cell_viscosity(k), power_law->viscosity(rate), 1e-12 * power_law->viscosity(rate));
  }
}

struct DragRun {
  double profile_error = 0;  // max |u − u_exact| / U over the layer centres
  double wall_error = 0;     // (τ_top − exact) / exact
};

// Particles at rest in every layer, K = μλ² with λH = 3, run to steady state.
DragRun run_with_drag(int layers, double dt) {
  const double viscosity = 1e-3, speed = 0.01, lambda = 3.0 / gap, drag = viscosity * lambda * lambda;
  CouetteColumn column(params(law("{model: newtonian, viscosity: 1.0e-3}"), layers, speed));
  double last_stress = 0;
  for (int step = 0; step < 100000; ++step) {
    column.clear_sources();
    for (std::size_t k = 0; k < column.layers(); ++k)
      column.add_reaction(k, drag * column.layer_volume(), column.velocity_at(column.centre(k)), {0.0, 0.0, 0.0});
    column.advance(dt);
    if (step > 10 && std::abs(column.wall_stress_top() - last_stress) < 1e-15 * std::abs(last_stress)) break;
    last_stress = column.wall_stress_top();
  }
  DragRun run;
  for (std::size_t k = 0; k < column.layers(); ++k) {
    const double z = column.centre(k);
    const double exact = speed * std::sinh(lambda * z) / std::sinh(lambda * gap);
    run.profile_error = std::max(run.profile_error, std::abs(column.velocity_at(z)[0] - exact) / speed);
  }
  const double exact_wall = viscosity * speed * lambda / std::tanh(lambda * gap);
  run.wall_error = (column.wall_stress_top() - exact_wall) / exact_wall;
  std::printf("[ measured ] %d layers: profile error %.3e U, top wall stress error %+.3e\n", layers, run.profile_error,
              run.wall_error);
  return run;
}

// The profile and the wall stress converge at second order (measured: profile 3.9e-3, 1.0e-3,
// 2.7e-4 of U and wall stress −4.3e-3, −1.1e-3, −2.7e-4 at 16, 32, 64 layers); the steady state
// does not depend on the step.
TEST(CouetteColumn, UniformDragGivesTheSinhProfile) {
  const DragRun coarse = run_with_drag(16, 1e-2), fine = run_with_drag(32, 1e-2), finest = run_with_drag(64, 1e-2);
  EXPECT_LT(finest.profile_error, 4e-4);
  EXPECT_GT(std::log2(fine.profile_error / finest.profile_error), 1.8);
  EXPECT_GT(std::log2(coarse.profile_error / fine.profile_error), 1.8);
  EXPECT_LT(std::abs(finest.wall_error), 4e-4);
  EXPECT_GT(std::log2(std::abs(fine.wall_error / finest.wall_error)), 1.8);
  const DragRun other_step = run_with_drag(32, 1e-4);
  EXPECT_NEAR(other_step.profile_error, fine.profile_error, 1e-9);
}

TEST(CouetteColumn, RefusesParametersByName) {
  const auto newtonian = law("{model: newtonian, viscosity: 1.0e-3}");
  EXPECT_THAT([&] { CouetteColumn c(params(newtonian, 0, 0.1)); },
              ::testing::ThrowsMessage<std::invalid_argument>(::testing::HasSubstr("layers")));
  auto p = params(newtonian, 8, 0.1);
  p.gap = -1;
  EXPECT_THAT([&] { CouetteColumn c(p); },
              ::testing::ThrowsMessage<std::invalid_argument>(::testing::HasSubstr("gap")));
  p = params(nullptr, 8, 0.1);
  EXPECT_THAT([&] { CouetteColumn c(p); },
              ::testing::ThrowsMessage<std::invalid_argument>(::testing::HasSubstr("rheology")));
}

}  // namespace
}  // namespace rheosim::fluid
