#include "rheosim/core/output.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <H5Cpp.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "rheosim/core/error.hpp"

namespace rheosim::core {

namespace fs = std::filesystem;

namespace {

std::string errno_message(int error) { return std::error_code(error, std::generic_category()).message(); }

// A name no other writer uses: hidden (so globs like *.vtk skip it), in the target's directory
// (so rename stays within one file system and is atomic).
fs::path temporary_name(const fs::path& path) {
  // The one piece of process-wide state here: two threads replacing the same file must never
  // pick the same temporary, and the pid alone does not separate them.
  static std::atomic<unsigned long long> counter{0};
  const fs::path directory = path.parent_path();
  while (true) {
    fs::path tmp = directory / fmt::format(".{}.tmp-{}-{}", path.filename().string(), ::getpid(), counter.fetch_add(1));
    std::error_code ec;
    if (!fs::exists(tmp, ec)) return tmp;  // a stale one from an earlier process with our pid
  }
}

// fsync through a fresh descriptor: it flushes the file's data whichever descriptor wrote it.
void sync_file(const fs::path& file, const fs::path& target) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    throw RunError(fmt::format("cannot write '{}': the temporary '{}' was not created ({})", target.string(),
                               file.string(), errno_message(errno)));
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    throw RunError(fmt::format("cannot write '{}': fsync failed ({})", target.string(), errno_message(error)));
  }
  ::close(fd);
}

// Makes the rename itself durable. Best effort: some file systems refuse fsync on directories.
void sync_directory(const fs::path& directory) {
  const int fd = ::open(directory.empty() ? "." : directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  static_cast<void>(::fsync(fd));
  ::close(fd);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Atomic replacement

void replace_atomically(const fs::path& path, const std::function<void(const fs::path& tmp)>& write) {
  if (path.filename().empty())
    throw std::invalid_argument(fmt::format("output path '{}' names no file", path.string()));
  const fs::path directory = path.parent_path();
  if (!directory.empty()) {
    std::error_code ec;
    fs::create_directories(directory, ec);
    if (ec)
      throw RunError(fmt::format("cannot create directory '{}' for '{}': {}", directory.string(),
                                 path.filename().string(), ec.message()));
  }
  const fs::path tmp = temporary_name(path);
  try {
    write(tmp);
    sync_file(tmp, path);
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw RunError(fmt::format("cannot replace '{}': {}", path.string(), ec.message()));
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
  sync_directory(directory);
}

void write_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  replace_atomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw RunError(fmt::format("cannot create '{}': {}", tmp.string(), errno_message(errno)));
    write(out);
    out.flush();
    if (!out) throw RunError(fmt::format("cannot write '{}': {}", path.string(), errno_message(errno)));
    out.close();
    if (out.fail()) throw RunError(fmt::format("cannot write '{}': {}", path.string(), errno_message(errno)));
  });
}

// ---------------------------------------------------------------------------------------------
// JSON

namespace {
template <class Json>
void write_any_json(const fs::path& path, const Json& value) {
  write_atomically(
      path, [&](std::ostream& out) { out << value.dump(2, ' ', false, Json::error_handler_t::replace) << '\n'; });
}
}  // namespace

void write_json(const fs::path& path, const nlohmann::json& value) { write_any_json(path, value); }
void write_json(const fs::path& path, const nlohmann::ordered_json& value) { write_any_json(path, value); }

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RunError(fmt::format("cannot open JSON file '{}': {}", path.string(), errno_message(errno)));
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw RunError(fmt::format("'{}' is not valid JSON: {}", path.string(), e.what()));
  }
}

// ---------------------------------------------------------------------------------------------
// CSV

CsvTable::CsvTable(std::vector<Column> numeric_columns, std::optional<Column> text_column)
    : columns_(std::move(numeric_columns)), text_column_(std::move(text_column)) {
  for (const Column& c : columns_)
    if (c.name.empty()) throw std::invalid_argument("CsvTable: a column has an empty name");
  if (text_column_ && text_column_->name.empty())
    throw std::invalid_argument("CsvTable: the text column has an empty name");
}

void CsvTable::add_row(std::span<const double> values, std::string text) {
  if (values.size() != columns_.size())
    throw std::invalid_argument(
        fmt::format("CsvTable::add_row: {} values for {} columns", values.size(), columns_.size()));
  if (!text_column_ && !text.empty())
    throw std::invalid_argument("CsvTable::add_row: text given but the table has no text column");
  values_.insert(values_.end(), values.begin(), values.end());
  texts_.push_back(std::move(text));
}

