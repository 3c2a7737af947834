#pragma once
// Ghia, Ghia & Shin (1982), J. Comput. Phys. 48, 387–411, Tables I–II: centre-line velocities of
// the square lid-driven cavity at Re = 100 and 1000, the reference a cavity run of a Newtonian
// liquid at one of these Reynolds numbers compares itself with (summary.json `ghia`, ghia.csv).
#include <optional>
#include <span>

#include "rheosim/core/case.hpp"
#include "rheosim/ldd/scene.hpp"

namespace rheosim::ldd {

struct GhiaPoint {
  char line;          // 'u': u/U on the vertical centre line (coordinate y/L); 'v': v/U on the horizontal one (x/L)
  double coordinate;  // y/L or x/L
  double re100, re1000;
  [[nodiscard]] double at(int reynolds) const { return reynolds == 1000 ? re1000 : re100; }
};

// The 34 tabulated points (17 per centre line).
[[nodiscard]] std::span<const GhiaPoint> ghia_1982();

// The tabulated Reynolds number (100 or 1000) that ρUL/μ of this cavity matches within 0.5 %,
// when the cavity is square and the liquid Newtonian; nullopt otherwise.
[[nodiscard]] std::optional<int> ghia_reynolds(const CavityScene& scene, const core::FluidProperties& fluid);

}  // namespace rheosim::ldd
