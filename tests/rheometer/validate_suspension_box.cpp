// The Lees–Edwards suspension box against measured non-Brownian suspensions, and the rheometer
// runner built on it (docs/suspension-box.md):
//   - dilute limit: η_r(0.05) within 5 % of Einstein's 1 + 2.5φ;
//   - η_r(φ), φ = 0.1 … 0.5, inside the band of Krieger–Dougherty (φ_m = 0.63, the frictionless
//     bound), Boyer, Guazzelli & Pouliquen (2011) and Zarraga, Hill & Leighton (2000), widened by
//     5 % for the scatter of the measurements — which the drag-only model (1 + 2.5φ) and a
//     lubrication stress off by a factor 1.5 both fail from φ = 0.2 on;
//   - friction moves the dense branch towards frictional jamming;
//   - rate independence in the Stokes regime: particle inertia at St = 0.02 and 0.2 within 5 %
//     of the overdamped limit;
//   - normal stress differences against Dai, Bertevas, Qi & Tanner (2013): N2/τ ≈ −4.4φ³,
//     N1/τ ≈ −0.8φ³, signs right and magnitudes within a factor 1.5 at φ = 0.3 and 0.45;
//   - the runner: T = η_r × the liquid's torque, F = πR²(N1 − N2)/3 for a rate-independent
//     suspension, and the sweep's N1 − N2 from F(γ̇_R) by the parallel-plate relation;
//   - the walled box: Einstein's dilute limit on the plates, the bulk approached as the gap
//     widens with an excess that falls like d/H (a wall layer), the viscosity lowered at gaps of
//     a whole number of diameters, where the spheres form layers that slide on each other
//     (Fornari, Brandt, Chaudhuri et al., PRL 116 (2016) 018301), and the runner using it below
//     H/d = 10.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "rheosim/core/config.hpp"
#include "rheosim/core/log.hpp"
#include "rheosim/coupling/suspension_box.hpp"
#include "rheosim/rheometer/analysis.hpp"
#include "rheosim/rheometer/box_point.hpp"
#include "rheosim/rheometer/case.hpp"
#include "rheosim/rheometer/plate.hpp"
#include "rheosim/rheometer/sweep.hpp"

