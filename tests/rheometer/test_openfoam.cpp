// OpenFOAM export: files, O-grid topology, kinematic units, errors; and, when
// Debian's OpenFOAM v1912 is installed, blockMesh + checkMesh (and one short simpleFoam run).
// The OpenFoamValidation.* tests run external programs; they skip when /usr/bin/blockMesh is
// missing. (They share this file's ctest label; filter them with -R OpenFoamValidation.)
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>

#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/openfoam.hpp"
#include "rheosim/rheometer/plate.hpp"

namespace rheosim::rheometer {
namespace {

namespace fs = std::filesystem;
using core::openfoam_transport;
using core::OpenFoamTransport;

Case rheometer_case(const std::string& rheology, double density = 1000.0) {
  return parse_case(
      "kind: rheometer\n"
      "geometry: {type: parallel_plate, radius: 0.015, gap: 0.0005}\n"
      "fluid:\n  density: " +
          std::to_string(density) + "\n  rheology: " + rheology + "\nshear_rates: [1, 10, 50, 100]\n",
      "plate.yaml");
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A fresh directory under the system temp dir, removed at the end of the test.
class TempDir {
 public:
  explicit TempDir(const std::string& tag)
      : path_(fs::temp_directory_path() / ("rheosim-openfoam-" + tag + "-" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// The text between "<keyword>\n(" and the matching top-level ");".
std::string list_body(const std::string& dict, const std::string& keyword) {
  const auto start = dict.find("\n" + keyword + "\n(");
  EXPECT_NE(start, std::string::npos) << keyword;
  if (start == std::string::npos) return {};
  const auto open = dict.find('(', start);
  const auto close = dict.find("\n);", open);
  return dict.substr(open + 1, close - open - 1);
}

std::size_t count(const std::string& text, const std::regex& re) {
  return static_cast<std::size_t>(
      std::distance(std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator()));
}

OpenFoamExportOptions m1_options() {
  OpenFoamExportOptions options;
  options.mesh = OpenFoamMesh::m1();
  return options;
}

std::map<std::string, double> coeffs(const OpenFoamTransport& t) { return {t.coeffs.begin(), t.coeffs.end()}; }

TEST(OpenFoamExport, MeshPresetsFollowCd) {
  EXPECT_EQ(OpenFoamMesh::preset("M1"), (OpenFoamMesh{15, 30, 4}));
  EXPECT_EQ(OpenFoamMesh::preset("m2"), (OpenFoamMesh{30, 60, 8}));
  EXPECT_EQ(OpenFoamMesh::preset("M3"), (OpenFoamMesh{60, 120, 16}));
  EXPECT_EQ(OpenFoamExportOptions{}.mesh, OpenFoamMesh::m2());
  EXPECT_EQ(OpenFoamMesh::m1().cell_count(), (30 * 30 + 4 * 15 * 30) * 4);
  EXPECT_EQ(OpenFoamMesh::m2().cell_count(), 86400);
  EXPECT_EQ(OpenFoamMesh::m3().cell_count(), 691200);
  EXPECT_THROW((void)OpenFoamMesh::preset("M4"), core::ConfigError);
}

TEST(OpenFoamExport, WritesEveryFileOfTheCase) {
  TempDir dir("files");
  const auto c = rheometer_case("{model: power_law, consistency: 1.0e-3, index: 0.6}");
  const auto result = export_openfoam(c, 50.0, dir.path(), {});
  const std::vector<std::string> expected = {"system/blockMeshDict",
                                             "system/controlDict",
                                             "system/fvSchemes",
                                             "system/fvSolution",
                                             "constant/transportProperties",
                                             "constant/turbulenceProperties",
                                             "0/U",
                                             "0/p",
                                             "README",
                                             "rheosim.json"};
  ASSERT_EQ(result.files.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(result.files[i], fs::path(expected[i]));
    EXPECT_TRUE(fs::is_regular_file(dir.path() / expected[i])) << expected[i];
    EXPECT_GT(fs::file_size(dir.path() / expected[i]), 0u) << expected[i];
  }
  // Atomic writes leave no temporaries behind.
  for (const auto& e : fs::recursive_directory_iterator(dir.path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();

  EXPECT_EQ(result.cells, 86400);
  EXPECT_EQ(result.transport.model, "powerLaw");
  EXPECT_DOUBLE_EQ(result.angular_velocity, 50.0 * 0.0005 / 0.015);
  const ParallelPlate plate{0.015, 0.0005};
  ASSERT_TRUE(result.closed_form_torque.has_value());
  EXPECT_DOUBLE_EQ(*result.closed_form_torque, power_law_torque(plate, 1e-3, 0.6, 50.0));
  EXPECT_NEAR(result.gap_reynolds_number,
              1000 * result.angular_velocity * 0.0005 * 0.0005 / (1e-3 * std::pow(50.0, -0.4)), 1e-12);

  // Boundary conditions, the forces function object and the README's command sequence.
  const std::string u = read(dir.path() / "0/U");
  EXPECT_NE(u.find("rotatingWallVelocity"), std::string::npos);
  EXPECT_NE(u.find("axis            (0 0 1);"), std::string::npos);
  const std::smatch m = [&] {
    std::smatch sm;
    std::regex_search(u, sm, std::regex(R"(omega\s+([-0-9.eE+]+);)"));
    return sm;
  }();
  ASSERT_EQ(m.size(), 2u);
  EXPECT_DOUBLE_EQ(std::stod(m[1].str()), 50.0 * 0.0005 / 0.015);
  EXPECT_NE(u.find("type            noSlip;"), std::string::npos);
  // Shear-free rim: partialSlip with one negative valueFraction −d/(R − d) per rim face.
  EXPECT_EQ(u.find("type            slip;"), std::string::npos);
  EXPECT_NE(u.find("type            partialSlip;"), std::string::npos);
  const auto list_at = u.find("valueFraction   nonuniform List<scalar> 1920\n(");
  ASSERT_NE(list_at, std::string::npos);  // 4 blocks × 60 × 8 faces on M2
  {
    std::istringstream values(u.substr(u.find('(', list_at) + 1));
    const double R = 0.015, s = 0.0075;
    for (int i = 0; i < 1920; ++i) {
      double f = 0;
      ASSERT_TRUE(values >> f) << i;
      // d lies between half a rim cell at the block corners and at the block middles.
      const double d = -f * R / (1 - f);
      EXPECT_GT(d, 0.95 * (R - s * std::sqrt(2.0)) / 60) << i;
      EXPECT_LT(d, 1.01 * (R - s) / 60) << i;
    }
  }
  const std::string control = read(dir.path() / "system/controlDict");
  EXPECT_NE(control.find("application     simpleFoam;"), std::string::npos);
  EXPECT_NE(control.find("type            forces;"), std::string::npos);
  EXPECT_NE(control.find("patches         (top);"), std::string::npos);
  EXPECT_NE(control.find("rhoInf          1000;"), std::string::npos);
  EXPECT_NE(control.find("CofR            (0 0 0);"), std::string::npos);
  EXPECT_NE(read(dir.path() / "system/fvSolution").find("residualControl"), std::string::npos);
  EXPECT_NE(read(dir.path() / "constant/turbulenceProperties").find("simulationType  laminar;"), std::string::npos);
  const std::string readme = read(dir.path() / "README");
  EXPECT_NE(readme.find("blockMesh"), std::string::npos);
  EXPECT_NE(readme.find("simpleFoam"), std::string::npos);
  EXPECT_NE(readme.find("WM_PROJECT_DIR=/usr/share/openfoam"), std::string::npos);

  const auto info = core::read_json(dir.path() / "rheosim.json");
  EXPECT_DOUBLE_EQ(info.at("shear_rate").get<double>(), 50.0);
  EXPECT_DOUBLE_EQ(info.at("torque_analytic").get<double>(), *result.closed_form_torque);
  EXPECT_EQ(info.at("openfoam_transport").at("model").get<std::string>(), "powerLaw");
  EXPECT_EQ(info.at("torque_file").get<std::string>(), "postProcessing/forces/0/moment.dat");
}

TEST(OpenFoamExport, BlockMeshDictIsAFiveBlockOGrid) {
  const core::PlateGeometry g{0.015, 0.0005};
  const OpenFoamMesh mesh{15, 30, 4};
  const std::string dict = openfoam_block_mesh_dict(g, mesh);

  const std::string vertices = list_body(dict, "vertices");
  const std::regex point(R"(\(\s*([-0-9.eE+]+)\s+([-0-9.eE+]+)\s+([-0-9.eE+]+)\s*\))");
  ASSERT_EQ(count(vertices, point), 16u);
  int on_rim = 0, on_top = 0;
  for (auto it = std::sregex_iterator(vertices.begin(), vertices.end(), point); it != std::sregex_iterator(); ++it) {
    const double x = std::stod((*it)[1]), y = std::stod((*it)[2]), z = std::stod((*it)[3]);
    const double r = std::hypot(x, y);
    if (std::abs(r - 0.015) < 1e-12)
      ++on_rim;
    else
      EXPECT_NEAR(r, 0.0075 * std::sqrt(2.0), 1e-12);  // core corners at s = R/2
    if (z == 0.0005)
      ++on_top;
    else
      EXPECT_EQ(z, 0.0);
  }
  EXPECT_EQ(on_rim, 8);
  EXPECT_EQ(on_top, 8);

  const std::string blocks = list_body(dict, "blocks");
  EXPECT_EQ(count(blocks, std::regex(R"(hex \()")), 5u);
  EXPECT_EQ(count(blocks, std::regex(R"(\(30 30 4\) simpleGrading)")), 1u);  // core
  EXPECT_EQ(count(blocks, std::regex(R"(\(15 30 4\) simpleGrading)")), 4u);  // outer blocks

  const std::string edges = list_body(dict, "edges");
  EXPECT_EQ(count(edges, std::regex(R"(arc \d+ \d+ \()")), 8u);
  // Every arc's interpolation point lies on r = R.
  for (auto it = std::sregex_iterator(edges.begin(), edges.end(), point); it != std::sregex_iterator(); ++it)
    EXPECT_NEAR(std::hypot(std::stod((*it)[1]), std::stod((*it)[2])), 0.015, 1e-15);

  const std::string boundary = list_body(dict, "boundary");
  const std::regex face(R"(\(\d+ \d+ \d+ \d+\))");
  const auto patch_faces = [&](const std::string& name) {
    const auto at = boundary.find(name);
    const auto end = boundary.find('}', at);
    const std::string body = boundary.substr(at, end - at);
    return count(body, face);
  };
  EXPECT_EQ(patch_faces("top"), 5u);
  EXPECT_EQ(patch_faces("bottom"), 5u);
  EXPECT_EQ(patch_faces("rim"), 4u);
  EXPECT_NE(boundary.find("type patch;"), std::string::npos);  // the rim is not a wall

  EXPECT_THROW((void)openfoam_block_mesh_dict(g, {0, 30, 4}), core::ConfigError);
  EXPECT_THROW((void)openfoam_block_mesh_dict(g, mesh, 0.9), core::ConfigError);
}

TEST(OpenFoamExport, TransportPropertiesAreKinematic) {
  const double rho = 1250.0;
  const auto fluid = [&](const std::string& rheology) {
    return std::get<RheometerCase>(rheometer_case(rheology, rho).spec).fluid;
  };

  auto t = openfoam_transport(fluid("{model: newtonian, viscosity: 2.5e-3}"));
  EXPECT_EQ(t.model, "Newtonian");
  EXPECT_DOUBLE_EQ(coeffs(t).at("nu"), 2.5e-3 / rho);
  EXPECT_TRUE(t.note.empty());

  t = openfoam_transport(fluid("{model: power_law, consistency: 1.0e-3, index: 0.3}"));
  EXPECT_EQ(t.model, "powerLaw");
  EXPECT_DOUBLE_EQ(coeffs(t).at("k"), 1e-3 / rho);
  EXPECT_DOUBLE_EQ(coeffs(t).at("n"), 0.3);
  EXPECT_DOUBLE_EQ(coeffs(t).at("nuMin"), 0.0);
  EXPECT_NEAR(coeffs(t).at("nuMax"), 1e-3 * std::pow(1e-6, -0.7) / rho, 1e-12 * coeffs(t).at("nuMax"));  // plateau
  t = openfoam_transport(fluid("{model: power_law, consistency: 1.0e-3, index: 1.5}"));
  EXPECT_NEAR(coeffs(t).at("nuMin"), 1e-3 * std::pow(1e-6, 0.5) / rho, 1e-25);
  EXPECT_GE(coeffs(t).at("nuMax"), 1e300);

  t = openfoam_transport(fluid("{model: bingham, plastic_viscosity: 0.01, yield_stress: 2.0, regularization: 500}"));
  EXPECT_EQ(t.model, "HerschelBulkley");
  EXPECT_DOUBLE_EQ(coeffs(t).at("k"), 0.01 / rho);
  EXPECT_DOUBLE_EQ(coeffs(t).at("n"), 1.0);
  EXPECT_DOUBLE_EQ(coeffs(t).at("tau0"), 2.0 / rho);
  EXPECT_NEAR(coeffs(t).at("nu0"), (0.01 + 2.0 * 500) / rho, 1e-12);  // rheosim's μ(0)/ρ
  EXPECT_NE(t.note.find("Papanastasiou"), std::string::npos);

  t = openfoam_transport(fluid("{model: herschel_bulkley, consistency: 0.5, index: 0.6, yield_stress: 3.0}"));
  EXPECT_EQ(t.model, "HerschelBulkley");
  EXPECT_DOUBLE_EQ(coeffs(t).at("k"), 0.5 / rho);
  EXPECT_DOUBLE_EQ(coeffs(t).at("n"), 0.6);
  EXPECT_DOUBLE_EQ(coeffs(t).at("tau0"), 3.0 / rho);
  EXPECT_NE(t.note.find("viscosity cap"), std::string::npos);

  t = openfoam_transport(fluid("{model: casson, plastic_viscosity: 0.01, yield_stress: 1.0e-2, regularization: 1000}"));
  EXPECT_EQ(t.model, "Casson");
  EXPECT_DOUBLE_EQ(coeffs(t).at("m"), 0.01 / rho);
  EXPECT_DOUBLE_EQ(coeffs(t).at("tau0"), 1e-2 / rho);
  EXPECT_DOUBLE_EQ(coeffs(t).at("nuMin"), 0.01 / rho);
  const double casson_rest = std::pow(std::sqrt(0.01) + std::sqrt(1e-2 * 1000), 2) / rho;
  EXPECT_NEAR(coeffs(t).at("nuMax"), casson_rest, 1e-5 * casson_rest);

  t =
      openfoam_transport(fluid("{model: carreau_yasuda, zero_shear_viscosity: 1.0, infinite_shear_viscosity: 0.001, "
                               "time_constant: 0.5, a: 2, n: 0.4}"));
  EXPECT_EQ(t.model, "BirdCarreau");
  EXPECT_DOUBLE_EQ(coeffs(t).at("nu0"), 1.0 / rho);
  EXPECT_DOUBLE_EQ(coeffs(t).at("nuInf"), 0.001 / rho);
  EXPECT_DOUBLE_EQ(coeffs(t).at("k"), 0.5);  // a time, not divided by ρ
  EXPECT_DOUBLE_EQ(coeffs(t).at("n"), 0.4);
  EXPECT_DOUBLE_EQ(coeffs(t).at("a"), 2.0);

  t =
      openfoam_transport(fluid("{model: cross, zero_shear_viscosity: 1.0, infinite_shear_viscosity: 0.001, "
                               "time_constant: 0.5, exponent: 0.7}"));
  EXPECT_EQ(t.model, "CrossPowerLaw");
  EXPECT_DOUBLE_EQ(coeffs(t).at("nu0"), 1.0 / rho);
  EXPECT_DOUBLE_EQ(coeffs(t).at("nuInf"), 0.001 / rho);
  EXPECT_DOUBLE_EQ(coeffs(t).at("m"), 0.5);
  EXPECT_DOUBLE_EQ(coeffs(t).at("n"), 0.7);
}

TEST(OpenFoamExport, ChoosesOneOfSeveralFluids) {
  TempDir dir("fluids");
  const auto c = parse_case(
      "kind: rheometer\n"
      "geometry: {type: parallel_plate, radius: 0.015, gap: 0.0005}\n"
      "fluids:\n"
      "  - {name: water, density: 1000, rheology: {model: newtonian, viscosity: 1.0e-3}}\n"
      "  - {name: thin, density: 1000, rheology: {model: power_law, consistency: 1.0e-3, index: 0.6}}\n"
      "shear_rates: [10]\n",
      "fluids.yaml");
  OpenFoamExportOptions options;
  options.mesh = OpenFoamMesh::m1();
  EXPECT_EQ(export_openfoam(c, 10.0, dir.path(), options).transport.model, "Newtonian");  // the first
  options.fluid = "thin";
  EXPECT_EQ(export_openfoam(c, 10.0, dir.path(), options).transport.model, "powerLaw");
  EXPECT_EQ(core::read_json(dir.path() / "rheosim.json").at("fluid").get<std::string>(), "thin");
  options.fluid = "honey";
  EXPECT_THROW((void)export_openfoam(c, 10.0, dir.path(), options), core::ConfigError);
}

TEST(OpenFoamExport, PlainSlipRimOnRequest) {
  TempDir dir("slip");
  OpenFoamExportOptions options;
  options.mesh = OpenFoamMesh::m1();
  options.rim = OpenFoamRim::slip;
  (void)export_openfoam(rheometer_case("{model: newtonian, viscosity: 1.0e-3}"), 10.0, dir.path(), options);
  const std::string u = read(dir.path() / "0/U");
  EXPECT_NE(u.find("type            slip;"), std::string::npos);
  EXPECT_EQ(u.find("partialSlip"), std::string::npos);
  EXPECT_EQ(core::read_json(dir.path() / "rheosim.json").at("rim").get<std::string>(), "slip");
}

// The CLI's `--rim` names (bench/openfoam_compare.sh passes them on).
TEST(OpenFoamExport, RimNamesParse) {
  EXPECT_EQ(parse_openfoam_rim("shear_free"), OpenFoamRim::shear_free);
  EXPECT_EQ(parse_openfoam_rim("slip"), OpenFoamRim::slip);
  EXPECT_THROW((void)parse_openfoam_rim("noSlip"), core::ConfigError);
  EXPECT_THROW((void)parse_openfoam_rim(""), core::ConfigError);
}

TEST(OpenFoamExport, TransportPropertiesFileHoldsTheKinematicValues) {
  TempDir dir("transport");
  (void)export_openfoam(rheometer_case("{model: power_law, consistency: 1.0e-3, index: 0.6}"), 10.0, dir.path(),
                        m1_options());
  const std::string text = read(dir.path() / "constant/transportProperties");
  EXPECT_NE(text.find("transportModel  powerLaw;"), std::string::npos);
  EXPECT_NE(text.find("powerLawCoeffs"), std::string::npos);
  EXPECT_NE(text.find("k       1e-06;"), std::string::npos) << text;
  EXPECT_NE(text.find("n       0.6;"), std::string::npos) << text;
}

TEST(OpenFoamExport, RejectsWhatOpenFoamCannotRun) {
  TempDir dir("errors");
  const auto water = rheometer_case("{model: newtonian, viscosity: 1.0e-3}");
  EXPECT_THROW((void)export_openfoam(water, 0.0, dir.path()), core::ConfigError);
  EXPECT_THROW((void)export_openfoam(water, -1.0, dir.path()), core::ConfigError);
  EXPECT_THROW((void)export_openfoam(water, std::nan(""), dir.path()), core::ConfigError);
  OpenFoamExportOptions bad;
  bad.mesh.axial_cells = 0;
  EXPECT_THROW((void)export_openfoam(water, 10.0, dir.path(), bad), core::ConfigError);

  const auto sweep = load_case(std::string(RHEOSIM_SOURCE_DIR) + "/cases/suspension_seed.yaml");
  EXPECT_THROW((void)export_openfoam(sweep, 10.0, dir.path()), core::ConfigError);
  // An LDD case never becomes a rheometer case that could be exported: its reader is the ldd module's.
  EXPECT_THROW((void)load_case(std::string(RHEOSIM_SOURCE_DIR) + "/cases/ldd_cavity_casson.yaml"), core::ConfigError);

  auto suspension = water;
  std::get<RheometerCase>(suspension.spec).particles = coupling::SuspendedParticles{{0.1, 2e-4, 1000}};
  try {
    (void)export_openfoam(suspension, 10.0, dir.path());
    ADD_FAILURE() << "a particle-laden case was exported";
  } catch (const core::ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "particles");
  }
  EXPECT_FALSE(fs::exists(dir.path() / "system/blockMeshDict"));  // nothing written on error
}

// ------------------------------------------------------------------ with OpenFOAM v1912 installed

bool have(const char* program) { return fs::exists(fs::path("/usr/bin") / program); }

// Runs `command` in `dir` with only WM_PROJECT_DIR added (Debian's OpenFOAM needs nothing else).
int run_in(const fs::path& dir, const std::string& command) {
  const std::string line = "cd '" + dir.string() + "' && export WM_PROJECT_DIR=/usr/share/openfoam && " + command;
  return std::system(line.c_str());
}

// The z component of the total moment on the last line of a forces moment.dat:
// "time (total_x total_y total_z) (pressure ...) (viscous ...)".
double moment_z(const fs::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') last = line;
  std::replace(last.begin(), last.end(), '(', ' ');
  std::replace(last.begin(), last.end(), ')', ' ');
  std::istringstream fields(last);
  double time = 0, mx = 0, my = 0, mz = std::nan("");
  fields >> time >> mx >> my >> mz;
  EXPECT_TRUE(std::isfinite(mz)) << file << ": " << last;
  return mz;
}

TEST(OpenFoamValidation, BlockMeshAndCheckMeshAcceptTheM1Grid) {
  if (!have("blockMesh") || !have("checkMesh")) GTEST_SKIP() << "OpenFOAM (/usr/bin/blockMesh) is not installed";
  TempDir dir("m1mesh");
  (void)export_openfoam(rheometer_case("{model: newtonian, viscosity: 1.0e-3}"), 10.0, dir.path(), m1_options());
  ASSERT_EQ(run_in(dir.path(), "blockMesh > log.blockMesh 2>&1"), 0) << read(dir.path() / "log.blockMesh");
  ASSERT_EQ(run_in(dir.path(), "checkMesh > log.checkMesh 2>&1"), 0) << read(dir.path() / "log.checkMesh");
  const std::string log = read(dir.path() / "log.checkMesh");
  EXPECT_NE(log.find("Mesh OK."), std::string::npos) << log;
  EXPECT_NE(log.find("cells:            10800"), std::string::npos) << log;
  // The mesh fills the gap up to the inscribed 120-gon: volume within 0.05 % of πR²H.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(log, m, std::regex(R"(Total volume = ([0-9.eE+-]+)\.)")));
  const double disk = std::numbers::pi * 0.015 * 0.015 * 0.0005;
  EXPECT_NEAR(std::stod(m[1].str()), disk, 5e-4 * disk);
}

TEST(OpenFoamValidation, SimpleFoamNewtonianTorqueOnM1) {
  if (!have("blockMesh") || !have("simpleFoam")) GTEST_SKIP() << "OpenFOAM (/usr/bin/simpleFoam) is not installed";
  TempDir dir("m1run");
  const auto result =
      export_openfoam(rheometer_case("{model: newtonian, viscosity: 1.0e-3}"), 10.0, dir.path(), m1_options());
  ASSERT_EQ(run_in(dir.path(), "blockMesh > log.blockMesh 2>&1 && simpleFoam > log.simpleFoam 2>&1"), 0)
      << read(dir.path() / "log.simpleFoam");
  EXPECT_NE(read(dir.path() / "log.simpleFoam").find("SIMPLE solution converged"), std::string::npos);
  const double top = -moment_z(dir.path() / "postProcessing/forces/0/moment.dat");
  const double bottom = moment_z(dir.path() / "postProcessing/forcesBottom/0/moment.dat");
  const double exact = *result.closed_form_torque;
  // The shear-free rim carries no torque: the plates balance (OpenFOAM's plain slip would leave
  // 2(H/R)² = 0.22 % of the torque on the rim).
  EXPECT_NEAR(bottom, top, 1e-5 * exact);
  // Re = 0.08: creeping. M1's rim is a 120-gon whose polar moment is 0.091 % below the disk's;
  // beyond that M1 is within 0.05 % (it converges at second order: −0.044 % M1, −0.011 % M2).
  const double n = 120, a = 2 * std::numbers::pi / n;
  const double polygon = n / (2 * std::numbers::pi) * std::sin(a) * (2 + std::cos(a)) / 3;
  EXPECT_NEAR(top, exact * polygon, 5e-4 * exact);
  EXPECT_NEAR(top, exact, 2e-3 * exact);
}

}  // namespace
}  // namespace rheosim::rheometer
