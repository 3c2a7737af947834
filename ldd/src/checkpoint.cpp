#include "checkpoint.hpp"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "rheosim/core/error.hpp"
#include "rheosim/core/version.hpp"

namespace rheosim::ldd::detail {

namespace {

// The solver state's numbers among the file's attributes; every other number is the scene's.
constexpr std::pair<const char*, double PhaseTimes::*> phase_seconds[] = {
    {"seconds_neighbours", &PhaseTimes::neighbours}, {"seconds_operators", &PhaseTimes::operators},
    {"seconds_rheology", &PhaseTimes::rheology},     {"seconds_pressure", &PhaseTimes::pressure},
    {"seconds_momentum", &PhaseTimes::momentum},     {"seconds_advection", &PhaseTimes::advection},
    {"seconds_reordering", &PhaseTimes::reordering}};
constexpr const char* state_numbers[] = {"time", "steps", "first_step"};

template <class T>
std::vector<double> as_doubles(const std::vector<T>& v) {
  std::vector<double> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), [](T x) { return static_cast<double>(x); });
  return out;
}

template <class T>
std::vector<T> from_doubles(const std::vector<double>& v) {
  std::vector<T> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), [](double x) { return static_cast<T>(x); });
  return out;
}

// The AMG hierarchies kept between steps, as state/amg/<name>/...
constexpr const char* amg_names[] = {"pressure", "velocity"};
numerics::AmgState& amg_of(SolverState& s, std::string_view name) {
  return name == "pressure" ? s.pressure_amg : s.velocity_amg;
}

}  // namespace

std::vector<std::size_t> as_counts(const std::vector<double>& values) { return from_doubles<std::size_t>(values); }

double RunRecordContent::number(const std::string& name, const std::filesystem::path& checkpoint) const {
  const auto it = numbers.find(name);
  if (it == numbers.end())
    throw core::RunError(
        fmt::format("checkpoint '{}' has no number '{}': not a checkpoint of this rheosim", checkpoint.string(), name));
  return it->second;
}

const std::vector<double>& RunRecordContent::values(const std::string& name,
                                                    const std::filesystem::path& checkpoint) const {
  const auto it = series.find(name);
  if (it == series.end())
    throw core::RunError(fmt::format("checkpoint '{}' has no series 'run/{}': not a checkpoint of this rheosim",
                                     checkpoint.string(), name));
  return it->second;
}

// Numbers go in as doubles (HDF5 through core/output.hpp): indices and counts are exact below 2^53.
void write_checkpoint(const std::filesystem::path& path, const Case& c, SolverState s, const RunRecordContent& record,
                      const core::CsvTable& history) {
  const std::size_t dim = s.kinds.empty() ? 1 : s.positions.size() / s.kinds.size();
  core::Hdf5Content h;
  h.attributes = {{"input_sha256", c.sha256},
                  {"git_revision", core::git_revision},
                  {"time", s.time},
                  {"steps", static_cast<double>(s.steps)},
                  {"first_step", s.first_step ? 1.0 : 0.0}};
  for (const auto& [name, member] : phase_seconds) h.attributes.push_back({name, s.times.*member});
  for (const auto& [name, value] : record.numbers) h.attributes.push_back({name, value});
  const auto add = [&](std::string name, std::vector<double> data, std::size_t width, std::string unit) {
    std::vector<std::size_t> shape{data.size() / std::max<std::size_t>(width, 1)};
    if (width > 1) shape.push_back(width);
    h.datasets.push_back({std::move(name), std::move(shape), std::move(data), std::move(unit), {}});
  };
  add("state/positions", std::move(s.positions), dim, "m");
  add("state/velocity", std::move(s.velocity), dim, "m/s");
  add("state/previous_velocity", std::move(s.previous_velocity), dim, "m/s");
  add("state/pressure", std::move(s.pressure), 1, "Pa");
  add("state/shear_rate", std::move(s.shear_rate), 1, "1/s");
  add("state/viscosity", std::move(s.viscosity), 1, "Pa s");
  add("state/kinds", as_doubles(s.kinds), 1, "");
  add("state/neighbours/offsets", as_doubles(s.neighbours.offsets), 1, "");
  add("state/neighbours/indices", as_doubles(s.neighbours.indices), 1, "");
  add("state/neighbours/distances", std::move(s.neighbours.distances), 1, "m");
  if (!s.momentum_increment.empty()) {  // the cavity's momentum initial guess
    add("state/momentum_increment", std::move(s.momentum_increment), dim, "m/s");
    add("state/older_momentum_increment", std::move(s.older_momentum_increment), dim, "m/s");
  }
  for (const char* name : amg_names) {
    numerics::AmgState& amg = amg_of(s, name);
    const std::string group = std::string("state/amg/") + name;
    add(group + "/diagonal", std::move(amg.diagonal), 1, "");
    add(group + "/off_diagonal", std::move(amg.off_diagonal), 1, "");
    add(group + "/offsets", as_doubles(amg.offsets), 1, "");
    add(group + "/columns", as_doubles(amg.columns), 1, "");
    add(group + "/counters",
        {static_cast<double>(amg.calls_since_setup), static_cast<double>(amg.reference_iterations),
         amg.setup_due ? 1.0 : 0.0, amg.smoothed.value_or(true) ? 1.0 : 0.0},
        1, "");
  }
  const std::size_t columns = history.numeric_columns().size();
  std::vector<double> rows;
  rows.reserve(history.row_count() * columns);
  for (std::size_t i = 0; i < history.row_count(); ++i)
    rows.insert(rows.end(), history.row(i).begin(), history.row(i).end());
  add("run/history", std::move(rows), columns, "");
  for (const auto& [name, values] : record.series) add("run/" + name, values, 1, "");
  core::write_hdf5(path, h);
}

