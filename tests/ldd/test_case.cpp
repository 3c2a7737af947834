// LDD case files: the ldd module reads its part of a case file into typed settings, and every
// kind of bad input is a ConfigError naming file:line:column, the key path and the valid choices.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>
#include <string>

#include "case_test_support.hpp"
#include "rheosim/core/case.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/ldd/case.hpp"

namespace rheosim::ldd {
namespace {

using core::ConfigError;
using ::testing::HasSubstr;

ConfigError parse_error(const std::string& text) {
  return test_support::config_error([](const std::string& t) { (void)parse_case(t, "case.yaml"); }, text);
}
using test_support::replace;

const std::string cavity_case = R"(kind: ldd
dimension: 2
scene: {type: skewed_cavity, size: [1.0, 1.0], lid_velocity: 1.0, skew_angle: 60}
fluid:
  density: 1.0
  rheology: {model: power_law, consistency: 0.002, index: 1.5}
gravity: [0, 0]
resolution: {spacing: 0.02}
time: {step: 1.0e-3, end: 20.0}
)";

TEST(Case, LddSkewAngleIsConvertedToRadians) {
  const Case c = parse_case(cavity_case, "skew.yaml");
  const auto& l = c.settings;
  EXPECT_EQ(l.scene_type, "skewed_cavity");
  EXPECT_NEAR(std::get<CavityScene>(l.scene).skew_angle, std::numbers::pi / 3, 1e-15);
  EXPECT_DOUBLE_EQ(l.smoothing_ratio, 1.6);
}

// time.step: auto keeps the advective Courant number at 0.25 for the scene's velocity scale:
// the lid speed of a cavity (0.25 · 0.02 / 1 = 5e-3 s), the collapse front 2√(gH) of a dam break
// (0.25 · 0.002 / (2√(9.81 · 0.2)) = 1.785e-4, rounded down to 1.7e-4 s); a word other than auto
// is refused with the alternatives.
TEST(Case, LddAutomaticTimeStepFollowsTheSceneVelocityScale) {
  const CaseSettings cavity = parse_case(replace(cavity_case, "step: 1.0e-3", "step: auto"), "auto.yaml").settings;
  EXPECT_DOUBLE_EQ(cavity.time_step, 5e-3);
  EXPECT_THAT(cavity.time_step_rule, HasSubstr("lid speed"));
  const std::string dam_break =
      "kind: ldd\ndimension: 2\nscene: {type: dam_break, reservoir: [0.1, 0.2], channel_length: 0.6}\n"
      "fluid: {density: 1000, rheology: {model: newtonian, viscosity: 1.0e-3}}\ngravity: [0, -9.81]\n"
      "resolution: {spacing: 0.002}\ntime: {step: auto, end: 0.3}\n";
  const CaseSettings water = parse_case(dam_break, "water.yaml").settings;
  EXPECT_NEAR(water.time_step, 1.7e-4, 1e-12);
  EXPECT_THAT(water.time_step_rule, HasSubstr("2√(|g|H)"));
  EXPECT_TRUE(parse_case(cavity_case, "given.yaml").settings.time_step_rule.empty());
  const auto e = parse_error(replace(cavity_case, "step: 1.0e-3", "step: fast"));
  EXPECT_EQ(e.details().key_path, "time.step");
  EXPECT_THAT(e.details().expected, HasSubstr("or auto"));
}

TEST(Case, LddGravityNeedsOneEntryPerDimension) {
  const auto e = parse_error(replace(cavity_case, "gravity: [0, 0]", "gravity: [0, 0, -9.81]"));
  EXPECT_EQ(e.details().key_path, "gravity");
  EXPECT_THAT(e.details().expected, HasSubstr("exactly 2"));
}

TEST(Case, LddSceneKeysDependOnTheType) {
  // skew_angle belongs to skewed cavities only.
  const auto e = parse_error(replace(cavity_case, "type: skewed_cavity", "type: cavity"));
  EXPECT_EQ(e.details().key_path, "scene.skew_angle");
  EXPECT_THAT(e.details().problem, HasSubstr("unknown key"));
}

TEST(Case, LddPreconditionersAreCheckedWithTheirLine) {
  const Case c = parse_case(cavity_case + "solver: {pressure_preconditioner: amg}\n", "amg.yaml");
  EXPECT_EQ(c.settings.solver.pressure_preconditioner, Preconditioner::amg);
  EXPECT_FALSE(c.settings.solver.velocity_preconditioner.has_value());  // auto
  const auto typo = parse_error(cavity_case + "solver: {pressure_preconditioner: multigrid}\n");
  EXPECT_EQ(typo.details().key_path, "solver.pressure_preconditioner");
  EXPECT_EQ(typo.details().where.line, 10);
  // A cavity's velocity solve has no sparse-LU preconditioner.
  const auto lu = parse_error(cavity_case + "solver: {velocity_preconditioner: lu}\n");
  EXPECT_EQ(lu.details().key_path, "solver.velocity_preconditioner");
  EXPECT_EQ(lu.details().where.line, 10);
}

// A cavity refuses `solver: {key: value}` with an error at that line naming what is valid.
void expect_cavity_refuses(const std::string& key, const std::string& value, const std::string& valid) {
  const auto e = parse_error(cavity_case + "solver: {" + key + ": " + value + "}\n");
  EXPECT_EQ(e.details().key_path, "solver." + key);
  EXPECT_EQ(e.details().where.line, 10);
  EXPECT_THAT(e.details().expected, HasSubstr(valid));
}

TEST(Case, LddGradientIsCheckedAgainstTheScene) {
  EXPECT_EQ(parse_case(cavity_case, "c.yaml").settings.solver.gradient, GradientChoice::automatic);
  EXPECT_EQ(parse_case(cavity_case + "solver: {gradient: renormalised}\n", "c.yaml").settings.solver.gradient,
            GradientChoice::renormalised);
  // A cavity's wall rows need the wall node's own value in its gradient.
  expect_cavity_refuses("gradient", "centred", "renormalised");
  const auto typo = parse_error(cavity_case + "solver: {gradient: centered}\n");
  EXPECT_EQ(typo.details().key_path, "solver.gradient");
}

// A slump's mould is a cone or, with equal diameters, a cylinder (Pashias' slump test); a mould
// wider at the top is refused at its key. time.settle_energy_ratio: 0 runs a slump to its end;
// time.arrest_stress_tolerance (default 0.1) is a share of τ₀ in [0, 1].
TEST(Case, LddSlumpMouldIsAConeOrACylinder) {
  const std::string slump =
      "kind: ldd\ndimension: 3\nscene: {type: slump, cone: {height: 0.1, bottom_diameter: 0.1, top_diameter: 0.1}, "
      "lift_velocity: 0.5}\nfluid: {density: 1000, rheology: {model: bingham, plastic_viscosity: 20.0, "
      "yield_stress: 98.1, regularization: 1000}}\ngravity: [0, 0, -9.81]\nresolution: {spacing: 0.01}\n"
      "time: {step: 1.0e-3, end: 1.0, settle_energy_ratio: 0}\n";
  const CaseSettings cylinder = parse_case(slump, "cylinder.yaml").settings;
  EXPECT_EQ(std::get<SlumpScene>(cylinder.scene).cone_top_diameter, 0.1);
  EXPECT_EQ(cylinder.settle_energy_ratio, 0.0);
  EXPECT_EQ(parse_case(replace(slump, ", settle_energy_ratio: 0", ""), "default.yaml").settings.settle_energy_ratio,
            1e-3);
  const auto e = parse_error(replace(slump, "top_diameter: 0.1}", "top_diameter: 0.12}"));
  EXPECT_EQ(e.details().key_path, "scene.cone.top_diameter");
  EXPECT_THAT(e.details().expected, HasSubstr("<= 0.1 m"));
  EXPECT_EQ(cylinder.arrest_stress_tolerance, 0.1);
  const auto tolerant =
      replace(slump, "settle_energy_ratio: 0}\n", "settle_energy_ratio: 0, arrest_stress_tolerance: ");
  EXPECT_EQ(parse_case(tolerant + "0.01}\n", "tight.yaml").settings.arrest_stress_tolerance, 0.01);
  const auto negative = parse_error(tolerant + "-0.1}\n");
  EXPECT_EQ(negative.details().key_path, "time.arrest_stress_tolerance");
  EXPECT_EQ(negative.details().where.line, 7);
  // time.stop_at_arrest (default 0: never) is a hold time in seconds, and only for a material
  // that can arrest.
  EXPECT_EQ(cylinder.arrest_hold_time, 0.0);
  const auto holding = replace(slump, "settle_energy_ratio: 0}\n", "settle_energy_ratio: 0, stop_at_arrest: ");
  EXPECT_EQ(parse_case(holding + "0.5}\n", "hold.yaml").settings.arrest_hold_time, 0.5);
  const auto backwards = parse_error(holding + "-1}\n");
  EXPECT_EQ(backwards.details().key_path, "time.stop_at_arrest");
  EXPECT_EQ(backwards.details().where.line, 7);
  const auto liquid = parse_error(replace(holding + "0.5}\n",
                                          "rheology: {model: bingham, plastic_viscosity: 20.0, "
                                          "yield_stress: 98.1, regularization: 1000}",
                                          "rheology: {model: newtonian, viscosity: 20.0}"));
  EXPECT_EQ(liquid.details().key_path, "time.stop_at_arrest");
  EXPECT_THAT(liquid.details().problem, HasSubstr("never arrests"));
}

// A cavity's nodes always return to the lattice: there is no reordering to choose.
TEST(Case, LddCavityHasNoReorderingKey) {
  const auto e = parse_error(cavity_case + "solver: {reordering: density}\n");
  EXPECT_EQ(e.details().key_path, "solver.reordering");
  EXPECT_EQ(e.details().where.line, 10);
}

TEST(Case, LddCavityRefusesTheFreeSurfaceSolverKeys) {
  // Keys only the free-surface solver reads are refused for a cavity, not ignored.
  expect_cavity_refuses("pressure_amg", "plain", "leave it out");
  expect_cavity_refuses("pbd_sweeps", "3", "leave it out");
  expect_cavity_refuses("moment_rcond", "0.01", "leave it out");
  expect_cavity_refuses("surface_moment_rcond", "0.01", "leave it out");
  expect_cavity_refuses("viscous_stress", "full", "leave it out");
  expect_cavity_refuses("surface_stress", "normal", "leave it out");
  expect_cavity_refuses("pbd_surface", "tangential", "leave it out");
  expect_cavity_refuses("surface_detection", "umbrella", "leave it out");
  expect_cavity_refuses("wall_viscosity", "face_shear_rate", "leave it out");
}

TEST(Case, LddChoicesArriveAsEnums) {
  const CaseSettings c = parse_case(cavity_case +
                                        "solver: {interpolation: shepard, pressure_preconditioner: jacobi, "
                                        "velocity_preconditioner: amg}\n",
                                    "c.yaml")
                             .settings;
  EXPECT_EQ(c.solver.interpolation, LatticeInterpolation::shepard);
  EXPECT_EQ(c.solver.pressure_preconditioner, Preconditioner::jacobi);
  EXPECT_EQ(c.solver.velocity_preconditioner, Preconditioner::amg);
  const std::string dam_break =
      "kind: ldd\ndimension: 2\nscene: {type: dam_break, reservoir: [0.1, 0.2], channel_length: 0.6}\n"
      "fluid: {density: 1000, rheology: {model: newtonian, viscosity: 1.0e-3}}\ngravity: [0, -9.81]\n"
      "resolution: {spacing: 0.002}\ntime: {step: 1.0e-4, end: 0.3}\n";
  const CaseSettings d = parse_case(dam_break +
                                        "solver: {gradient: surface_anchored, pbd_velocity: none, dry_walls: exclude, "
                                        "pressure_amg: plain, velocity_preconditioner: lu, viscous_stress: full, "
                                        "surface_stress: normal, pbd_surface: tangential, surface_detection: "
                                        "umbrella, wall_viscosity: face_shear_rate}\n",
                                    "d.yaml")
                             .settings;
  EXPECT_EQ(d.solver.gradient, GradientChoice::surface_anchored);
  EXPECT_FALSE(d.solver.pbd_velocity_correction);
  EXPECT_EQ(d.solver.dry_walls, DryWalls::exclude);
  EXPECT_TRUE(d.solver.full_viscous_stress);
  EXPECT_FALSE(parse_case(dam_break, "d.yaml").settings.solver.full_viscous_stress);  // laplacian
  EXPECT_TRUE(d.solver.surface_normal_stress);
  EXPECT_FALSE(parse_case(dam_break, "d.yaml").settings.solver.surface_normal_stress);  // none
  EXPECT_TRUE(d.solver.pbd_surface_tangential);
  EXPECT_FALSE(parse_case(dam_break, "d.yaml").settings.solver.pbd_surface_tangential);  // full
  EXPECT_TRUE(d.solver.surface_umbrella);
  EXPECT_FALSE(parse_case(dam_break, "d.yaml").settings.solver.surface_umbrella);  // local
  EXPECT_TRUE(d.solver.wall_face_shear_rate);
  EXPECT_FALSE(parse_case(dam_break, "d.yaml").settings.solver.wall_face_shear_rate);  // mean
  EXPECT_EQ(parse_case(dam_break, "d.yaml").settings.solver.dry_walls, DryWalls::include);
  EXPECT_EQ(parse_case(dam_break + "solver: {dry_walls: extrapolate}\n", "e.yaml").settings.solver.dry_walls,
            DryWalls::extrapolate);
  EXPECT_EQ(d.solver.pressure_amg, AmgAggregation::plain);
  EXPECT_EQ(parse_case(dam_break, "d.yaml").settings.solver.pressure_amg, AmgAggregation::smoothed);
  EXPECT_EQ(parse_case(dam_break + "solver: {pressure_amg: auto}\n", "a.yaml").settings.solver.pressure_amg,
            AmgAggregation::automatic);
  try {
    (void)parse_case(dam_break + "solver: {pressure_amg: smooth}\n", "s.yaml");
    ADD_FAILURE() << "pressure_amg: smooth was accepted";
  } catch (const core::ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("s.yaml:8:24: solver.pressure_amg"));
    EXPECT_THAT(e.what(), HasSubstr("one of: smoothed, plain, auto"));
    EXPECT_THAT(e.what(), HasSubstr("did you mean 'smoothed'"));
  }
  EXPECT_EQ(d.solver.velocity_preconditioner, Preconditioner::sparse_lu);
  EXPECT_FALSE(d.solver.pressure_preconditioner.has_value());  // auto: the scene's own
  // The names the benchmarks' command lines use are the case file's, and nothing else.
  EXPECT_EQ(preconditioner_named("lu"), Preconditioner::sparse_lu);
  EXPECT_FALSE(preconditioner_named("multigrid").has_value());
  EXPECT_EQ(lattice_interpolation_named("gradient_corrected"), LatticeInterpolation::gradient_corrected);
  EXPECT_FALSE(lattice_interpolation_named("anything else").has_value());
  EXPECT_EQ(name_of(Preconditioner::sparse_lu), "lu");
}

TEST(Case, TheLddReaderRefusesARheometerCase) {
  const auto e = parse_error("kind: rheometer\n");
  EXPECT_EQ(e.details().key_path, "kind");
  EXPECT_THAT(e.details().problem, HasSubstr("not 'rheometer'"));
}

// Every shipped LDD case reads (the CLI test validate_shipped_cases runs every kind).
TEST(Case, EveryShippedLddCaseReads) {
  const std::filesystem::path cases = std::filesystem::path(RHEOSIM_SOURCE_DIR) / "cases";
  int read = 0;
  for (const auto& entry : std::filesystem::directory_iterator(cases)) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const core::CaseFile file = core::CaseFile::open(entry.path().string());
    if (file.header().kind != "ldd") continue;
    EXPECT_EQ(ldd::read_case(file).kind, "ldd");
    ++read;
  }
  EXPECT_GE(read, 10);
}

}  // namespace
}  // namespace rheosim::ldd
