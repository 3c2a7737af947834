#pragma once
// Output files of a run: JSON (summary.json), CSV tables, HDF5 datasets, legacy VTK frames and
// their time-series index. Every writer is atomic: it writes a temporary file next to the
// target and renames it into place, so a crash or a full disk never leaves a half-written
// summary.json or a truncated sweep file for `--resume` to trip over.
//
// I/O failures throw RunError naming the file; misuse (mismatched sizes) throws
// std::invalid_argument. HDF5 stays private to core: no HDF5 type appears here.
#include <array>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <iosfwd>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

namespace rheosim::core {

// ---------------------------------------------------------------------------------------------
// Atomic replacement

// Writes `path` through `write`: the stream goes to a temporary file in the same directory
// (".<name>.tmp-<pid>-<counter>"), which is flushed, fsync'ed and renamed onto `path`
// (atomic on POSIX). Parent directories are created. If `write` throws, or the stream fails,
// the temporary is removed, `path` keeps its previous content, and the exception propagates.
void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

// The same for writers that need a file name rather than a stream (HDF5): `write` must create
// the file `tmp`; it is then fsync'ed and renamed onto `path`.
void replace_atomically(const std::filesystem::path& path,
                        const std::function<void(const std::filesystem::path& tmp)>& write);

// Escapes &, <, > and " for XML and HTML text and attribute values.
[[nodiscard]] std::string escape_markup(std::string_view text);

// ---------------------------------------------------------------------------------------------
// JSON

// Pretty-printed (indent 2), atomic. Doubles are written in the shortest form that reads back
// to the same bits (nlohmann's Grisu2), so values round-trip exactly. NaN and ±inf have no JSON
// form and are written as null. Invalid UTF-8 in strings is replaced rather than aborting a
// finished run at the last step.
void write_json(const std::filesystem::path& path, const nlohmann::json& value);
// Keeps the insertion order of keys (readable summary.json: points before fits).
void write_json(const std::filesystem::path& path, const nlohmann::ordered_json& value);

// Throws RunError naming the file if it cannot be opened or is not valid JSON.
[[nodiscard]] nlohmann::json read_json(const std::filesystem::path& path);

// ---------------------------------------------------------------------------------------------
// CSV

// A table of doubles with named, unit-carrying columns and optionally one leading text column
// (e.g. a model name or point label). The header reads `name [unit]`, e.g.
// `shear_rate [1/s],torque [N m]`; a column with an empty unit is written as `name`.
class CsvTable {
 public:
  struct Column {
    std::string name;  // e.g. "shear_rate"
    std::string unit;  // SI unit, e.g. "1/s"; empty for none
    bool operator==(const Column&) const = default;
  };

  CsvTable() = default;
  explicit CsvTable(std::vector<Column> numeric_columns, std::optional<Column> text_column = std::nullopt);

  // Appends a row; values.size() must equal numeric_columns().size(). `text` is the text
  // column's cell and must be empty when the table has no text column.
  void add_row(std::span<const double> values, std::string text = {});
  void add_row(std::initializer_list<double> values, std::string text = {});

  [[nodiscard]] const std::vector<Column>& numeric_columns() const { return columns_; }
  [[nodiscard]] const std::optional<Column>& text_column() const { return text_column_; }
  [[nodiscard]] std::size_t row_count() const { return texts_.size(); }
  [[nodiscard]] std::span<const double> row(std::size_t i) const;
  [[nodiscard]] const std::string& text(std::size_t i) const { return texts_.at(i); }
  // All values of the numeric column named `name`; throws std::out_of_range if unknown.
  [[nodiscard]] std::vector<double> column(std::string_view name) const;

  bool operator==(const CsvTable&) const = default;

