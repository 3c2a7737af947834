#pragma once
// The constructor-side invariant check shared by every law: the same ranges the YAML reader
// enforces with located errors, so an invalid law cannot be built from code either.
#include <cmath>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "rheosim/core/config.hpp"

namespace rheosim::core::detail {

inline void check_parameter(std::string_view model, std::string_view key, double value, const Range& range) {
  if (!std::isfinite(value) || !range.contains(value))
    throw std::invalid_argument(
        fmt::format("{}: {} = {} is out of range, expected {}", model, key, value, range.str()));
}

}  // namespace rheosim::core::detail