StoredCheckpoint read_checkpoint(const std::filesystem::path& path, const Case& c, core::CsvTable& history) {
  std::map<std::string, core::Hdf5Attribute> a;
  for (auto& attribute : core::read_hdf5_attributes(path)) a.emplace(attribute.name, std::move(attribute));
  const auto text = [&](const char* name) {
    const auto it = a.find(name);
    return it != a.end() && std::holds_alternative<std::string>(it->second.value)
               ? std::get<std::string>(it->second.value)
               : std::string();
  };
  const std::string stored_sha = text("input_sha256");
  if (stored_sha != c.sha256) {
    core::ConfigError::Details d;
    d.where = core::FileLocation{path.string(), 0, 0};
    d.key_path = "input_sha256";
    d.problem = fmt::format("this folder holds the checkpoint of another input deck (sha256 {}, this deck {})",
                            stored_sha.substr(0, 12), c.sha256.substr(0, 12));
    d.expected = "a folder without checkpoint.h5, or the checkpoint of this very deck (resume)";
    d.hint = fmt::format("run into a new --out folder, or delete {} to start this deck afresh", path.string());
    throw core::ConfigError(d);
  }
  StoredCheckpoint out;
  out.git_revision = text("git_revision");
  for (const auto& [name, attribute] : a)
    if (std::holds_alternative<double>(attribute.value)) out.record.numbers[name] = std::get<double>(attribute.value);
  const auto number = [&](const char* name) { return out.record.number(name, path); };
  const auto data = [&](std::string_view name) { return core::read_hdf5_dataset(path, name).data; };
  SolverState& s = out.state;
  s.time = number("time");
  s.steps = static_cast<std::size_t>(number("steps"));
  s.first_step = number("first_step") != 0;
  for (const auto& [name, member] : phase_seconds) s.times.*member = number(name);
  for (const char* name : state_numbers) out.record.numbers.erase(name);
  for (const auto& [name, member] : phase_seconds) out.record.numbers.erase(name);
  s.positions = data("state/positions");
  s.velocity = data("state/velocity");
  s.previous_velocity = data("state/previous_velocity");
  s.pressure = data("state/pressure");
  s.shear_rate = data("state/shear_rate");
  s.viscosity = data("state/viscosity");
  s.kinds = from_doubles<NodeKind>(data("state/kinds"));
  s.neighbours.offsets = from_doubles<std::size_t>(data("state/neighbours/offsets"));
  s.neighbours.indices = from_doubles<std::size_t>(data("state/neighbours/indices"));
  s.neighbours.distances = data("state/neighbours/distances");
  const std::vector<std::string> state_names = core::hdf5_dataset_names(path, "state");
  if (std::binary_search(state_names.begin(), state_names.end(), "momentum_increment")) {
    s.momentum_increment = data("state/momentum_increment");
    s.older_momentum_increment = data("state/older_momentum_increment");
  }
  for (const char* name : amg_names) {
    numerics::AmgState& amg = amg_of(s, name);
    const std::string group = std::string("state/amg/") + name;
    amg.diagonal = data(group + "/diagonal");
    amg.off_diagonal = data(group + "/off_diagonal");
    amg.offsets = from_doubles<std::size_t>(data(group + "/offsets"));
    amg.columns = from_doubles<std::size_t>(data(group + "/columns"));
    const std::vector<double> counters = data(group + "/counters");
    // The fourth, the aggregation in use, is absent from checkpoints written before it was kept.
    if (counters.size() != 3 && counters.size() != 4)
      throw core::RunError(fmt::format("checkpoint '{}': {}/counters is not 3 or 4 numbers", path.string(), group));
    amg.calls_since_setup = static_cast<int>(counters[0]);
    amg.reference_iterations = static_cast<int>(counters[1]);
    amg.setup_due = counters[2] != 0;
    if (counters.size() == 4) amg.smoothed.emplace(counters.back() != 0);
  }
  for (const std::string& name : core::hdf5_dataset_names(path, "run"))
    if (name != "history") out.record.series[name] = data("run/" + name);
  const std::vector<double> rows = data("run/history");
  const std::size_t columns = history.numeric_columns().size();
  if (columns == 0 || rows.size() % columns != 0)
    throw core::RunError(
        fmt::format("checkpoint '{}': its probe history does not have this case's {} columns", path.string(), columns));
  for (std::size_t i = 0; i < rows.size(); i += columns)
    history.add_row(std::span<const double>(rows).subspan(i, columns));
  return out;
}

}  // namespace rheosim::ldd::detail
