#pragma once
// centre: each particle's whole volume goes to the cell holding its centre (void_fraction.hpp).
// Parameters: none.  YAML: void_fraction: {model: centre}
#include <string_view>

#include "rheosim/core/config.hpp"
#include "rheosim/coupling/void_fraction.hpp"

namespace rheosim::coupling {

class CentreVoidFraction final : public VoidFractionSchemeBase<CentreVoidFraction> {
 public:
  static constexpr std::string_view name = "centre";
  struct Params {
    static Params from(const core::Section& section);
  };
  explicit CentreVoidFraction(Params /*params*/) {}

  void split(const CellLocator& locator, const ParticleView& particles, ParticleCellMap& out) const override;
};

}  // namespace rheosim::coupling