void CsvTable::add_row(std::initializer_list<double> values, std::string text) {
  add_row(std::span<const double>(values.begin(), values.size()), std::move(text));
}

std::span<const double> CsvTable::row(std::size_t i) const {
  if (i >= row_count()) throw std::out_of_range(fmt::format("CsvTable::row: {} >= {}", i, row_count()));
  return std::span<const double>(values_).subspan(i * columns_.size(), columns_.size());
}

std::vector<double> CsvTable::column(std::string_view name) const {
  for (std::size_t j = 0; j < columns_.size(); ++j) {
    if (columns_[j].name != name) continue;
    std::vector<double> out;
    out.reserve(row_count());
    for (std::size_t i = 0; i < row_count(); ++i) out.push_back(values_[i * columns_.size() + j]);
    return out;
  }
  throw std::out_of_range(fmt::format("CsvTable: no column '{}'", name));
}

namespace {

std::string csv_quote(std::string_view cell) {
  const bool needs_quotes = cell.find_first_of(",\"\r\n") != std::string_view::npos ||
                            (!cell.empty() && (cell.front() == ' ' || cell.back() == ' '));
  if (!needs_quotes) return std::string(cell);
  std::string out = "\"";
  for (const char c : cell) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
  return out;
}

std::string csv_header(const CsvTable::Column& c) {
  return csv_quote(c.unit.empty() ? c.name : c.name + " [" + c.unit + "]");
}

// Shortest text that parses back to the same double.
std::string format_number(double x) {
  if (std::isnan(x)) return "nan";  // to_chars would give "-nan" for some NaNs
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, x);
  if (ec != std::errc()) throw std::logic_error("to_chars failed for a double");
  return std::string(buffer, end);
}

std::optional<double> parse_number(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double x = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return x;
}

CsvTable::Column parse_header(const std::string& cell) {
  const auto open = cell.rfind(" [");
  if (open != std::string::npos && cell.size() >= open + 3 && cell.back() == ']')
    return {cell.substr(0, open), cell.substr(open + 2, cell.size() - open - 3)};
  return {cell, ""};
}

struct CsvRecord {
  std::vector<std::string> cells;
  int line = 0;  // 1-based line where the record starts
};

// RFC 4180 records: quoted cells may hold commas, doubled quotes and line breaks.
std::vector<CsvRecord> parse_records(const std::string& text, const fs::path& path) {
  std::vector<CsvRecord> records;
  CsvRecord record{{}, 1};
  std::string cell;
  bool in_quotes = false;
  bool record_has_content = false;
  int line = 1;
  const auto end_record = [&](int next_line) {
    if (record_has_content) {
      record.cells.push_back(std::move(cell));
      records.push_back(std::move(record));
    }
    record = CsvRecord{{}, next_line};
    cell.clear();
    record_has_content = false;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_quotes) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        in_quotes = false;
      } else {
        if (c == '\n') ++line;
        cell += c;
      }
      continue;
    }
    if (c == '"') {
      in_quotes = true;
      record_has_content = true;
    } else if (c == ',') {
      record.cells.push_back(std::move(cell));
      cell.clear();
      record_has_content = true;
    } else if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') {
      continue;  // CRLF line ends
    } else if (c == '\n') {
      ++line;
      end_record(line);
    } else {
      cell += c;
      record_has_content = true;
    }
  }
  if (in_quotes) throw RunError(fmt::format("{}:{}: unterminated quoted CSV cell", path.string(), record.line));
  end_record(line);
  return records;
}

}  // namespace

void write_csv(const fs::path& path, const CsvTable& table) {
  write_atomically(path, [&](std::ostream& out) {
    std::string line;
    const auto& columns = table.numeric_columns();
    if (table.text_column()) line += csv_header(*table.text_column());
    for (std::size_t j = 0; j < columns.size(); ++j) {
      if (j > 0 || table.text_column()) line += ',';
      line += csv_header(columns[j]);
    }
    out << line << '\n';
    for (std::size_t i = 0; i < table.row_count(); ++i) {
      line.clear();
      if (table.text_column()) line += csv_quote(table.text(i));
      const auto values = table.row(i);
      for (std::size_t j = 0; j < values.size(); ++j) {
        if (j > 0 || table.text_column()) line += ',';
        line += format_number(values[j]);
      }
      out << line << '\n';
    }
  });
}

