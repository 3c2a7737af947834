// The LDD report (ldd/report.hpp): a dam-break run through run_case gets its own report.html
// from its typed summary, and the summary reader names what is missing or of another kind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rheosim/core/error.hpp"
#include "rheosim/core/log.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/cavity_reference.hpp"
#include "rheosim/ldd/report.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd {
namespace {

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A short run of LDD §4.3's Bingham release (coarse: Δ = 20 mm) into its own folder (each test has
// one: ctest runs them in parallel processes).
class LddReport : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string text =
        "kind: ldd\ndimension: 2\nscene: {type: dam_break, reservoir: [2.0, 0.1], channel_length: 3.0}\n"
        "fluid: {density: 1200, rheology: {model: bingham, plastic_viscosity: 25.0, yield_stress: 25.0, "
        "regularization: 1000}}\ngravity: [0, -9.81]\nresolution: {spacing: 0.02}\ntime: {step: 1.0e-3, end: 0.05}\n"
        "solver: {threads: 1}\n";
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() / (std::string("rheosim_ldd_report_") + test->name());
    std::filesystem::remove_all(dir_);
    ASSERT_EQ(run_case(ldd::parse_case(text, "report_dam_break.yaml"), dir_, core::Log::null()).status, "end_time");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  [[nodiscard]] const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

TEST_F(LddReport, DamBreakRunGetsItsOwnReportFromItsTypedSummary) {
  const RunSummary s = read_run_summary(dir() / "summary.json");
  const auto json = core::read_json(dir() / "summary.json");
  EXPECT_EQ(s.scene, "dam_break");
  EXPECT_TRUE(s.free_surface());
  EXPECT_EQ(s.nodes, json["nodes"].get<std::size_t>());
  EXPECT_EQ(s.steps, 50u);
  ASSERT_TRUE(s.final_spread.has_value());
  EXPECT_DOUBLE_EQ(*s.final_spread, json["final_spread"].get<double>());
  ASSERT_TRUE(s.energy_gain.has_value());
  ASSERT_TRUE(s.thin_film_arrest.has_value());  // a yield-stress dam break: its shallow arrest
  EXPECT_DOUBLE_EQ(s.thin_film_arrest->length, json["thin_film_arrest"]["length"].get<double>());
  EXPECT_EQ(nlohmann::json::parse(to_json(s).dump()), json);  // every key read, and written back the same

  const ReportFiles files = write_report(dir());
  // front, final profile, the yield test, energy, volume
  EXPECT_EQ(files.plots.size() + files.missing_plots.size(), 5u);
  for (const char* script : {"front.gp", "profile.gp", "yield_test.gp", "energy.gp", "volume.gp"})
    EXPECT_TRUE(std::filesystem::exists(dir() / script)) << script;
  const std::string html = read_text(files.html);
  EXPECT_NE(html.find("rheosim LDD report: report_dam_break"), std::string::npos);
  EXPECT_NE(html.find("dam_break (2D)"), std::string::npos);
  EXPECT_NE(html.find("<td>0.103</td>"), std::string::npos);  // LDD Table 1's experiment at 0.09 s
  EXPECT_NE(html.find("shallow arrest (thin film)"), std::string::npos);
  ASSERT_TRUE(s.thin_film_arrest->fitted_yield_stress.has_value());  // the 0.1 m layer is five spacings high
  EXPECT_NE(html.find("final surface read as a shallow arrest"), std::string::npos);
  ASSERT_TRUE(s.largest_stress_ratio.has_value());  // a yield-stress law: the end state's yield test
  EXPECT_NE(html.find(fmt::format("the largest stress {:.4g} τ₀", *s.largest_stress_ratio)), std::string::npos);
  EXPECT_NE(html.find("<h2>Yield test</h2>"), std::string::npos);
  const core::CsvTable probes = core::read_csv(dir() / "front.csv");  // the last column, 1-based for gnuplot
  ASSERT_EQ(probes.numeric_columns().back().name, "largest_stress_ratio");
  EXPECT_NE(read_text(dir() / "yield_test.gp").find(fmt::format("using 1:{} ", probes.numeric_columns().size())),
            std::string::npos);
  EXPECT_EQ(html.find("nan"), std::string::npos);  // no missing value rendered as a number
}

TEST_F(LddReport, SummaryReaderNamesAMissingKeyAndRefusesAnotherKind) {
  const auto folder = dir() / "broken";
  std::filesystem::create_directories(folder);
  auto json = core::read_json(dir() / "summary.json");
  json.erase("ms_per_step");
  core::write_json(folder / "summary.json", json);
  try {
    (void)read_run_summary(folder / "summary.json");
    FAIL() << "a summary without ms_per_step was read";
  } catch (const core::ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "ms_per_step");
    EXPECT_NE(std::string(e.what()).find((folder / "summary.json").string()), std::string::npos) << e.what();
  }
  json = core::read_json(dir() / "summary.json");
  json["thin_film_arrest"].erase("length");
  core::write_json(folder / "summary.json", json);
  try {
    (void)read_run_summary(folder / "summary.json");
    FAIL() << "a yield-stress dam break's summary without its shallow arrest length was read";
  } catch (const core::ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "thin_film_arrest.length");
  }
  // A summary without the final surface's fit or the largest stress (older revisions) is read,
  // those values empty.
  json = core::read_json(dir() / "summary.json");
  json["thin_film_arrest"].erase("fitted_yield_stress");
  json["thin_film_arrest"].erase("fitted_length");
  json.erase("largest_stress_ratio");
  core::write_json(folder / "summary.json", json);
  const RunSummary without_fit = read_run_summary(folder / "summary.json");
  ASSERT_TRUE(without_fit.thin_film_arrest.has_value());
  EXPECT_FALSE(without_fit.thin_film_arrest->fitted_yield_stress.has_value());
  EXPECT_FALSE(without_fit.largest_stress_ratio.has_value());
  EXPECT_TRUE(without_fit.yielded_fraction.has_value());
  json = core::read_json(dir() / "summary.json");
  json["kind"] = "sweep";
  core::write_json(folder / "summary.json", json);
  try {
    (void)write_report(folder);
    FAIL() << "a sweep's summary got an LDD report";
  } catch (const core::ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "kind");
  }
}

