#include "rheosim/core/config.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace rheosim::core {

namespace detail {
struct DocumentState {
  std::string name;
  std::string text;
  YAML::Node root;
  std::set<std::string, std::less<>> known_paths;  // dotted key paths some reader asked for
};
struct NodeHandle {
  YAML::Node node;
};
}  // namespace detail

namespace {

using detail::DocumentState;
using detail::NodeHandle;

FileLocation location_of(const DocumentState& doc, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  if (mark.is_null()) return {doc.name, 0, 0};
  return {doc.name, mark.line + 1, mark.column + 1};
}

std::string join_path(std::string_view parent, std::string_view key) {
  if (parent.empty()) return std::string(key);
  return fmt::format("{}.{}", parent, key);
}

std::string describe(const KeyInfo& key) {
  if (key.unit.empty() || key.unit == "-") return std::string(key.description);
  return fmt::format("{} [{}]", key.description, key.unit);
}

// The YAML node of a key in a mapping, and the node of the key itself (for its position).
struct Found {
  YAML::Node key;
  YAML::Node value;
};
std::optional<Found> find_key(const YAML::Node& map, std::string_view key) {
  if (!map.IsMap()) return std::nullopt;
  for (auto it = map.begin(); it != map.end(); ++it) {
    if (it->first.IsScalar() && it->first.Scalar() == key) return Found{it->first, it->second};
  }
  return std::nullopt;
}

std::string scalar_text(const YAML::Node& node) {
  if (node.IsNull()) return "nothing";
  if (node.IsScalar()) return fmt::format("'{}'", node.Scalar());
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a mapping";
  return "an undefined value";
}

}  // namespace

// ---------------------------------------------------------------------------------- Range

bool Range::contains(double x) const {
  if (std::isnan(x)) return false;
  const bool above = lower_open ? x > lower : x >= lower;
  const bool below = upper_open ? x < upper : x <= upper;
  return above && below;
}

std::string Range::str() const {
  const bool no_lower = std::isinf(lower) && lower < 0;
  const bool no_upper = std::isinf(upper) && upper > 0;
  if (no_lower && no_upper) return "any finite number";
  if (no_upper) return fmt::format("{} {}", lower_open ? ">" : ">=", lower);
  if (no_lower) return fmt::format("{} {}", upper_open ? "<" : "<=", upper);
  return fmt::format("{}{}, {}{}", lower_open ? "(" : "[", lower, upper, upper_open ? ")" : "]");
}

std::string Range::phrase() const {
  const bool two_sided = !std::isinf(lower) && !std::isinf(upper);
  return two_sided ? "in " + str() : str();
}

// --------------------------------------------------------------------------- suggestions

