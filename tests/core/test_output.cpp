// Output writers: exact round trips (JSON, CSV, HDF5), VTK byte layout, atomic replacement.
#include "rheosim/core/output.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "rheosim/core/error.hpp"

namespace rheosim::core {
namespace {

namespace fs = std::filesystem;

class OutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("rheosim_test_output_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  // Every file name in dir_ (to catch leftover temporaries).
  [[nodiscard]] std::vector<std::string> files() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  fs::path dir_;
};

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& path, const std::string& text) {
  write_atomically(path, [&](std::ostream& out) { out << text; });
}

// Doubles spread over the whole range, including subnormals and awkward decimals.
std::vector<double> awkward_doubles() {
  std::vector<double> v = {0.1,
                           1.0 / 3.0,
                           -2.0 / 3.0,
                           0.1 + 0.2,
                           M_PI,
                           1e-300,
                           std::numeric_limits<double>::denorm_min(),
                           std::numeric_limits<double>::min(),
                           std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::lowest(),
                           std::numeric_limits<double>::epsilon(),
                           123456789.123456789,
                           -0.0,
                           0.0};
  std::mt19937_64 random(12345);
  while (v.size() < 500) {
    const double x = std::bit_cast<double>(random());
    if (std::isfinite(x)) v.push_back(x);
  }
  return v;
}

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// ---------------------------------------------------------------------------------------------
// Atomic replacement

TEST_F(OutputTest, WriteCreatesParentDirectories) {
  const fs::path path = dir_ / "a" / "b" / "c.txt";
  write_text(path, "hello\n");
  EXPECT_EQ(slurp(path), "hello\n");
}

TEST_F(OutputTest, WriteReplacesAnExistingFile) {
  const fs::path path = dir_ / "f.txt";
  write_text(path, "a first, rather long content\n");
  write_text(path, "x");
  EXPECT_EQ(slurp(path), "x");
  EXPECT_EQ(files(), std::vector<std::string>{"f.txt"});
}

TEST_F(OutputTest, ThrowingWriterKeepsOldContentAndLeavesNoTemporary) {
  const fs::path path = dir_ / "summary.json";
  write_text(path, "old content\n");
  const auto failing = [](std::ostream& out) {
    out << "half of the new con";
    out.flush();  // the partial content really reached the temporary file
    throw std::runtime_error("writer failed midway");
  };
  EXPECT_THROW(write_atomically(path, failing), std::runtime_error);
  EXPECT_EQ(slurp(path), "old content\n");
  EXPECT_EQ(files(), std::vector<std::string>{"summary.json"});
}

TEST_F(OutputTest, ThrowingFileWriterKeepsOldContentAndLeavesNoTemporary) {
  const fs::path path = dir_ / "sweep.h5";
  write_text(path, "old");
  fs::path seen_tmp;
  const auto failing = [&](const fs::path& tmp) {
    seen_tmp = tmp;
    std::ofstream(tmp) << "partial";
    throw std::runtime_error("HDF5 writer failed midway");
  };
  EXPECT_THROW(replace_atomically(path, failing), std::runtime_error);
  EXPECT_EQ(slurp(path), "old");
  EXPECT_EQ(seen_tmp.parent_path(), path.parent_path());  // same directory: rename stays atomic
  EXPECT_NE(seen_tmp.filename().string().find(std::to_string(::getpid())), std::string::npos);
  EXPECT_EQ(files(), std::vector<std::string>{"sweep.h5"});
}

TEST_F(OutputTest, FileWriterThatCreatesNothingIsAnError) {
  EXPECT_THROW(replace_atomically(dir_ / "x.h5", [](const fs::path&) {}), RunError);
  EXPECT_TRUE(files().empty());
}

TEST_F(OutputTest, UnwritableDirectoryIsARunErrorNamingTheFile) {
  write_text(dir_ / "plain_file", "x");
  try {
    write_text(dir_ / "plain_file" / "summary.json", "y");
    FAIL() << "expected RunError";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("plain_file"), std::string::npos) << e.what();
  }
}

TEST_F(OutputTest, ConcurrentWritersNeverMixContentOrLeaveTemporaries) {
  const fs::path path = dir_ / "shared.txt";
  const auto content = [](int writer) { return std::string(10000, static_cast<char>('a' + writer)); };
  std::vector<std::thread> threads;
  for (int w = 0; w < 4; ++w)
    threads.emplace_back([&, w] {
      for (int i = 0; i < 10; ++i) write_text(path, content(w));
    });
  for (auto& t : threads) t.join();
  const std::string final_text = slurp(path);
  ASSERT_EQ(final_text.size(), 10000U);
  EXPECT_EQ(final_text, content(final_text.front() - 'a'));
  EXPECT_EQ(files(), std::vector<std::string>{"shared.txt"});
}

