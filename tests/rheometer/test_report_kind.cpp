// The rheometer report is written from a rheometer or sweep summary only: an LDD run's summary
// is refused by name instead of rendering a flow-curve report from keys it does not have.
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

}  // namespace
}  // namespace rheosim::rheometer
