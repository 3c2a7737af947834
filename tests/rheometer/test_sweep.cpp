// The sweep runner with injected point runners (rheometer/sweep.hpp): what the CFD-DEM coupling
// will plug into. Fake runners return closed-form torques, so the analysis in summary.json can be
// checked against known parameters, and resuming can be checked by counting calls.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/plate.hpp"
#include "rheosim/rheometer/sweep.hpp"

namespace fs = std::filesystem;
using namespace rheosim;
using rheometer::PointProgress;
using rheometer::PointProgressCallback;
using rheometer::PointResult;
using rheometer::SweepPoint;

namespace {

constexpr const char* deck = R"(kind: sweep
geometry: {type: parallel_plate, radius: 0.015, gap: 0.0005}
fluid:
  density: 1000
  rheology: {model: newtonian, viscosity: 1.0e-3}
shear_rates: [10, 20, 40, 60, 80, 100]
volume_fractions: [0, 0.2, 0.4]
particles: {diameter: 2.0e-5, density: 1000}
)";

const rheometer::ParallelPlate plate{0.015, 0.0005};
constexpr double liquid_viscosity = 1.0e-3;

// A Bingham suspension: τ_y and η_p grow with φ (η_p by Krieger–Dougherty, φ_m = 0.6).
double yield_stress_of(double phi) { return 0.5 * phi * phi; }
double plastic_viscosity_of(double phi) { return liquid_viscosity * std::pow(1.0 - phi / 0.6, -2.5 * 0.6); }

struct Calls {
  int single_phase = 0;
  int suspension = 0;
};

rheometer::PointRunners fake_runners(Calls& calls) {
  rheometer::PointRunners r;
  r.single_phase = [&calls](const SweepPoint& p, const PointProgressCallback&) {
    ++calls.single_phase;
    PointResult out;
    out.converged = true;
    out.method = "fake steady";
    out.torque = rheometer::newtonian_torque(plate, liquid_viscosity, p.rim_shear_rate);
    out.torque_analytic = out.torque;
    return out;
  };
  r.suspension = [&calls](const SweepPoint& p, const PointProgressCallback& progress) {
    ++calls.suspension;
    for (int step = 1; step <= 3; ++step) progress(PointProgress{10.0 * step, 30.0});
    PointResult out;
    out.converged = true;
    out.method = "fake transient";
    out.strain = 30.0;
    out.torque = rheometer::bingham_torque(plate, plastic_viscosity_of(p.volume_fraction),
                                           yield_stress_of(p.volume_fraction), p.rim_shear_rate);
    out.torque_fluid = 0.8 * out.torque;
    out.torque_contact = 0.2 * out.torque;
    return out;
  };
  return r;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("rheosim_test_sweep_" + name);
  fs::remove_all(dir);
  return dir;
}

const nlohmann::json* find_yield(const nlohmann::json& summary, double phi, const std::string& method) {
  for (const auto& y : summary["yield_stress"])
    if (y["volume_fraction"].get<double>() == phi && y["method"] == method) return &y;
  return nullptr;
}

}  // namespace

TEST(Sweep, PointsAreEveryFluidPhiAndRateInOrder) {
  const auto c = rheometer::parse_case(deck, "sweep");
  const auto points = rheometer::sweep_points(std::get<rheometer::SweepCase>(c.spec));
  ASSERT_EQ(points.size(), 18u);
  EXPECT_EQ(points[0].volume_fraction, 0.0);
  EXPECT_EQ(points[0].rim_shear_rate, 10.0);
  EXPECT_EQ(points[7].volume_fraction, 0.2);
  EXPECT_EQ(points[7].rim_shear_rate, 20.0);
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_EQ(points[i].index, i);
}

