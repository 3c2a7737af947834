#pragma once
// Helpers of the case-reader tests (tests/core, tests/rheometer, tests/ldd, tests/dem and tests/coupling case tests).
#include <gtest/gtest.h>

#include <string>

#include "rheosim/core/error.hpp"

namespace rheosim::test_support {

// The ConfigError read(text) throws; a test failure (and an empty error) when it throws none.
template <class Read>
core::ConfigError config_error(Read read, const std::string& text) {
  try {
    read(text);
  } catch (const core::ConfigError& e) {
    return e;
  }
  ADD_FAILURE() << "expected a ConfigError for:\n" << text;
  return core::ConfigError({});
}

// text with its first `from` replaced by `to`; a test failure when it has none.
inline std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

}  // namespace rheosim::test_support
