#pragma once
// schiller_naumann: the drag of an isolated sphere (Schiller & Naumann, Z. Ver. Dtsch. Ing. 77
// (1933) 318), with no voidage (hindrance) function:
//
//   F   = 3π η d (u_f − u_p) (1 + 0.15 Re^0.687),   Re = ρ d |u_f − u_p| / η   (Re ≤ 1000)
//
// i.e. C_d = 24/Re (1 + 0.15 Re^0.687); Stokes' 3πηd at low Re. Beyond Re = 1000 C_d = 0.44
// (Newton's regime), continuous at the switch to 0.4 %.
//
// When to use it: with the near-field hydrodynamics (particles.hydrodynamics with lubrication),
// the Fast-Lubrication-Dynamics split (Kumar & Higdon, Phys. Rev. E 82 (2010) 051401; Mari et
// al., J. Rheol. 58 (2014) 1693) gives each sphere its isolated-sphere drag and leaves the
// interactions to the pair lubrication. Di Felice's voidage function ε^(−χ) (×2.6 at ε = 0.7)
// is the many-body resistance of a homogeneous bed, which the lubrication pairs already carry;
// both together count the crowding twice (docs/hydrodynamics.md).
//
// Parameters: none.
// YAML:
//   drag: {model: schiller_naumann}
#include <string_view>

#include "rheosim/core/config.hpp"
#include "rheosim/coupling/drag.hpp"

namespace rheosim::coupling {

class SchillerNaumann final : public DragModelBase<SchillerNaumann> {
 public:
  static constexpr std::string_view name = "schiller_naumann";

  struct Params {
    static Params from(const core::Section& section);
  };

  explicit SchillerNaumann(Params params);

  [[nodiscard]] double beta(const DragInput& particle) const;
};

}  // namespace rheosim::coupling
