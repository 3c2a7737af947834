// LDD lid-driven cavity against Ghia, Ghia & Shin (1982), Tables I–II
// (tests/ldd/data/ghia1982_centerlines.csv) at Re = 100 and 1000, and robustness at Bn = 10.
//
// Cheap resolutions so the whole file stays under a minute on one core; docs/ldd.md holds the
// finer study. Tolerances (max |Δu|/U over Ghia's 34 centre-line points), set from the measured
// errors of the quadratic lattice interpolation (docs/ldd.md, Accuracy): Re = 100 at 32² < 0.02
// (measured 0.017) and 48² < 0.01 (0.008), falling at an observed order > 1.5 (1.84; the
// first-order Shepard interpolation gave 0.055 / 0.046, order 0.4); Re = 1000 at 64², run to
// steady state, < 0.13 (0.111; Shepard: 0.33 at 50², 0.20 at 100²).
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "data/ghia1982.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd {
namespace {

using reference::GhiaPoint;

std::vector<GhiaPoint> ghia() { return reference::ghia1982(RHEOSIM_SOURCE_DIR); }

std::vector<double> probe_fractions(const std::vector<GhiaPoint>& points) {
  return reference::ghia_probe_fractions(points);
}

class RheologyFromYaml {
 public:
  static std::shared_ptr<const core::Rheology> make(const std::string& rheology_yaml) {
    const std::string text =
        "kind: ldd\ndimension: 2\nscene: {type: cavity, size: [1, 1], lid_velocity: 1}\n"
        "fluid: {density: 1, rheology: " +
        rheology_yaml + "}\ngravity: [0, 0]\nresolution: {spacing: 0.1}\ntime: {step: 1, end: 1}\n";
    return ldd::parse_case(text, "inline.yaml").settings.fluid.rheology;
  }
};

struct GhiaRun {
  CavityResult result;
  double max_error = 0;
};

GhiaRun run_against_ghia(int cells, double dt, double end, double steady_tolerance, bool re1000) {
  omp_set_num_threads(1);
  const auto points = ghia();
  ldd::CavityScene scene;
  scene.size = {1.0, 1.0};
  scene.lid_velocity = 1.0;
  SolverParams params;
  params.rheology =
      RheologyFromYaml::make(re1000 ? "{model: newtonian, viscosity: 0.001}" : "{model: newtonian, viscosity: 0.01}");
  params.spacing = 1.0 / cells;
  params.time_step = dt;
  GhiaRun run;
  run.result = simulate_cavity(scene, params, end, steady_tolerance, probe_fractions(points));
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double computed = run.result.probe_velocity[2 * k + (points[k].line == 'u' ? 0 : 1)];
    const double reference = re1000 ? points[k].re1000 : points[k].re100;
    run.max_error = std::max(run.max_error, std::abs(computed - reference));
  }
  std::printf(
      "[ measured ] Re %d, %d² cells, δt %g: t = %.2f s (%zu steps, residual %.1e), max |error| vs Ghia = %.4f, "
      "%.2f ms/step\n",
      re1000 ? 1000 : 100, cells, dt, run.result.time, run.result.steps, run.result.final_residual, run.max_error,
      run.result.ms_per_step);
  return run;
}

TEST(CavityValidation, Re100ConvergesToGhia) {
  ASSERT_EQ(ghia().size(), 34U);
  const GhiaRun coarse = run_against_ghia(32, 0.01, 40.0, 1e-4, false);
  const GhiaRun fine = run_against_ghia(48, 0.01, 40.0, 1e-4, false);
  ASSERT_FALSE(coarse.result.diverged) << coarse.result.message;
  ASSERT_FALSE(fine.result.diverged) << fine.result.message;
  EXPECT_LT(coarse.max_error, 0.02);
  EXPECT_LT(fine.max_error, 0.01);
  const double order = std::log(coarse.max_error / fine.max_error) / std::log(48.0 / 32.0);
  std::printf("[ measured ] observed order 32² → 48²: %.2f\n", order);
  EXPECT_GT(order, 1.5);
}

TEST(CavityValidation, Re1000ReachesSteadyStateNearGhia) {
  // δt = 0.0075 s: Courant number 0.48 at the lid; the primary vortex settles by t ≈ 56 s.
  const GhiaRun run = run_against_ghia(64, 0.0075, 80.0, 1e-4, true);
  if (run.result.diverged) std::printf("diverged: %s\n", run.result.message.c_str());
  ASSERT_FALSE(run.result.diverged) << run.result.message;
  EXPECT_LT(run.result.final_residual, 1e-4);
  EXPECT_LT(run.max_error, 0.13);
}

TEST(CavityValidation, BinghamNumber10RunsWithoutNaN) {
  // Bn = τ₀L/(μ∞U) = 10 at Re = 100: μ∞ = 0.01 Pa·s, τ₀ = 0.1 Pa (LDD eqs. 7, 21–22).
  omp_set_num_threads(1);
  ldd::CavityScene scene;
  scene.size = {1.0, 1.0};
  scene.lid_velocity = 1.0;
  SolverParams params;
  params.rheology =
      RheologyFromYaml::make("{model: bingham, plastic_viscosity: 0.01, yield_stress: 0.1, regularization: 1000}");
  params.spacing = 1.0 / 32;
  params.time_step = 0.01;
  const std::vector<double> centre{0.5, 0.5, 0.5, 0.9};
  const CavityResult r = simulate_cavity(scene, params, 10.0, 1e-4, centre);
  if (r.diverged) std::printf("diverged: %s\n", r.message.c_str());
  std::printf("[ measured ] Bingham Bn 10, 32² cells: t = %.2f s, residual %.1e, u(0.5, 0.9) = %.4f, %.2f ms/step\n",
              r.time, r.final_residual, r.probe_velocity[2], r.ms_per_step);
  ASSERT_FALSE(r.diverged) << r.message;
  for (double v : r.probe_velocity) EXPECT_TRUE(std::isfinite(v));
}

}  // namespace
}  // namespace rheosim::ldd
