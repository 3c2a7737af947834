#pragma once
// The reference a column is compared with (run_free_surface.cpp writes it beside the run and into
// its RunSummary; the LDD report draws it): with a wave_amplitude A > 0, the first sloshing mode
// in linear theory (linear_sloshing, run.hpp) — the left-wall elevation H + A cos ωt in
// sloshing.csv beside the run's, and summary "sloshing": the period from the run's zero crossings
// about H up to the first time its kinetic energy exceeds 1.5 E (past that it is no longer the
// linear wave), against 2π/ω.
#include <filesystem>

#include "rheosim/core/log.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/summary.hpp"

namespace rheosim::ldd::detail {

// `history` is the run's column.csv (time, left_wall_height, kinetic_energy, ...).
void compare_with_linear_sloshing(const CaseSettings& l, const core::CsvTable& history,
                                  const std::filesystem::path& out_dir, RunSummary& summary, const core::Log& log);

}  // namespace rheosim::ldd::detail
