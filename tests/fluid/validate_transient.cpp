// Transient 3D solver against the steady axisymmetric SwirlSolver: from rest, with the top
// plate spinning up impulsively, the torque must settle on the steady torque of the same (r, z)
// grid within 0.1 % — Newtonian (creeping and at a gap Reynolds number ρΩH²/μ of about 3) and
// power law n = 0.6 (creeping and inertial), with N_θ = 1 and N_θ = 8. The 3D runs must stay
// axisymmetric to round-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"
#include "rheosim/fluid/swirl.hpp"
#include "rheosim/fluid/transient.hpp"
#include "rheosim/rheometer/plate.hpp"

namespace rheosim::fluid {
namespace {

constexpr double radius = 0.015, gap = 0.0005, density = 1000;  // CD §2.3 plate, water density
constexpr int radial_cells = 16, axial_cells = 8;
const rheometer::ParallelPlate plate{radius, gap};

std::shared_ptr<const core::Rheology> law(const std::string& yaml) {
  return core::make_rheology(core::Document::from_string(yaml, "test.yaml").root());
}

struct Case {
  std::string name;
  std::string yaml;
  bool inertia = false;
  double reynolds = 0;  // target ρΩH²/μ(γ̇_R); 0: creeping at γ̇_R = 10 1/s
};

struct Outcome {
  double steady_torque = 0, transient_torque = 0, relative_difference = 0, asymmetry = 0, time = 0, wall_time = 0;
  double creeping_torque = 0;
  long steps = 0;
  int max_pressure_iterations = 0;
};

// Largest spread over θ of any field at fixed (r, z), relative to its scale.
double asymmetry(const TransientSolver& s) {
  const auto& g = s.grid();
  const std::size_t nr = g.radial_cells(), nt = g.azimuthal_cells(), nz = g.axial_cells();
  const double speed = std::abs(s.params().top_angular_velocity) * g.params().radius;
  double worst = 0;
  const auto spread = [&](std::span<const double> f, std::size_t n_i, std::size_t n_k, double scale) {
    for (std::size_t i = 0; i < n_i; ++i)
      for (std::size_t k = 0; k < n_k; ++k) {
        double lo = f[(i * nt) * n_k + k], hi = lo;
        for (std::size_t j = 1; j < nt; ++j) {
          lo = std::min(lo, f[(i * nt + j) * n_k + k]);
          hi = std::max(hi, f[(i * nt + j) * n_k + k]);
        }
        worst = std::max(worst, (hi - lo) / scale);
      }
  };
  spread(s.radial_velocity(), nr + 1, nz, speed);
  spread(s.azimuthal_velocity(), nr, nz, speed);
  spread(s.axial_velocity(), nr, nz + 1, speed);
  double p_scale = 0;
  for (double p : s.pressure()) p_scale = std::max(p_scale, std::abs(p));
  if (p_scale > 0) spread(s.pressure(), nr, nz, p_scale);
  return worst;
}

Outcome run(const Case& c, int azimuthal_cells) {
  const auto rheology = law(c.yaml);
  double rate = 10;
  if (c.reynolds > 0) {
    // Solve ρΩH²/μ(ΩR/H) = Re for Ω by fixed point (μ varies slowly with the rate).
    for (int it = 0; it < 100; ++it)
      rate = plate.rim_shear_rate(c.reynolds * rheology->viscosity(rate) / (density * gap * gap));
  }
  const double omega = plate.angular_velocity(rate);
  const double mu_rim = rheology->viscosity(rate);
  const double viscous_time = density * gap * gap / mu_rim;  // the slowest (least viscous) region

  SwirlParams sp;
  sp.grid = {radius, gap, radial_cells, 1, axial_cells, 1.0};
  sp.density = density;
  sp.rheology = rheology;
  sp.inertia = c.inertia;
  sp.tolerance = 1e-12;
  const auto steady = SwirlSolver(sp).solve(omega);
  EXPECT_TRUE(steady.converged) << c.name << ": " << steady.failure;

  TransientParams tp;
  tp.grid = {radius, gap, radial_cells, azimuthal_cells, axial_cells, 1.0};
  tp.density = density;
  tp.rheology = rheology;
  tp.inertia = c.inertia;
  tp.top_angular_velocity = omega;
  TransientSolver solver(tp);

  Outcome out;
  out.steady_torque = steady.torque;
  out.creeping_torque = rheometer::creeping_torque(plate, *rheology, rate);
  const double dt = 0.05 * viscous_time;
  const auto start = std::chrono::steady_clock::now();
  double previous = 0;
  int quiet = 0;
  while (solver.time() < 20 * viscous_time) {
    const StepReport report = solver.advance(dt);
    out.max_pressure_iterations = std::max(out.max_pressure_iterations, report.pressure_iterations);
    const double change = std::abs(report.torque - previous) / std::abs(report.torque);
    previous = report.torque;
    quiet = change < 1e-11 ? quiet + 1 : 0;
    if (quiet >= 5) break;
  }
  out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.steps = solver.step_count();
  out.time = solver.time() / viscous_time;
  out.transient_torque = solver.torque();
  out.relative_difference = std::abs(out.transient_torque - out.steady_torque) / out.steady_torque;
  out.asymmetry = azimuthal_cells > 1 ? asymmetry(solver) : 0.0;
  std::printf(
      "%-28s N_theta=%d Re=%.2f rate=%.4g 1/s: %ld steps (t = %.2f H^2 rho/mu_R), wall %.3f s, max PCG iterations %d\n"
      "    transient torque %.10e N m, steady SwirlSolver %.10e N m, rel. difference %.2e; "
      "inertia effect (steady/creeping - 1) %.3e; axisymmetry defect %.1e\n",
      c.name.c_str(), azimuthal_cells, density * omega * gap * gap / mu_rim, rate, out.steps, out.time,
      out.wall_time, out.max_pressure_iterations, out.transient_torque, out.steady_torque, out.relative_difference,
      out.steady_torque / out.creeping_torque - 1, out.asymmetry);
  return out;
}

const std::vector<Case>& cases() {
  static const std::vector<Case> all = {
      {"newtonian creeping", "model: newtonian\nviscosity: 1.0e-3\n", false, 0},
      {"newtonian inertia", "model: newtonian\nviscosity: 1.0e-3\n", true, 3},
      {"power law n=0.6 creeping", "model: power_law\nconsistency: 1.0e-3\nindex: 0.6\n", false, 0},
      {"power law n=0.6 inertia", "model: power_law\nconsistency: 1.0e-3\nindex: 0.6\n", true, 3},
  };
  return all;
}

class TransientReachesSteadyTorque : public ::testing::TestWithParam<int> {};

TEST_P(TransientReachesSteadyTorque, WithinOneTenthOfAPercent) {
  const int azimuthal_cells = GetParam();
  for (const Case& c : cases()) {
    const Outcome out = run(c, azimuthal_cells);
    EXPECT_LT(out.relative_difference, 1e-3) << c.name;
    if (azimuthal_cells > 1) {
      EXPECT_LT(out.asymmetry, 1e-12) << c.name;
    }
  }
}

std::string azimuthal_name(const ::testing::TestParamInfo<int>& param_info) {
  return "Ntheta" + std::to_string(param_info.param);
}

INSTANTIATE_TEST_SUITE_P(AzimuthalCells, TransientReachesSteadyTorque, ::testing::Values(1, 8), azimuthal_name);

}  // namespace
}  // namespace rheosim::fluid