// A slump's summary written before the slump formulas' implied yield stresses (or the end state's
// largest stress) existed is read with those values empty; written with them, it round-trips.
TEST(LddSummary, SlumpSummariesWithoutTheImpliedYieldStressAreRead) {
  RunSummary s;
  s.head = {"slump", "ldd", "0", "unknown", ""};
  s.scene = "slump";
  s.dimension = 3;
  s.status = "end_time";
  s.spread = {{0.0, 0.1, 0.1}, {1.0, 0.2, 0.05}};
  s.final_spread = 0.2;
  s.final_height = 0.05;
  s.yielded_fraction = 0.5;
  s.largest_stress_ratio = 1.01;
  s.arrested = true;
  s.pashias = CylinderSlumpComparison{
      0.1, pashias_slump(0.1), 0.5, 0.5 - pashias_slump(0.1), von_mises_cylinder_slump(0.1), 106.4};
  s.roussel_coussot = ConeSpreadComparison{0.21, -0.05, 120.0};
  const auto dir = std::filesystem::temp_directory_path() / "rheosim_ldd_old_slump_summary";
  std::filesystem::create_directories(dir);
  core::write_json(dir / "summary.json", nlohmann::json::parse(to_json(s).dump()));
  EXPECT_EQ(read_run_summary(dir / "summary.json"), s);
  auto json = core::read_json(dir / "summary.json");
  json["pashias"].erase("implied_yield_stress");
  json["roussel_coussot"].erase("implied_yield_stress");
  json.erase("largest_stress_ratio");
  core::write_json(dir / "summary.json", json);
  const RunSummary old = read_run_summary(dir / "summary.json");
  ASSERT_TRUE(old.pashias.has_value());
  ASSERT_TRUE(old.roussel_coussot.has_value());
  EXPECT_FALSE(old.pashias->implied_yield_stress.has_value());
  EXPECT_FALSE(old.roussel_coussot->implied_yield_stress.has_value());
  EXPECT_FALSE(old.largest_stress_ratio.has_value());
  EXPECT_EQ(old.pashias->measured_slump, s.pashias->measured_slump);
  EXPECT_EQ(old.roussel_coussot->diameter, 0.21);
  std::filesystem::remove_all(dir);
}

