// Bingham dam break (LDD §4.3) at a coarse Δ = 10 mm, δt = 1e-3 s: the run must finish, keep
// its volume within 1 %, and its mass front must follow the viscous lubrication (thin-film) model
// of the same release, ∂h/∂t = ∂/∂x(ρ g h³/(3μ) ∂h/∂x) with no slip below (Huppert 1982), solved
// here independently by finite volumes. The lubrication front for μ = μ_B without the yield
// stress is an independent reference once the collapsing front is long and thin (t ≥ 0.5 s).
// LDD Table 1's experimental front is printed beside it (not asserted: with μ_B = 25 Pa·s the
// lubrication model itself reaches only 0.21 m at 1.14 s against the measured 0.60 m; see
// docs/ldd.md).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "rheosim/core/case.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd {
namespace {

// Front of the lubrication model for a reservoir [−length, 0] × height released at t = 0 (cells
// of dx, front = last cell with h > 1e-4 m), at each of `times` (ascending).
std::vector<double> lubrication_front(double rho, double g, double mu, double length, double height,
                                      const std::vector<double>& times) {
  const double dx = 0.002;
  const auto n = static_cast<std::size_t>((length + 1.5) / dx);
  std::vector<double> x(n), h(n), flux(n + 1, 0.0), fronts;
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = -length + (static_cast<double>(i) + 0.5) * dx;
    h[i] = x[i] < 0 ? height : 0.0;
  }
  const double d0 = rho * g / (3 * mu);
  double t = 0;
  for (double target : times) {
    while (t < target) {
      const double h_max = *std::max_element(h.begin(), h.end());
      const double dt = std::min(0.4 * dx * dx / (d0 * h_max * h_max * h_max), target - t);
      for (std::size_t i = 1; i < n; ++i) {
        const double hf = 0.5 * (h[i] + h[i - 1]);
        flux[i] = -d0 * hf * hf * hf * (h[i] - h[i - 1]) / dx;
      }
      for (std::size_t i = 0; i < n; ++i) h[i] -= dt / dx * (flux[i + 1] - flux[i]);
      t += dt;
    }
    double front = -length;
    for (std::size_t i = 0; i < n; ++i)
      if (h[i] > 1e-4) front = x[i] + 0.5 * dx;
    fronts.push_back(front);
  }
  return fronts;
}

TEST(DamBreakValidation, CoarseBinghamFrontFollowsTheLubricationModelAndKeepsItsVolume) {
  // One thread: the run is bit-identical per thread count, and with two threads this coarse run
  // diverges at t = 1.07 s at a free-surface node with 5 neighbours (Courant guard, 251 m/s):
  // a known robustness gap of the splash handling, recorded in docs/ldd.md.
  omp_set_num_threads(1);
  const std::string text =
      "kind: ldd\ndimension: 2\nscene: {type: dam_break, reservoir: [2.0, 0.1], channel_length: 3.0}\n"
      "fluid: {density: 1200, rheology: {model: bingham, plastic_viscosity: 25.0, yield_stress: 25.0, "
      "regularization: 1000}}\ngravity: [0, -9.81]\nresolution: {spacing: 0.01}\ntime: {step: 1.0e-3, end: 1.14}\n"
      "solver: {velocity_tolerance: 1.0e-6}\n";
  const core::LddCase l = std::get<core::LddCase>(core::parse_case(text, "inline.yaml").spec);
  const DamBreakResult r = simulate_dam_break(std::get<core::DamBreakScene>(l.scene), free_surface_params(l), l.end_time);
  ASSERT_FALSE(r.diverged) << r.message;
  const std::vector<double> times(std::begin(DamBreakReference::times), std::end(DamBreakReference::times));
  const std::vector<double> lubrication = lubrication_front(1200, 9.81, 25.0, 2.0, 0.1, times);
  std::printf("[ measured ] dam break Δ = 10 mm, δt = 1e-3 s: %zu nodes, %.3g ms/step, volume drift %.3g %%\n"
              "[ measured ] %8s %10s %12s %12s\n",
              r.nodes, r.ms_per_step, 100 * r.volume_drift, "t (s)", "exp. (m)", "LDD (m)", "lubric. (m)");
  for (std::size_t q = 0; q < times.size(); ++q)
    std::printf("[ measured ] %8.2f %10.3f %12.3f %12.3f\n", times[q], DamBreakReference::experiment[q],
                r.front_at_table1[q], lubrication[q]);
  EXPECT_LT(r.volume_drift, 0.01);
  for (std::size_t q = 3; q < times.size(); ++q)  // t = 0.56, 0.74, 1.14 s
    EXPECT_NEAR(r.front_at_table1[q] / lubrication[q], 1.0, 0.2) << "t = " << times[q];
}

}  // namespace
}  // namespace rheosim::ldd