void require_increasing(const Section& s, std::string_view key, const std::vector<double>& values) {
  for (std::size_t i = 1; i < values.size(); ++i)
    if (!(values[i] > values[i - 1]))
      s.fail(key, fmt::format("entry {} ({}) does not exceed entry {} ({})", i, values[i], i - 1, values[i - 1]),
             "a strictly increasing list", "sort the list and remove repeated values");
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      const std::size_t substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({above + 1, row[j - 1] + 1, substitution});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::optional<std::string> nearest(std::string_view word, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& candidate : candidates) {
    const std::size_t d = edit_distance(word, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  // Plausible misspelling: a few edits, relative to the word length.
  const std::size_t allowed = std::max<std::size_t>(2, word.size() / 3);
  if (best && best_distance <= allowed) return best;
  return std::nullopt;
}

// -------------------------------------------------------------------------------- Section

Section::Section(std::shared_ptr<DocumentState> doc, std::shared_ptr<const NodeHandle> node, std::string path)
    : doc_(std::move(doc)), node_(std::move(node)), path_(std::move(path)) {}

FileLocation Section::where() const { return location_of(*doc_, node_->node); }

FileLocation Section::where(std::string_view key) const {
  if (auto found = find_key(node_->node, key)) return location_of(*doc_, found->key);
  return where();
}

std::string Section::key_path(std::string_view key) const { return join_path(path_, key); }

bool Section::has(std::string_view key) const {
  auto found = find_key(node_->node, key);
  return found && !found->value.IsNull();
}

void Section::fail(std::string_view key, std::string problem, std::string expected, std::string hint) const {
  throw ConfigError({key.empty() ? where() : where(key), key.empty() ? path_ : key_path(key), std::move(problem),
                     std::move(expected), std::move(hint)});
}

namespace {

// Looks a key up, records it as known, and reports a missing required key, pointing at a
// sibling that looks like a misspelling of it when there is one.
struct Lookup {
  const Section& section;
  const YAML::Node& map;
  DocumentState& doc;

  std::optional<YAML::Node> optional(const KeyInfo& key) const {
    doc.known_paths.insert(section.key_path(key.name));
    auto found = find_key(map, key.name);
    if (!found || found->value.IsNull()) return std::nullopt;
    return found->value;
  }

  YAML::Node required(const KeyInfo& key) const {
    if (auto value = optional(key)) return *value;
    if (auto found = find_key(map, key.name)) {
      section.fail(key.name, "has no value", describe(key), fmt::format("write '{}: <value>'", key.name));
    }
    std::vector<std::string> siblings;
    if (map.IsMap())
      for (auto it = map.begin(); it != map.end(); ++it)
        if (it->first.IsScalar()) siblings.push_back(it->first.Scalar());
    // A sibling the readers do not know and that is close to the missing key is a misspelling.
    std::vector<std::string> unknown;
    for (const auto& s : siblings)
      if (!doc.known_paths.contains(section.key_path(s)) || s == key.name) unknown.push_back(s);
    if (auto typo = nearest(key.name, unknown)) {
      throw ConfigError({section.where(*typo), section.key_path(*typo), fmt::format("unknown key '{}'", *typo),
                         describe(key), fmt::format("did you mean '{}'?", key.name)});
    }
    const std::string where_text = section.path().empty() ? "at the top level" : "in '" + section.path() + "'";
    section.fail({}, fmt::format("missing required key '{}'", key.name), describe(key),
                 fmt::format("add '{}: <value>' {}", key.name, where_text));
  }
};

double to_number(const Section& s, const KeyInfo& key, const YAML::Node& node, const Range& range,
                 const FileLocation& where, const std::string& path) {
  const std::string expected = fmt::format("{}, a number {}", describe(key), range.phrase());
  if (!node.IsScalar())
    throw ConfigError({where, path, fmt::format("expected a number, got {}", scalar_text(node)), expected, {}});
  double value = 0;
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    throw ConfigError({where, path, fmt::format("expected a number, got '{}'", node.Scalar()), expected,
                       "write the value in SI units without unit suffixes, e.g. 1.0e-3"});
  }
  if (!std::isfinite(value))
    throw ConfigError({where, path, fmt::format("{} is not a finite number", node.Scalar()), expected, {}});
  if (!range.contains(value))
    throw ConfigError({where, path, fmt::format("{} is not {}", value, range.phrase()), expected,
                       fmt::format("change it to a value {} (SI units)", range.phrase())});
  (void)s;
  return value;
}

}  // namespace

double Section::number(const KeyInfo& key, const Range& range) const {
  Lookup lookup{*this, node_->node, *doc_};
  const YAML::Node node = lookup.required(key);
  return to_number(*this, key, node, range, location_of(*doc_, node), key_path(key.name));
}

std::optional<double> Section::number_or_word(const KeyInfo& key, std::string_view word, const Range& range) const {
  Lookup lookup{*this, node_->node, *doc_};
  const YAML::Node node = lookup.required(key);
  if (node.IsScalar() && node.Scalar() == word) return std::nullopt;
  try {
    return to_number(*this, key, node, range, location_of(*doc_, node), key_path(key.name));
  } catch (const ConfigError& e) {
    ConfigError::Details d = e.details();
    d.expected += fmt::format(", or {}", word);
    throw ConfigError(d);
  }
}

double Section::number_or(const KeyInfo& key, double fallback, const Range& range) const {
  Lookup lookup{*this, node_->node, *doc_};
  auto node = lookup.optional(key);
  if (!node) return fallback;
  return to_number(*this, key, *node, range, location_of(*doc_, *node), key_path(key.name));
}

namespace {
int to_integer(const KeyInfo& key, const YAML::Node& node, int lower, int upper, const FileLocation& where,
               const std::string& path) {
  const std::string expected = fmt::format("{}, an integer in [{}, {}]", describe(key), lower, upper);
  long long value = 0;
  try {
    if (!node.IsScalar()) throw YAML::Exception(YAML::Mark::null_mark(), "not a scalar");
    value = node.as<long long>();
  } catch (const YAML::Exception&) {
    throw ConfigError({where, path, fmt::format("expected an integer, got {}", scalar_text(node)), expected, {}});
  }
  if (value < lower || value > upper)
    throw ConfigError({where, path, fmt::format("{} is not in [{}, {}]", value, lower, upper), expected, {}});
  return static_cast<int>(value);
}
}  // namespace

int Section::integer(const KeyInfo& key, int lower, int upper) const {
  Lookup lookup{*this, node_->node, *doc_};
  const YAML::Node node = lookup.required(key);
  return to_integer(key, node, lower, upper, location_of(*doc_, node), key_path(key.name));
}

int Section::integer_or(const KeyInfo& key, int fallback, int lower, int upper) const {
  Lookup lookup{*this, node_->node, *doc_};
  auto node = lookup.optional(key);
  if (!node) return fallback;
  return to_integer(key, *node, lower, upper, location_of(*doc_, *node), key_path(key.name));
}

bool Section::boolean_or(const KeyInfo& key, bool fallback) const {
  Lookup lookup{*this, node_->node, *doc_};
  auto node = lookup.optional(key);
  if (!node) return fallback;
  try {
    if (!node->IsScalar()) throw YAML::Exception(YAML::Mark::null_mark(), "not a scalar");
    return node->as<bool>();
  } catch (const YAML::Exception&) {
    throw ConfigError({location_of(*doc_, *node),
                       key_path(key.name),
                       fmt::format("expected true or false, got {}", scalar_text(*node)),
                       describe(key),
                       {}});
  }
}

namespace {
std::string to_text(const KeyInfo& key, const YAML::Node& node, const FileLocation& where, const std::string& path) {
  if (!node.IsScalar())
    throw ConfigError(
        {where, path, fmt::format("expected a text value, got {}", scalar_text(node)), describe(key), {}});
  return node.Scalar();
}
}  // namespace

std::string Section::text(const KeyInfo& key) const {
  Lookup lookup{*this, node_->node, *doc_};
  const YAML::Node node = lookup.required(key);
  return to_text(key, node, location_of(*doc_, node), key_path(key.name));
}

std::string Section::text_or(const KeyInfo& key, std::string fallback) const {
  Lookup lookup{*this, node_->node, *doc_};
  auto node = lookup.optional(key);
  if (!node) return fallback;
  return to_text(key, *node, location_of(*doc_, *node), key_path(key.name));
}

namespace {
std::string check_choice(const KeyInfo& key, const std::string& value, const std::vector<std::string>& choices,
                         const FileLocation& where, const std::string& path) {
  if (std::find(choices.begin(), choices.end(), value) != choices.end()) return value;
  std::string listed;
  for (const auto& c : choices) listed += (listed.empty() ? "" : ", ") + c;
  std::string hint;
  if (auto near = nearest(value, choices)) hint = fmt::format("did you mean '{}'?", *near);
  throw ConfigError(
      {where, path, fmt::format("unknown {} '{}'", key.description, value), fmt::format("one of: {}", listed), hint});
}
}  // namespace

std::string Section::choice(const KeyInfo& key, const std::vector<std::string>& choices) const {
  Lookup lookup{*this, node_->node, *doc_};
  const YAML::Node node = lookup.required(key);
  const auto where_node = location_of(*doc_, node);
  return check_choice(key, to_text(key, node, where_node, key_path(key.name)), choices, where_node, key_path(key.name));
}

std::string Section::choice_or(const KeyInfo& key, std::string fallback,
                               const std::vector<std::string>& choices) const {
  Lookup lookup{*this, node_->node, *doc_};
  auto node = lookup.optional(key);
  if (!node) return fallback;
  const auto where_node = location_of(*doc_, *node);
  return check_choice(key, to_text(key, *node, where_node, key_path(key.name)), choices, where_node,
                      key_path(key.name));
}

namespace {
std::vector<double> to_numbers(const Section& s, const DocumentState& doc, const KeyInfo& key, const YAML::Node& node,
                               const Range& range, std::size_t min_size, std::size_t max_size,
                               const std::string& path) {
  const FileLocation where = location_of(doc, node);
  const std::string size_text =
      max_size == std::numeric_limits<std::size_t>::max()
          ? fmt::format("at least {}", min_size)
          : (min_size == max_size ? fmt::format("exactly {}", min_size) : fmt::format("{} to {}", min_size, max_size));
  const std::string expected =
      fmt::format("{}: a list of {} numbers, each {}", describe(key), size_text, range.phrase());
  if (!node.IsSequence())
    throw ConfigError(
        {where, path, fmt::format("expected a list like [1, 2, 3], got {}", scalar_text(node)), expected, {}});
  if (node.size() < min_size || node.size() > max_size)
    throw ConfigError({where, path, fmt::format("the list has {} entries", node.size()), expected, {}});
  std::vector<double> values;
  values.reserve(node.size());
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    values.push_back(to_number(s, key, item, range, location_of(doc, item), fmt::format("{}[{}]", path, i)));
  }
  return values;
}
}  // namespace