// A dam break is compared with the experiment of its material: a Newtonian liquid in a reservoir
// twice as high as long with Martin & Moyce's water column (front Z = x/a against T = t√(2g/a)),
// not with LDD Table 1's Bingham experiment; a Newtonian reservoir of another shape with none.
// (Accuracy is checked by bench/ldd_water_column.sh; this run is a coarse 0.1 s.)
TEST(LddReportReferences, AWaterColumnIsComparedWithMartinAndMoyce) {
  const std::string water =
      "kind: ldd\ndimension: 2\nscene: {type: dam_break, reservoir: [0.1, 0.2], channel_length: 0.6}\n"
      "fluid: {density: 1000, rheology: {model: newtonian, viscosity: 1.0e-3}}\ngravity: [0, -9.81]\n"
      "resolution: {spacing: 0.01}\ntime: {step: 1.0e-3, end: 0.1}\n"
      "solver: {threads: 1, velocity_tolerance: 1.0e-6, gradient: surface_anchored, pbd_velocity: none}\n";
  const auto dir = std::filesystem::temp_directory_path() / "rheosim_ldd_report_martin_moyce";
  std::filesystem::remove_all(dir);
  ASSERT_EQ(run_case(ldd::parse_case(water, "water.yaml"), dir, core::Log::null()).status, "end_time");
  EXPECT_FALSE(std::filesystem::exists(dir / "table1.csv"));
  ASSERT_TRUE(std::filesystem::exists(dir / "martin_moyce.csv"));
  const auto summary = core::read_json(dir / "summary.json");
  EXPECT_FALSE(summary.contains("table1"));
  const auto& rows = summary["martin_moyce"]["rows"];
  ASSERT_EQ(rows.size(), 5u);
  // T = 0.832 is t = 0.059 s (reached), T = 1.997 is t = 0.143 s (not reached by 0.1 s).
  EXPECT_DOUBLE_EQ(rows[0]["Z_experiment"].get<double>(), 1.217);
  ASSERT_TRUE(rows[0]["Z"].is_number());
  EXPECT_GT(rows[0]["Z"].get<double>(), 1.0);  // the front has left the gate
  EXPECT_TRUE(rows[2]["Z"].is_null());
  const std::string html = read_text(write_report(dir).html);
  EXPECT_NE(html.find("Martin &amp; Moyce"), std::string::npos);
  EXPECT_NE(html.find("<td>1.217</td>"), std::string::npos);
  EXPECT_NE(html.find("not reached"), std::string::npos);
  EXPECT_EQ(html.find("table1.csv"), std::string::npos);  // no Bingham experiment for water
  std::filesystem::remove_all(dir);

  // The same liquid in a square reservoir: no experiment to compare with.
  std::string square = water;
  square.replace(square.find("[0.1, 0.2]"), 10, "[0.1, 0.1]");
  ASSERT_EQ(run_case(ldd::parse_case(square, "square.yaml"), dir, core::Log::null()).status, "end_time");
  EXPECT_FALSE(std::filesystem::exists(dir / "table1.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "martin_moyce.csv"));
  EXPECT_NE(read_text(write_report(dir).html).find("rheosim LDD report"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rheosim::ldd

namespace rheosim::ldd {
namespace {

// A short Re = 100 cavity (16², 0.2 s) compares itself with Ghia et al.'s table: summary.json
// `ghia` with one computed value per tabulated point, ghia.csv, and a report row; a Re = 400 one
// (no table) does not.
TEST(LddReportReferences, ASquareNewtonianCavityIsComparedWithGhia) {
  const auto dir = std::filesystem::temp_directory_path() / "rheosim_ldd_report_ghia";
  std::filesystem::remove_all(dir);
  const auto deck = [](const char* viscosity) {
    return std::string(
               "kind: ldd\ndimension: 2\nscene: {type: cavity, size: [1, 1], lid_velocity: 1}\n"
               "fluid: {density: 1, rheology: {model: newtonian, viscosity: ") +
           viscosity + "}}\ngravity: [0, 0]\nresolution: {spacing: 0.0625}\ntime: {step: 0.01, end: 0.2}\n" +
           "solver: {threads: 1}\n";
  };
  ASSERT_EQ(run_case(ldd::parse_case(deck("0.01"), "ghia_cavity.yaml"), dir, core::Log::null()).status, "end_time");
  const auto json = core::read_json(dir / "summary.json");
  ASSERT_TRUE(json.contains("ghia"));
  EXPECT_EQ(json["ghia"]["reynolds"], 100);
  ASSERT_EQ(json["ghia"]["points"].size(), 34u);
  double largest = 0;
  for (const auto& p : json["ghia"]["points"])
    largest = std::max(largest, std::abs(p["computed"].get<double>() - p["reference"].get<double>()));
  EXPECT_DOUBLE_EQ(json["ghia"]["max_error"].get<double>(), largest);
  EXPECT_EQ(core::read_csv(dir / "ghia.csv", true).row_count(), 34u);
  const RunSummary s = read_run_summary(dir / "summary.json");
  ASSERT_TRUE(s.ghia.has_value());
  EXPECT_EQ(s.ghia->max_error, largest);
  EXPECT_EQ(nlohmann::json::parse(to_json(s).dump()), json);
  EXPECT_NE(read_text(write_report(dir).html).find("centre lines against Ghia et al. (1982)"), std::string::npos);

  std::filesystem::remove_all(dir);
  ASSERT_EQ(run_case(ldd::parse_case(deck("0.0025"), "re400_cavity.yaml"), dir, core::Log::null()).status, "end_time");
  EXPECT_FALSE(core::read_json(dir / "summary.json").contains("ghia"));
  EXPECT_FALSE(std::filesystem::exists(dir / "ghia.csv"));
  EXPECT_FALSE(read_run_summary(dir / "summary.json").ghia.has_value());
  std::filesystem::remove_all(dir);
}

// A sloshing column (coarse: Δ = 5 mm, to 0.3 s, past the first zero crossing) compares itself with
// the first mode's linear theory: summary.json `sloshing`, sloshing.csv beside column.csv, and the
// report's table and dashed curve; a resting column (no wave_amplitude) does not.
TEST(LddReportReferences, ASloshingColumnIsComparedWithLinearTheory) {
  const auto dir = std::filesystem::temp_directory_path() / "rheosim_ldd_report_sloshing";
  std::filesystem::remove_all(dir);
  const auto deck = [](const char* amplitude) {
    return std::string("kind: ldd\ndimension: 2\nscene: {type: column, size: [0.1, 0.05], wave_amplitude: ") +
           amplitude +
           "}\nfluid: {density: 1000, rheology: {model: newtonian, viscosity: 0.1}}\ngravity: [0, -9.81]\n"
           "resolution: {spacing: 0.005}\ntime: {step: 2.0e-3, end: 0.3}\n"
           "solver: {threads: 1, velocity_tolerance: 1.0e-6, gradient: surface_anchored, dry_walls: extrapolate}\n";
  };
  ASSERT_EQ(run_case(ldd::parse_case(deck("0.002"), "sloshing.yaml"), dir, core::Log::null()).status, "end_time");
  const auto json = core::read_json(dir / "summary.json");
  ASSERT_TRUE(json.contains("sloshing"));
  const LinearSloshing theory = linear_sloshing(0.1, 0.05, 0.002, 1000, 9.81);
  EXPECT_DOUBLE_EQ(json["sloshing"]["period"].get<double>(), theory.period);
  EXPECT_DOUBLE_EQ(json["sloshing"]["wave_energy"].get<double>(), theory.wave_energy);
  const core::CsvTable column = core::read_csv(dir / "column.csv");
  const auto t = column.column("time"), h = column.column("left_wall_height");
  const std::vector<double> crossings = level_crossings(t, h, 0.05, t.size());
  ASSERT_FALSE(crossings.empty());
  EXPECT_EQ(json["sloshing"]["first_crossing"].get<double>(), crossings.front());
  const core::CsvTable sloshing = core::read_csv(dir / "sloshing.csv");
  ASSERT_EQ(sloshing.row_count(), column.row_count());
  EXPECT_DOUBLE_EQ(sloshing.column("linear_theory").front(), 0.052);  // H + A at t = 0
  const RunSummary s = read_run_summary(dir / "summary.json");
  ASSERT_TRUE(s.sloshing.has_value());
  EXPECT_EQ(nlohmann::json::parse(to_json(s).dump()), json);
  const std::string html = read_text(write_report(dir).html);
  EXPECT_NE(html.find("period, linear theory [s]"), std::string::npos);
  EXPECT_NE(read_text(dir / "wall_height.gp").find("sloshing.csv"), std::string::npos);

  std::filesystem::remove_all(dir);
  ASSERT_EQ(run_case(ldd::parse_case(deck("0"), "resting.yaml"), dir, core::Log::null()).status, "end_time");
  EXPECT_FALSE(core::read_json(dir / "summary.json").contains("sloshing"));
  EXPECT_FALSE(std::filesystem::exists(dir / "sloshing.csv"));
  std::filesystem::remove_all(dir);
}

TEST(GhiaReference, OnlyASquareNewtonianCavityAtATabulatedReynoldsNumber) {
  const auto fluid = [](const std::string& rheology) {
    return ldd::parse_case(
               "kind: ldd\ndimension: 2\nscene: {type: cavity, size: [1, 1], lid_velocity: 1}\n"
               "fluid: {density: 1, rheology: " +
                   rheology + "}\ngravity: [0, 0]\nresolution: {spacing: 0.1}\ntime: {step: 1, end: 1}\n",
               "f.yaml")
        .settings.fluid;
  };
  const auto water = fluid("{model: newtonian, viscosity: 0.001}");
  CavityScene square{{2.0, 2.0}, 0.5, 0.0};  // ρUL/μ = 1000
  EXPECT_EQ(ghia_reynolds(square, water), 1000);
  EXPECT_EQ(ghia_reynolds(square, fluid("{model: newtonian, viscosity: 0.0010049}")), 1000);  // within 0.5 %
  EXPECT_FALSE(ghia_reynolds(square, fluid("{model: newtonian, viscosity: 0.00101}")));
  EXPECT_FALSE(ghia_reynolds(square, fluid("{model: casson, plastic_viscosity: 0.001, yield_stress: 1.0e-4, "
                                           "regularization: 1000}")));
  CavityScene tall = square;
  tall.size = {2.0, 1.0};
  EXPECT_FALSE(ghia_reynolds(tall, water));
  CavityScene skewed = square;
  skewed.skew_angle = 0.5;
  EXPECT_FALSE(ghia_reynolds(skewed, water));
  EXPECT_EQ(ghia_1982().size(), 34u);
}

}  // namespace
}  // namespace rheosim::ldd

namespace rheosim::ldd {
namespace {

// A run that accepts a linear solve above its tolerance (one BiCGStab iteration a solve, below the
// 1000× divergence limit) says so in summary.json `warnings`, with the counts and the worst ratio,
// and its report lists it among the rules the run bent.
TEST(LddRunWarnings, ASolveAcceptedAboveItsToleranceIsAWarning) {
  const auto dir = std::filesystem::temp_directory_path() / "rheosim_ldd_accepted_solves";
  std::filesystem::remove_all(dir);
  const std::string deck =
      "kind: ldd\ndimension: 2\nscene: {type: cavity, size: [1, 1], lid_velocity: 1}\n"
      "fluid: {density: 1, rheology: {model: newtonian, viscosity: 0.01}}\ngravity: [0, 0]\n"
      "resolution: {spacing: 0.0625}\ntime: {step: 0.01, end: 0.1}\n"
      "solver: {velocity_tolerance: 1.0e-4, max_iterations: 1, threads: 1}\n";
  ASSERT_EQ(run_case(ldd::parse_case(deck, "accepted.yaml"), dir, core::Log::null()).status, "end_time");
  const auto warnings = core::read_json(dir / "summary.json")["warnings"];
  ASSERT_EQ(warnings.size(), 1u);
  const std::string w = warnings[0].get<std::string>();
  EXPECT_NE(w.find("linear solves accepted above their tolerance: 0 pressure and"), std::string::npos) << w;
  EXPECT_NE(w.find("velocity solves of 10 steps, at most"), std::string::npos) << w;
  EXPECT_NE(read_text(write_report(dir).html).find("linear solves accepted above their tolerance"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rheosim::ldd
