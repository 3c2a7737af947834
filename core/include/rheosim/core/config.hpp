#pragma once
// Location-aware, validating view of a YAML case file. This is the only place that knows
// about yaml-cpp: everything else receives typed structs built from a Section.
//
// Every lookup records the key as known; after a whole document has been read,
// Document::check_all_keys_known() reports any key that no reader asked for as an error
// with the nearest known sibling as a suggestion. A missing required key next to an unknown
// sibling that resembles it is reported as the misspelling it most likely is.
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rheosim/core/error.hpp"

namespace rheosim::core {

// A closed/open interval on the real line for validating numbers.
struct Range {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  bool lower_open = true;
  bool upper_open = true;

  static Range positive() { return {0.0, inf(), true, true}; }              // (0, inf)
  static Range non_negative() { return {0.0, inf(), false, true}; }         // [0, inf)
  static Range open(double lo, double hi) { return {lo, hi, true, true}; }  // (lo, hi)
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static Range open_closed(double lo, double hi) { return {lo, hi, true, false}; }
  static Range closed_open(double lo, double hi) { return {lo, hi, false, true}; }
  static Range any() { return {}; }

  [[nodiscard]] bool contains(double x) const;
  [[nodiscard]] std::string str() const;     // "(0, 2]", "> 0", ">= 0", "any finite number"
  [[nodiscard]] std::string phrase() const;  // for "x is not ...": "in (0, 2]", "> 0"
  static constexpr double inf() { return std::numeric_limits<double>::infinity(); }
};

// What a key means: shown in errors as "expected: <description>, <unit>".
struct KeyInfo {
  std::string_view name;
  std::string_view description;  // e.g. "plate radius"
  std::string_view unit;         // SI unit, e.g. "m", "Pa·s", "1/s", "-" for dimensionless
};

namespace detail {
struct DocumentState;  // parsed tree, file name, text, and the set of keys asked for
struct NodeHandle;     // a yaml-cpp node, kept out of this header
}  // namespace detail

// A mapping node of the case file, with its dotted path and file location.
class Section {
 public:
  // The file location of this section (or of one of its keys) for error messages.
  [[nodiscard]] FileLocation where() const;
  [[nodiscard]] FileLocation where(std::string_view key) const;
  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] std::string key_path(std::string_view key) const;

  [[nodiscard]] bool has(std::string_view key) const;

  // Required and optional scalars. Numbers must be finite and inside range.
  [[nodiscard]] double number(const KeyInfo& key, const Range& range) const;
  [[nodiscard]] double number_or(const KeyInfo& key, double fallback, const Range& range) const;
  // A required number, or the word `word` (e.g. `auto`): nullopt for the word.
  [[nodiscard]] std::optional<double> number_or_word(const KeyInfo& key, std::string_view word,
                                                     const Range& range) const;
  [[nodiscard]] int integer(const KeyInfo& key, int lower, int upper) const;
  [[nodiscard]] int integer_or(const KeyInfo& key, int fallback, int lower, int upper) const;
  [[nodiscard]] bool boolean_or(const KeyInfo& key, bool fallback) const;
  [[nodiscard]] std::string text(const KeyInfo& key) const;
  [[nodiscard]] std::string text_or(const KeyInfo& key, std::string fallback) const;
  // A string that must be one of `choices`; the error lists them and suggests the nearest.
  [[nodiscard]] std::string choice(const KeyInfo& key, const std::vector<std::string>& choices) const;
  [[nodiscard]] std::string choice_or(const KeyInfo& key, std::string fallback,
                                      const std::vector<std::string>& choices) const;

  // Lists of numbers: every element in range, length within [min_size, max_size].
  [[nodiscard]] std::vector<double> numbers(const KeyInfo& key, const Range& range, std::size_t min_size = 1,
                                            std::size_t max_size = std::numeric_limits<std::size_t>::max()) const;
  [[nodiscard]] std::vector<double> numbers_or(const KeyInfo& key, std::vector<double> fallback, const Range& range,
                                               std::size_t min_size = 1,
                                               std::size_t max_size = std::numeric_limits<std::size_t>::max()) const;

  // Nested mappings.
  [[nodiscard]] Section section(const KeyInfo& key) const;
  [[nodiscard]] std::optional<Section> optional_section(const KeyInfo& key) const;
  // A list of mappings (e.g. `fluids: [{name: a, ...}, {name: b, ...}]`), paths "key[i]".
  [[nodiscard]] std::vector<Section> sections(const KeyInfo& key, std::size_t min_size = 1) const;

  // Raises a ConfigError located at `key` (or at this section when key is empty).
  [[noreturn]] void fail(std::string_view key, std::string problem, std::string expected, std::string hint = {}) const;

 private:
  friend class Document;
  Section(std::shared_ptr<detail::DocumentState> doc, std::shared_ptr<const detail::NodeHandle> node, std::string path);

  std::shared_ptr<detail::DocumentState> doc_;
  std::shared_ptr<const detail::NodeHandle> node_;
  std::string path_;
};

// A parsed case file. Parse errors (malformed YAML) become ConfigErrors with the line.
class Document {
 public:
  static Document from_file(const std::string& path);
  static Document from_string(std::string_view text, std::string name);

  [[nodiscard]] Section root() const;
  [[nodiscard]] const std::string& name() const;
  [[nodiscard]] const std::string& text() const;  // the exact input, for reports and hashing

  // After all readers ran: every key in the file must have been asked for by some reader.
  void check_all_keys_known() const;

 private:
  explicit Document(std::shared_ptr<detail::DocumentState> state);
  std::shared_ptr<detail::DocumentState> state_;
};

// A list of values read from `key` of `section` must be strictly increasing (a repeated point is
// almost always a typo); else a ConfigError at that key.
void require_increasing(const Section& section, std::string_view key, const std::vector<double>& values);

// Levenshtein distance, used for "did you mean" suggestions.
[[nodiscard]] std::size_t edit_distance(std::string_view a, std::string_view b);
// The closest candidate if it is close enough to be a plausible misspelling.
[[nodiscard]] std::optional<std::string> nearest(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace rheosim::core