std::vector<double> Section::numbers(const KeyInfo& key, const Range& range, std::size_t min_size,
                                     std::size_t max_size) const {
  Lookup lookup{*this, node_->node, *doc_};
  const YAML::Node node = lookup.required(key);
  return to_numbers(*this, *doc_, key, node, range, min_size, max_size, key_path(key.name));
}

std::vector<double> Section::numbers_or(const KeyInfo& key, std::vector<double> fallback, const Range& range,
                                        std::size_t min_size, std::size_t max_size) const {
  Lookup lookup{*this, node_->node, *doc_};
  auto node = lookup.optional(key);
  if (!node) return fallback;
  return to_numbers(*this, *doc_, key, *node, range, min_size, max_size, key_path(key.name));
}

Section Section::section(const KeyInfo& key) const {
  Lookup lookup{*this, node_->node, *doc_};
  const YAML::Node node = lookup.required(key);
  if (!node.IsMap())
    throw ConfigError({location_of(*doc_, node), key_path(key.name),
                       fmt::format("expected a mapping of keys, got {}", scalar_text(node)), describe(key),
                       fmt::format("write '{}:' followed by indented 'key: value' lines", key.name)});
  return Section(doc_, std::make_shared<const NodeHandle>(NodeHandle{node}), key_path(key.name));
}