CsvTable read_csv(const fs::path& path, bool first_column_is_text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RunError(fmt::format("cannot open CSV file '{}': {}", path.string(), errno_message(errno)));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::vector<CsvRecord> records = parse_records(buffer.str(), path);
  if (records.empty()) throw RunError(fmt::format("'{}' is empty, expected a CSV header", path.string()));

  const std::vector<std::string>& header = records.front().cells;
  const std::size_t first_numeric = first_column_is_text ? 1 : 0;
  if (header.size() < first_numeric)
    throw RunError(fmt::format("{}:1: expected a text column in the header", path.string()));
  std::vector<CsvTable::Column> columns;
  for (std::size_t j = first_numeric; j < header.size(); ++j) columns.push_back(parse_header(header[j]));
  std::optional<CsvTable::Column> text_column;
  if (first_column_is_text) text_column = parse_header(header.front());

  CsvTable table(std::move(columns), std::move(text_column));
  std::vector<double> values;
  for (std::size_t r = 1; r < records.size(); ++r) {
    const CsvRecord& record = records[r];
    if (record.cells.size() != header.size())
      throw RunError(fmt::format("{}:{}: {} cells, the header has {}", path.string(), record.line, record.cells.size(),
                                 header.size()));
    values.clear();
    for (std::size_t j = first_numeric; j < record.cells.size(); ++j) {
      const auto x = parse_number(record.cells[j]);
      if (!x)
        throw RunError(fmt::format("{}:{}: column '{}': '{}' is not a number", path.string(), record.line, header[j],
                                   record.cells[j]));
      values.push_back(*x);
    }
    table.add_row(values, first_column_is_text ? record.cells.front() : std::string());
  }
  return table;
}

// ---------------------------------------------------------------------------------------------
// HDF5

namespace {

[[noreturn]] void throw_hdf5_error(const fs::path& path, const H5::Exception& e) {
  throw RunError(fmt::format("HDF5 file '{}': {} failed: {}", path.string(), e.getFuncName(), e.getDetailMsg()));
}

// HDF5 prints its error stack to stderr by default; we report through exceptions instead.
// (The setting belongs to the HDF5 library's default error stack, not to this file.)
void silence_hdf5() { H5::Exception::dontPrint(); }

std::size_t element_count(const std::vector<std::size_t>& shape) {
  std::size_t n = 1;
  for (const std::size_t d : shape) n *= d;
  return n;
}

void check_dataset(const Hdf5Dataset& d) {
  if (d.path.empty()) throw std::invalid_argument("write_hdf5: a dataset has an empty path");
  if (d.shape.empty() || d.shape.size() > H5S_MAX_RANK)
    throw std::invalid_argument(fmt::format("write_hdf5: dataset '{}' has rank {}", d.path, d.shape.size()));
  if (element_count(d.shape) != d.data.size())
    throw std::invalid_argument(fmt::format("write_hdf5: dataset '{}' has shape [{}] but {} values", d.path,
                                            fmt::join(d.shape, ", "), d.data.size()));
}

bool is_root(std::string_view object_path) { return object_path.empty() || object_path == "/"; }

H5::LinkCreatPropList with_intermediate_groups() {
  H5::LinkCreatPropList lcpl;
  lcpl.setCreateIntermediateGroup(true);
  return lcpl;
}

void write_attribute(H5::H5Object& object, const Hdf5Attribute& attribute) {
  const H5::DataSpace scalar(H5S_SCALAR);
  if (const auto* number = std::get_if<double>(&attribute.value)) {
    H5::Attribute a = object.createAttribute(attribute.name, H5::PredType::IEEE_F64LE, scalar);
    a.write(H5::PredType::NATIVE_DOUBLE, number);
  } else {
    H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
    type.setCset(H5T_CSET_UTF8);
    H5::Attribute a = object.createAttribute(attribute.name, type, scalar);
    a.write(type, std::get<std::string>(attribute.value));
  }
}

void write_attributes(H5::H5Object& object, const std::vector<Hdf5Attribute>& attributes) {
  for (const Hdf5Attribute& a : attributes) write_attribute(object, a);
}

bool group_exists(const H5::H5File& file, std::string_view group_path) {
  // nameExists fails (rather than returning false) when an intermediate group is missing.
  std::string prefix;
  std::size_t start = 0;
  while (start <= group_path.size()) {
    const std::size_t slash = std::min(group_path.find('/', start), group_path.size());
    if (slash > start) {
      prefix += (prefix.empty() && group_path.front() != '/') ? "" : "/";
      prefix += group_path.substr(start, slash - start);
      if (!file.nameExists(prefix)) return false;
    }
    start = slash + 1;
  }
  return true;
}

void check_attribute_is_scalar(const H5::Attribute& a, const std::string& name) {
  if (a.getSpace().getSimpleExtentNpoints() != 1) throw RunError(fmt::format("attribute '{}' is not a scalar", name));
}

void collect_name(H5::H5Object&, const H5std_string name, void* names) {
  static_cast<std::vector<std::string>*>(names)->push_back(name);
}

std::vector<Hdf5Attribute> read_attributes(H5::H5Object& object) {
  std::vector<std::string> names;
  object.iterateAttrs(collect_name, nullptr, &names);  // name order
  std::vector<Hdf5Attribute> out;
  for (const std::string& name : names) {
    const H5::Attribute a = object.openAttribute(name);
    check_attribute_is_scalar(a, name);
    switch (a.getTypeClass()) {
      case H5T_STRING: {
        std::string value;
        a.read(a.getStrType(), value);
        out.push_back({name, std::move(value)});
        break;
      }
      case H5T_FLOAT:
      case H5T_INTEGER: {
        double value = 0;
        a.read(H5::PredType::NATIVE_DOUBLE, &value);
        out.push_back({name, value});
        break;
      }
      default:
        throw RunError(fmt::format("attribute '{}' is neither a number nor a string", name));
    }
  }
  return out;
}

}  // namespace

