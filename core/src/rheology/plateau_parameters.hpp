#pragma once
// The parameters the two plateau laws (Carreau–Yasuda, Cross) share: μ0 > 0, 0 <= μ∞ < μ0 and
// λ > 0. Read from YAML with located errors (read_plateaus, then the law's own keys, then
// check_plateau_order) and checked again by the constructors (check_plateaus).
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "parameter_check.hpp"
#include "rheosim/core/config.hpp"

namespace rheosim::core::detail {

inline Range zero_shear_viscosity_range() { return Range::positive(); }
inline Range infinite_shear_viscosity_range() { return Range::non_negative(); }
inline Range time_constant_range() { return Range::positive(); }

template <class Params>
void read_plateaus(const Section& section, Params& p) {
  p.zero_shear_viscosity =
      section.number({"zero_shear_viscosity", "zero-shear viscosity μ0", "Pa·s"}, zero_shear_viscosity_range());
  p.infinite_shear_viscosity = section.number({"infinite_shear_viscosity", "infinite-shear viscosity μ∞ < μ0", "Pa·s"},
                                              infinite_shear_viscosity_range());
  p.time_constant = section.number({"time_constant", "time constant λ", "s"}, time_constant_range());
}

template <class Params>
void check_plateau_order(const Section& section, const Params& p) {
  if (!(p.infinite_shear_viscosity < p.zero_shear_viscosity))
    section.fail(
        "infinite_shear_viscosity",
        fmt::format("{} is not below zero_shear_viscosity = {}", p.infinite_shear_viscosity, p.zero_shear_viscosity),
        fmt::format("infinite-shear viscosity μ∞ in [0, {}), Pa·s", p.zero_shear_viscosity),
        "μ∞ is the high-shear plateau and must lie below the zero-shear plateau μ0");
}

template <class Params>
void check_plateaus(std::string_view model, const Params& p) {
  check_parameter(model, "zero_shear_viscosity", p.zero_shear_viscosity, zero_shear_viscosity_range());
  check_parameter(model, "infinite_shear_viscosity", p.infinite_shear_viscosity, infinite_shear_viscosity_range());
  check_parameter(model, "time_constant", p.time_constant, time_constant_range());
  if (!(p.infinite_shear_viscosity < p.zero_shear_viscosity))
    throw std::invalid_argument(fmt::format("{}: infinite_shear_viscosity = {} must be below zero_shear_viscosity = {}",
                                            model, p.infinite_shear_viscosity, p.zero_shear_viscosity));
}

}  // namespace rheosim::core::detail
