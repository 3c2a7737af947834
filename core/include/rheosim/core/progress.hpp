#pragma once
// Progress report for long runs (sweep points, time steps), written to a stream:
//   on a terminal, one line redrawn with '\r' at most ~10 times a second:
//     sweep [#########...............]  37.5%  3/8  phi 0.1, 50 1/s, strain 4.2  ETA 2m 10s
//   otherwise (log files, CI), a plain line at most every 10 s, and one at finish():
//     sweep: 3/8 (37.5%) phi 0.1, 50 1/s, strain 4.2, elapsed 1m 18s, ETA 2m 10s
// The estimate uses the average rate so far. The clock is injectable so tests can drive time.
//
//   auto progress = Progress::for_stderr("sweep", points.size());
//   for (...) { ...; progress.update(i + 1, fmt::format("strain {:.1f}", strain)); }
//   progress.finish();
#include <cstddef>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>

namespace rheosim::core {

struct ProgressOptions {
  double plain_interval = 10.0;  // s between plain lines when not on a terminal
  double redraw_interval = 0.1;  // s between redraws on a terminal
  std::size_t line_width = 0;    // terminal columns to stay within (0: no limit)
  std::size_t bar_width = 24;    // characters inside the bar's brackets
  std::size_t initial_done = 0;  // work done before this run (resume): shown, not in the rate
};

class Progress {
 public:
  using Clock = std::function<double()>;  // monotonic time in seconds

  // `out` must outlive the Progress. `is_terminal` selects redrawn line vs plain lines.
  Progress(std::string label, std::size_t total, std::ostream& out, bool is_terminal, Clock clock = steady_seconds(),
           ProgressOptions options = {});
  // Writes to stderr; terminal mode and line width are detected (isatty, TIOCGWINSZ).
  [[nodiscard]] static Progress for_stderr(std::string label, std::size_t total, ProgressOptions options = {});

  // Identity type: it owns a line on the stream.
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  // Without finish() (e.g. unwinding after an error) ends a terminal line so output that
  // follows starts on a fresh line; it does not claim completion.
  ~Progress();

  // `done` units of `total` are complete; `detail` describes the current item.
  void update(std::size_t done, std::string_view detail = {});
  // Prints the final line with the elapsed time (once).
  void finish();

  [[nodiscard]] std::size_t done() const { return done_; }
  [[nodiscard]] std::size_t total() const { return total_; }
  // Seconds from construction to the last update (or finish).
  [[nodiscard]] double elapsed() const { return last_update_ - start_; }
  // Seconds left at the last update's average rate; nullopt before any measurable progress.
  [[nodiscard]] std::optional<double> eta() const;

  // "0.4s", "42s", "3m 05s", "2h 07m"; "--" for negative or non-finite values.
  [[nodiscard]] static std::string format_duration(double seconds);
  // The default clock: std::chrono::steady_clock in seconds.
  [[nodiscard]] static Clock steady_seconds();

 private:
  [[nodiscard]] double percent() const;
  [[nodiscard]] std::string counts() const;  // "3/8"
  void draw_terminal_line(std::string_view tail);
  void print_plain_line(std::string_view tail);

  std::string label_;
  std::size_t total_;
  std::ostream& out_;  // not owned
  bool is_terminal_;
  Clock clock_;
  ProgressOptions options_;

  double start_ = 0;
  double last_update_ = 0;
  double last_output_ = 0;
  bool has_output_ = false;
  bool is_finished_ = false;
  std::size_t done_ = 0;
  std::string detail_;
  std::size_t last_line_columns_ = 0;  // to blank out the rest of a longer previous line
};

}  // namespace rheosim::core
