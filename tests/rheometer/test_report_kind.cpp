// The rheometer report is written from a rheometer or sweep summary only: an LDD run's summary
// is refused by name instead of rendering a flow-curve report from keys it does not have, and
// a summary that lacks a key the report reads is refused naming the key.
#include <gtest/gtest.h>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/rheometer/report.hpp"

namespace rheosim::rheometer {
namespace {

TEST(RheometerReport, RefusesTheSummaryOfAnLddRun) {
  const auto folder = std::filesystem::temp_directory_path() / "rheosim_report_of_ldd_summary";
  std::filesystem::create_directories(folder);
  core::write_json(folder / "summary.json", nlohmann::json{{"kind", "ldd"}, {"case", "dam_break"}});
  try {
    (void)write_report(folder);
    FAIL() << "an LDD summary got a rheometer report";
  } catch (const core::ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "kind");
  }
  EXPECT_FALSE(std::filesystem::exists(folder / "report.html"));
  std::filesystem::remove_all(folder);
}

// The smallest summary the report draws: one converged point, no fits.
nlohmann::json minimal_summary() {
  return {{"case", "minimal"},
          {"kind", "sweep"},
          {"rheosim_version", "0"},
          {"git_revision", "test"},
          {"input_sha256", "0"},
          {"radius", 0.02},
          {"gap", 0.001},
          {"wall_time", 1.0},
          {"points_failed", 0},
          {"inertia", false},
          {"points", {{{"fluid", "oil"}, {"shear_rate", 10.0}, {"converged", true}, {"torque", 1e-4}}}},
          {"series", {{{"label", "oil"}, {"fluid", "oil"}, {"volume_fraction", 0.0}, {"points", 1}}}},
          {"fits", nlohmann::json::array()},
          {"yield_stress", nlohmann::json::array()},
          {"relative_viscosity", nlohmann::json::array()}};
}

// A summary without a key the report reads, or with one of another type, is refused with the
// key's path in the file, and no report.html is written; with every key it is drawn.
TEST(RheometerReport, NamesAMissingOrMistypedKeyOfTheSummary) {
  const auto folder = std::filesystem::temp_directory_path() / "rheosim_report_missing_key";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  const auto refused_at = [&](const nlohmann::json& summary) -> std::string {
    core::write_json(folder / "summary.json", summary);
    try {
      (void)write_report(folder);
    } catch (const core::ConfigError& e) {
      EXPECT_FALSE(std::filesystem::exists(folder / "report.html"));
      return e.details().key_path;
    }
    return "";
  };
  EXPECT_EQ(refused_at(minimal_summary()), "");
  EXPECT_TRUE(std::filesystem::exists(folder / "report.html"));
  std::filesystem::remove(folder / "report.html");
  nlohmann::json other_kind = minimal_summary();
  other_kind["kind"] = "rheometer";  // every rheometer case runs as a sweep and writes kind "sweep"
  EXPECT_EQ(refused_at(other_kind), "kind");
  for (const char* key : {"case", "gap", "points_failed", "inertia", "points", "series", "fits"}) {
    nlohmann::json summary = minimal_summary();
    summary.erase(key);
    EXPECT_EQ(refused_at(summary), key);
  }
  nlohmann::json no_rate = minimal_summary();
  no_rate["points"][0].erase("shear_rate");
  EXPECT_EQ(refused_at(no_rate), "points[0].shear_rate");
  nlohmann::json text_radius = minimal_summary();
  text_radius["radius"] = "0.02";
  EXPECT_EQ(refused_at(text_radius), "radius");
  nlohmann::json no_torque = minimal_summary();
  no_torque["points"][0].erase("torque");
  EXPECT_EQ(refused_at(no_torque), "points[0].torque");
  no_torque["points"][0]["converged"] = false;  // a failed point has no torque, by design
  EXPECT_EQ(refused_at(no_torque), "");
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace rheosim::rheometer