void write_hdf5(const fs::path& path, const Hdf5Content& content) {
  for (const Hdf5Dataset& d : content.datasets) check_dataset(d);
  silence_hdf5();
  replace_atomically(path, [&](const fs::path& tmp) {
    try {
      H5::H5File file(tmp.string(), H5F_ACC_EXCL);
      const H5::LinkCreatPropList lcpl = with_intermediate_groups();
      {
        H5::Group root = file.openGroup("/");
        write_attributes(root, content.attributes);
      }
      for (const Hdf5Group& g : content.groups) {
        if (!is_root(g.path) && !group_exists(file, g.path)) file.createGroup(g.path, lcpl);
        H5::Group group = file.openGroup(is_root(g.path) ? "/" : g.path);
        write_attributes(group, g.attributes);
      }
      for (const Hdf5Dataset& d : content.datasets) {
        const std::vector<hsize_t> dims(d.shape.begin(), d.shape.end());
        const H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
        H5::DataSet dataset = file.createDataSet(d.path, H5::PredType::IEEE_F64LE, space,
                                                 H5::DSetCreatPropList::DEFAULT, H5::DSetAccPropList::DEFAULT, lcpl);
        if (!d.data.empty()) dataset.write(d.data.data(), H5::PredType::NATIVE_DOUBLE);
        if (!d.unit.empty()) write_attribute(dataset, {"unit", d.unit});
        write_attributes(dataset, d.attributes);
      }
    } catch (const H5::Exception& e) {
      throw_hdf5_error(path, e);
    }
  });
}

Hdf5Dataset read_hdf5_dataset(const fs::path& path, std::string_view dataset_path) {
  silence_hdf5();
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    H5::DataSet dataset = file.openDataSet(std::string(dataset_path));
    const H5::DataSpace space = dataset.getSpace();
    const int rank = space.getSimpleExtentNdims();
    std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
    if (rank > 0) space.getSimpleExtentDims(dims.data());

    Hdf5Dataset out;
    out.path = std::string(dataset_path);
    out.shape.assign(dims.begin(), dims.end());
    out.data.resize(static_cast<std::size_t>(space.getSimpleExtentNpoints()));
    if (!out.data.empty()) dataset.read(out.data.data(), H5::PredType::NATIVE_DOUBLE);
    for (Hdf5Attribute& a : read_attributes(dataset)) {
      if (a.name == "unit" && std::holds_alternative<std::string>(a.value))
        out.unit = std::get<std::string>(std::move(a.value));
      else
        out.attributes.push_back(std::move(a));
    }
    return out;
  } catch (const H5::Exception& e) {
    throw_hdf5_error(path, e);
  } catch (const RunError& e) {
    throw RunError(fmt::format("HDF5 file '{}', dataset '{}': {}", path.string(), dataset_path, e.what()));
  }
}

