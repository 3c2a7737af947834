#pragma once
// What a slump of a yield-stress material is compared with at its end (run_free_surface.cpp
// puts it into the RunSummary; the LDD report shows it):
//   - a cylinder mould (top diameter = bottom diameter): Pashias et al.'s slump s′ = s/H against
//     τ′ = τ₀/(ρgH) (pashias_slump, run.hpp), summary "pashias";
//   - a cone: Roussel & Coussot's pancake spread for the cone's volume (roussel_coussot_spread),
//     summary "roussel_coussot";
// each with the yield stress its formula reads from the run's final shape, as a slump test would.
#include "rheosim/core/log.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/summary.hpp"

namespace rheosim::ldd::detail {

// Nothing for a law without a yield stress or a run without a final shape.
void compare_slump(const CaseSettings& l, RunSummary& summary, const core::Log& log);

}  // namespace rheosim::ldd::detail