TEST(Sweep, InjectedRunnersFeedTheAnalysisAndResumeSkipsStoredPoints) {
  const auto c = rheometer::parse_case(deck, "sweep");
  const fs::path out = fresh_dir("inject");
  Calls calls;
  const auto first = rheometer::run_sweep(c, out, core::Log::null(), fake_runners(calls));
  EXPECT_EQ(first.points, 18);
  EXPECT_EQ(first.failed_points, 0);
  EXPECT_EQ(first.computed_points, 18);
  EXPECT_EQ(calls.single_phase, 6);
  EXPECT_EQ(calls.suspension, 12);
  const auto summary = core::read_json(out / "summary.json");
  ASSERT_EQ(summary["points"].size(), 18u);
  EXPECT_EQ(summary["points"][6]["volume_fraction"].get<double>(), 0.2);
  EXPECT_EQ(summary["points"][6]["strain"].get<double>(), 30.0);

  // The seed's torque line is exact for Bingham torques (T = 2πR³(τ_y/3 + η_p γ̇_R/4)); the
  // Bingham fit on the plate-corrected stress recovers τ_y within its interval.
  for (const double phi : {0.2, 0.4}) {
    const auto* line = find_yield(summary, phi, "torque_intercept");
    ASSERT_NE(line, nullptr);
    EXPECT_NEAR((*line)["value"].get<double>(), yield_stress_of(phi), 1e-9 * yield_stress_of(phi) + 1e-12);
    const auto* bingham = find_yield(summary, phi, "bingham_intercept");
    ASSERT_NE(bingham, nullptr);
    // Within 1 %: n′ of a Bingham torque comes from a local quadratic in ln γ̇_R, exact only for power laws.
    EXPECT_NEAR((*bingham)["value"].get<double>(), yield_stress_of(phi), 1e-2 * yield_stress_of(phi));
    EXPECT_LE((*bingham)["ci95"][0].get<double>(), yield_stress_of(phi));
    EXPECT_GE((*bingham)["ci95"][1].get<double>(), yield_stress_of(phi));
    EXPECT_TRUE((*bingham)["significant"].get<bool>());
  }
  // The liquid has no yield stress by any method.
  EXPECT_FALSE((*find_yield(summary, 0.0, "torque_intercept"))["significant"].get<bool>());

  // η_r(φ): measured liquid at φ = 0, suspensions above 1, correlations compared.
  ASSERT_EQ(summary["relative_viscosity"].size(), 1u);
  const auto& rv = summary["relative_viscosity"][0];
  EXPECT_EQ(rv["reference_shear_rate"].get<double>(), 100.0);
  ASSERT_EQ(rv["points"].size(), 3u);
  EXPECT_DOUBLE_EQ(rv["points"][0]["relative_viscosity"].get<double>(), 1.0);
  const double expected = (yield_stress_of(0.4) / 100.0 + plastic_viscosity_of(0.4)) / liquid_viscosity;
  EXPECT_NEAR(rv["points"][2]["relative_viscosity"].get<double>(), expected, 2e-3 * expected);
  EXPECT_EQ(rv["correlations"].size(), 4u);
  EXPECT_TRUE(fs::exists(out / "report.html"));
  EXPECT_TRUE(fs::exists(out / "sweep.h5"));

  // Started again: nothing left to compute, identical analysis.
  Calls again;
  const auto second = rheometer::run_sweep(c, out, core::Log::null(), fake_runners(again));
  EXPECT_EQ(second.reused_points, 18);
  EXPECT_EQ(second.computed_points, 0);
  EXPECT_EQ(again.single_phase + again.suspension, 0);
  const auto resumed = core::read_json(out / "summary.json");
  EXPECT_EQ(resumed["fits"], summary["fits"]);
  EXPECT_EQ(resumed["yield_stress"], summary["yield_stress"]);
  fs::remove_all(out);
}

