#pragma once
// The part of summary.json every LDD run writes (cavity and free-surface scenes): the case, the
// build, the outcome, the cloud, the step and where the time went. One place, so both runners
// report the same keys.
#include <chrono>

#include <nlohmann/json.hpp>

#include "rheosim/core/case.hpp"
#include "rheosim/core/version.hpp"
#include "rheosim/ldd/run.hpp"
#include "rheosim/ldd/solver.hpp"

namespace rheosim::ldd::detail {

// Solver: ldd::Solver or ldd::FreeSurfaceSolver (node_count, fluid_node_count, steps, time,
// phase_times).
template <class Solver>
[[nodiscard]] nlohmann::ordered_json summary_head(const core::Case& c, const core::LddCase& l, const Solver& solver,
                                                  const RunOutcome& outcome, int threads) {
  const PhaseTimes& t = solver.phase_times();
  nlohmann::ordered_json summary;
  summary["case"] = c.name;
  summary["kind"] = c.kind();
  summary["scene"] = l.scene_type;
  summary["dimension"] = l.dimension;
  summary["rheosim_version"] = core::version;
  summary["git_revision"] = core::git_revision;
  summary["input_sha256"] = c.sha256;
  summary["status"] = outcome.status;
  if (!outcome.message.empty()) summary["message"] = outcome.message;
  summary["nodes"] = solver.node_count();
  summary["fluid_nodes"] = solver.fluid_node_count();
  summary["spacing"] = l.spacing;
  summary["time_step"] = l.time_step;
  summary["steps"] = solver.steps();
  summary["time"] = solver.time();
  summary["threads"] = threads;
  summary["ms_per_step"] = outcome.ms_per_step;
  summary["phase_seconds"] = {{"neighbours", t.neighbours}, {"operators", t.operators}, {"rheology", t.rheology},
                              {"pressure", t.pressure},     {"momentum", t.momentum},   {"advection", t.advection},
                              {"reordering", t.reordering}};
  return summary;
}

}  // namespace rheosim::ldd::detail
