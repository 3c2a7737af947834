// Log (levels, file copy, no global registry) and Progress (throttling, ETA, terminal line).
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rheosim/core/error.hpp"
#include "rheosim/core/log.hpp"
#include "rheosim/core/progress.hpp"

namespace rheosim::core {
namespace {

namespace fs = std::filesystem;

std::size_t count(const std::string& text, std::string_view what) {
  std::size_t n = 0;
  for (auto pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + what.size())) ++n;
  return n;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// ---------------------------------------------------------------------------------------------
// Log

void log_each_level(const Log& log) {
  log.debug("debug {}", 1);
  log.info("info {}", 2);
  log.warn("warn {}", 3);
  log.error("error {:.1f}", 4.0);
}

TEST(Log, VerbosityChoosesLevels) {
  std::ostringstream quiet, normal, verbose;
  log_each_level(Log::to_stream(quiet, Verbosity::quiet));
  log_each_level(Log::to_stream(normal, Verbosity::normal));
  log_each_level(Log::to_stream(verbose, Verbosity::verbose));
  EXPECT_EQ(quiet.str(), "warning: warn 3\nerror: error 4.0\n");
  EXPECT_EQ(normal.str(), "info: info 2\nwarning: warn 3\nerror: error 4.0\n");
  EXPECT_EQ(verbose.str(), "debug: debug 1\ninfo: info 2\nwarning: warn 3\nerror: error 4.0\n");
}

TEST(Log, FileGetsEverythingWhileConsoleStaysQuiet) {
  const fs::path dir = fs::temp_directory_path() / ("rheosim_test_log_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const fs::path file = dir / "run" / "rheosim.log";
  std::ostringstream console;
  const Log base = Log::to_stream(console, Verbosity::quiet);
  {
    const Log log = base.with_file(file);
    log_each_level(log);
    log.flush();
  }
  base.info("not in the file: the base log has no file sink");
  const std::string text = slurp(file);
  EXPECT_NE(text.find("[debug] debug 1"), std::string::npos) << text;
  EXPECT_NE(text.find("[info] info 2"), std::string::npos) << text;
  EXPECT_NE(text.find("[error] error 4.0"), std::string::npos) << text;
  EXPECT_EQ(text.find("not in the file"), std::string::npos) << text;
  EXPECT_EQ(console.str(), "warning: warn 3\nerror: error 4.0\n");
  fs::remove_all(dir);
}

TEST(Log, UnopenableFileIsARunError) {
  const fs::path dir = fs::temp_directory_path() / ("rheosim_test_log_bad_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "a_file") << "x";
  EXPECT_THROW(static_cast<void>(Log::null().with_file(dir / "a_file" / "rheosim.log")), RunError);
  fs::remove_all(dir);
}

TEST(Log, NeverTouchesTheSpdlogRegistry) {
  const auto default_before = spdlog::default_logger();
  const Log console = Log::console(Verbosity::quiet);
  const Log null = Log::null();
  const Log defaulted;
  log_each_level(null);
  log_each_level(defaulted);
  EXPECT_EQ(spdlog::get("rheosim"), nullptr);
  EXPECT_EQ(spdlog::default_logger(), default_before);
}

// ---------------------------------------------------------------------------------------------
// Progress

// A clock the test moves by hand.
struct FakeClock {
  double now = 0;
  Progress::Clock clock() {
    return [this] { return now; };
  }
};

TEST(Progress, FormatsDurations) {
  EXPECT_EQ(Progress::format_duration(0.43), "0.4s");
  EXPECT_EQ(Progress::format_duration(42.4), "42s");
  EXPECT_EQ(Progress::format_duration(90), "1m 30s");
  EXPECT_EQ(Progress::format_duration(185), "3m 05s");
  EXPECT_EQ(Progress::format_duration(2 * 3600 + 7 * 60 + 10), "2h 07m");
  EXPECT_EQ(Progress::format_duration(-1), "--");
}

TEST(Progress, EtaFollowsAConstantRate) {
  FakeClock t;
  std::ostringstream out;
  Progress progress("sweep", 100, out, false, t.clock(), {.plain_interval = 5});
  EXPECT_FALSE(progress.eta());
  t.now = 10;
  progress.update(10, "strain 4.2");
  ASSERT_TRUE(progress.eta());
  EXPECT_DOUBLE_EQ(*progress.eta(), 90.0);
  EXPECT_EQ(out.str(), "sweep: 10/100 (10.0%) strain 4.2, elapsed 10s, ETA 1m 30s\n");
  t.now = 60;
  progress.update(60);
  EXPECT_DOUBLE_EQ(*progress.eta(), 40.0);
}

TEST(Progress, EtaOfAResumedRunCountsOnlyThisRun) {
  FakeClock t;
  std::ostringstream out;
  Progress progress("sweep", 100, out, false, t.clock(), {.initial_done = 50});
  EXPECT_EQ(progress.done(), 50U);
  t.now = 10;
  progress.update(60);
  EXPECT_DOUBLE_EQ(*progress.eta(), 40.0);  // 10 units in 10 s, 40 left
}

TEST(Progress, PlainLinesAreThrottledByTheClock) {
  FakeClock t;
  std::ostringstream out;
  Progress progress("steps", 100, out, false, t.clock(), {.plain_interval = 10});
  for (int i = 1; i <= 100; ++i) {  // 0.5 s per step: 50 s in all
    t.now = 0.5 * i;
    progress.update(static_cast<std::size_t>(i));
  }
  // A line at t = 10, 20, 30, 40, 50 s, none in between.
  EXPECT_EQ(count(out.str(), "\n"), 5U) << out.str();
  EXPECT_EQ(out.str().rfind("steps: 20/100 (20.0%), elapsed 10s, ETA 40s\n", 0), 0U) << out.str();
  EXPECT_EQ(count(out.str(), "\r"), 0U);
  t.now = 65;
  progress.finish();
  EXPECT_EQ(count(out.str(), "\n"), 6U);
  EXPECT_NE(out.str().find("steps: 100/100 (100.0%), done in 1m 05s\n"), std::string::npos) << out.str();
  progress.finish();  // only once
  EXPECT_EQ(count(out.str(), "\n"), 6U);
}

TEST(Progress, ShortRunsPrintOnlyTheFinalLine) {
  FakeClock t;
  std::ostringstream out;
  Progress progress("fit", 3, out, false, t.clock());
  for (std::size_t i = 1; i <= 3; ++i) {
    t.now += 0.1;
    progress.update(i);
  }
  progress.finish();
  EXPECT_EQ(out.str(), "fit: 3/3 (100.0%), done in 0.3s\n");
}

TEST(Progress, TerminalLineIsRedrawnAtMostTenTimesASecond) {
  FakeClock t;
  std::ostringstream out;
  Progress progress("sweep", 8, out, true, t.clock(), {.bar_width = 8});
  t.now = 30;
  progress.update(3, "phi 0.1, 50 1/s");
  EXPECT_EQ(out.str(), "\rsweep [###.....]  37.5%  3/8  phi 0.1, 50 1/s  ETA 50s");

  std::ostringstream many;
  Progress fast("steps", 2000, many, true, t.clock());
  for (std::size_t i = 1; i <= 1000; ++i) {  // 1000 updates in one second
    t.now += 0.001;
    fast.update(i);
  }
  const auto redraws = count(many.str(), "\r");
  EXPECT_GE(redraws, 9U);
  EXPECT_LE(redraws, 11U);
  EXPECT_EQ(count(many.str(), "\n"), 0U);
  EXPECT_NE(many.str().find("%"), std::string::npos);
}

TEST(Progress, TerminalFinishEndsTheLineWithElapsedTime) {
  FakeClock t;
  std::ostringstream out;
  {
    Progress progress("sweep", 4, out, true, t.clock(), {.bar_width = 4});
    t.now = 1;
    progress.update(2, "a much longer detail text");
    t.now = 3;
    progress.update(4);
    t.now = 4;
    progress.finish();
  }
  const std::string text = out.str();
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(count(text, "\n"), 1U);  // the destructor adds nothing after finish()
  // Segments: 2/4 with the long detail, 4/4 (drawn at completion), the final line.
  std::vector<std::string> segments;
  for (auto pos = text.find('\r'); pos != std::string::npos;) {
    const auto next = text.find('\r', pos + 1);
    segments.push_back(text.substr(pos + 1, next == std::string::npos ? std::string::npos : next - pos - 1));
    pos = next;
  }
  ASSERT_EQ(segments.size(), 3U) << text;
  EXPECT_EQ(segments[2], "sweep [####] 100.0%  4/4  done in 4.0s\n");
  // The shorter 4/4 line blanks out what the longer line before it left behind.
  EXPECT_EQ(segments[1].size(), segments[0].size());
  EXPECT_EQ(segments[1].rfind("sweep [####] 100.0%  4/4  ETA 0.0s   ", 0), 0U) << segments[1];
}

TEST(Progress, UnfinishedTerminalLineIsEndedByTheDestructor) {
  FakeClock t;
  std::ostringstream out;
  {
    Progress progress("sweep", 4, out, true, t.clock());
    progress.update(1);
  }
  EXPECT_EQ(out.str().back(), '\n');
  EXPECT_EQ(out.str().find("done"), std::string::npos);
}

TEST(Progress, TerminalLineFitsTheWidth) {
  FakeClock t;
  std::ostringstream out;
  Progress progress("sweep", 4, out, true, t.clock(), {.line_width = 30});
  progress.update(1, "γ̇ = 50 1/s, a long detail that does not fit");
  const std::string line = out.str().substr(1);
  std::size_t columns = 0;
  for (const char c : line) columns += (static_cast<unsigned char>(c) & 0xC0U) != 0x80U;
  EXPECT_EQ(columns, 30U) << line;
}

}  // namespace
}  // namespace rheosim::core
