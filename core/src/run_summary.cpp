#include "rheosim/core/run_summary.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "rheosim/core/error.hpp"

namespace rheosim::core {

void refuse_summary_value(const std::filesystem::path& file, std::string_view key, std::string_view expected,
                          std::string_view hint) {
  ConfigError::Details d;
  d.where = FileLocation{file.string(), 0, 0};
  d.key_path = std::string(key);
  d.problem = fmt::format("summary.json has no usable '{}'", key);
  d.expected = std::string(expected);
  d.hint = std::string(hint);
  throw ConfigError(d);
}

SummaryReader::SummaryReader(const nlohmann::json& json, std::filesystem::path file, std::string writer,
                             std::string hint, std::string path)
    : json_(json), file_(std::move(file)), writer_(std::move(writer)), hint_(std::move(hint)), path_(std::move(path)) {
  if (!json_.is_object()) refuse_summary_value(file_, path_.empty() ? "(top level)" : path_, "an object", hint_);
}

void SummaryReader::refuse(std::string_view key, std::string_view expected) const {
  refuse_summary_value(file_, path_.empty() ? std::string(key) : path_ + "." + std::string(key), expected, hint_);
}

const nlohmann::json& SummaryReader::at(std::string_view key) const {
  if (!has(key)) refuse(key, fmt::format("the key, as {} writes it", writer_));
  return json_.at(std::string(key));
}

double SummaryReader::number(std::string_view key) const {
  const nlohmann::json& v = at(key);
  if (!v.is_number()) refuse(key, "a number");
  return v.get<double>();
}

std::optional<double> SummaryReader::number_or_null(std::string_view key) const {
  const nlohmann::json& v = at(key);
  if (v.is_null()) return std::nullopt;
  if (!v.is_number()) refuse(key, "a number or null");
  return v.get<double>();
}

std::size_t SummaryReader::count(std::string_view key) const {
  const nlohmann::json& v = at(key);
  if (!v.is_number_unsigned()) refuse(key, "a count (an integer >= 0)");
  return v.get<std::size_t>();
}

long long SummaryReader::integer(std::string_view key) const {
  const nlohmann::json& v = at(key);
  if (!v.is_number_integer()) refuse(key, "an integer");
  return v.get<long long>();
}

std::string SummaryReader::text(std::string_view key) const {
  const nlohmann::json& v = at(key);
  if (!v.is_string()) refuse(key, "a string");
  return v.get<std::string>();
}

bool SummaryReader::boolean(std::string_view key) const {
  const nlohmann::json& v = at(key);
  if (!v.is_boolean()) refuse(key, "true or false");
  return v.get<bool>();
}

std::vector<std::string> SummaryReader::texts(std::string_view key) const {
  const nlohmann::json& v = at(key);
  if (!v.is_array() || !std::all_of(v.begin(), v.end(), [](const nlohmann::json& e) { return e.is_string(); }))
    refuse(key, "a list of strings");
  return v.get<std::vector<std::string>>();
}

std::vector<double> SummaryReader::numbers(std::string_view key) const {
  const nlohmann::json& v = at(key);
  if (!v.is_array() || !std::all_of(v.begin(), v.end(), [](const nlohmann::json& e) { return e.is_number(); }))
    refuse(key, "a list of numbers");
  return v.get<std::vector<double>>();
}

std::vector<std::optional<double>> SummaryReader::numbers_or_null(std::string_view key) const {
  const nlohmann::json& v = at(key);
  if (!v.is_array() ||
      !std::all_of(v.begin(), v.end(), [](const nlohmann::json& e) { return e.is_number() || e.is_null(); }))
    refuse(key, "a list of numbers (or nulls)");
  std::vector<std::optional<double>> out;
  out.reserve(v.size());
  for (const auto& e : v) out.push_back(e.is_null() ? std::nullopt : std::optional<double>(e.get<double>()));
  return out;
}

SummaryReader SummaryReader::object(std::string_view key) const {
  return SummaryReader(at(key), file_, writer_, hint_,
                       path_.empty() ? std::string(key) : path_ + "." + std::string(key));
}

std::optional<double> SummaryReader::optional_number(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  return number_or_null(key);
}

std::optional<bool> SummaryReader::optional_boolean(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  return boolean(key);
}

std::optional<SummaryReader> SummaryReader::optional_object(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  return object(key);
}

std::vector<SummaryReader> SummaryReader::objects(std::string_view key) const {
  const nlohmann::json& v = at(key);
  if (!v.is_array()) refuse(key, "a list");
  std::vector<SummaryReader> out;
  out.reserve(v.size());
  const std::string base = path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_object()) refuse(fmt::format("{}[{}]", key, i), "an object");
    out.emplace_back(v[i], file_, writer_, hint_, fmt::format("{}[{}]", base, i));
  }
  return out;
}

SummaryHead read_summary_head(const SummaryReader& r) {
  return {r.text("case"), r.text("kind"), r.text("rheosim_version"), r.text("git_revision"), r.text("input_sha256")};
}

}  // namespace rheosim::core
