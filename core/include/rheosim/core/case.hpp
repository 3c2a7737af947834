#pragma once
// Typed, validated case files (docs/case-files.md). CaseFile parses the YAML and reads the header
// every kind shares; the module that owns the kind reads the rest from its Section, validating
// every key (SI units, ranges, cross-key checks) and rejecting unknown ones, and returns plain
// structs (rheometer::read_case for rheometer and sweep, ldd::read_case for ldd). Solvers take
// these structs and never see YAML. Here: the envelope and the physics types every kind shares.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"

namespace rheosim::core {

// ------------------------------------------------------------------ shared building blocks

struct FluidProperties {
  double density = 0;                        // ρ [kg/m³]
  std::shared_ptr<const Rheology> rheology;  // μ(γ̇), never null
};

struct PlateGeometry {  // geometry: {type: parallel_plate, radius, gap}
  double radius = 0;    // R [m]
  double gap = 0;       // H [m], < R
};

// ---------------------------------------------------------------------------- the case

// The part every case file shares, read here: who the case is and which module reads the rest.
struct CaseHeader {
  std::string file;    // path as given
  std::string text;    // the exact input deck
  std::string sha256;  // of text, for reports and resume checks
  std::string name;    // optional `name:`, else the file's stem
  std::string description;
  std::string kind;  // "rheometer" | "sweep" | "ldd"
};

// A parsed case file: its header, and the root Section from which the module that owns the kind
// reads the rest (rheometer::read_case for rheometer and sweep, ldd::read_case for ldd), the way each
// OpenFOAM model reads its own sub-dictionary. The reader ends with check_all_keys_known().
class CaseFile {
 public:
  // Parses the YAML and reads the header; throws ConfigError naming file:line:col and key.
  [[nodiscard]] static CaseFile open(const std::string& path);
  [[nodiscard]] static CaseFile parse(std::string_view text, const std::string& name);

  [[nodiscard]] const CaseHeader& header() const { return header_; }
  [[nodiscard]] Section root() const { return document_.root(); }
  // The case file's directory: relative paths in the case (an STL wall) resolve against it.
  [[nodiscard]] std::filesystem::path directory() const;
  // A reader's first check: `kind` is one it reads, or a ConfigError at `kind` names the reader.
  void require_kind(const std::vector<std::string>& kinds, std::string_view reader) const;
  // After the reader: every key of the file was asked for, or a ConfigError names the stray one.
  void check_all_keys_known() const { document_.check_all_keys_known(); }

 private:
  [[nodiscard]] static CaseFile read_header(Document document);
  CaseFile(Document document, CaseHeader header) : document_(std::move(document)), header_(std::move(header)) {}
  Document document_;
  CaseHeader header_;
};

// `fluid: {density, rheology}` under `section`: the liquid of every kind of case.
[[nodiscard]] FluidProperties read_fluid(const Section& section);
// The keys density and rheology of one liquid's own section (an item of a `fluids:` list).
[[nodiscard]] FluidProperties read_fluid_properties(const Section& fluid);

// SHA-256 (FIPS 180-4) of a byte string, lower-case hex.
[[nodiscard]] std::string sha256_hex(std::string_view bytes);

}  // namespace rheosim::core

namespace rheosim::core {
// The `fluid:` lines of such a listing ("  fluid: density …, rheology …\n").
[[nodiscard]] std::string describe_fluid(const FluidProperties& fluid);
}  // namespace rheosim::core
