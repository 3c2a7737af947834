
#include "rheosim/core/case.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <utility>

#include "rheosim/core/config.hpp"

namespace rheosim::core {

FluidProperties read_fluid_properties(const Section& fluid) {
  FluidProperties out;
  out.density = fluid.number({"density", "fluid density", "kg/m³"}, Range::positive());
  out.rheology = make_rheology(fluid.section({"rheology", "viscosity law {model: name, parameters}", "-"}));
  return out;
}

FluidProperties read_fluid(const Section& section) {
  return read_fluid_properties(section.section({"fluid", "the liquid (matrix) phase", "-"}));
}

std::filesystem::path CaseFile::directory() const { return std::filesystem::path(header_.file).parent_path(); }

void CaseFile::require_kind(const std::vector<std::string>& kinds, std::string_view reader) const {
  if (std::find(kinds.begin(), kinds.end(), header_.kind) != kinds.end()) return;
  std::string names;
  for (const auto& k : kinds) names += (names.empty() ? "" : " or ") + k;
  root().fail("kind", fmt::format("{} reads {} cases, not '{}'", reader, names, header_.kind), names);
}

CaseFile CaseFile::read_header(Document doc) {
  const Section root = doc.root();
  CaseHeader h;
  h.file = doc.name();
  h.text = doc.text();
  h.sha256 = sha256_hex(h.text);
  h.name = root.text_or({"name", "case name", "-"}, std::filesystem::path(h.file).stem().string());
  h.description = root.text_or({"description", "free-text description", "-"}, "");
  h.kind = root.choice({"kind", "case kind", "-"}, {"rheometer", "sweep", "ldd"});
  return CaseFile(std::move(doc), std::move(h));
}

CaseFile CaseFile::parse(std::string_view text, const std::string& name) {
  return read_header(Document::from_string(text, name));
}

CaseFile CaseFile::open(const std::string& path) { return read_header(Document::from_file(path)); }

}  // namespace rheosim::core