namespace rheosim {
namespace {

using coupling::SuspensionBoxResult;
using coupling::SuspensionBoxSettings;

SuspensionBoxSettings at(double phi) {
  SuspensionBoxSettings s;
  s.volume_fraction = phi;
  return s;
}

// One box per φ and settings, run once for all the tests of this file. min_averaging > 0:
// average over at least that strain (the normal stress differences need longer averages
// than η_r: N1 is a tenth of τ).
const SuspensionBoxResult& box(double phi, double friction = 0.3, double stokes = 0.0, double min_averaging = 0.0) {
  static std::map<std::array<double, 4>, SuspensionBoxResult> runs;
  const std::array<double, 4> key{phi, friction, stokes, min_averaging};
  if (const auto it = runs.find(key); it != runs.end()) return it->second;
  auto s = at(phi);
  s.friction = friction;
  s.stokes_number = stokes;
  if (min_averaging > 0.0) {
    s.min_averaging_strain = min_averaging;
    s.max_strain = s.warmup_strain + min_averaging + 1.0;
  }
  const auto r = coupling::run_suspension_box(s);
  std::printf(
      "box φ %.3f μ_c %.2f St %.3g: η_r %.4f ± %.4f, N1/τ %.4f ± %.4f, N2/τ %.4f ± %.4f, Π/τ %.3f, "
      "contacts/sphere %.2f, overlap max %.4f, strain %.1f, %.1f s\n",
      phi, friction, stokes, r.relative_viscosity.mean, r.relative_viscosity.error,
      r.n1.mean / r.relative_viscosity.mean, r.n1.error / r.relative_viscosity.mean,
      r.n2.mean / r.relative_viscosity.mean, r.n2.error / r.relative_viscosity.mean,
      r.particle_pressure.mean / r.relative_viscosity.mean, r.mean_contacts_per_particle, r.max_overlap, r.strain,
      r.wall_time);
  return runs.emplace(key, r).first->second;
}

// The walled box at φ between plates gap_diameters d apart (500 spheres, the defaults).
const SuspensionBoxResult& walled(double phi, double gap_diameters) {
  static std::map<std::array<double, 2>, SuspensionBoxResult> runs;
  const std::array<double, 2> key{phi, gap_diameters};
  if (const auto it = runs.find(key); it != runs.end()) return it->second;
  auto s = at(phi);
  s.wall_gap = 2.0 * gap_diameters;
  const auto r = coupling::run_suspension_box(s);
  std::printf("walled box φ %.3f H/d %.2f: η_r %.4f ± %.4f, liquid shear core %.3f plates %.3f, %.1f s\n", phi,
              gap_diameters, r.relative_viscosity.mean, r.relative_viscosity.error, r.core_shear_rate,
              r.plate_shear_rate, r.wall_time);
  return runs.emplace(key, r).first->second;
}

TEST(SuspensionBoxValidation, DiluteLimitIsEinstein) {
  const double phi = 0.05;
  const auto& r = box(phi);
  EXPECT_NEAR(r.relative_viscosity.mean, 1.0 + 2.5 * phi, 0.05 * (1.0 + 2.5 * phi));
  // And above it: pair interactions add O(φ²) (Batchelor & Green: 5.2φ² = 0.013).
  EXPECT_GT(r.relative_viscosity.mean, 1.0 + 2.5 * phi);
}

TEST(SuspensionBoxValidation, ViscosityInsideTheMeasuredBand) {
  for (const double phi : {0.1, 0.2, 0.3, 0.4, 0.5}) {
    const double kd = rheometer::krieger_dougherty_relative_viscosity(phi, 0.63);
    const double boyer = rheometer::boyer_relative_viscosity(phi);
    const double zarraga = rheometer::zarraga_relative_viscosity(phi);
    const double low = 0.95 * std::min({kd, boyer, zarraga}), high = 1.05 * std::max({kd, boyer, zarraga});
    const double eta = box(phi).relative_viscosity.mean;
    EXPECT_GT(eta, low) << "φ = " << phi;
    EXPECT_LT(eta, high) << "φ = " << phi;
    // The tolerance fails what it guards against: the drag-only model, and a particle stress
    // (η_r − 1) off by a factor 1.5 either way.
    // (At φ = 0.5 the measured correlations themselves differ by 3.5×, so only the drag-only
    // model is excluded there.)
    if (phi >= 0.2) {
      EXPECT_LT(1.0 + 2.5 * phi, low) << "φ = " << phi;
    }
    if (phi >= 0.2 && phi <= 0.4) {
      EXPECT_TRUE(1.0 + 1.5 * (eta - 1.0) > high || 1.0 + (eta - 1.0) / 1.5 < low) << "φ = " << phi;
    }
  }
}

// The jamming fraction φ_J of Boyer et al.'s law that fits η_r over the given φ best (least
// squares in ln η_r, golden section on [0.52, 0.75]).
double fitted_jamming_fraction(const std::vector<double>& phis, double friction) {
  const auto misfit = [&](double jamming) {
    double sum = 0.0;
    for (const double phi : phis) {
      const double d = std::log(rheometer::boyer_relative_viscosity(phi, jamming)) -
                       std::log(box(phi, friction).relative_viscosity.mean);
      sum += d * d;
    }
    return sum;
  };
  double lo = 0.52, hi = 0.75;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int k = 0; k < 60; ++k) {
    const double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
    if (misfit(a) < misfit(b))
      hi = b;
    else
      lo = a;
  }
  return 0.5 * (lo + hi);
}

TEST(SuspensionBoxValidation, FrictionMovesTheDenseBranchTowardsFrictionalJamming) {
  // Measured non-Brownian suspensions jam at φ_J ≈ 0.585 (Boyer et al. 2011), frictionless
  // spheres near random close packing (≈ 0.64). Boyer's law fitted to the box's dense branch
  // (φ = 0.3–0.5) gives the box's jamming fraction: with the case's friction μ_c = 0.3 it must
  // lie in the measured frictional band, and without friction well above it.
  const std::vector<double> dense{0.3, 0.4, 0.5};
  const double frictional = fitted_jamming_fraction(dense, 0.3);
  const double frictionless = fitted_jamming_fraction(dense, 0.0);
  std::printf("Boyer-law jamming fraction over φ = 0.3–0.5: μ_c = 0.3: %.4f, μ_c = 0: %.4f\n", frictional,
              frictionless);
  EXPECT_GT(frictional, 0.56);
  EXPECT_LT(frictional, 0.61);
  EXPECT_GT(frictionless, frictional + 0.02);
  EXPECT_GT(box(0.5, 0.3).relative_viscosity.mean, 1.4 * box(0.5, 0.0).relative_viscosity.mean);
}

TEST(SuspensionBoxValidation, RateIndependentInTheStokesRegime) {
  // The CD §4 spheres (a = 100 µm, ρ_p = 1000, μ = 1e-3) at 10 and 100 1/s have St = 0.022 and
  // 0.22: their inertia leaves η_r within 5 % of the overdamped limit.
  const double overdamped = box(0.3).relative_viscosity.mean;
  for (const double st : {0.02, 0.2})
    EXPECT_NEAR(box(0.3, 0.3, st).relative_viscosity.mean, overdamped, 0.05 * overdamped);
}

TEST(SuspensionBoxValidation, NormalStressDifferencesAgainstDai2013) {
  for (const double phi : {0.3, 0.45}) {
    const auto& r = box(phi, 0.3, 0.0, 40.0);
    const double tau = r.relative_viscosity.mean;
    const double n1 = r.n1.mean / tau, n2 = r.n2.mean / tau;
    const double dai_n1 = -0.8 * phi * phi * phi, dai_n2 = -4.4 * phi * phi * phi;
    EXPECT_LT(n2, 0.0) << phi;
    EXPECT_LT(n1, 0.0) << phi;
    EXPECT_GT(n2 / dai_n2, 1.0 / 1.5) << phi;
    EXPECT_LT(n2 / dai_n2, 1.5) << phi;
    EXPECT_GT(n1 / dai_n1, 1.0 / 1.5) << phi;
    EXPECT_LT(n1 / dai_n1, 1.5) << phi;
    // Particle pressure positive (the spheres push the plates apart).
    EXPECT_GT(r.particle_pressure.mean, 0.0) << phi;
  }
}

TEST(SuspensionBoxValidation, YieldStressOfAPlasticMatrixFollowsChateauOvarlezTrung) {
  // A Bingham matrix at Bn = τ_y/(μ_p γ̇) = 1000, close to plastic: σ_s/τ_y → τ_y,s/τ_y. Chateau,
  // Ovarlez & Trung (2008): τ_y,s/τ_y = √((1 − φ) η_r(φ)) with the suspension's Newtonian η_r
  // (here the box's own). Measured +9 % at φ = 0.3 and +14 % at 0.4 (the pairs use Newtonian
  // resistance functions at the gap's secant viscosity); the 20 % tolerance fails the
  // defects it guards against: the secant stresslet (+43 % at 0.3) or Newtonian lubrication
  // at μ(γ̇) (+120 %).
  constexpr double bingham = 1000.0;
  for (const double phi : {0.3, 0.4}) {
    auto s = at(phi);
    s.viscosity_ratio = [](double ratio) { return (1.0 + bingham / ratio) / (1.0 + bingham); };
    s.stresslet_viscosity_ratio = 0.3 + 0.7 / (1.0 + bingham);
    const auto plastic = coupling::run_suspension_box(s);
    const double yield_ratio = plastic.relative_viscosity.mean * (1.0 + bingham) / bingham;
    const double cot = std::sqrt((1.0 - phi) * box(phi).relative_viscosity.mean);
    std::printf("φ %.2f: τ_y,s/τ_y = %.4f ± %.4f, COT √((1 − φ)η_r) = %.4f (%+.1f %%), contact part %.3f\n", phi,
                yield_ratio, plastic.relative_viscosity.error, cot, 100.0 * (yield_ratio / cot - 1.0),
                plastic.part_contact);
    EXPECT_NEAR(yield_ratio, cot, 0.2 * cot) << phi;
    EXPECT_GT(yield_ratio, 1.0 + 0.75 * phi) << phi;  // above the dilute plastic limit
  }
}

TEST(SuspensionBoxValidation, WalledBoxDiluteLimitIsEinstein) {
  // φ = 0.05 between plates 10 d apart: Einstein within 5 %, and within 3 % of the bulk box
  // (at this φ few spheres meet a plate or each other).
  const double phi = 0.05;
  const double eta = walled(phi, 10.0).relative_viscosity.mean;
  EXPECT_NEAR(eta, 1.0 + 2.5 * phi, 0.05 * (1.0 + 2.5 * phi));
  EXPECT_NEAR(eta, box(phi).relative_viscosity.mean, 0.03 * box(phi).relative_viscosity.mean);
}

TEST(SuspensionBoxValidation, WalledBoxApproachesTheBulkAsTheGapWidens) {
  // φ = 0.3: the plates add a layer about a diameter thick to the bulk stress, so the excess
  // over the Lees–Edwards box falls like d/H — about halves from H/d = 10 to 20 — and is under
  // 15 % at 20 d.
  const double bulk = box(0.3).relative_viscosity.mean;
  const double excess_10 = walled(0.3, 10.0).relative_viscosity.mean / bulk - 1.0;
  const double excess_20 = walled(0.3, 20.0).relative_viscosity.mean / bulk - 1.0;
  EXPECT_GT(excess_20, 0.0);
  EXPECT_LT(excess_20, 0.15);
  EXPECT_GT(excess_10 / excess_20, 1.3);
  EXPECT_LT(excess_10 / excess_20, 3.0);
}

TEST(SuspensionBoxValidation, WalledBoxLayersAtWholeNumbersOfDiameters) {
  // Fornari et al. (2016): at H = 2d and 3d the spheres layer and the viscosity drops; at 2.5 d
  // they cannot, and it is at least 30 % higher than at either.
  const double at_2 = walled(0.3, 2.0).relative_viscosity.mean;
  const double at_2_5 = walled(0.3, 2.5).relative_viscosity.mean;
  const double at_3 = walled(0.3, 3.0).relative_viscosity.mean;
  EXPECT_GT(at_2_5, 1.3 * std::max(at_2, at_3));
}

TEST(SuspensionBoxValidation, RunnerUsesTheWalledBoxInANarrowGap) {
  // The Stokes-regime case in a gap of 2.5 diameters: auto runs the walled box, and the torque
  // is its η_r times the liquid's.
  const rheometer::Case c = rheometer::parse_case(R"(kind: sweep
name: walled_runner
geometry: {type: parallel_plate, radius: 0.02, gap: 1.25e-4}
fluid:
  density: 1000
  rheology: {model: newtonian, viscosity: 1.0}
shear_rates: [1, 10]
volume_fractions: [0, 0.3]
particles: {diameter: 5.0e-5, density: 1050}
)",
                                                  "walled_runner.yaml");
  const auto& r = std::get<rheometer::SweepCase>(c.spec).rheometer;
  ASSERT_TRUE(rheometer::box_has_walls(r));
  const auto runner = rheometer::make_box_suspension_runner(r);
  const rheometer::ParallelPlate plate{0.02, 1.25e-4};
  const auto& b = walled(0.3, 2.5);
  for (const double rate : r.shear_rates) {
    const auto point = runner({0, "fluid", 0.3, rate}, {});
    ASSERT_TRUE(point.converged) << point.failure;
    EXPECT_EQ(point.model, "walled_box");
    EXPECT_NEAR(point.torque, b.relative_viscosity.mean * rheometer::newtonian_torque(plate, 1.0, rate),
                1e-9 * point.torque);
    EXPECT_NE(point.model_reason.find("plates:"), std::string::npos) << point.model_reason;
  }
}

