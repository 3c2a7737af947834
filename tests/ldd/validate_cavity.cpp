// LDD lid-driven cavity against Ghia, Ghia & Shin (1982), Tables I–II (ldd/cavity_reference.hpp)
// at Re = 100 and 1000, and robustness at Bn = 10. The runs are ldd::run_case, the loop
// `rheosim run` uses, read back from their summary.json (`ghia`: the run's own comparison).
//
// Cheap resolutions so the whole file stays under a minute on one core; docs/ldd.md holds the
// finer study. Tolerances (max |Δu|/U over Ghia's 34 centre-line points), set from the measured
// errors of the quadratic lattice interpolation (docs/ldd.md, Accuracy): Re = 100 at 32² < 0.02
// (measured 0.017) and 48² < 0.01 (0.008), falling at an observed order > 1.5 (1.84; the
// first-order Shepard interpolation gave 0.055 / 0.046, order 0.4); Re = 1000 at 64², run to
// steady state, < 0.13 (0.111; Shepard: 0.33 at 50², 0.20 at 100²).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rheosim/core/log.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/cavity_reference.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd {
namespace {

// A unit cavity (ρ = 1, U = 1, L = 1) run to steady state on one thread, the residual sampled every
// 0.25 L/U; returns its summary.json.
nlohmann::json run_cavity(const std::string& name, const std::string& rheology, int cells, double dt, double end) {
  const std::string deck = fmt::format(
      "kind: ldd\nname: {}\ndimension: 2\nscene: {{type: cavity, size: [1, 1], lid_velocity: 1}}\n"
      "fluid: {{density: 1, rheology: {}}}\ngravity: [0, 0]\nresolution: {{spacing: {:.17g}}}\n"
      "time: {{step: {}, end: {}, steady_tolerance: 1.0e-4}}\noutput: {{frame_interval: {}, probe_interval: 0.25}}\n"
      "solver: {{threads: 1}}\n",
      name, rheology, 1.0 / cells, dt, end, end);
  const auto dir = std::filesystem::temp_directory_path() / ("rheosim_validate_cavity_" + name);
  std::filesystem::remove_all(dir);
  (void)run_case(parse_case(deck, name + ".yaml"), dir, core::Log::null());
  auto summary = core::read_json(dir / "summary.json");
  std::printf("[ measured ] %s, %d² cells, δt %g: %s at t = %.2f s (%d steps, residual %.1e), %.2f ms/step%s\n",
              name.c_str(), cells, dt, summary["status"].get<std::string>().c_str(), summary["time"].get<double>(),
              summary["steps"].get<int>(), summary["final_residual"].get<double>(),
              summary["ms_per_step"].get<double>(),
              summary.contains("ghia")
                  ? fmt::format(", max |error| vs Ghia = {:.4f}", summary["ghia"]["max_error"].get<double>()).c_str()
                  : "");
  std::filesystem::remove_all(dir);
  return summary;
}

constexpr const char* re100 = "{model: newtonian, viscosity: 0.01}";
constexpr const char* re1000 = "{model: newtonian, viscosity: 0.001}";

TEST(CavityValidation, Re100ConvergesToGhia) {
  ASSERT_EQ(ghia_1982().size(), 34U);
  const auto coarse = run_cavity("re100_32", re100, 32, 0.01, 40.0);
  const auto fine = run_cavity("re100_48", re100, 48, 0.01, 40.0);
  ASSERT_EQ(coarse["status"], "steady");
  ASSERT_EQ(fine["status"], "steady");
  ASSERT_EQ(coarse["ghia"]["reynolds"], 100);
  const double coarse_error = coarse["ghia"]["max_error"].get<double>();
  const double fine_error = fine["ghia"]["max_error"].get<double>();
  EXPECT_LT(coarse_error, 0.02);
  EXPECT_LT(fine_error, 0.01);
  const double order = std::log(coarse_error / fine_error) / std::log(48.0 / 32.0);
  std::printf("[ measured ] observed order 32² → 48²: %.2f\n", order);
  EXPECT_GT(order, 1.5);
}

TEST(CavityValidation, Re1000ReachesSteadyStateNearGhia) {
  // δt = 0.0075 s: Courant number 0.48 at the lid; the primary vortex settles by t ≈ 56 s.
  const auto run = run_cavity("re1000_64", re1000, 64, 0.0075, 80.0);
  ASSERT_EQ(run["status"], "steady");
  ASSERT_EQ(run["ghia"]["reynolds"], 1000);
  EXPECT_LT(run["final_residual"].get<double>(), 1e-4);
  EXPECT_LT(run["ghia"]["max_error"].get<double>(), 0.13);
}

TEST(CavityValidation, BinghamNumber10RunsWithoutNaN) {
  // Bn = τ₀L/(μ∞U) = 10 at Re = 100: μ∞ = 0.01 Pa·s, τ₀ = 0.1 Pa (LDD eqs. 7, 21–22).
  const auto run =
      run_cavity("bingham_bn10", "{model: bingham, plastic_viscosity: 0.01, yield_stress: 0.1, regularization: 1000}",
                 32, 0.01, 10.0);
  ASSERT_NE(run["status"], "diverged") << run.value("message", "");
  EXPECT_FALSE(run.contains("ghia")) << "Ghia's table is for Newtonian liquids";
  for (const auto& line : {"vertical", "horizontal"})
    for (const auto& p : run["centerlines"][line])
      EXPECT_TRUE(p[std::string(line) == "vertical" ? "u" : "v"].is_number()) << line;
  std::printf("[ measured ] Bingham Bn 10: u(0.5, 0.9) = %.4f U\n",
              run["centerlines"]["vertical"][90]["u"].get<double>());
}

}  // namespace
}  // namespace rheosim::ldd
