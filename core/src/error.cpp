#include "rheosim/core/error.hpp"

#include <fmt/format.h>

namespace rheosim::core {

std::string FileLocation::str() const {
  if (line <= 0) return file;
  if (column <= 0) return fmt::format("{}:{}", file, line);
  return fmt::format("{}:{}:{}", file, line, column);
}

namespace {
std::string render(const ConfigError::Details& d) {
  std::string out = d.where.str();
  if (!out.empty()) out += ": ";
  if (!d.key_path.empty()) out += d.key_path + ": ";
  out += d.problem;
  if (!d.expected.empty()) out += "\n  expected: " + d.expected;
  if (!d.hint.empty()) out += "\n  hint: " + d.hint;
  return out;
}
}  // namespace

ConfigError::ConfigError(Details details) : std::runtime_error(render(details)), details_(std::move(details)) {}

void throw_config_error(std::string file, std::string key, std::string problem, std::string expected,
                        std::string hint) {
  throw ConfigError(
      {FileLocation{std::move(file), 0, 0}, std::move(key), std::move(problem), std::move(expected), std::move(hint)});
}

RunError::RunError(const std::string& message, std::source_location origin)
    : std::runtime_error(message), origin_(origin) {}

}  // namespace rheosim::core
