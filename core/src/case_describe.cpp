#include <fmt/format.h>

#include "rheosim/core/case.hpp"

namespace rheosim::core {

std::string describe_fluid(const FluidProperties& fluid) {
  std::string out = fmt::format("  fluid: density {} kg/m³, rheology {}", fluid.density, fluid.rheology->name());
  for (const auto& p : fluid.rheology->parameters()) out += fmt::format(", {} {} {}", p.name, p.value, p.unit);
  return out + "\n";
}

}  // namespace rheosim::core