std::optional<Section> Section::optional_section(const KeyInfo& key) const {
  if (!has(key.name)) {
    doc_->known_paths.insert(key_path(key.name));
    return std::nullopt;
  }
  return section(key);
}

std::vector<Section> Section::sections(const KeyInfo& key, std::size_t min_size) const {
  Lookup lookup{*this, node_->node, *doc_};
  const YAML::Node node = lookup.required(key);
  const auto where_node = location_of(*doc_, node);
  if (!node.IsSequence() || node.size() < min_size)
    throw ConfigError({where_node, key_path(key.name),
                       node.IsSequence() ? fmt::format("the list has {} entries", node.size())
                                         : fmt::format("expected a list of mappings, got {}", scalar_text(node)),
                       fmt::format("{}: a list of at least {} mappings", describe(key), min_size),
                       fmt::format("write '{}:' followed by '- key: value' items", key.name)});
  std::vector<Section> out;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    const std::string path = fmt::format("{}[{}]", key_path(key.name), i);
    if (!item.IsMap())
      throw ConfigError({location_of(*doc_, item), path, fmt::format("expected a mapping, got {}", scalar_text(item)),
                         describe(key), ""});
    doc_->known_paths.insert(path);
    out.push_back(Section(doc_, std::make_shared<const NodeHandle>(NodeHandle{item}), path));
  }
  return out;
}

