#include "herschel_bulkley.hpp"
#include "parameter_check.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace rheosim::core {
namespace {

// Valid ranges, shared by the YAML reader (located errors) and the constructor (invariants).
const Range consistency_range = Range::positive();
const Range index_range = Range::open_closed(0.0, 2.0);
const Range yield_stress_range = Range::non_negative();
const Range regularization_range = Range::positive();
const Range min_shear_rate_range = Range::positive();

void check(std::string_view key, double value, const Range& range) {
  detail::check_parameter(HerschelBulkley::name, key, value, range);
}

}  // namespace

HerschelBulkley::Params HerschelBulkley::Params::from(const Section& section) {
  const Params defaults;
  Params p;
  p.consistency = section.number({"consistency", "flow-consistency index k", "Pa·s^n"}, consistency_range);
  p.index = section.number({"index", "flow-behaviour index n", "-"}, index_range);
  p.yield_stress = section.number({"yield_stress", "yield stress τ0", "Pa"}, yield_stress_range);
  p.regularization = section.number_or({"regularization", "Papanastasiou regularisation parameter m", "s"},
                                       defaults.regularization, regularization_range);
  p.min_shear_rate =
      section.number_or({"min_shear_rate", "shear rate below which the power-law term is held constant", "1/s"},
                        defaults.min_shear_rate, min_shear_rate_range);
  return p;
}

HerschelBulkley::HerschelBulkley(Params params) : params_(params) {
  check("consistency", params_.consistency, consistency_range);
  check("index", params_.index, index_range);
  check("yield_stress", params_.yield_stress, yield_stress_range);
  check("regularization", params_.regularization, regularization_range);
  check("min_shear_rate", params_.min_shear_rate, min_shear_rate_range);
}

std::vector<Parameter> HerschelBulkley::parameters() const {
  return {{"consistency", params_.consistency, "Pa·s^n"},
          {"index", params_.index, "-"},
          {"yield_stress", params_.yield_stress, "Pa"},
          {"regularization", params_.regularization, "s"},
          {"min_shear_rate", params_.min_shear_rate, "1/s"}};
}

}  // namespace rheosim::core
