#include "rheosim/core/log.hpp"

#include <spdlog/common.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>

#include <system_error>
#include <vector>

#include "rheosim/core/error.hpp"

namespace rheosim::core {

namespace {

constexpr const char* logger_name = "rheosim";
constexpr const char* console_pattern = "[%H:%M:%S] %^%l%$: %v";
constexpr const char* stream_pattern = "%l: %v";
constexpr const char* file_pattern = "[%Y-%m-%d %H:%M:%S.%e] [%l] %v";

spdlog::level::level_enum level_of(Verbosity verbosity) {
  switch (verbosity) {
    case Verbosity::quiet:
      return spdlog::level::warn;
    case Verbosity::normal:
      return spdlog::level::info;
    case Verbosity::verbose:
      return spdlog::level::debug;
  }
  return spdlog::level::info;
}

}  // namespace

Log::Log() : Log(null()) {}

Log::Log(std::shared_ptr<spdlog::logger> logger) : logger_(std::move(logger)) {}

Log Log::console(Verbosity verbosity) {
  // The sink class itself, not spdlog::stderr_color_mt(), which would register a global logger.
  auto sink = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  sink->set_pattern(console_pattern);
  sink->set_level(level_of(verbosity));
  auto logger = std::make_shared<spdlog::logger>(logger_name, std::move(sink));
  logger->set_level(level_of(verbosity));  // debug messages are not even formatted when quiet
  return Log(std::move(logger));
}

Log Log::to_stream(std::ostream& out, Verbosity verbosity) {
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(out, /*force_flush=*/true);
  sink->set_pattern(stream_pattern);
  sink->set_level(level_of(verbosity));
  auto logger = std::make_shared<spdlog::logger>(logger_name, std::move(sink));
  logger->set_level(level_of(verbosity));
  return Log(std::move(logger));
}

Log Log::null() {
  auto logger = std::make_shared<spdlog::logger>(logger_name);  // no sinks
  logger->set_level(spdlog::level::off);
  return Log(std::move(logger));
}

Log Log::with_file(const std::filesystem::path& path) const {
  if (const auto directory = path.parent_path(); !directory.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(directory, ec);
    if (ec)
      throw RunError(
          fmt::format("cannot create directory '{}' for the log file: {}", directory.string(), ec.message()));
  }
  spdlog::sink_ptr file_sink;
  try {
    file_sink = std::make_shared<spdlog::sinks::basic_file_sink_mt>(path.string(), /*truncate=*/false);
  } catch (const spdlog::spdlog_ex& e) {
    throw RunError(fmt::format("cannot open log file '{}': {}", path.string(), e.what()));
  }
  file_sink->set_pattern(file_pattern);
  file_sink->set_level(spdlog::level::debug);

  std::vector<spdlog::sink_ptr> sinks = logger_->sinks();  // shared with this Log
  sinks.push_back(std::move(file_sink));
  auto logger = std::make_shared<spdlog::logger>(logger_->name(), sinks.begin(), sinks.end());
  logger->set_level(spdlog::level::debug);
  logger->flush_on(spdlog::level::info);  // what matters survives a crash
  return Log(std::move(logger));
}

void Log::flush() const { logger_->flush(); }

}  // namespace rheosim::core
