#pragma once
// Logging for runs: a small value type around one spdlog logger. Each Log owns its logger
// (never spdlog's global registry or default logger), so libraries, tests and concurrent runs
// cannot step on each other, and a copy is cheap (shared sinks).
//
//   Log log = Log::console(Verbosity::normal).with_file(run_dir / "rheosim.log");
//   log.info("point {}/{}: shear rate {} 1/s", i + 1, n, shear_rate);
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <utility>

#include <fmt/format.h>
#include <spdlog/logger.h>

namespace rheosim::core {

// How much reaches the console: quiet = warnings and errors, normal = + info, verbose = + debug.
enum class Verbosity { quiet, normal, verbose };

class Log {
 public:
  // Same as Log::null(): a default member needs no setup.
  Log();

  // Messages at the verbosity's level and above go to stderr (coloured on a terminal).
  [[nodiscard]] static Log console(Verbosity verbosity);
  // Messages go to `out` as "<level>: <message>" lines; `out` must outlive every copy. For tests.
  [[nodiscard]] static Log to_stream(std::ostream& out, Verbosity verbosity);
  // Discards everything.
  [[nodiscard]] static Log null();

  // A copy that also writes every message from debug level up to `path` (appended, so a
  // resumed run keeps the history of earlier attempts; parent directories are created).
  // Throws RunError if the file cannot be opened.
  [[nodiscard]] Log with_file(const std::filesystem::path& path) const;

  template <class... Args>
  void debug(fmt::format_string<Args...> format, Args&&... args) const {
    logger_->debug(format, std::forward<Args>(args)...);
  }
  template <class... Args>
  void info(fmt::format_string<Args...> format, Args&&... args) const {
    logger_->info(format, std::forward<Args>(args)...);
  }
  template <class... Args>
  void warn(fmt::format_string<Args...> format, Args&&... args) const {
    logger_->warn(format, std::forward<Args>(args)...);
  }
  template <class... Args>
  void error(fmt::format_string<Args...> format, Args&&... args) const {
    logger_->error(format, std::forward<Args>(args)...);
  }

  // Writes buffered messages (the log file is flushed at info level and above anyway).
  void flush() const;

 private:
  explicit Log(std::shared_ptr<spdlog::logger> logger);
  std::shared_ptr<spdlog::logger> logger_;
};

}  // namespace rheosim::core