// ------------------------------------------------------------------------------- Document

Document::Document(std::shared_ptr<DocumentState> state) : state_(std::move(state)) {}

Document Document::from_string(std::string_view text, std::string name) {
  auto state = std::make_shared<DocumentState>();
  state->name = std::move(name);
  state->text = std::string(text);
  try {
    state->root = YAML::Load(state->text);
  } catch (const YAML::ParserException& e) {
    throw ConfigError({FileLocation{state->name, e.mark.line + 1, e.mark.column + 1}, "",
                       fmt::format("malformed YAML: {}", e.msg),
                       "YAML 'key: value' lines, nested by indentation with spaces (no tabs)",
                       "check the indentation and the ':' on this line and the one before"});
  }
  if (!state->root.IsMap())
    throw ConfigError({FileLocation{state->name, 1, 1}, "", "the case file is not a mapping of keys",
                       "top-level 'key: value' lines, starting with 'kind: rheometer | sweep | ldd'", ""});
  return Document(std::move(state));
}

Document Document::from_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ConfigError({FileLocation{path, 0, 0}, "", "cannot open the case file", "a readable YAML file",
                       "check the path and the permissions"});
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return from_string(buffer.str(), path);
}

Section Document::root() const {
  return Section(state_, std::make_shared<const NodeHandle>(NodeHandle{state_->root}), "");
}

const std::string& Document::name() const { return state_->name; }
const std::string& Document::text() const { return state_->text; }

namespace {
void check_map(const DocumentState& doc, const YAML::Node& map, const std::string& path) {
  std::set<std::string> seen;
  std::vector<std::string> known_here;
  const std::string prefix = path.empty() ? "" : path + ".";
  for (auto it = doc.known_paths.lower_bound(prefix); it != doc.known_paths.end() && it->starts_with(prefix); ++it) {
    const std::string rest = it->substr(prefix.size());
    if (rest.find('.') == std::string::npos && rest.find('[') == std::string::npos) known_here.push_back(rest);
  }
  for (auto it = map.begin(); it != map.end(); ++it) {
    const std::string key = it->first.IsScalar() ? it->first.Scalar() : std::string("<non-text key>");
    const std::string key_path = join_path(path, key);
    if (!seen.insert(key).second)
      throw ConfigError({location_of(doc, it->first), key_path, fmt::format("key '{}' appears twice", key),
                         "each key once per section", "remove one of them"});
    if (!doc.known_paths.contains(key_path)) {
      std::string listed;
      for (const auto& k : known_here) listed += (listed.empty() ? "" : ", ") + k;
      std::string hint;
      if (auto near = nearest(key, known_here)) hint = fmt::format("did you mean '{}'?", *near);
      throw ConfigError({location_of(doc, it->first), key_path, fmt::format("unknown key '{}'", key),
                         listed.empty() ? std::string("no keys here") : fmt::format("one of: {}", listed), hint});
    }
    if (it->second.IsMap()) check_map(doc, it->second, key_path);
    if (it->second.IsSequence())
      for (std::size_t i = 0; i < it->second.size(); ++i) {
        const std::string item_path = fmt::format("{}[{}]", key_path, i);
        if (it->second[i].IsMap() && doc.known_paths.contains(item_path)) check_map(doc, it->second[i], item_path);
      }
  }
}
}  // namespace

void Document::check_all_keys_known() const { check_map(*state_, state_->root, ""); }

}  // namespace rheosim::core