std::vector<std::string> hdf5_dataset_names(const fs::path& path, std::string_view group_path) {
  silence_hdf5();
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    if (!is_root(group_path) && !group_exists(file, group_path)) return {};
    const H5::Group group = file.openGroup(is_root(group_path) ? std::string("/") : std::string(group_path));
    std::vector<std::string> names;
    for (hsize_t i = 0; i < group.getNumObjs(); ++i)
      if (group.getObjTypeByIdx(i) == H5G_DATASET) names.push_back(group.getObjnameByIdx(i));
    std::sort(names.begin(), names.end());
    return names;
  } catch (const H5::Exception& e) {
    throw_hdf5_error(path, e);
  }
}

std::vector<Hdf5Attribute> read_hdf5_attributes(const fs::path& path, std::string_view object_path) {
  silence_hdf5();
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    if (is_root(object_path)) {
      H5::Group root = file.openGroup("/");
      return read_attributes(root);
    }
    const std::string name(object_path);
    if (file.childObjType(name) == H5O_TYPE_DATASET) {
      H5::DataSet dataset = file.openDataSet(name);
      return read_attributes(dataset);
    }
    H5::Group group = file.openGroup(name);
    return read_attributes(group);
  } catch (const H5::Exception& e) {
    throw_hdf5_error(path, e);
  } catch (const RunError& e) {
    throw RunError(fmt::format("HDF5 file '{}', object '{}': {}", path.string(), object_path, e.what()));
  }
}

// ---------------------------------------------------------------------------------------------
// VTK

