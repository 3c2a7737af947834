#pragma once
// di_felice: Di Felice drag with voidage correction (Di Felice, Int. J. Multiph. Flow 20 (1994)
// 153), as written in the CFD-DEM seed (CD eqs. 30–33):
//
//   F   = (1/8) C_d ρ π d² (u_f − u_p) |u_f − u_p| ε^(−χ)            (CD eq. 30)
//   C_d = (0.63 + 4.8/√Re_p)²                                         (CD eq. 31)
//   Re_p = ε ρ d |u_f − u_p| / η                                      (CD eq. 32)
//   χ   = 3.7 − 0.65 exp(−(1.5 − log10 Re_p)²/2)                      (CD eq. 33)
//
// so β = F/(u_f − u_p) = (π/8) C_d ρ d² |u_f − u_p| ε^(−χ). Using ρ d |u_f − u_p| = Re_p η/ε and
// C_d Re_p = (0.63 √Re_p + 4.8)², this is evaluated as
//   β = (π/8) η d ε^(−1−χ) (4.8 + 0.63 √Re_p)²
// which is exact, has no division by the slip speed, and is finite at zero slip.
//
// Low-Re limit: Re_p → 0 gives χ → 3.7 and β → (23.04 π/8) η d ε^(−4.7) = 2.88 π η d ε^(−4.7).
// At ε = 1 that is 0.96 × Stokes' 3π η d: Di Felice's C_d tends to 23.04/Re_p, not 24/Re_p.
//
// Note for comparison with CFDEMcoupling: its DiFeliceDrag multiplies by ε^(2−χ) (Di Felice's
// original form, written with the superficial velocity ε(u_f − u_p)), i.e. ε² times the seed's
// eq. 30; this class follows the seed as written.
//
// Parameters: none.
// YAML:
//   drag: {model: di_felice}
#include <string_view>

#include "rheosim/core/config.hpp"
#include "rheosim/coupling/drag.hpp"

namespace rheosim::coupling {

class DiFelice final : public DragModelBase<DiFelice> {
 public:
  static constexpr std::string_view name = "di_felice";

  struct Params {
    static Params from(const core::Section& section);
  };

  explicit DiFelice(Params params);

  [[nodiscard]] double beta(const DragInput& particle) const;
};

}  // namespace rheosim::coupling
