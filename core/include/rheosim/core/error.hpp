#pragma once
// Error types. Input errors (bad case files, bad CLI arguments) are ConfigError and map to
// exit code 2; failures while running (divergence, solver breakdown) are RunError, exit code 1.
#include <source_location>
#include <stdexcept>
#include <string>

namespace rheosim::core {

// A position in a case file. line and column are 1-based; 0 means unknown.
struct FileLocation {
  std::string file;
  int line = 0;
  int column = 0;
  [[nodiscard]] std::string str() const;  // "case.yaml:12:5" (or "case.yaml" when unknown)
};

// A user error in an input file: where, which key, what is wrong, and how to fix it.
// what() renders as:
//   case.yaml:12:5: fluid.rheology.index: 2.7 is not in (0, 2]
//     expected: flow-behaviour index n, dimensionless
//     hint: ...
class ConfigError : public std::runtime_error {
 public:
  struct Details {
    FileLocation where;
    std::string key_path;  // dotted path, e.g. "fluid.rheology.index"
    std::string problem;   // what is wrong, e.g. "2.7 is not in (0, 2]"
    std::string expected;  // what was expected, with units
    std::string hint;      // how to fix it (may be empty)
  };
  explicit ConfigError(Details details);
  [[nodiscard]] const Details& details() const { return details_; }

 private:
  Details details_;
};

// A ConfigError about an input whose line is not known (a command-line option, a whole case):
// file may be empty; key is a dotted case key or an option such as "--mesh".
[[noreturn]] void throw_config_error(std::string file, std::string key, std::string problem, std::string expected,
                                     std::string hint = {});

// A failure while running a valid case: divergence, a solver that did not converge,
// an external engine that reported an error. Carries where in the code it was raised.
class RunError : public std::runtime_error {
 public:
  explicit RunError(const std::string& message, std::source_location origin = std::source_location::current());
  [[nodiscard]] const std::source_location& origin() const { return origin_; }

 private:
  std::source_location origin_;
};

}  // namespace rheosim::core
