#include "commands.hpp"

#include <fmt/format.h>

#include <iostream>

#include "rheosim/core/case.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/core/version.hpp"
#include "rheosim/rheometer/report.hpp"

namespace rheosim::app {

namespace {

// Prints a user error in one block: "error: file:line:col: key: problem" + expected + hint.
int bad_input(const core::Log& log, const std::exception& e) {
  log.error("{}", e.what());
  return exit_bad_input;
}

}  // namespace

int validate(const std::vector<std::string>& case_files, const core::Log& log) {
  int status = exit_success;
  for (const auto& file : case_files) {
    try {
      const core::Case c = core::load_case(file);
      std::cout << fmt::format("{}: valid {} case\n{}", file, c.kind(), core::describe(c));
    } catch (const core::ConfigError& e) {
      status = bad_input(log, e);
    }
  }
  return status;
}

int run(const std::string& case_file, const std::filesystem::path& out_dir, const core::Log& log) {
  core::Case c;
  try {
    c = core::load_case(case_file);
  } catch (const core::ConfigError& e) {
    return bad_input(log, e);
  }
  const std::filesystem::path out = out_dir.empty() ? std::filesystem::path("results") / c.name : out_dir;
  // No solver has landed yet: say so plainly instead of writing anything that looks like a result.
  log.error("'{}' is a valid {} case, but the {} solver is not built yet in rheosim {}; nothing was run "
            "and nothing was written to {}",
            case_file, c.kind(), c.kind() == "ldd" ? "LDD" : "rheometer", core::version, out.string());
  return exit_run_failure;
}

int report(const std::filesystem::path& run_dir, const core::Log& log) {
  try {
    const auto html = rheometer::write_report(run_dir);
    log.info("report written to {}", html.string());
    return exit_success;
  } catch (const core::ConfigError& e) {
    return bad_input(log, e);
  } catch (const std::exception& e) {
    log.error("report failed: {}", e.what());
    return exit_run_failure;
  }
}

}  // namespace rheosim::app