TEST(SuspensionBoxValidation, RunnerTorqueAndNormalForce) {
  // A Stokes-regime suspension (50 µm spheres in a 1 Pa·s liquid, H/d = 20): one box serves
  // every rate, T = η_r T_liquid and F = πR²(N1 − N2)/3 at every rate, and the sweep's
  // N1 − N2 from F(γ̇_R) returns the box's N1 − N2.
  const rheometer::Case c = rheometer::parse_case(R"(kind: sweep
name: box_runner
geometry: {type: parallel_plate, radius: 0.02, gap: 0.001}
fluid:
  density: 1000
  rheology: {model: newtonian, viscosity: 1.0}
shear_rates: [1, 10, 100]
volume_fractions: [0, 0.3]
particles: {diameter: 5.0e-5, density: 1050}
)",
                                                  "box_runner.yaml");
  const auto& sweep = std::get<rheometer::SweepCase>(c.spec);
  const auto& r = sweep.rheometer;
  ASSERT_TRUE(rheometer::box_is_rate_independent(r));
  const auto runner = rheometer::make_box_suspension_runner(r);
  const rheometer::ParallelPlate plate{0.02, 0.001};
  const auto& b = box(0.3);  // the same settings as box_settings gives this case
  const double area = std::acos(-1.0) * 0.02 * 0.02;
  for (const double rate : r.shear_rates) {
    const auto point = runner({0, "fluid", 0.3, rate}, {});
    ASSERT_TRUE(point.converged) << point.failure;
    EXPECT_NEAR(point.torque, b.relative_viscosity.mean * rheometer::newtonian_torque(plate, 1.0, rate),
                1e-9 * point.torque);
    EXPECT_NEAR(point.normal_force, area * (b.n1.mean - b.n2.mean) * rate / 3.0, 1e-9 * std::abs(point.normal_force));
    EXPECT_GT(point.normal_force, 0.0);
    EXPECT_NEAR(point.n2, b.n2.mean * rate, 1e-12 * std::abs(point.n2));
    EXPECT_EQ(point.model, "lees_edwards");
  }
  // Through the sweep: summary.json has normal_force, n1, n2 and n1_minus_n2 per point.
  const std::filesystem::path out = std::filesystem::path("test-runs") / "box_runner";
  std::filesystem::remove_all(out);
  auto runners = rheometer::default_point_runners(r);
  runners.suspension = runner;
  const core::Log log = core::Log::console(core::Verbosity::quiet);
  const auto outcome = rheometer::run_sweep(c, out, log, runners);
  EXPECT_EQ(outcome.failed_points, 0);
  std::ifstream in(out / "summary.json");
  const auto summary = nlohmann::json::parse(in);
  int suspension_points = 0;
  for (const auto& p : summary["points"]) {
    if (p["volume_fraction"].get<double>() == 0.0) continue;
    ++suspension_points;
    const double rate = p["shear_rate"].get<double>();
    EXPECT_NEAR(p["n1_minus_n2"].get<double>(), (b.n1.mean - b.n2.mean) * rate, 1e-6 * std::abs(b.n1.mean * rate));
  }
  EXPECT_EQ(suspension_points, 3);
  // One box serves every rate, so the flow-curve fit sees no scatter: η_r's error is the box's.
  bool found = false;
  for (const auto& p : summary["relative_viscosity"][0]["points"])
    if (p["volume_fraction"].get<double>() == 0.3) {
      found = true;
      EXPECT_NEAR(p["std_error"].get<double>(), b.relative_viscosity.error, 0.02 * b.relative_viscosity.error);
      EXPECT_EQ(p["std_error_source"].get<std::string>(), "the points' shared statistical error");
    }
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace rheosim
