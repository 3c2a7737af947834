#pragma once
// divided: each particle's volume split over 29 sub-points of V_p/29 (void_fraction.hpp): the
// centre and two shells of 14 points (cube face and corner directions) at 0.6276 r and 0.9085 r,
// the volume-weighted mean radii of the equal-volume shells r (1/29)^(1/3) .. r (15/29)^(1/3)
// and r (15/29)^(1/3) .. r. Sub-points in the same cell are merged into one share.
// Parameters: none.  YAML: void_fraction: {model: divided}
#include <array>
#include <string_view>

#include "rheosim/core/config.hpp"
#include "rheosim/coupling/void_fraction.hpp"

namespace rheosim::coupling {

class DividedVoidFraction final : public VoidFractionSchemeBase<DividedVoidFraction> {
 public:
  static constexpr std::string_view name = "divided";
  static constexpr int sub_points = 29;
  struct Params {
    static Params from(const core::Section& section);
  };
  explicit DividedVoidFraction(Params params);

  void split(const CellLocator& locator, const ParticleView& particles, ParticleCellMap& out) const override;

  // Sub-point offsets for a unit radius (index 0 is the centre).
  [[nodiscard]] static std::array<Vector3, sub_points> unit_offsets();
  // Radii of the two shells' points for a unit radius.
  [[nodiscard]] static std::array<double, 2> shell_radii();

 private:
  std::array<Vector3, sub_points> offsets_;
};

}  // namespace rheosim::coupling
