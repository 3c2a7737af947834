// A sweep killed with SIGKILL mid-way and started again computes only the missing points and
// ends with the same results as an uninterrupted run. Drives the built `rheosim`
// binary as a user would: fork/exec, kill -9, run again.
#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "rheosim/core/output.hpp"

namespace fs = std::filesystem;

namespace {

const std::string binary = RHEOSIM_BINARY;
const fs::path case_file = fs::path(RHEOSIM_SOURCE_DIR) / "tests/apps/data/small_sweep.yaml";
const fs::path runs = fs::path(RHEOSIM_BINARY_DIR) / "test-runs";
constexpr int sweep_points = 16;    // 2 φ × 8 rates
constexpr int finished_points = 8;  // φ = 0; the φ = 0.1 points fail (over the CFD-DEM point budget)

// Starts `rheosim run CASE --out DIR` with output to DIR.log; returns the child's pid.
pid_t start_run(const fs::path& case_path, const fs::path& out, const fs::path& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    execl(binary.c_str(), binary.c_str(), "run", case_path.c_str(), "--out", out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

int wait_exit_code(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

int run_to_end(const fs::path& case_path, const fs::path& out, const fs::path& log) {
  return wait_exit_code(start_run(case_path, out, log));
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<fs::path> stored_points(const fs::path& out) {
  std::vector<fs::path> files;
  if (fs::exists(out / "points"))
    for (const auto& e : fs::directory_iterator(out / "points"))
      if (e.path().extension() == ".h5") files.push_back(e.path());
  return files;
}

}  // namespace

TEST(SweepResume, KilledSweepResumesWithOnlyTheMissingPointsAndTheSameResults) {
  const fs::path killed = runs / "sweep_resume_killed";
  const fs::path reference = runs / "sweep_resume_reference";
  fs::remove_all(killed);
  fs::remove_all(reference);
  fs::create_directories(runs);

  // 1. Start the sweep and SIGKILL it once three points are stored.
  const pid_t pid = start_run(case_file, killed, runs / "sweep_resume_killed.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (stored_points(killed).size() < 3 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  ASSERT_EQ(wait_exit_code(pid), -SIGKILL) << read_text(runs / "sweep_resume_killed.log");
  const auto before = stored_points(killed);
  const int kept = static_cast<int>(before.size());
  ASSERT_GE(kept, 3);
  ASSERT_LT(kept, finished_points) << "the sweep finished before the kill: make its points slower";
  EXPECT_FALSE(fs::exists(killed / "summary.json")) << "killed before the end, so no summary yet";
  std::map<fs::path, fs::file_time_type> written;
  for (const auto& f : before) written[f] = fs::last_write_time(f);

  // 2. Run again: only the missing points are computed, the stored ones are not touched.
  const fs::path resume_log = runs / "sweep_resume_second.log";
  EXPECT_EQ(run_to_end(case_file, killed, resume_log), 1) << "φ > 0 points fail: exit 1\n" << read_text(resume_log);
  const std::string log = read_text(resume_log);
  EXPECT_NE(log.find(fmt::format("resuming: {} of {} points are stored", kept, sweep_points)), std::string::npos)
      << log;
  EXPECT_NE(log.find(fmt::format("{} computed now, {} read back", sweep_points - kept, kept)), std::string::npos)
      << log;
  for (const auto& [file, time] : written) EXPECT_EQ(fs::last_write_time(file), time) << file << " was rewritten";
  EXPECT_EQ(static_cast<int>(stored_points(killed).size()), finished_points);

  // 3. The same results as a run that was never interrupted.
  EXPECT_EQ(run_to_end(case_file, reference, runs / "sweep_resume_reference.log"), 1);
  const auto resumed = rheosim::core::read_json(killed / "summary.json");
  const auto clean = rheosim::core::read_json(reference / "summary.json");
  EXPECT_EQ(resumed["points_resumed"].get<int>(), kept);
  EXPECT_EQ(clean["points_resumed"].get<int>(), 0);
  ASSERT_EQ(resumed["points"].size(), clean["points"].size());
  int compared = 0;
  for (std::size_t i = 0; i < clean["points"].size(); ++i) {
    const auto& a = resumed["points"][i];
    const auto& b = clean["points"][i];
    EXPECT_EQ(a["converged"], b["converged"]);
    if (!b["converged"].get<bool>()) continue;
    EXPECT_EQ(a["torque"].get<double>(), b["torque"].get<double>()) << "point " << i;  // bit for bit
    EXPECT_EQ(a["rim_stress"].get<double>(), b["rim_stress"].get<double>()) << "point " << i;
    ++compared;
  }
  EXPECT_EQ(compared, finished_points);
  // The analysis, too: every fitted parameter and every yield-stress estimate.
  ASSERT_EQ(resumed["fits"].size(), clean["fits"].size());
  for (std::size_t f = 0; f < clean["fits"].size(); ++f)
    EXPECT_EQ(resumed["fits"][f]["parameters"], clean["fits"][f]["parameters"]) << clean["fits"][f]["model"];
  EXPECT_EQ(resumed["yield_stress"], clean["yield_stress"]);
  EXPECT_EQ(resumed["relative_viscosity"], clean["relative_viscosity"]);
}

TEST(SweepResume, RefusesToMixPointsOfAChangedDeck) {
  const fs::path out = runs / "sweep_resume_changed_deck";
  fs::remove_all(out);
  fs::create_directories(out);
  // Store one point from the deck as shipped...
  const pid_t pid = start_run(case_file, out, runs / "sweep_resume_changed_first.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (stored_points(out).empty() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  kill(pid, SIGKILL);
  wait_exit_code(pid);
  ASSERT_FALSE(stored_points(out).empty());
  // ...then resume with an edited deck: refused as bad input, nothing overwritten.
  const fs::path edited = runs / "small_sweep_edited.yaml";
  {
    std::ofstream os(edited);
    os << read_text(case_file) << "description: edited after the first run\n";
  }
  const fs::path log = runs / "sweep_resume_changed_second.log";
  EXPECT_EQ(run_to_end(edited, out, log), 2) << read_text(log);
  EXPECT_NE(read_text(log).find("another input deck"), std::string::npos) << read_text(log);
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}