// ---------------------------------------------------------------------------------------------
// JSON

TEST_F(OutputTest, JsonRoundTripKeepsDoublesExact) {
  const std::vector<double> values = awkward_doubles();
  nlohmann::json doc;
  doc["values"] = values;
  doc["point"] = {{"shear_rate", 0.1}, {"torque", 1.0 / 3.0}, {"label", "phi = 0.3, \"dense\""}};
  const fs::path path = dir_ / "summary.json";
  write_json(path, doc);

  const nlohmann::json back = read_json(path);
  EXPECT_EQ(back, doc);
  const auto read_values = back.at("values").get<std::vector<double>>();
  ASSERT_EQ(read_values.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    EXPECT_TRUE(same_bits(read_values[i], values[i])) << i << ": " << values[i] << " read back as " << read_values[i];
  EXPECT_EQ(slurp(path).back(), '\n');
}

TEST_F(OutputTest, OrderedJsonKeepsKeyOrder) {
  nlohmann::ordered_json doc;
  doc["points"] = nlohmann::ordered_json::array();
  doc["fits"] = 1;
  const fs::path path = dir_ / "summary.json";
  write_json(path, doc);
  const std::string text = slurp(path);
  EXPECT_LT(text.find("points"), text.find("fits"));
}

TEST_F(OutputTest, ReadJsonErrorsNameTheFile) {
  const fs::path broken = dir_ / "broken.json";
  write_text(broken, "{\"a\": [1, 2,\n");
  try {
    static_cast<void>(read_json(broken));
    FAIL() << "expected RunError";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.json"), std::string::npos) << e.what();
  }
  try {
    static_cast<void>(read_json(dir_ / "missing.json"));
    FAIL() << "expected RunError";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.json"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// CSV

TEST_F(OutputTest, CsvHeaderCarriesUnits) {
  CsvTable table({{"shear_rate", "1/s"}, {"torque", "N m"}, {"count", ""}}, CsvTable::Column{"model", ""});
  table.add_row({10.0, 0.5, 3.0}, "power_law");
  const fs::path path = dir_ / "flow_curve.csv";
  write_csv(path, table);
  EXPECT_EQ(slurp(path), "model,shear_rate [1/s],torque [N m],count\npower_law,10,0.5,3\n");
}

TEST_F(OutputTest, CsvRoundTripIsExact) {
  const std::vector<double> values = awkward_doubles();
  CsvTable table({{"shear_rate", "1/s"}, {"torque", "N m"}}, CsvTable::Column{"label", ""});
  const std::vector<std::string> labels = {"plain", "with, comma", "with \"quotes\"", "two\nlines", ""};
  for (std::size_t i = 0; i + 1 < values.size(); i += 2)
    table.add_row({values[i], values[i + 1]}, labels[(i / 2) % labels.size()]);
  table.add_row({std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}, "inf");

  const fs::path path = dir_ / "table.csv";
  write_csv(path, table);
  const CsvTable back = read_csv(path, /*first_column_is_text=*/true);
  EXPECT_EQ(back, table);
  ASSERT_EQ(back.row_count(), table.row_count());
  for (std::size_t i = 0; i < table.row_count(); ++i)
    for (std::size_t j = 0; j < 2; ++j) EXPECT_TRUE(same_bits(back.row(i)[j], table.row(i)[j])) << i << "," << j;
}

TEST_F(OutputTest, CsvWithoutTextColumnKeepsNan) {
  CsvTable table(std::vector<CsvTable::Column>{{"torque_analytic", "N m"}});
  table.add_row({std::nan("")});
  table.add_row({2.5});
  const fs::path path = dir_ / "t.csv";
  write_csv(path, table);
  const CsvTable back = read_csv(path);
  ASSERT_EQ(back.row_count(), 2U);
  EXPECT_TRUE(std::isnan(back.row(0)[0]));
  EXPECT_EQ(back.column("torque_analytic")[1], 2.5);
  EXPECT_EQ(back.numeric_columns(), table.numeric_columns());
}

TEST_F(OutputTest, CsvTableRejectsMismatchedRows) {
  CsvTable table({{"a", ""}, {"b", ""}});
  EXPECT_THROW(table.add_row({1.0}), std::invalid_argument);
  EXPECT_THROW(table.add_row({1.0, 2.0}, "text without a text column"), std::invalid_argument);
}

TEST_F(OutputTest, ReadCsvReportsFileAndLine) {
  const fs::path path = dir_ / "bad.csv";
  write_text(path, "a [m],b\n1,2\n3,oops\n");
  try {
    static_cast<void>(read_csv(path));
    FAIL() << "expected RunError";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:3"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// HDF5

std::vector<Hdf5Attribute> sorted_by_name(std::vector<Hdf5Attribute> attributes) {
  std::sort(attributes.begin(), attributes.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return attributes;
}

TEST_F(OutputTest, Hdf5RoundTripIsExact) {
  const std::vector<double> values = awkward_doubles();
  Hdf5Content content;
  content.attributes = {
      {"rheosim_version", std::string("0.1.0")}, {"input_hash", std::string("ab12")}, {"wall_time", 12.5}};
  content.groups = {{"sweep", {{"volume_fraction", 0.3}, {"note", std::string("φ sweep, γ̇ in 1/s")}}}};
  content.datasets.push_back({"sweep/shear_rate", {3}, {10.0, 50.0, 100.0}, "1/s", {}});
  content.datasets.push_back({"sweep/torque",
                              {2, 3},
                              {0.1, 1.0 / 3.0, 1e-300, -0.0, 7.0, M_PI},
                              "N m",
                              {{"steady", 1.0}, {"method", std::string("strain window")}}});
  content.datasets.push_back({"raw/values", {values.size()}, values, "", {}});
  content.datasets.push_back({"empty", {0}, {}, "", {}});
  const fs::path path = dir_ / "sweep.h5";
  write_hdf5(path, content);

  EXPECT_EQ(sorted_by_name(read_hdf5_attributes(path)), sorted_by_name(content.attributes));
  EXPECT_EQ(sorted_by_name(read_hdf5_attributes(path, "sweep")), sorted_by_name(content.groups[0].attributes));
  for (const Hdf5Dataset& d : content.datasets) {
    Hdf5Dataset back = read_hdf5_dataset(path, d.path);
    EXPECT_EQ(back.shape, d.shape) << d.path;
    EXPECT_EQ(back.unit, d.unit) << d.path;
    EXPECT_EQ(back.attributes, sorted_by_name(d.attributes)) << d.path;
    ASSERT_EQ(back.data.size(), d.data.size()) << d.path;
    for (std::size_t i = 0; i < d.data.size(); ++i) EXPECT_TRUE(same_bits(back.data[i], d.data[i])) << d.path << i;
  }
  const auto unit_attribute = read_hdf5_attributes(path, "sweep/torque");
  EXPECT_NE(std::find(unit_attribute.begin(), unit_attribute.end(), Hdf5Attribute{"unit", std::string("N m")}),
            unit_attribute.end());
  EXPECT_EQ(files(), std::vector<std::string>{"sweep.h5"});
}

TEST_F(OutputTest, Hdf5ShapeMismatchIsRejectedBeforeWriting) {
  Hdf5Content content;
  content.datasets.push_back({"x", {2, 2}, {1.0, 2.0, 3.0}, "", {}});
  EXPECT_THROW(write_hdf5(dir_ / "x.h5", content), std::invalid_argument);
  EXPECT_TRUE(files().empty());
}

TEST_F(OutputTest, Hdf5FailureMidwayKeepsThePreviousFile) {
  const fs::path path = dir_ / "sweep.h5";
  Hdf5Content good;
  good.datasets.push_back({"torque", {1}, {1.5}, "N m", {}});
  write_hdf5(path, good);
  Hdf5Content duplicate;  // the second dataset of the same name fails inside HDF5
  duplicate.datasets.push_back({"torque", {1}, {2.5}, "N m", {}});
  duplicate.datasets.push_back({"torque", {1}, {3.5}, "N m", {}});
  try {
    write_hdf5(path, duplicate);
    FAIL() << "expected RunError";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("sweep.h5"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_hdf5_dataset(path, "torque").data, std::vector<double>{1.5});
  EXPECT_EQ(files(), std::vector<std::string>{"sweep.h5"});
}

TEST_F(OutputTest, Hdf5MissingDatasetIsARunError) {
  Hdf5Content content;
  content.datasets.push_back({"a", {1}, {1.0}, "", {}});
  write_hdf5(dir_ / "f.h5", content);
  EXPECT_THROW(static_cast<void>(read_hdf5_dataset(dir_ / "f.h5", "b")), RunError);
  EXPECT_THROW(static_cast<void>(read_hdf5_dataset(dir_ / "missing.h5", "a")), RunError);
}

// ---------------------------------------------------------------------------------------------
// VTK

// Reads a legacy VTK file: text lines and big-endian binary blocks in order.
class VtkReader {
 public:
  explicit VtkReader(std::string bytes) : bytes_(std::move(bytes)) {}
  std::string line() {
    const auto end = bytes_.find('\n', pos_);
    if (end == std::string::npos) throw std::runtime_error("no more lines");
    std::string out = bytes_.substr(pos_, end - pos_);
    pos_ = end + 1;
    return out;
  }
  std::vector<std::uint32_t> words(std::size_t count) {
    if (pos_ + 4 * count + 1 > bytes_.size()) throw std::runtime_error("binary block too short");
    std::vector<std::uint32_t> out(count);
    for (auto& w : out) {
      for (int b = 0; b < 4; ++b) w = (w << 8) | static_cast<unsigned char>(bytes_[pos_++]);
    }
    if (bytes_[pos_++] != '\n') throw std::runtime_error("binary block not followed by a newline");
    return out;
  }
  std::vector<float> floats(std::size_t count) {
    std::vector<float> out;
    for (const auto w : words(count)) out.push_back(std::bit_cast<float>(w));
    return out;
  }
  std::vector<std::int32_t> ints(std::size_t count) {
    std::vector<std::int32_t> out;
    for (const auto w : words(count)) out.push_back(std::bit_cast<std::int32_t>(w));
    return out;
  }
  [[nodiscard]] bool at_end() const { return pos_ == bytes_.size(); }

 private:
  std::string bytes_;
  std::size_t pos_ = 0;
};

std::vector<float> as_floats(const std::vector<double>& v) { return {v.begin(), v.end()}; }

TEST_F(OutputTest, VtkPointsLayoutIsLegacyBigEndian) {
  const std::vector<double> positions = {0.0, 0.1, 0.2, 1.0, 1.1, 1.2, -2.0, 2.1, 1e-6};
  const std::vector<double> radius = {1e-4, 2e-4, 3e-4};
  const std::vector<double> velocity = {1, 2, 3, 4, 5, 6};  // 2D vectors, padded with z = 0
  const fs::path path = dir_ / "frames" / "particles_0001.vtk";
  write_vtk_points(path, positions, {{"radius", 1, radius}, {"velocity", 2, velocity}});

  const std::string bytes = slurp(path);
  const std::string header = "# vtk DataFile Version 3.0\nrheosim\nBINARY\nDATASET POLYDATA\nPOINTS 3 float\n";
  const std::size_t expected_size = header.size() + 36 + 1 + std::string("VERTICES 3 6\n").size() + 24 + 1 +
                                    std::string("POINT_DATA 3\n").size() +
                                    std::string("SCALARS radius float 1\nLOOKUP_TABLE default\n").size() + 12 + 1 +
                                    std::string("VECTORS velocity float\n").size() + 36 + 1;
  EXPECT_EQ(bytes.size(), expected_size);

  VtkReader vtk(bytes);
  EXPECT_EQ(vtk.line(), "# vtk DataFile Version 3.0");
  EXPECT_EQ(vtk.line(), "rheosim");
  EXPECT_EQ(vtk.line(), "BINARY");
  EXPECT_EQ(vtk.line(), "DATASET POLYDATA");
  EXPECT_EQ(vtk.line(), "POINTS 3 float");
  EXPECT_EQ(vtk.floats(9), as_floats(positions));
  EXPECT_EQ(vtk.line(), "VERTICES 3 6");
  EXPECT_EQ(vtk.ints(6), (std::vector<std::int32_t>{1, 0, 1, 1, 1, 2}));
  EXPECT_EQ(vtk.line(), "POINT_DATA 3");
  EXPECT_EQ(vtk.line(), "SCALARS radius float 1");
  EXPECT_EQ(vtk.line(), "LOOKUP_TABLE default");
  EXPECT_EQ(vtk.floats(3), as_floats(radius));
  EXPECT_EQ(vtk.line(), "VECTORS velocity float");
  EXPECT_EQ(vtk.floats(9), (std::vector<float>{1, 2, 0, 3, 4, 0, 5, 6, 0}));
  EXPECT_TRUE(vtk.at_end());

  // The very first coordinate after the header is 0.0f, the second 0.1f in big-endian order.
  const float first = 0.1F;
  const auto bits = std::bit_cast<std::uint32_t>(first);
  EXPECT_EQ(static_cast<unsigned char>(bytes[header.size() + 4]), bits >> 24);
}

TEST_F(OutputTest, VtkPointsIn2DArePaddedAndArraysOfPointsWork) {
  const std::vector<double> xy = {1, 2, 3, 4};
  write_vtk_points(dir_ / "a.vtk", xy, {}, 2);
  const std::vector<std::array<double, 3>> xyz = {{1, 2, 0}, {3, 4, 0}};
  write_vtk_points(dir_ / "b.vtk", std::span<const std::array<double, 3>>(xyz));
  EXPECT_EQ(slurp(dir_ / "a.vtk"), slurp(dir_ / "b.vtk"));
}

TEST_F(OutputTest, VtkRejectsMismatchedFields) {
  const std::vector<double> positions = {0, 0, 0, 1, 1, 1};
  const std::vector<double> wrong = {1, 2, 3};
  EXPECT_THROW(write_vtk_points(dir_ / "x.vtk", positions, {{"r", 1, wrong}}), std::invalid_argument);
  EXPECT_THROW(write_vtk_points(dir_ / "x.vtk", positions, {{"bad name", 3, wrong}}), std::invalid_argument);
  EXPECT_TRUE(files().empty());
}

TEST_F(OutputTest, VtkStructuredGridLayout) {
  // 3 x 2 x 1 points in the plane z = 0.5: 2 x 1 x 1 cells.
  std::vector<double> points;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) points.insert(points.end(), {0.5 * i, 0.25 * j, 0.5});
  const std::vector<double> pressure = {1, 2, 3, 4, 5, 6};
  const std::vector<double> viscosity = {0.25, 0.125};
  const fs::path path = dir_ / "grid.vtk";
  write_vtk_structured_grid(path, {3, 2, 1}, points, {{"pressure", 1, pressure}}, {{"viscosity", 1, viscosity}});

  VtkReader vtk(slurp(path));
  EXPECT_EQ(vtk.line(), "# vtk DataFile Version 3.0");
  EXPECT_EQ(vtk.line(), "rheosim");
  EXPECT_EQ(vtk.line(), "BINARY");
  EXPECT_EQ(vtk.line(), "DATASET STRUCTURED_GRID");
  EXPECT_EQ(vtk.line(), "DIMENSIONS 3 2 1");
  EXPECT_EQ(vtk.line(), "POINTS 6 float");
  EXPECT_EQ(vtk.floats(18), as_floats(points));
  EXPECT_EQ(vtk.line(), "POINT_DATA 6");
  EXPECT_EQ(vtk.line(), "SCALARS pressure float 1");
  EXPECT_EQ(vtk.line(), "LOOKUP_TABLE default");
  EXPECT_EQ(vtk.floats(6), as_floats(pressure));
  EXPECT_EQ(vtk.line(), "CELL_DATA 2");
  EXPECT_EQ(vtk.line(), "SCALARS viscosity float 1");
  EXPECT_EQ(vtk.line(), "LOOKUP_TABLE default");
  EXPECT_EQ(vtk.floats(2), as_floats(viscosity));
  EXPECT_TRUE(vtk.at_end());

  EXPECT_THROW(write_vtk_structured_grid(path, {3, 3, 1}, points), std::invalid_argument);
}

TEST_F(OutputTest, TimeSeriesIndexes) {
  const std::vector<TimeSeriesEntry> entries = {{0.0, "frames/p_0000.vtk"}, {0.1, "frames/p_0001.vtk"}};
  write_pvd(dir_ / "particles.pvd", entries);
  const std::string pvd = slurp(dir_ / "particles.pvd");
  EXPECT_EQ(pvd.rfind("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\"", 0), 0U) << pvd;
  EXPECT_NE(pvd.find("<DataSet timestep=\"0.1\" group=\"\" part=\"0\" file=\"frames/p_0001.vtk\"/>"), std::string::npos)
      << pvd;
  EXPECT_NE(pvd.find("</Collection>\n</VTKFile>\n"), std::string::npos);

  write_vtk_series(dir_ / "particles.vtk.series", entries);
  const nlohmann::json series = read_json(dir_ / "particles.vtk.series");
  EXPECT_EQ(series.at("file-series-version"), "1.0");
  ASSERT_EQ(series.at("files").size(), 2U);
  EXPECT_EQ(series.at("files")[1].at("name"), "frames/p_0001.vtk");
  EXPECT_EQ(series.at("files")[1].at("time").get<double>(), 0.1);
}

}  // namespace
}  // namespace rheosim::core