TEST(Sweep, AFailingPointIsRecordedNotStoredAndTriedAgain) {
  const auto c = rheometer::parse_case(deck, "sweep");
  const fs::path out = fresh_dir("failure");
  Calls calls;
  auto runners = fake_runners(calls);
  const auto working = runners.suspension;
  runners.suspension = [&](const SweepPoint& p, const PointProgressCallback& progress) -> PointResult {
    if (p.volume_fraction == 0.4 && p.rim_shear_rate == 60.0) throw std::runtime_error("DEM blew up");
    return working(p, progress);
  };
  const auto first = rheometer::run_sweep(c, out, core::Log::null(), runners);
  EXPECT_EQ(first.failed_points, 1);
  const auto summary = core::read_json(out / "summary.json");
  const auto& failed = summary["points"][15];
  EXPECT_FALSE(failed["converged"].get<bool>());
  EXPECT_EQ(failed["failure"], "DEM blew up");
  EXPECT_FALSE(failed.contains("torque")) << "no number for a failed point";
  EXPECT_EQ(summary["points_failed"].get<int>(), 1);

  Calls retry;
  const auto second = rheometer::run_sweep(c, out, core::Log::null(), fake_runners(retry));
  EXPECT_EQ(second.computed_points, 1);
  EXPECT_EQ(retry.suspension, 1);
  EXPECT_EQ(second.failed_points, 0);
  fs::remove_all(out);
}

TEST(Sweep, UnavailableSuspensionRunnerSaysWhy) {
  const auto result = rheometer::make_unavailable_suspension_runner()(SweepPoint{0, "fluid", 0.1, 10.0}, {});
  EXPECT_FALSE(result.converged);
  EXPECT_NE(result.failure.find("CFD-DEM"), std::string::npos);
  EXPECT_TRUE(std::isnan(result.torque));
}

TEST(Sweep, StoreRefusesPointsOfAnotherDeck) {
  const auto c = rheometer::parse_case(deck, "sweep");
  const fs::path out = fresh_dir("changed");
  Calls calls;
  (void)rheometer::run_sweep(c, out, core::Log::null(), fake_runners(calls));
  const auto changed = rheometer::parse_case(std::string(deck) + "description: changed\n", "sweep");
  EXPECT_THROW((void)rheometer::run_sweep(changed, out, core::Log::null(), fake_runners(calls)), core::ConfigError);
  fs::remove_all(out);
}

// A rheometer case runs as a sweep: the liquid alone over φ ∈ {0}, or {0, φ} with particles;
// a sweep case is itself.
TEST(Sweep, ARheometerCaseRunsAsTheSweepOfItsVolumeFractions) {
  const std::string plates =
      "geometry: {type: parallel_plate, radius: 0.015, gap: 0.0005}\n"
      "fluid: {density: 1000, rheology: {model: newtonian, viscosity: 1.0e-3}}\nshear_rates: [10, 100]\n";
  const auto liquid = rheometer::as_sweep(rheometer::parse_case("kind: rheometer\n" + plates, "liquid.yaml"));
  EXPECT_EQ(liquid.kind, "sweep");
  EXPECT_EQ(std::get<rheometer::SweepCase>(liquid.spec).volume_fractions, (std::vector<double>{0.0}));
  const auto suspension = rheometer::as_sweep(rheometer::parse_case(
      "kind: rheometer\n" + plates + "particles: {volume_fraction: 0.3, diameter: 2.0e-5, density: 1000}\n",
      "suspension.yaml"));
  EXPECT_EQ(std::get<rheometer::SweepCase>(suspension.spec).volume_fractions, (std::vector<double>{0.0, 0.3}));
  const auto sweep = rheometer::parse_case(deck, "sweep");
  EXPECT_EQ(std::get<rheometer::SweepCase>(rheometer::as_sweep(sweep).spec).volume_fractions,
            std::get<rheometer::SweepCase>(sweep.spec).volume_fractions);
}