 private:
  std::vector<Column> columns_;
  std::optional<Column> text_column_;
  std::vector<double> values_;      // row-major, row_count() x columns_.size()
  std::vector<std::string> texts_;  // one per row (empty strings without a text column)
};

// Atomic. Numbers use the shortest form that reads back exactly (std::to_chars), so a CSV
// round trip is bit-exact; NaN and infinities are written as nan, inf, -inf. Text cells and
// headers are quoted as RFC 4180 requires (commas, quotes, line breaks).
void write_csv(const std::filesystem::path& path, const CsvTable& table);
// Reads a file written by write_csv. With `first_column_is_text` the first column becomes the
// text column; every other cell must be a number.
[[nodiscard]] CsvTable read_csv(const std::filesystem::path& path, bool first_column_is_text = false);

// ---------------------------------------------------------------------------------------------
// HDF5

struct Hdf5Attribute {
  std::string name;
  std::variant<double, std::string> value;  // strings are variable-length UTF-8
  bool operator==(const Hdf5Attribute&) const = default;
};

// A double dataset at `path` ("sweep/torque"; groups on the way are created), row-major.
struct Hdf5Dataset {
  std::string path;
  std::vector<std::size_t> shape;  // {n} or {rows, cols} (any rank >= 1 is accepted)
  std::vector<double> data;        // product(shape) values
  std::string unit;                // stored as the string attribute "unit" when not empty
  std::vector<Hdf5Attribute> attributes;
  bool operator==(const Hdf5Dataset&) const = default;
};

struct Hdf5Group {
  std::string path;  // e.g. "sweep"; "/" is the root group
  std::vector<Hdf5Attribute> attributes;
};

// Everything one HDF5 file holds; write_hdf5 replaces the whole file.
struct Hdf5Content {
  std::vector<Hdf5Attribute> attributes;  // on the root group (file attributes)
  std::vector<Hdf5Group> groups;          // groups with attributes (or empty groups)
  std::vector<Hdf5Dataset> datasets;
};

// Atomic (via replace_atomically). Throws RunError on failure, std::invalid_argument when a
// dataset's shape does not match its data.
void write_hdf5(const std::filesystem::path& path, const Hdf5Content& content);

// Reads one dataset back as doubles with its attributes; the "unit" attribute goes to `unit`,
// the others come back in name order (HDF5's default index).
[[nodiscard]] Hdf5Dataset read_hdf5_dataset(const std::filesystem::path& path, std::string_view dataset_path);
// The names of the datasets directly in `group_path` ("run"), in name order; none when the group
// does not exist.
[[nodiscard]] std::vector<std::string> hdf5_dataset_names(const std::filesystem::path& path,
                                                          std::string_view group_path);
// Attributes of a group or dataset ("/" for the file attributes), in name order.
[[nodiscard]] std::vector<Hdf5Attribute> read_hdf5_attributes(const std::filesystem::path& path,
                                                              std::string_view object_path = "/");

// ---------------------------------------------------------------------------------------------
// VTK (legacy binary format, version 3.0: big-endian, as the format requires)
//
// Values are written as 32-bit floats: VTK files are for looking at; exact data goes to HDF5.

// A named per-point or per-cell array. A view: `values` must outlive the call.
struct VtkField {
  std::string name;                // no whitespace (the legacy format is whitespace-separated)
  int components = 1;              // 1: SCALARS; 2 or 3: VECTORS (2 is padded with z = 0)
  std::span<const double> values;  // count * components, interleaved (x0 y0 z0 x1 ...)
};

// Particles or meshless nodes as POLYDATA with one VERTEX per point. `positions` holds
// dimension * N coordinates (dimension 2 pads z = 0).
void write_vtk_points(const std::filesystem::path& path, std::span<const double> positions,
                      const std::vector<VtkField>& point_data = {}, int dimension = 3);
void write_vtk_points(const std::filesystem::path& path, std::span<const std::array<double, 3>> positions,
                      const std::vector<VtkField>& point_data = {});

// A curvilinear grid (STRUCTURED_GRID) with dims = {nx, ny, nz} points, x varying fastest.
// `points` holds dimension * nx*ny*nz coordinates. Cell data has one value per cell,
// max(nx-1,1) * max(ny-1,1) * max(nz-1,1) cells.
void write_vtk_structured_grid(const std::filesystem::path& path, std::array<std::size_t, 3> dims,
                               std::span<const double> points, const std::vector<VtkField>& point_data = {},
                               const std::vector<VtkField>& cell_data = {}, int dimension = 3);

// One frame of a time series: `file` relative to the index file's directory.
struct TimeSeriesEntry {
  double time = 0;  // s
  std::filesystem::path file;
};

// ParaView's XML collection (.pvd). Note: ParaView's PVD reader expects XML VTK pieces
// (.vtp/.vts/.vtu); for legacy .vtk frames use write_vtk_series.
void write_pvd(const std::filesystem::path& path, std::span<const TimeSeriesEntry> entries);
// ParaView's file-series index ("frames.vtk.series", JSON), which works with legacy .vtk frames.
// Name it after the frames plus ".series", e.g. "particles.vtk.series".
void write_vtk_series(const std::filesystem::path& path, std::span<const TimeSeriesEntry> entries);

}  // namespace rheosim::core
