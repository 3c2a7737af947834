// rheometer/shear_cell.hpp: the plate torque integrated from a local
// flow curve reproduces the closed forms (Newtonian CD eq. 8, power law CD eq. 9); the piecewise
// power-law curve is exact at its points; dimensionless groups of the seed; the case key
// `model:` and the automatic choice with its reason (the walled box below H/d = 10).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rheosim/core/config.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/rheology.hpp"
#include "rheosim/rheometer/box_point.hpp"
#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/plate.hpp"
#include "rheosim/rheometer/shear_cell.hpp"

namespace rheosim::rheometer {
namespace {

using Model = RheometerCase::SuspensionModel;

const std::string seed_case = R"(kind: sweep
geometry: {type: parallel_plate, radius: 0.015, gap: 0.0005}
fluid:
  density: 1000
  rheology: {model: newtonian, viscosity: 1.0e-3}
shear_rates: [10, 25, 50, 75, 100]
volume_fractions: [0, 0.1, 0.3]
particles: {diameter: 2.0e-4, density: 1000}
)";

RheometerCase seed(const std::string& extra = "") {
  return std::get<SweepCase>(parse_case(seed_case + extra, "seed.yaml").spec).rheometer;
}

TEST(ShearCellTorque, LinearCurveGivesTheNewtonianTorque) {
  LocalFlowCurve curve{.shear_rate = {50.0, 100.0}, .stress = {0.065, 0.13}, .linear = true, .viscosity = 1.3e-3};
  const ParallelPlate plate{0.015, 0.0005};
  for (const double rate : {10.0, 100.0})
    EXPECT_NEAR(plate_torque(curve, 0.015, rate), newtonian_torque(plate, 1.3e-3, rate),
                1e-12 * newtonian_torque(plate, 1.3e-3, rate));
}

TEST(ShearCellTorque, PowerLawPointsGiveThePowerLawTorque) {
  // τ = K γ̇ⁿ sampled at three rates: the piecewise power law is the law itself, extrapolation too.
  const double k = 0.02, n = 0.6;
  LocalFlowCurve curve;
  for (const double rate : {20.0, 50.0, 100.0}) {
    curve.shear_rate.push_back(rate);
    curve.stress.push_back(k * std::pow(rate, n));
  }
  const ParallelPlate plate{0.015, 0.0005};
  for (const double rate : {10.0, 35.0, 100.0, 150.0}) {
    const double exact = power_law_torque(plate, k, n, rate);
    EXPECT_NEAR(plate_torque(curve, 0.015, rate), exact, 1e-9 * exact) << rate;
  }
  EXPECT_DOUBLE_EQ(curve.stress_at(50.0), k * std::pow(50.0, n));
}

TEST(ShearCellGroups, SeedPointAtTheEdgeOfTheStokesRegime) {
  const auto r = seed();
  auto p = *r.particles;
  const auto g = dimensionless_groups(r, r.fluid, p, 100.0);
  EXPECT_NEAR(g.gap_reynolds, 0.8333333333, 1e-9);
  EXPECT_NEAR(g.particle_reynolds, 1.0, 1e-12);  // ρ γ̇ a² / μ
  EXPECT_NEAR(g.stokes, 2.0 / 9.0, 1e-12);       // (2/9) ρ_p γ̇ a² / μ
  EXPECT_EQ(g.bingham, 0.0);
  EXPECT_NEAR(g.stiffness, 0.1 / (3e9 / (2 * (1 - 0.33 * 0.33))), 1e-20);
  EXPECT_DOUBLE_EQ(g.gap_over_diameter, 2.5);
  EXPECT_TRUE(g.stokes_regime());
  EXPECT_FALSE(dimensionless_groups(r, r.fluid, p, 200.0).stokes_regime());
}

TEST(ShearCellModelChoice, CaseKeyAndAutomaticChoice) {
  EXPECT_EQ(seed().suspension_model, Model::automatic);
  EXPECT_EQ(seed("model: shear_cell\n").suspension_model, Model::shear_cell);
  EXPECT_EQ(seed("model: full_disk\n").suspension_model, Model::full_disk);
  EXPECT_EQ(seed("model: lees_edwards\n").suspension_model, Model::lees_edwards);
  EXPECT_EQ(seed("model: walled_box\n").suspension_model, Model::walled_box);
  EXPECT_THROW((void)seed("model: shearcell\n"), core::ConfigError);
  EXPECT_STREQ(name_of(Model::shear_cell), "shear_cell");
  EXPECT_STREQ(name_of(Model::lees_edwards), "lees_edwards");
  EXPECT_STREQ(name_of(Model::walled_box), "walled_box");

  // No hydrodynamics block: the predictive box, and the reason names how to get the seed's model.
  // The seed's gap is 2.5 diameters: the plates are simulated (the walled box); `model:
  // lees_edwards` gives the bulk there, and from H/d = 10 on auto gives it too.
  const auto predictive = choose_suspension_model(seed(), 0.3, 600);
  EXPECT_EQ(predictive.model, Model::walled_box);
  EXPECT_NE(predictive.reason.find("no hydrodynamics block"), std::string::npos) << predictive.reason;
  EXPECT_NE(predictive.reason.find("{model: none}"), std::string::npos) << predictive.reason;
  EXPECT_NE(predictive.reason.find("H/d = 2.5 < 10"), std::string::npos) << predictive.reason;
  EXPECT_TRUE(box_has_walls(seed()));
  EXPECT_FALSE(box_has_walls(seed("model: lees_edwards\n")));
  EXPECT_EQ(choose_suspension_model(seed("model: lees_edwards\n"), 0.3, 600).model, Model::lees_edwards);
  EXPECT_DOUBLE_EQ(box_settings(seed(), 0.3, 100.0).wall_gap, 5.0);  // H/a
  EXPECT_EQ(box_settings(seed("model: lees_edwards\n"), 0.3, 100.0).wall_gap, 0.0);
  auto wide = seed();
  wide.geometry.gap = 0.002;  // H/d = 10
  EXPECT_EQ(choose_suspension_model(wide, 0.3, 600).model, Model::lees_edwards);
  EXPECT_FALSE(box_has_walls(wide));
  // A near field with lubrication runs in the box too; a small disk (R/H = 6) is still the box,
  // with the rim named as a limit.
  auto lubricated = seed();
  lubricated.particles->hydrodynamics_given = true;
  lubricated.particles->hydrodynamics.terms.lubrication = true;
  EXPECT_EQ(choose_suspension_model(lubricated, 0.3, 600).model, Model::walled_box);
  auto small_predictive = seed();
  small_predictive.geometry.radius = 0.003;
  const auto small_box = choose_suspension_model(small_predictive, 0.1, 1e9);
  EXPECT_EQ(small_box.model, Model::walled_box);
  EXPECT_NE(small_box.reason.find("R/H = 6"), std::string::npos) << small_box.reason;
}

TEST(ShearCellModelChoice, DragOnlyAutomaticChoice) {
  const std::string drag_only_case = R"(kind: sweep
geometry: {type: parallel_plate, radius: 0.015, gap: 0.0005}
fluid:
  density: 1000
  rheology: {model: newtonian, viscosity: 1.0e-3}
shear_rates: [10, 25, 50, 75, 100]
volume_fractions: [0, 0.1, 0.3]
particles: {diameter: 2.0e-4, density: 1000, hydrodynamics: {model: none}}
)";
  const auto drag_only = [&](const std::string& extra = "") {
    return std::get<SweepCase>(parse_case(drag_only_case + extra, "seed.yaml").spec).rheometer;
  };
  // The seed's drag-only model: R/H = 30, Re_gap 0.83, monodisperse: the cell, with both costs.
  const auto choice = choose_suspension_model(drag_only(), 0.3, 600);
  EXPECT_EQ(choice.model, Model::shear_cell);
  EXPECT_NE(choice.reason.find("full disk ≈"), std::string::npos) << choice.reason;
  EXPECT_EQ(choose_suspension_model(drag_only("model: full_disk\n"), 0.3, 600).model, Model::full_disk);

  // A small disk (R/H = 6) that fits the budget: the full disk, and the reason says why.
  auto small = drag_only();
  small.geometry.radius = 0.003;
  const auto small_choice = choose_suspension_model(small, 0.1, 1e9);
  EXPECT_EQ(small_choice.model, Model::full_disk);
  EXPECT_NE(small_choice.reason.find("R/H"), std::string::npos) << small_choice.reason;

  // The study estimate that the dispatcher holds against --point-budget: seconds for the seed.
  EXPECT_GT(choice.cell_study_seconds, 0.0);
  EXPECT_LT(choice.cell_study_seconds, 600.0);
}

}  // namespace
}  // namespace rheosim::rheometer
