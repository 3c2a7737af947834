// summary.json of a sweep read back typed: required keys are values, optional ones (absent or
// null) are empty, and a mistyped key anywhere is refused with its path.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "rheosim/core/config.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/rheology.hpp"
#include "rheosim/rheometer/plate.hpp"
#include "rheosim/rheometer/run_analysis.hpp"
#include "rheosim/rheometer/sweep_summary.hpp"

namespace rheosim::rheometer {
namespace {

nlohmann::json summary_with_analysis() {
  using J = nlohmann::json;
  J converged = {{"fluid", "oil"},
                 {"volume_fraction", 0.2},
                 {"shear_rate", 10.0},
                 {"converged", true},
                 {"method", "box"},
                 {"torque", 2.5e-4},
                 {"torque_std_error", nullptr},
                 {"iterations", 7},
                 {"rim_stress", 31.0},
                 {"normal_force", -0.01},
                 {"validity",
                  {{"gap_reynolds", 1e-3},
                   {"particle_reynolds", nullptr},
                   {"stokes", nullptr},
                   {"gap_to_diameter", 20.0},
                   {"gap_reynolds_ok", true},
                   {"particle_reynolds_ok", true},
                   {"stokes_ok", true},
                   {"gap_to_diameter_ok", true},
                   {"valid", true},
                   {"messages", J::array()}}},
                 {"used_in_fits", false}};
  J failed = {{"fluid", "oil"},     {"volume_fraction", 0.4}, {"shear_rate", 10.0},
              {"converged", false}, {"method", "box"},        {"failure", "over budget"}};
  J fit = {{"label", "oil φ 0.2"},
           {"fluid", "oil"},
           {"volume_fraction", 0.2},
           {"model", "carreau"},
           {"equation", "η = ..."},
           {"converged", true},
           {"iterations", 9},
           {"stop_reason", "small step"},
           {"points", 2},
           {"rank", 2},
           {"degrees_of_freedom", -1},
           {"delta", 1.5},
           {"akaike_weight", nullptr},
           {"aicc", nullptr},
           {"aic", 3.0},
           {"residual_std", 0.01},
           {"sum_of_squares", 2e-4},
           {"min_shear_rate", 1.0},
           {"max_shear_rate", 100.0},
           {"parameters",
            {{{"name", "viscosity"},
              {"symbol", "η"},
              {"unit", "Pa·s"},
              {"value", 1.1},
              {"std_error", nullptr},
              {"ci95", {nullptr, 1.3}}}}},
           {"warnings", {{{"kind", "k"}, {"parameter", "p"}, {"message", "not identifiable"}}}},
           {"shear_rate", {1.0, 10.0}},
           {"residuals", {0.01, nullptr}},
           {"correlation", {{1.0, nullptr}, {nullptr, 1.0}}}};
  return {{"case", "typed"},
          {"kind", "sweep"},
          {"rheosim_version", "0"},
          {"git_revision", "test"},
          {"input_sha256", "0"},
          {"radius", 0.02},
          {"gap", 0.001},
          {"wall_time", 1.0},
          {"points_failed", 1},
          {"points_resumed", 0},
          {"inertia", false},
          {"grid", {{"radial_cells", 48}, {"axial_cells", 12}, {"radial_grading", 1.0}}},
          {"warnings", {{{"warning", "ε clamped"}, {"points", 2}}}},
          {"points", {converged, failed}},
          {"series",
           {{{"label", "oil φ 0.2"},
             {"fluid", "oil"},
             {"volume_fraction", 0.2},
             {"points", 1},
             {"torque_line",
              {{"intercept", 1e-5},
               {"intercept_std_error", nullptr},
               {"slope", 2e-5},
               {"slope_std_error", 1e-6},
               {"plastic_viscosity", 0.1},
               {"plastic_viscosity_ci95", {0.05, 0.15}},
               {"residuals", {1e-7, -1e-7}}}}}}},
          {"fits", {fit}},
          {"yield_stress",
           {{{"label", "oil φ 0.2"},
             {"fluid", "oil"},
             {"method", "torque_intercept"},
             {"volume_fraction", 0.2},
             {"value", 0.5},
             {"std_error", 0.1},
             {"ci95", {0.3, 0.7}},
             {"significant", true},
             {"converged", true}}}},
          {"relative_viscosity", {{{"fluid", "oil"}, {"warnings", {"oil: no flow curve could be fitted"}}}}}};
}

class SweepSummaryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
  }
  void TearDown() override { std::filesystem::remove_all(folder); }
  SweepSummary read(const nlohmann::json& json) {
    core::write_json(folder / "summary.json", json);
    return read_sweep_summary(folder);
  }
  std::string refused_at(const nlohmann::json& json) {
    try {
      (void)read(json);
    } catch (const core::ConfigError& e) {
      return e.details().key_path;
    }
    return "";
  }
  // One folder per test: ctest runs the tests of this file in parallel.
  std::filesystem::path folder =
      std::filesystem::temp_directory_path() /
      (std::string("rheosim_sweep_summary_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
};

TEST_F(SweepSummaryTest, ReadsRequiredValuesAndLeavesAbsentOrNullOnesEmpty) {
  const SweepSummary s = read(summary_with_analysis());
  EXPECT_EQ(s.head.case_name, "typed");
  EXPECT_EQ(s.points_failed, 1U);
  ASSERT_TRUE(s.points_resumed.has_value());
  EXPECT_FALSE(s.inertia);
  ASSERT_TRUE(s.grid.has_value());
  EXPECT_EQ(s.grid->radial_cells, 48);
  EXPECT_EQ(s.grid->axial_stretching, 0.0);  // absent: the uniform grid
  ASSERT_EQ(s.warnings.size(), 1U);
  EXPECT_EQ(s.warnings[0].points, 2);

  ASSERT_EQ(s.points.size(), 2U);
  const SweepPointRecord& p = s.points[0];
  EXPECT_TRUE(p.converged);
  EXPECT_EQ(p.torque, 2.5e-4);
  EXPECT_FALSE(p.torque_std_error.has_value());  // null
  EXPECT_FALSE(p.torque_analytic.has_value());   // absent
  EXPECT_EQ(p.iterations, 7.0);
  EXPECT_EQ(p.normal_force, -0.01);
  ASSERT_TRUE(p.validity.has_value());
  EXPECT_TRUE(p.validity->valid);
  EXPECT_FALSE(p.validity->stokes.has_value());
  EXPECT_EQ(p.used_in_fits, false);
  EXPECT_FALSE(s.points[1].converged);
  EXPECT_EQ(s.points[1].failure, "over budget");

  ASSERT_EQ(s.series.size(), 1U);
  EXPECT_FALSE(s.series[0].best_model.has_value());
  ASSERT_TRUE(s.series[0].torque_line.has_value());
  EXPECT_EQ(s.series[0].torque_line->slope, 2e-5);

  ASSERT_EQ(s.fits.size(), 1U);
  const FitRecord& f = s.fits[0];
  EXPECT_EQ(f.rank, 2U);
  EXPECT_EQ(f.degrees_of_freedom, -1.0);
  EXPECT_FALSE(f.aicc.has_value());
  ASSERT_EQ(f.parameters.size(), 1U);
  EXPECT_FALSE(f.parameters[0].ci95.lower.has_value());
  EXPECT_EQ(f.parameters[0].ci95.upper, 1.3);
  ASSERT_EQ(f.warnings.size(), 1U);
  EXPECT_EQ(f.warnings[0].message, "not identifiable");
  EXPECT_EQ(f.stop_reason, "small step");
  ASSERT_EQ(f.residuals.size(), 2U);
  EXPECT_FALSE(f.residuals[1].has_value());
  ASSERT_EQ(f.correlation.size(), 2U);
  EXPECT_EQ(f.correlation[1][1], 1.0);

  ASSERT_EQ(s.yield_stress.size(), 1U);
  EXPECT_FALSE(s.yield_stress[0].akaike_weight.has_value());
  EXPECT_EQ(s.yield_stress[0].ci95.lower, 0.3);
  ASSERT_EQ(s.relative_viscosity.size(), 1U);
  EXPECT_TRUE(s.relative_viscosity[0].points.empty());  // no fitted flow curve: a warning only
  EXPECT_EQ(s.relative_viscosity[0].warnings.size(), 1U);
}

TEST_F(SweepSummaryTest, RefusesAMissingOrMistypedKeyAtItsPath) {
  EXPECT_EQ(refused_at(summary_with_analysis()), "");
  auto no_rank = summary_with_analysis();
  no_rank["fits"][0].erase("rank");
  EXPECT_EQ(refused_at(no_rank), "fits[0].rank");
  auto text_valid = summary_with_analysis();
  text_valid["points"][0]["validity"]["valid"] = "yes";
  EXPECT_EQ(refused_at(text_valid), "points[0].validity.valid");
  auto text_force = summary_with_analysis();  // an optional value present is still checked
  text_force["points"][0]["normal_force"] = "large";
  EXPECT_EQ(refused_at(text_force), "points[0].normal_force");
  auto short_interval = summary_with_analysis();
  short_interval["yield_stress"][0]["ci95"] = {0.3};
  EXPECT_EQ(refused_at(short_interval), "yield_stress[0].ci95");
  auto no_slope = summary_with_analysis();
  no_slope["series"][0]["torque_line"].erase("slope");
  EXPECT_EQ(refused_at(no_slope), "series[0].torque_line.slope");
  auto ldd = summary_with_analysis();
  ldd["kind"] = "ldd";
  EXPECT_EQ(refused_at(ldd), "kind");
}

// A point written by to_json reads back as the same record: every group the writer emits only
// when known (near-field torques, extrapolation, closed form, normal force, model, cost) and the
// ones it always writes, null when empty.
TEST_F(SweepSummaryTest, APointWrittenByToJsonReadsBackTheSame) {
  SweepPointRecord p;
  p.fluid = "oil";
  p.volume_fraction = 0.2;
  p.shear_rate = 10;
  p.converged = true;
  p.method = "box";
  p.model = "lees_edwards";
  p.model_reason = "H/d >= 10";
  p.angular_velocity = 0.5;
  p.torque = 2.5e-4;
  p.torque_fluid = 2.0e-4;  // torque_contact empty: written as null
  p.torque_lubrication = 1e-5;
  p.torque_stresslet = 2e-5;
  p.torque_grid = 2.4e-4;
  p.torque_half_grid = 2.3e-4;
  p.torque_creeping = 2.2e-4;
  p.inertia_effect = 0.1;
  p.torque_analytic = 2.45e-4;
  p.rel_error = 0.02;
  p.normal_force = -0.01;
  p.n1 = -0.1;
  p.warnings = {"ε clamped"};
  p.gap_reynolds_number = 1e-3;
  p.estimated_error = 0.01;
  p.iterations = 12;
  p.wall_time = 3.5;
  p.cost = PointCost{1.0, 0.2, 0.3, 0.4, 0.5, 0.05};
  SweepPointRecord failed;
  failed.fluid = "oil";
  failed.shear_rate = 100;
  failed.method = "cfd_dem";
  failed.failure = "over budget";

  nlohmann::json json = summary_with_analysis();
  json["points"] =
      nlohmann::json::array({nlohmann::json::parse(to_json(p).dump()), nlohmann::json::parse(to_json(failed).dump())});
  const SweepSummary s = read(json);
  ASSERT_EQ(s.points.size(), 2U);
  const SweepPointRecord& q = s.points[0];
  EXPECT_EQ(q.model, p.model);
  EXPECT_EQ(q.model_reason, p.model_reason);
  for (auto [read_back, written] : {std::pair{q.angular_velocity, p.angular_velocity},
                                    {q.torque_fluid, p.torque_fluid},
                                    {q.torque_contact, p.torque_contact},
                                    {q.torque_lubrication, p.torque_lubrication},
                                    {q.torque_stresslet, p.torque_stresslet},
                                    {q.torque_couple, p.torque_couple},
                                    {q.torque_grid, p.torque_grid},
                                    {q.torque_half_grid, p.torque_half_grid},
                                    {q.torque_creeping, p.torque_creeping},
                                    {q.inertia_effect, p.inertia_effect},
                                    {q.torque_quadrature, p.torque_quadrature},
                                    {q.torque_analytic, p.torque_analytic},
                                    {q.rel_error, p.rel_error},
                                    {q.creeping_rel_error, p.creeping_rel_error},
                                    {q.normal_force, p.normal_force},
                                    {q.n1, p.n1},
                                    {q.n2, p.n2},
                                    {q.gap_reynolds_number, p.gap_reynolds_number},
                                    {q.strain, p.strain},
                                    {q.estimated_error, p.estimated_error},
                                    {q.iterations, p.iterations},
                                    {q.wall_time, p.wall_time}})
    EXPECT_EQ(read_back, written);
  EXPECT_EQ(q.torque, p.torque);
  EXPECT_EQ(q.warnings, p.warnings);
  ASSERT_TRUE(q.cost.has_value());
  EXPECT_EQ(q.cost->forces, 0.3);
  EXPECT_EQ(q.cost->near_field, 0.05);
  EXPECT_FALSE(s.points[1].converged);
  EXPECT_EQ(s.points[1].failure, "over budget");
  EXPECT_EQ(s.points[1].method, "cfd_dem");
}

// The flow analysis of two flow curves (a Bingham liquid alone and with φ = 0.2 at 1.6 times its
// stress) in a whole summary written by to_json and read back: the same records, and the
// analysis found what the torques hold.
TEST_F(SweepSummaryTest, ASummaryWrittenByToJsonReadsBackTheSame) {
  const ParallelPlate plate{0.02, 0.001};
  const auto law = core::make_rheology(
      core::Document::from_string("model: bingham\nplastic_viscosity: 0.5\nyield_stress: 10.0\n", "law.yaml").root());
  std::vector<SweepPointRecord> points;
  for (const double phi : {0.0, 0.2})
    for (const double rate : {1.0, 3.0, 10.0, 30.0, 100.0}) {
      SweepPointRecord p;
      p.fluid = "paste";
      p.volume_fraction = phi;
      p.shear_rate = rate;
      p.converged = true;
      p.method = "closed form";
      p.torque = (phi > 0 ? 1.6 : 1.0) * bingham_torque(plate, 0.5, 10.0, rate);
      p.torque_std_error = 0.01 * p.torque;
      p.iterations = 1;  // to_json writes a converged point's count always
      points.push_back(p);
    }
  SweepPointRecord failed;
  failed.fluid = "paste";
  failed.volume_fraction = 0.2;
  failed.shear_rate = 300;
  failed.failure = "over budget";
  points.push_back(failed);
  const FlowAnalysis analysis = analyse_flow_curves(points, {plate, {{"paste", {1000.0, law}}}, std::nullopt});

  ASSERT_EQ(analysis.series.size(), 2U);
  EXPECT_EQ(analysis.series[1].points, 5U);
  EXPECT_EQ(analysis.series[1].best_model, "bingham");
  const auto torque_yield = std::find_if(analysis.yield_stress.begin(), analysis.yield_stress.end(),
                                         [](const YieldRecord& y) { return y.method == "torque_intercept"; });
  ASSERT_NE(torque_yield, analysis.yield_stress.end());  // T = 2πR³(τ₀/3 + μγ̇_R/4) is a straight line
  EXPECT_NEAR(torque_yield->value.value_or(0), 10.0, 1e-6);
  ASSERT_EQ(analysis.relative_viscosity.size(), 1U);
  ASSERT_EQ(analysis.relative_viscosity[0].points.size(), 2U);
  EXPECT_NEAR(analysis.relative_viscosity[0].points[1].relative_viscosity.value_or(0), 1.6, 1e-3);
  EXPECT_TRUE(points[0].apparent_stress.has_value());
  EXPECT_EQ(points[0].used_in_fits, true);
  EXPECT_FALSE(points.back().apparent_stress.has_value());

  SweepSummary summary;
  summary.head = {"paste", "sweep", "0", "test", "0"};
  summary.radius = plate.radius;
  summary.gap = plate.gap;
  summary.grid = SweepGridRecord{48, 12, 0.5, 1.5, true, "the φ = 0 points"};
  summary.inertia = false;
  summary.volume_fractions = {0.0, 0.2};
  summary.shear_rates = {1.0, 3.0, 10.0, 30.0, 100.0, 300.0};
  summary.points_total = 12;
  summary.points_failed = 1;
  summary.points_resumed = 3;
  summary.wall_time = 2.5;
  summary.points = points;
  summary.warnings = {{"ε clamped", 2}};
  summary.series = analysis.series;
  summary.fits = analysis.fits;
  summary.yield_stress = analysis.yield_stress;
  summary.relative_viscosity = analysis.relative_viscosity;
  const SweepSummary s = read(nlohmann::json::parse(to_json(summary).dump()));
  ASSERT_EQ(s.points.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_EQ(to_json(s.points[i]), to_json(points[i])) << i;
  EXPECT_EQ(s.points, points);
  EXPECT_EQ(s.series, analysis.series);
  EXPECT_EQ(s.fits, analysis.fits);
  EXPECT_EQ(s.yield_stress, analysis.yield_stress);
  EXPECT_EQ(s.relative_viscosity, analysis.relative_viscosity);
  EXPECT_EQ(s, summary);
}

}  // namespace
}  // namespace rheosim::rheometer
