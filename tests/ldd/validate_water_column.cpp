// The 2D water column collapse (cases/ldd_water_column.yaml, Martin & Moyce 1952, n² = 2,
// Δ = a/50), run through run_case as `rheosim run` does. With the shipped settings (eq. 14 on
// free-surface nodes, no PBD velocity update) it reaches its end time and its kinetic energy never
// exceeds the potential energy released; with the solver's defaults the front's nodes gain
// energy until the Courant guard stops the run, and the summary says so. The front against
// Martin & Moyce is measured by bench/ldd_water_column.sh (docs/ldd.md, "Water column").
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

#include "rheosim/core/log.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd {
namespace {

// The shipped deck on one thread (ctest runs two tests at once) and to t = 0.2 s (T = 2.8).
std::string shipped_deck() {
  std::ifstream in(std::string(RHEOSIM_SOURCE_DIR) + "/cases/ldd_water_column.yaml");
  std::stringstream stream;
  stream << in.rdbuf();
  std::string text = stream.str();
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"solver: {", "solver: {threads: 1, "}, {"end: 0.3", "end: 0.2"}}) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  return text;
}

nlohmann::json run(const std::string& text, const std::string& name, RunOutcome& outcome) {
  const ldd::Case c = ldd::parse_case(text, name + ".yaml");
  const auto dir = std::filesystem::temp_directory_path() / ("rheosim_" + name);
  std::filesystem::remove_all(dir);
  outcome = run_case(c, dir, core::Log::null());
  auto summary = core::read_json(dir / "summary.json");
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(dir);
  return summary;
}

bool has_warning(const nlohmann::json& summary, const std::string& words) {
  for (const auto& w : summary["warnings"])
    if (w.get<std::string>().find(words) != std::string::npos) return true;
  return false;
}

TEST(WaterColumn, ShippedSettingsRunToTheEndWithoutCreatingEnergy) {
  RunOutcome outcome;
  const auto summary = run(shipped_deck(), "water_column", outcome);
  EXPECT_EQ(outcome.status, "end_time") << outcome.message;
  EXPECT_LT(summary["energy_gain"].get<double>(), energy_gain_tolerance);
  EXPECT_FALSE(has_warning(summary, "created energy"));
  EXPECT_GT(summary["front"].back()["x"].get<double>(), 0.2);  // the water ran
  // The volume drift is reported, with a warning when it exceeds its tolerance.
  EXPECT_EQ(has_warning(summary, "volume drifted"), summary["volume_drift"].get<double>() > volume_drift_tolerance);
}

TEST(WaterColumn, DefaultSettingsAreCaughtCreatingEnergy) {
  std::string text = shipped_deck();
  const std::string settings = ", gradient: surface_anchored, pbd_velocity: none";
  const auto at = text.find(settings);
  ASSERT_NE(at, std::string::npos);
  text.erase(at, settings.size());
  RunOutcome outcome;
  const auto summary = run(text, "water_column_defaults", outcome);
  EXPECT_EQ(outcome.status, "diverged");
  EXPECT_GT(summary["energy_gain"].get<double>(), energy_gain_tolerance);
  EXPECT_TRUE(has_warning(summary, "created energy"));
}

}  // namespace
}  // namespace rheosim::ldd
