// Dam breaks run by LDD and by OpenFOAM's interFoam from rheosim's own export of the same case
// (docs/ldd.md, "Dam break against interFoam"): the water column (cases/ldd_water_column.yaml at
// Δ = a/25), whose mass fronts agree within 5 % at Martin & Moyce's times up to T = 3.35, and
// the Bingham dam break at Δ = 4 mm. interFoam
// runs as a program; the tests skip when /usr/bin/interFoam is missing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "rheosim/core/log.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/openfoam.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd {
namespace {

namespace fs = std::filesystem;

constexpr double spacing = 0.004;  // Δ [m] of both comparisons

// A shipped deck with its text edits (from → to), on one thread.
std::string deck(const std::string& file, std::vector<std::pair<std::string, std::string>> edits) {
  std::ifstream in(std::string(RHEOSIM_SOURCE_DIR) + "/cases/" + file);
  std::stringstream stream;
  stream << in.rdbuf();
  std::string text = stream.str();
  edits.emplace_back("solver: {", "solver: {threads: 1, ");
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  return text;
}

// (time, front) pairs in increasing time.
using Fronts = std::vector<std::pair<double, double>>;

double front_at(const Fronts& f, double t) {
  for (std::size_t k = 1; k < f.size(); ++k)
    if (f[k].first >= t) {
      const double w = (t - f[k - 1].first) / (f[k].first - f[k - 1].first);
      return f[k - 1].second + w * (f[k].second - f[k - 1].second);
    }
  return std::numeric_limits<double>::quiet_NaN();
}

// interFoam's front: at each sampled time the largest cell-centre x with α >= 0.5 in the lowest
// rows, plus Δ/2 (the LDD front is the largest x of a fluid node plus Δ/2).
Fronts interfoam_fronts(const fs::path& dir) {
  Fronts out;
  for (const auto& time_dir : fs::directory_iterator(dir / "postProcessing/front")) {
    double front = -std::numeric_limits<double>::infinity();
    for (const auto& file : fs::directory_iterator(time_dir.path())) {
      std::ifstream in(file.path());
      double x = 0, alpha = 0;
      while (in >> x >> alpha)
        if (alpha >= 0.5) front = std::max(front, x + 0.5 * spacing);
    }
    out.emplace_back(std::stod(time_dir.path().filename().string()), front);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// LDD's front.csv: time [s], front [m], …
Fronts ldd_fronts(const fs::path& dir) {
  Fronts out;
  std::ifstream in(dir / "front.csv");
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string time, front;
    std::getline(fields, time, ',');
    std::getline(fields, front, ',');
    out.emplace_back(std::stod(time), std::stod(front));
  }
  return out;
}

bool have_openfoam() {
  return fs::exists("/usr/bin/interFoam") && fs::exists("/usr/bin/blockMesh") && fs::exists("/usr/bin/setFields");
}

// The case run by interFoam (from rheosim's export) and by LDD in a scratch folder.
struct BothFronts {
  Fronts interfoam, ldd;
  fs::path work;
};

BothFronts run_both(const std::string& text, const std::string& name) {
  BothFronts out;
  out.work = fs::temp_directory_path() / fmt::format("rheosim_validate_interfoam_{}_{}", name, ::getpid());
  fs::remove_all(out.work);
  const Case c = parse_case(text, name + ".yaml");
  (void)export_interfoam(c, out.work / "interfoam");
  const std::string command = fmt::format(
      "cd '{}' && export WM_PROJECT_DIR=/usr/share/openfoam && blockMesh > log.blockMesh 2>&1 && "
      "setFields > log.setFields 2>&1 && interFoam > log.interFoam 2>&1",
      (out.work / "interfoam").string());
  EXPECT_EQ(std::system(command.c_str()), 0) << "see " << (out.work / "interfoam").string();
  out.interfoam = interfoam_fronts(out.work / "interfoam");
  const RunOutcome outcome = run_case(c, out.work / "ldd", core::Log::null());
  EXPECT_EQ(outcome.status, "end_time") << outcome.message;
  out.ldd = ldd_fronts(out.work / "ldd");
  return out;
}

TEST(InterFoamComparison, WaterColumnFrontsAgreeWithLdd) {
  if (!have_openfoam()) GTEST_SKIP() << "OpenFOAM (/usr/bin/interFoam) is not installed";
  // Δ = a/25, δt = 5e-4 s, to t = 0.25 s. Measured +2.4 / +0.2 / +2.9 / +0.4 / −2.6 %; with the
  // PBD's whole shift on the surface (pbd_surface: full) the front's spray put it 6.9 % ahead at T = 2.
  const auto fronts = run_both(
      deck("ldd_water_column.yaml",
           {{"spacing: 0.002", "spacing: 0.004"}, {"step: 2.5e-4", "step: 5.0e-4"}, {"end: 0.3", "end: 0.25"}}),
      "water_column");
  ASSERT_FALSE(::testing::Test::HasFailure());
  // Martin & Moyce (1952), n² = 2: T = t√(2g/a), Z = x/a from the back wall.
  constexpr double a = 0.1;  // the column's width [m]
  constexpr std::pair<double, double> martin_moyce[] = {
      {0.832, 1.217}, {1.219, 1.474}, {1.997, 2.292}, {2.547, 2.995}, {3.345, 4.134}};
  for (const auto& [T, z_experiment] : martin_moyce) {
    const double t = T / std::sqrt(2 * 9.81 / a);
    const double z_foam = (front_at(fronts.interfoam, t) + a) / a, z_ldd = (front_at(fronts.ldd, t) + a) / a;
    std::printf("T %.3f: Z Martin & Moyce %.3f, interFoam %.3f, LDD %.3f (%+.1f %%)\n", T, z_experiment, z_foam, z_ldd,
                100 * (z_ldd / z_foam - 1));
    EXPECT_NEAR(z_ldd / z_foam, 1.0, 0.05) << "T = " << T;
  }
  if (!::testing::Test::HasFailure()) fs::remove_all(fronts.work);
}

// The Bingham dam break of LDD §4.3 (cases/ldd_dam_break_bingham.yaml, the whole viscous stress)
// at Δ = 4 mm to 0.74 s, both solvers run here: the LDD front within 10 % of interFoam's from
// 0.38 s on (measured −4.2 / −6.4 / −8.5 %): interFoam's own front moves by −6 to −12 % from 4 to
// 2 mm at these times, so the two 4 mm runs cannot agree more closely. The LDD front at 4 mm is
// also within 5 % of interFoam's 2 mm front (measured +1.6 / +2.9 / +3.8 %; with the seed's
// ∇·(μ∇u) it is +3.5 / +4.9 / +8.9 %). interFoam's 2 mm fronts (19 min on one core) are from
// `bench/ldd_dam_break_interfoam.sh build OUT` (docs/ldd.md). Both far below Table 1's experiment.
TEST(InterFoamComparison, BinghamDamBreakFrontsAgreeWithLdd) {
  if (!have_openfoam()) GTEST_SKIP() << "OpenFOAM (/usr/bin/interFoam) is not installed";
  const auto fronts = run_both(
      deck("ldd_dam_break_bingham.yaml", {{"spacing: 0.002", "spacing: 0.004"}, {"end: 1.2", "end: 0.75"}}), "bingham");
  ASSERT_FALSE(::testing::Test::HasFailure());
  struct Reference {
    double time, experiment, interfoam_2mm;  // [s], Table 1's front [m], interFoam's at Δ = 2 mm [m]
  };
  constexpr Reference references[] = {{0.38, 0.297, 0.098}, {0.56, 0.399, 0.120}, {0.74, 0.499, 0.134}};
  for (const auto& [t, experiment, interfoam_2mm] : references) {
    const double x_foam = front_at(fronts.interfoam, t), x_ldd = front_at(fronts.ldd, t);
    std::printf(
        "t %.2f s: front Table 1 experiment %.3f m, interFoam %.3f m (2 mm: %.3f m), LDD %.3f m (%+.1f %%, %+.1f %% of "
        "interFoam at 2 mm)\n",
        t, experiment, x_foam, interfoam_2mm, x_ldd, 100 * (x_ldd / x_foam - 1), 100 * (x_ldd / interfoam_2mm - 1));
    EXPECT_NEAR(x_ldd / x_foam, 1.0, 0.10) << "t = " << t;
    EXPECT_NEAR(x_ldd / interfoam_2mm, 1.0, 0.05) << "t = " << t;
    EXPECT_LT(x_foam, 0.5 * experiment);  // the stated material cannot reach the measured front
  }
  if (!::testing::Test::HasFailure()) fs::remove_all(fronts.work);
}

}  // namespace
}  // namespace rheosim::ldd
