#pragma once
// The head every run's summary.json starts with: which case (its name and the SHA-256 of the
// exact input deck), which kind of run wrote it (the report reads it to pick its layout), and
// which rheosim (version and git revision). Each kind appends its own keys after these.
#include <nlohmann/json.hpp>

#include <string_view>

#include "rheosim/core/case.hpp"
#include "rheosim/core/version.hpp"

namespace rheosim::core {

[[nodiscard]] inline nlohmann::ordered_json summary_head(const CaseHeader& header, std::string_view kind) {
  nlohmann::ordered_json summary;
  summary["case"] = header.name;
  summary["kind"] = kind;
  summary["rheosim_version"] = version;
  summary["git_revision"] = git_revision;
  summary["input_sha256"] = header.sha256;
  return summary;
}

}  // namespace rheosim::core
