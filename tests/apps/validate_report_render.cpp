// The report of a sweep opens offline with every plot present, and renders in a real browser
// (headless Chromium, Debian's `chromium`) to a screenshot a person can look at:
// build-sweep/test-runs/report_render/report_screenshot.png.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <cstdint>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "rheosim/core/case.hpp"

namespace fs = std::filesystem;

namespace {

const std::string binary = RHEOSIM_BINARY;
const fs::path case_file = fs::path(RHEOSIM_SOURCE_DIR) / "tests/apps/data/small_sweep.yaml";
const fs::path runs = fs::path(RHEOSIM_BINARY_DIR) / "test-runs";

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int shell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct PngSize {
  std::uint32_t width = 0, height = 0;
};
// Width and height from the IHDR chunk; zeros when the file is not a PNG.
PngSize png_size(const fs::path& path) {
  const std::string bytes = read_text(path);
  if (bytes.size() < 24 || bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0 || bytes.compare(12, 4, "IHDR") != 0)
    return {};
  const auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
    return v;
  };
  return {be32(16), be32(20)};
}

}  // namespace

TEST(ReportRender, SweepReportHasEveryPlotAndRendersInChromium) {
  const fs::path out = runs / "report_render";
  fs::remove_all(out);
  fs::create_directories(runs);
  // The φ = 0.1 points (8e6 particles) are over the CFD-DEM point budget and fail at once (exit 1);
  // the report is written all the same.
  ASSERT_EQ(shell(binary + " run '" + case_file.string() + "' --out '" + out.string() + "' -q > '" +
                  (runs / "report_render.log").string() + "' 2>&1"),
            1)
      << read_text(runs / "report_render.log");
  fs::remove(out / "report.html");
  ASSERT_EQ(shell(binary + " report '" + out.string() + "' -q"), 0);

  const std::string html = read_text(out / "report.html");
  for (const char* plot : {"torque", "stress", "viscosity", "residuals", "relative_viscosity", "yield_stress"}) {
    SCOPED_TRACE(plot);
    const std::string name(plot);
    EXPECT_TRUE(fs::exists(out / (name + ".gp")));
    EXPECT_TRUE(fs::exists(out / (name + ".svg")));
    const PngSize size = png_size(out / (name + ".png"));
    EXPECT_GE(size.width, 800u);
    EXPECT_GE(size.height, 500u);
    EXPECT_NE(html.find("src=\"" + name + ".png\""), std::string::npos);
    EXPECT_EQ(read_text(out / (name + ".gnuplot.log")).find("rror"), std::string::npos)
        << read_text(out / (name + ".gnuplot.log"));
  }
  for (const char* csv :
       {"flow_curve.csv", "fits.csv", "fit_curves.csv", "residuals.csv", "torque_lines.csv", "yield_stress.csv",
        "relative_viscosity.csv", "relative_viscosity_curves.csv", "speed_error.csv", "torque.csv"})
    EXPECT_TRUE(fs::exists(out / csv)) << csv;
  // Offline: nothing is fetched from the network.
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  // The deck and its hash; the failed points with their reason; the four yield-stress methods.
  EXPECT_NE(html.find(rheosim::core::sha256_hex(read_text(case_file))), std::string::npos);
  EXPECT_NE(html.find("above the point budget"), std::string::npos);
  for (const char* method : {"bingham_intercept", "casson_intercept", "herschel_bulkley", "torque_intercept"})
    EXPECT_NE(html.find(method), std::string::npos) << method;

  if (shell("command -v chromium > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "chromium is not installed (apt-get install -y chromium): the report was checked as files, "
                    "not rendered";
  const fs::path shot = out / "report_screenshot.png";
  const std::string command = "cd '" + out.string() +
                              "' && timeout 120 chromium --headless --no-sandbox --disable-gpu --hide-scrollbars "
                              "--screenshot='" +
                              shot.string() + "' --window-size=1280,9000 'file://" +
                              fs::absolute(out / "report.html").string() + "' > chromium.log 2>&1";
  EXPECT_EQ(shell(command), 0) << read_text(out / "chromium.log");
  const PngSize size = png_size(shot);
  EXPECT_EQ(size.width, 1280u);
  EXPECT_EQ(size.height, 9000u);
  // A page of text alone compresses to far less; the plots make up most of the bytes.
  EXPECT_GT(fs::file_size(shot), 300'000u) << "screenshot suspiciously small: are the plots missing?";
  std::cout << "screenshot: " << shot.string() << "\n";
}