namespace {

// The legacy binary format is big-endian whatever the machine: build the bytes by shifting.
void put_big_endian(std::string& bytes, std::uint32_t word) {
  bytes += static_cast<char>((word >> 24) & 0xffU);
  bytes += static_cast<char>((word >> 16) & 0xffU);
  bytes += static_cast<char>((word >> 8) & 0xffU);
  bytes += static_cast<char>(word & 0xffU);
}

void put_float(std::string& bytes, double value) {
  put_big_endian(bytes, std::bit_cast<std::uint32_t>(static_cast<float>(value)));
}

void put_int32(std::string& bytes, std::int32_t value) { put_big_endian(bytes, std::bit_cast<std::uint32_t>(value)); }

// Writes count tuples of `components` values as 3-component tuples (padding with zeros) when
// `as_vectors`, else as they are. Ends with a newline, as VTK's own writers do.
void write_tuples(std::ostream& out, std::span<const double> values, std::size_t count, int components,
                  bool as_vectors) {
  const auto stride = static_cast<std::size_t>(components);
  const std::size_t width = as_vectors ? 3 : stride;
  std::string bytes;
  bytes.reserve(count * width * 4 + 1);
  for (std::size_t i = 0; i < count; ++i)
    for (std::size_t c = 0; c < width; ++c) put_float(bytes, c < stride ? values[i * stride + c] : 0.0);
  bytes += '\n';
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

void check_dimension(int dimension, const char* who) {
  if (dimension != 2 && dimension != 3)
    throw std::invalid_argument(fmt::format("{}: dimension must be 2 or 3, not {}", who, dimension));
}

void check_fields(const std::vector<VtkField>& fields, std::size_t count, const char* who) {
  for (const VtkField& f : fields) {
    if (f.name.empty() || f.name.find_first_of(" \t\r\n") != std::string::npos)
      throw std::invalid_argument(fmt::format("{}: field name '{}' must be non-empty without spaces", who, f.name));
    if (f.components < 1 || f.components > 3)
      throw std::invalid_argument(
          fmt::format("{}: field '{}' has {} components (1 to 3 allowed)", who, f.name, f.components));
    if (f.values.size() != count * static_cast<std::size_t>(f.components))
      throw std::invalid_argument(fmt::format("{}: field '{}' has {} values, expected {} x {}", who, f.name,
                                              f.values.size(), count, f.components));
  }
}

void write_fields(std::ostream& out, const char* section, const std::vector<VtkField>& fields, std::size_t count) {
  if (fields.empty() || count == 0) return;
  out << section << ' ' << count << '\n';
  for (const VtkField& f : fields) {
    if (f.components == 1)
      out << "SCALARS " << f.name << " float 1\nLOOKUP_TABLE default\n";
    else
      out << "VECTORS " << f.name << " float\n";
    write_tuples(out, f.values, count, f.components, f.components > 1);
  }
}

void write_vtk_header(std::ostream& out, std::string_view dataset) {
  out << "# vtk DataFile Version 3.0\nrheosim\nBINARY\nDATASET " << dataset << '\n';
}

}  // namespace

void write_vtk_points(const fs::path& path, std::span<const double> positions, const std::vector<VtkField>& point_data,
                      int dimension) {
  constexpr const char* who = "write_vtk_points";
  check_dimension(dimension, who);
  const auto dim = static_cast<std::size_t>(dimension);
  if (positions.size() % dim != 0)
    throw std::invalid_argument(
        fmt::format("{}: {} coordinates are not a multiple of {}", who, positions.size(), dimension));
  const std::size_t count = positions.size() / dim;
  if (2 * count > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw std::invalid_argument(fmt::format("{}: {} points exceed the format's 32-bit indices", who, count));
  check_fields(point_data, count, who);

  write_atomically(path, [&](std::ostream& out) {
    write_vtk_header(out, "POLYDATA");
    out << "POINTS " << count << " float\n";
    write_tuples(out, positions, count, dimension, true);
    if (count == 0) return;
    out << "VERTICES " << count << ' ' << 2 * count << '\n';
    std::string bytes;
    bytes.reserve(8 * count + 1);
    for (std::size_t i = 0; i < count; ++i) {
      put_int32(bytes, 1);
      put_int32(bytes, static_cast<std::int32_t>(i));
    }
    bytes += '\n';
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    write_fields(out, "POINT_DATA", point_data, count);
  });
}

void write_vtk_points(const fs::path& path, std::span<const std::array<double, 3>> positions,
                      const std::vector<VtkField>& point_data) {
  std::vector<double> flat;
  flat.reserve(3 * positions.size());
  for (const auto& p : positions) flat.insert(flat.end(), p.begin(), p.end());
  write_vtk_points(path, flat, point_data, 3);
}

void write_vtk_structured_grid(const fs::path& path, std::array<std::size_t, 3> dims, std::span<const double> points,
                               const std::vector<VtkField>& point_data, const std::vector<VtkField>& cell_data,
                               int dimension) {
  constexpr const char* who = "write_vtk_structured_grid";
  check_dimension(dimension, who);
  for (const std::size_t n : dims)
    if (n == 0) throw std::invalid_argument(fmt::format("{}: a grid dimension is 0", who));
  const std::size_t point_count = dims[0] * dims[1] * dims[2];
  const std::size_t cell_count = std::max<std::size_t>(dims[0] - 1, 1) * std::max<std::size_t>(dims[1] - 1, 1) *
                                 std::max<std::size_t>(dims[2] - 1, 1);
  if (points.size() != point_count * static_cast<std::size_t>(dimension))
    throw std::invalid_argument(fmt::format("{}: {} coordinates for {} x {} x {} points in {}D", who, points.size(),
                                            dims[0], dims[1], dims[2], dimension));
  check_fields(point_data, point_count, who);
  check_fields(cell_data, cell_count, who);

  write_atomically(path, [&](std::ostream& out) {
    write_vtk_header(out, "STRUCTURED_GRID");
    out << "DIMENSIONS " << dims[0] << ' ' << dims[1] << ' ' << dims[2] << '\n';
    out << "POINTS " << point_count << " float\n";
    write_tuples(out, points, point_count, dimension, true);
    write_fields(out, "POINT_DATA", point_data, point_count);
    write_fields(out, "CELL_DATA", cell_data, cell_count);
  });
}

namespace {

void check_times(std::span<const TimeSeriesEntry> entries, const char* who) {
  for (const TimeSeriesEntry& e : entries)
    if (!std::isfinite(e.time))
      throw std::invalid_argument(fmt::format("{}: time of '{}' is not finite", who, e.file.string()));
}

}  // namespace

void write_pvd(const fs::path& path, std::span<const TimeSeriesEntry> entries) {
  check_times(entries, "write_pvd");
  write_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
           "  <Collection>\n";
    for (const TimeSeriesEntry& e : entries)
      out << fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", e.time,
                         escape_markup(e.file.generic_string()));
    out << "  </Collection>\n</VTKFile>\n";
  });
}

void write_vtk_series(const fs::path& path, std::span<const TimeSeriesEntry> entries) {
  check_times(entries, "write_vtk_series");
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const TimeSeriesEntry& e : entries) files.push_back({{"name", e.file.generic_string()}, {"time", e.time}});
  write_json(path, nlohmann::ordered_json{{"file-series-version", "1.0"}, {"files", std::move(files)}});
}

std::string escape_markup(std::string_view s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace rheosim::core
