// The interFoam export of an LDD dam break: the mesh, the starting column, the phases and the
// gravity of the case, and the refusals (docs/ldd.md, "Dam break against interFoam").
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/openfoam.hpp"

namespace rheosim::ldd {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// A Bingham reservoir 0.4 m × 0.1 m, floor 0.6 m beyond the gate, Δ = 5 mm.
const std::string dam_break = R"(kind: ldd
dimension: 2
scene: {type: dam_break, reservoir: [0.4, 0.1], channel_length: 1.0}
fluid:
  density: 1200
  rheology: {model: bingham, plastic_viscosity: 25.0, yield_stress: 30.0, regularization: 1000}
gravity: [0, -9.81]
resolution: {spacing: 0.005}
time: {step: 1.0e-3, end: 0.5}
output: {probe_interval: 0.02}
)";

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class InterFoamExportTest : public ::testing::Test {
 protected:
  fs::path dir_ = fs::temp_directory_path() / fmt::format("rheosim_test_interfoam_{}", ::getpid());
  void TearDown() override { fs::remove_all(dir_); }
};

TEST_F(InterFoamExportTest, WritesTheDamBreakOfTheCase) {
  const auto exported = export_interfoam(parse_case(dam_break, "dam.yaml"), dir_);
  // x from the back wall (−0.4) to the end wall (+0.6): 200 cells; y to H + H/2 = 0.15 m: 30.
  EXPECT_EQ(exported.cells_x, 200);
  EXPECT_EQ(exported.cells_y, 30);
  const std::string mesh = read(dir_ / "system/blockMeshDict");
  EXPECT_THAT(mesh, HasSubstr("hex (0 1 2 3 4 5 6 7) (200 30 1)"));
  EXPECT_THAT(mesh, HasSubstr("(-0.4 0 0)"));
  EXPECT_THAT(mesh, HasSubstr("(0.6 0.15 0.005)"));
  for (const char* patch : {"floor", "backWall", "endWall", "atmosphere", "frontAndBack"})
    EXPECT_THAT(mesh, HasSubstr(patch));
  EXPECT_THAT(read(dir_ / "system/setFieldsDict"), HasSubstr("box (-0.4 0 -1) (0 0.1 1);"));
  // Bingham as HerschelBulkley in kinematic units: k = μ_B/ρ, tau0 = τ_B/ρ, cap μ(0)/ρ.
  const std::string transport = read(dir_ / "constant/transportProperties");
  EXPECT_THAT(transport, HasSubstr("phases (water air);"));
  EXPECT_THAT(transport, HasSubstr("transportModel  HerschelBulkley;"));
  EXPECT_THAT(transport, HasSubstr(fmt::format("tau0    {};", 30.0 / 1200)));
  EXPECT_THAT(transport, HasSubstr(fmt::format("nu0     {};", (25.0 + 30.0 * 1000) / 1200)));
  EXPECT_THAT(transport, HasSubstr("rho             1200;"));
  EXPECT_THAT(transport, HasSubstr("sigma           0;"));
  EXPECT_THAT(read(dir_ / "constant/g"), HasSubstr("value           (0 -9.81 0);"));
  const std::string control = read(dir_ / "system/controlDict");
  EXPECT_THAT(control, HasSubstr("endTime         0.5;"));
  EXPECT_THAT(control, HasSubstr("maxCo           0.5;"));
  EXPECT_THAT(control, HasSubstr("writeInterval   0.02;"));          // the front at every probe interval
  EXPECT_THAT(control, HasSubstr("start   (-0.4 0.0025 0.0025);"));  // the lowest row's cell centres
  // The first step: 0.01 Δ/√(gH), not the LDD run's 1e-3 s.
  EXPECT_THAT(control, HasSubstr(fmt::format("deltaT          {};", 0.01 * 0.005 / std::sqrt(9.81 * 0.1))));
  EXPECT_THAT(read(dir_ / "0/U"), HasSubstr("noSlip"));
  EXPECT_THAT(read(dir_ / "0/p_rgh"), HasSubstr("totalPressure"));
  // What a comparison reads back.
  const auto info = core::read_json(dir_ / "rheosim.json");
  EXPECT_DOUBLE_EQ(info.at("cell_size").get<double>(), 0.005);
  EXPECT_EQ(info.at("cells").at(0).get<int>(), 200);
  EXPECT_EQ(info.at("front_rows").get<int>(), 3);
}

TEST_F(InterFoamExportTest, RefusesAnotherSceneAndACourantOutOfRange) {
  const std::string cavity =
      "kind: ldd\ndimension: 2\nscene: {type: cavity, size: [1, 1], lid_velocity: 1}\n"
      "fluid: {density: 1, rheology: {model: newtonian, viscosity: 0.01}}\n"
      "gravity: [0, 0]\nresolution: {spacing: 0.05}\ntime: {step: 1.0e-3, end: 0.1}\n";
  try {
    (void)export_interfoam(parse_case(cavity, "cavity.yaml"), dir_);
    ADD_FAILURE() << "a cavity was exported";
  } catch (const core::ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "scene.type") << e.what();
  }
  try {
    (void)export_interfoam(parse_case(dam_break, "dam.yaml"), dir_, {.max_courant = 2.0});
    ADD_FAILURE() << "maxCo 2 was accepted";
  } catch (const core::ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "--max-courant") << e.what();
  }
  EXPECT_FALSE(fs::exists(dir_ / "system/controlDict"));  // nothing written before the checks
}

}  // namespace
}  // namespace rheosim::ldd
