#pragma once
// The head every run's summary.json starts with: which case (its name and the SHA-256 of the
// exact input deck), which kind of run wrote it (the report reads it to pick its layout), and
// which rheosim (version and git revision). Each kind appends its own keys after these.
// SummaryReader reads them back: a report fails loudly on a missing or mistyped key instead of
// drawing NaN.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rheosim/core/case.hpp"
#include "rheosim/core/version.hpp"

namespace rheosim::core {

struct SummaryHead {
  std::string case_name, kind, rheosim_version, git_revision, input_sha256;
  friend bool operator==(const SummaryHead&, const SummaryHead&) = default;
};

[[nodiscard]] inline SummaryHead summary_head_of(const CaseHeader& header, std::string_view kind) {
  return {header.name, std::string(kind), std::string(version), std::string(git_revision), header.sha256};
}

[[nodiscard]] inline nlohmann::ordered_json to_json(const SummaryHead& head) {
  nlohmann::ordered_json summary;
  summary["case"] = head.case_name;
  summary["kind"] = head.kind;
  summary["rheosim_version"] = head.rheosim_version;
  summary["git_revision"] = head.git_revision;
  summary["input_sha256"] = head.input_sha256;
  return summary;
}

// An optional number of a typed summary: empty where the computation gave NaN or infinity, and
// written as null (summary.json has no NaN).
[[nodiscard]] inline std::optional<double> finite_or_empty(double x) {
  return std::isfinite(x) ? std::optional<double>(x) : std::nullopt;
}
[[nodiscard]] inline nlohmann::ordered_json value_or_null(const std::optional<double>& x) {
  return x ? nlohmann::ordered_json(*x) : nlohmann::ordered_json(nullptr);
}

[[nodiscard]] inline nlohmann::ordered_json summary_head(const CaseHeader& header, std::string_view kind) {
  return to_json(summary_head_of(header, kind));
}

// A ConfigError at summary.json's `key` (a dotted path, "points[3].shear_rate"): it has no
// usable value; `expected` says what was wanted, `hint` what to pass instead.
[[noreturn]] void refuse_summary_value(const std::filesystem::path& file, std::string_view key,
                                       std::string_view expected, std::string_view hint);

// Required values of one object of a summary.json: a missing key, or one of another type, is a
// ConfigError that names its path in the file.
class SummaryReader {
 public:
  // `writer` completes "the key, as ... writes it" ("every LDD run"); hint: see refuse_summary_value.
  SummaryReader(const nlohmann::json& json, std::filesystem::path file, std::string writer, std::string hint,
                std::string path = {});

  [[nodiscard]] bool has(std::string_view key) const { return json_.contains(std::string(key)); }
  [[nodiscard]] const nlohmann::json& at(std::string_view key) const;
  [[nodiscard]] double number(std::string_view key) const;
  [[nodiscard]] std::optional<double> number_or_null(std::string_view key) const;
  [[nodiscard]] std::size_t count(std::string_view key) const;
  [[nodiscard]] long long integer(std::string_view key) const;  // of either sign
  [[nodiscard]] std::string text(std::string_view key) const;
  [[nodiscard]] bool boolean(std::string_view key) const;
  [[nodiscard]] std::vector<std::string> texts(std::string_view key) const;
  [[nodiscard]] std::vector<double> numbers(std::string_view key) const;
  // A list of numbers, each possibly null.
  [[nodiscard]] std::vector<std::optional<double>> numbers_or_null(std::string_view key) const;
  // A nested object, its path "key".
  [[nodiscard]] SummaryReader object(std::string_view key) const;
  // A list of objects: one reader per element, its path "key[i]".
  [[nodiscard]] std::vector<SummaryReader> objects(std::string_view key) const;

  // Values only some runs write: absent (or null) is nothing; present, the type is checked.
  [[nodiscard]] std::optional<double> optional_number(std::string_view key) const;
  [[nodiscard]] std::optional<bool> optional_boolean(std::string_view key) const;
  [[nodiscard]] std::optional<SummaryReader> optional_object(std::string_view key) const;

  // A ConfigError at this object's `key`: its value is not `expected`.
  [[noreturn]] void refuse(std::string_view key, std::string_view expected) const;

 private:
  const nlohmann::json& json_;
  std::filesystem::path file_;
  std::string writer_, hint_, path_;
};

// The head of a summary.json (case, kind, rheosim_version, git_revision, input_sha256).
[[nodiscard]] SummaryHead read_summary_head(const SummaryReader& summary);

}  // namespace rheosim::core
