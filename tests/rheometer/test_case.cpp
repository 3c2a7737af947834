// Case files: valid cases parse into the right typed values; every kind of bad input is a
// ConfigError that names file:line:column, the key path, the valid range and a fix.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>
#include <set>
#include <string>
#include <utility>

#include "case_test_support.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/rheometer/case.hpp"

namespace rheosim::rheometer {
namespace {

using core::CaseFile;
using core::ConfigError;
using core::sha256_hex;
using coupling::DragLaw;

using ::testing::HasSubstr;

const std::string plate_case = R"(kind: rheometer
geometry: {type: parallel_plate, radius: 0.015, gap: 0.0005}
fluid:
  density: 1000
  rheology: {model: power_law, consistency: 1.0e-3, index: 0.6}
shear_rates: [1, 10, 100]
)";

ConfigError parse_error(const std::string& text) {
  return test_support::config_error([](const std::string& t) { (void)parse_case(t, "case.yaml"); }, text);
}
using test_support::replace;

TEST(Case, RheometerCaseParsesIntoTypedValues) {
  const Case c = parse_case(plate_case, "cases/plate.yaml");
  EXPECT_EQ(c.kind, "rheometer");
  EXPECT_EQ(c.name, "plate");
  const auto& r = std::get<RheometerCase>(c.spec);
  EXPECT_DOUBLE_EQ(r.geometry.radius, 0.015);
  EXPECT_DOUBLE_EQ(r.geometry.gap, 0.0005);
  EXPECT_DOUBLE_EQ(r.fluid.density, 1000);
  EXPECT_EQ(r.fluid.rheology->name(), "power_law");
  EXPECT_EQ(r.shear_rates, (std::vector<double>{1, 10, 100}));
  EXPECT_FALSE(r.particles.has_value());
  EXPECT_EQ(c.sha256, sha256_hex(plate_case));
}

TEST(Case, ParticleDefaultsAreTheSeedValues) {
  const Case c =
      parse_case(plate_case + "particles: {volume_fraction: 0.1, diameter: 2.0e-4, density: 1000}\n", "p.yaml");
  const auto& p = *std::get<RheometerCase>(c.spec).particles;
  EXPECT_DOUBLE_EQ(p.volume_fraction, 0.1);
  EXPECT_DOUBLE_EQ(p.youngs_modulus, 3.0e9);  // CD §4
  EXPECT_DOUBLE_EQ(p.poisson_ratio, 0.33);
  EXPECT_DOUBLE_EQ(p.restitution, 0.9);
  EXPECT_DOUBLE_EQ(p.friction, 0.3);
}

TEST(Case, DragLawIsTheSeedsUnlessTheNearFieldHasLubrication) {
  const std::string particles = "particles: {volume_fraction: 0.1, diameter: 2.0e-4, density: 1000";
  const auto drag_of = [&](const std::string& rest) {
    const Case c = parse_case(plate_case + particles + rest + "}\n", "p.yaml");
    const auto& p = *std::get<RheometerCase>(c.spec).particles;
    return std::pair{p.drag, p.drag_automatic};
  };
  EXPECT_EQ(drag_of(""), std::pair(DragLaw::di_felice, true));
  EXPECT_EQ(drag_of(", hydrodynamics: {model: stresslet}"), std::pair(DragLaw::di_felice, true));
  EXPECT_EQ(drag_of(", hydrodynamics: {model: lubrication+stresslet}"), std::pair(DragLaw::schiller_naumann, true));
  EXPECT_EQ(drag_of(", drag: {model: auto}, hydrodynamics: {model: lubrication}"),
            std::pair(DragLaw::schiller_naumann, true));
  EXPECT_EQ(drag_of(", drag: {model: di_felice}, hydrodynamics: {model: lubrication}"),
            std::pair(DragLaw::di_felice, false));
  EXPECT_EQ(drag_of(", drag: {model: schiller_naumann}"), std::pair(DragLaw::schiller_naumann, false));
  EXPECT_STREQ(name_of(DragLaw::schiller_naumann), "schiller_naumann");

  const ConfigError e = parse_error(plate_case + particles + ",\n  drag: {model: stokes}}\n");
  EXPECT_THAT(e.what(), HasSubstr("case.yaml:8:"));  // the drag line
  EXPECT_THAT(e.what(), HasSubstr("particles.drag.model"));
  EXPECT_THAT(e.what(), HasSubstr("schiller_naumann"));
}

TEST(Case, MisspeltKeyNamesLineColumnAndSuggestion) {
  const auto e = parse_error(replace(plate_case, "consistency: 1.0e-3", "consistancy: 1.0e-3"));
  EXPECT_EQ(e.details().where.line, 5);
  EXPECT_EQ(e.details().where.column, 32);
  EXPECT_EQ(e.details().key_path, "fluid.rheology.consistancy");
  EXPECT_THAT(e.details().hint, HasSubstr("did you mean 'consistency'?"));
  EXPECT_THAT(std::string(e.what()), HasSubstr("case.yaml:5:32"));
}

TEST(Case, UnknownOptionalKeyIsAnErrorWithTheValidKeys) {
  const auto e = parse_error(plate_case + "shear_rate_unit: rpm\n");
  EXPECT_EQ(e.details().key_path, "shear_rate_unit");
  EXPECT_EQ(e.details().where.line, 7);
  EXPECT_THAT(e.details().expected, HasSubstr("shear_rates"));
}

TEST(Case, NegativeValueNamesTheRange) {
  const auto e = parse_error(replace(plate_case, "density: 1000", "density: -1000"));
  EXPECT_EQ(e.details().key_path, "fluid.density");
  EXPECT_EQ(e.details().where.line, 4);
  EXPECT_THAT(e.details().problem, HasSubstr("-1000 is not > 0"));
  EXPECT_THAT(e.details().expected, HasSubstr("kg/m³"));
}

TEST(Case, TextWhereANumberBelongs) {
  const auto e = parse_error(replace(plate_case, "radius: 0.015", "radius: 15mm"));
  EXPECT_EQ(e.details().key_path, "geometry.radius");
  EXPECT_EQ(e.details().where.line, 2);
  EXPECT_THAT(e.details().problem, HasSubstr("expected a number, got '15mm'"));
  EXPECT_THAT(e.details().hint, HasSubstr("SI"));
}

// extrapolate needs the solver's half grid (even counts >= 8); the stretching is read as given.
TEST(Case, SolverExtrapolationNeedsCellCountsThatHalve) {
  const auto solver = [](const std::string& settings) { return plate_case + "solver: {" + settings + "}\n"; };
  const Case c =
      parse_case(solver("radial_cells: 20, axial_cells: 16, axial_stretching: 2, extrapolate: true"), "c.yaml");
  const auto& s = std::get<RheometerCase>(c.spec).solver;
  EXPECT_TRUE(s.extrapolate);
  EXPECT_DOUBLE_EQ(s.axial_stretching, 2.0);
  EXPECT_FALSE(std::get<RheometerCase>(parse_case(plate_case, "d.yaml").spec).solver.extrapolate);
  const auto odd = parse_error(solver("radial_cells: 20, axial_cells: 15, extrapolate: true"));
  EXPECT_EQ(odd.details().key_path, "solver.axial_cells");
  EXPECT_THAT(odd.details().expected, HasSubstr("even"));
  const auto few = parse_error(solver("radial_cells: 6, axial_cells: 16, extrapolate: true"));
  EXPECT_EQ(few.details().key_path, "solver.radial_cells");
  EXPECT_EQ(parse_error(solver("axial_stretching: -1")).details().key_path, "solver.axial_stretching");
}

TEST(Case, MissingRequiredKey) {
  const auto e = parse_error(replace(plate_case, "shear_rates: [1, 10, 100]\n", ""));
  EXPECT_THAT(e.details().problem, HasSubstr("missing required key 'shear_rates'"));
}

TEST(Case, ListEntriesAreCheckedOneByOne) {
  const auto e = parse_error(replace(plate_case, "[1, 10, 100]", "[1, -10, 100]"));
  EXPECT_EQ(e.details().key_path, "shear_rates[1]");
  EXPECT_EQ(e.details().where.line, 6);
  EXPECT_EQ(e.details().where.column, 18);
}

TEST(Case, ShearRatesMustIncrease) {
  const auto e = parse_error(replace(plate_case, "[1, 10, 100]", "[1, 100, 10]"));
  EXPECT_EQ(e.details().key_path, "shear_rates");
  EXPECT_THAT(e.details().problem, HasSubstr("does not exceed"));
}

TEST(Case, GapMustBeSmallerThanRadius) {
  const auto e = parse_error(replace(plate_case, "gap: 0.0005", "gap: 0.02"));
  EXPECT_EQ(e.details().key_path, "geometry.gap");
}

TEST(Case, ParticlesMustFitInTheGap) {
  const auto e = parse_error(plate_case + "particles: {volume_fraction: 0.1, diameter: 1.0e-3, density: 1000}\n");
  EXPECT_EQ(e.details().key_path, "particles.diameter");
}

TEST(Case, VolumeFractionRange) {
  const auto e = parse_error(plate_case + "particles: {volume_fraction: 0.7, diameter: 2.0e-4, density: 1000}\n");
  EXPECT_EQ(e.details().key_path, "particles.volume_fraction");
  EXPECT_THAT(e.details().problem, HasSubstr("[0, 0.5]"));
}

TEST(Case, SweepNeedsParticlesForNonZeroFractions) {
  const auto e = parse_error(replace(plate_case, "kind: rheometer", "kind: sweep") + "volume_fractions: [0, 0.1]\n");
  EXPECT_EQ(e.details().key_path, "volume_fractions");
  const Case ok = parse_case(replace(plate_case, "kind: rheometer", "kind: sweep") +
                                 "volume_fractions: [0, 0.1]\nparticles: {diameter: 2.0e-4, density: 1000}\n",
                             "sweep.yaml");
  EXPECT_EQ(std::get<SweepCase>(ok.spec).volume_fractions.size(), 2u);
}

TEST(Case, SweepParticlesRejectAVolumeFraction) {
  const auto e =
      parse_error(replace(plate_case, "kind: rheometer", "kind: sweep") +
                  "volume_fractions: [0, 0.1]\nparticles: {volume_fraction: 0.1, diameter: 2.0e-4, density: 1000}\n");
  EXPECT_EQ(e.details().key_path, "particles.volume_fraction");
}

// core::CaseFile reads the header of every kind; the rheometer reader refuses an LDD case,
// whose body the ldd module reads (tests/ldd/test_case.cpp).
TEST(Case, TheRheometerReaderRefusesAnLddCase) {
  const CaseFile file = CaseFile::parse("kind: ldd\nname: c\n", "c.yaml");
  EXPECT_EQ(file.header().kind, "ldd");
  EXPECT_EQ(file.header().name, "c");
  try {
    (void)read_case(file);
    ADD_FAILURE() << "an ldd case was read as a rheometer case";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.details().key_path, "kind");
    EXPECT_THAT(e.details().problem, HasSubstr("not 'ldd'"));
  }
}

// Every shipped rheometer and sweep case reads (the CLI test validate_shipped_cases runs every kind).
TEST(Case, EveryShippedRheometerCaseReads) {
  const std::filesystem::path cases = std::filesystem::path(RHEOSIM_SOURCE_DIR) / "cases";
  std::set<std::string> kinds;
  for (const auto& entry : std::filesystem::directory_iterator(cases)) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const CaseFile file = CaseFile::open(entry.path().string());
    if (file.header().kind == "ldd") continue;
    kinds.insert(read_case(file).kind);
  }
  EXPECT_EQ(kinds, (std::set<std::string>{"rheometer", "sweep"}));
}

}  // namespace
}  // namespace rheosim::rheometer