// A single-phase rheometer case through the sweep: each point carries the swirl solve's numbers
// (creeping torque, inertia effect, the closed form and its quadrature, which agree for a power
// law), its fields with the grid in its point file, and a second run into the same folder
// computes nothing and reports the same torques.
TEST(Sweep, ARheometerCaseStoresItsPointsAndResumes) {
  const auto c = rheometer::as_sweep(
      rheometer::parse_case("kind: rheometer\nname: one\ngeometry: {type: parallel_plate, radius: 0.015, gap: 0.0005}\n"
                            "fluid: {density: 1000, rheology: {model: power_law, consistency: 1.0e-3, index: 0.6}}\n"
                            "shear_rates: [50, 100]\nsolver: {radial_cells: 12, axial_cells: 8, inertia: true}\n",
                            "rheometer.yaml"));
  const auto& r = std::get<rheometer::SweepCase>(c.spec).rheometer;
  const fs::path out = fresh_dir("rheometer_case");
  const auto first = rheometer::run_sweep(c, out, core::Log::null(), rheometer::default_point_runners(r));
  EXPECT_EQ(first.computed_points, 2);
  EXPECT_EQ(first.failed_points, 0);
  const auto summary = core::read_json(out / "summary.json");
  ASSERT_EQ(summary["points"].size(), 2u);
  for (const auto& p : summary["points"]) {
    ASSERT_TRUE(p["converged"].get<bool>());
    const double analytic = p["torque_analytic"].get<double>();
    EXPECT_NEAR(p["torque_quadrature"].get<double>(), analytic, 1e-6 * analytic);
    EXPECT_DOUBLE_EQ(p["inertia_effect"].get<double>(),
                     p["torque"].get<double>() / p["torque_creeping"].get<double>() - 1.0);
    EXPECT_GT(p["inertia_effect"].get<double>(), 0.0) << "inertia raises the torque";
    EXPECT_LT(std::abs(p["creeping_rel_error"].get<double>()), 0.02);
  }
  const fs::path point_file = out / "points" / "point_0001.h5";
  EXPECT_EQ(core::read_hdf5_dataset(point_file, "fields/angular_velocity").shape, (std::vector<std::size_t>{12, 8}));
  const auto radial = core::read_hdf5_dataset(point_file, "fields/radial_centres");
  ASSERT_EQ(radial.data.size(), 12u);
  EXPECT_LT(radial.data.back(), 0.015);
  EXPECT_EQ(core::read_hdf5_dataset(point_file, "fields/axial_centres").data.size(), 8u);

  Calls calls;  // a second run computes nothing
  const auto second = rheometer::run_sweep(c, out, core::Log::null(), fake_runners(calls));
  EXPECT_EQ(second.reused_points, 2);
  EXPECT_EQ(calls.single_phase, 0);
  const auto resumed = core::read_json(out / "summary.json");
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_EQ(resumed["points"][i]["torque"].get<double>(), summary["points"][i]["torque"].get<double>());
  fs::remove_all(out);
}

// A failed point with fields keeps its last iterate and reason beside the stored points; a later
// success replaces it.
TEST(Sweep, AFailedPointKeepsItsLastIterateUntilItSucceeds) {
  const auto c = rheometer::parse_case(deck, "sweep");
  const fs::path out = fresh_dir("failed_iterate");
  Calls calls;
  auto runners = fake_runners(calls);
  runners.single_phase = [](const SweepPoint&, const PointProgressCallback&) {
    PointResult failed;
    failed.failure = "Picard iteration stalled";
    core::Hdf5Dataset omega;
    omega.path = "fields/angular_velocity";
    omega.shape = {2};
    omega.data = {0.5, 1.0};
    omega.unit = "rad/s";
    failed.fields.push_back(omega);
    return failed;
  };
  (void)rheometer::run_sweep(c, out, core::Log::null(), runners);
  const rheometer::PointStore store(out, c.sha256);
  const SweepPoint first_point{0, "fluid", 0.0, 10.0};
  ASSERT_TRUE(fs::exists(store.failure_file(first_point)));
  EXPECT_FALSE(fs::exists(store.file(first_point)));
  std::string failure;
  for (const auto& a : core::read_hdf5_attributes(store.failure_file(first_point)))
    if (a.name == "failure") failure = std::get<std::string>(a.value);
  EXPECT_EQ(failure, "Picard iteration stalled");

  (void)rheometer::run_sweep(c, out, core::Log::null(), fake_runners(calls));
  EXPECT_TRUE(fs::exists(store.file(first_point)));
  EXPECT_FALSE(fs::exists(store.failure_file(first_point)));
  fs::remove_all(out);
}
