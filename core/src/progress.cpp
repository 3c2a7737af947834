#include "rheosim/core/progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <ostream>

namespace rheosim::core {

namespace {

bool is_utf8_continuation(char c) { return (static_cast<unsigned char>(c) & 0xC0U) == 0x80U; }

// Terminal columns, approximated by UTF-8 code points (γ̇ is one column, not four bytes).
std::size_t columns(std::string_view s) {
  return static_cast<std::size_t>(std::count_if(s.begin(), s.end(), [](char c) { return !is_utf8_continuation(c); }));
}

// Cuts `s` to at most `width` columns without splitting a UTF-8 sequence.
std::string fit(std::string s, std::size_t width) {
  if (width == 0 || columns(s) <= width) return s;
  std::size_t seen = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (is_utf8_continuation(s[i])) continue;
    if (seen == width) {
      s.resize(i);
      break;
    }
    ++seen;
  }
  return s;
}

}  // namespace

Progress::Progress(std::string label, std::size_t total, std::ostream& out, bool is_terminal, Clock clock,
                   ProgressOptions options)
    : label_(std::move(label)),
      total_(total),
      out_(out),
      is_terminal_(is_terminal),
      clock_(std::move(clock)),
      options_(options),
      done_(std::min(options.initial_done, total)) {
  start_ = clock_();
  last_update_ = start_;
  last_output_ = start_;
}

Progress Progress::for_stderr(std::string label, std::size_t total, ProgressOptions options) {
  const bool is_terminal = ::isatty(STDERR_FILENO) == 1;
  if (is_terminal && options.line_width == 0) {
    winsize size{};
    // One column spare: writing the last column makes some terminals wrap before the '\r'.
    if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 1) options.line_width = size.ws_col - 1U;
  }
  return Progress(std::move(label), total, std::cerr, is_terminal, steady_seconds(), options);
}

Progress::~Progress() {
  if (is_finished_ || !is_terminal_ || !has_output_) return;
  try {
    out_ << '\n' << std::flush;
  } catch (...) {  // a destructor must not throw; losing a newline is harmless
  }
}

Progress::Clock Progress::steady_seconds() {
  return [] { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); };
}

std::string Progress::format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--";
  if (seconds < 9.95) return fmt::format("{:.1f}s", seconds);
  const auto whole = std::llround(seconds);
  if (whole < 60) return fmt::format("{}s", whole);
  if (whole < 3600) return fmt::format("{}m {:02}s", whole / 60, whole % 60);
  const auto minutes = (whole + 30) / 60;  // hours-long estimates need no seconds
  return fmt::format("{}h {:02}m", minutes / 60, minutes % 60);
}

std::optional<double> Progress::eta() const {
  const double seconds = elapsed();
  const std::size_t done_here = done_ - std::min(options_.initial_done, done_);
  if (seconds <= 0 || done_here == 0) return std::nullopt;
  const double rate = static_cast<double>(done_here) / seconds;  // units per second, average so far
  return static_cast<double>(total_ - done_) / rate;
}

double Progress::percent() const {
  return total_ == 0 ? 100.0 : 100.0 * static_cast<double>(done_) / static_cast<double>(total_);
}

std::string Progress::counts() const { return fmt::format("{}/{}", done_, total_); }

void Progress::update(std::size_t done, std::string_view detail) {
  if (is_finished_) return;
  const double now = clock_();
  done_ = std::min(done, total_);
  detail_ = detail;
  last_update_ = now;
  const auto eta_text = [this] {
    const auto left = eta();
    return left ? format_duration(*left) : std::string("--");
  };

  if (is_terminal_) {
    const bool is_complete = done_ == total_;
    if (has_output_ && now - last_output_ < options_.redraw_interval && !is_complete) return;
    draw_terminal_line("ETA " + eta_text());
  } else {
    // Nothing for runs shorter than one interval: finish() alone says it all.
    if (now - last_output_ < options_.plain_interval) return;
    print_plain_line(fmt::format("elapsed {}, ETA {}", format_duration(elapsed()), eta_text()));
  }
  last_output_ = now;
  has_output_ = true;
}

void Progress::finish() {
  if (is_finished_) return;
  last_update_ = clock_();
  const std::string tail = "done in " + format_duration(elapsed());
  if (is_terminal_) {
    draw_terminal_line(tail);
    out_ << '\n';
  } else {
    print_plain_line(tail);
  }
  out_ << std::flush;
  is_finished_ = true;
  has_output_ = true;
}

void Progress::draw_terminal_line(std::string_view tail) {
  const double fraction = percent() / 100.0;
  const auto filled =
      std::min(options_.bar_width, static_cast<std::size_t>(fraction * static_cast<double>(options_.bar_width)));
  std::string line = fmt::format("{}{}[{}{}] {:5.1f}%  {}", label_, label_.empty() ? "" : " ", std::string(filled, '#'),
                                 std::string(options_.bar_width - filled, '.'), percent(), counts());
  if (!detail_.empty()) line += "  " + detail_;
  line += "  ";
  line += tail;
  line = fit(std::move(line), options_.line_width);
  const std::size_t width = columns(line);
  // Blank out what a longer previous line left behind.
  if (width < last_line_columns_) line.append(last_line_columns_ - width, ' ');
  last_line_columns_ = width;
  out_ << '\r' << line << std::flush;
}

void Progress::print_plain_line(std::string_view tail) {
  std::string line = fmt::format("{}{}{} ({:.1f}%)", label_, label_.empty() ? "" : ": ", counts(), percent());
  if (!detail_.empty()) line += " " + detail_;
  line += ", ";
  line += tail;
  out_ << line << '\n' << std::flush;
}

}  // namespace rheosim::core
