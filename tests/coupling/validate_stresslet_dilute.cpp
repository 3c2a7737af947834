// Dilute suspension in an imposed simple shear u∞ = γ̇ (z − z_c) e_x:
// LIGGGHTS spheres, periodic in x and y, advected by the near-field hook with
// stokes_drag + stresslet + lubrication (implicit, δt = 0.45 × the drag relaxation time and
// 1e-4 strain per step). Checked on the DEM particles as they move:
//   - they become force- and torque-free: isolated particles (no surface within a/2) move with
//     the flow (|U − u∞| < 0.01 γ̇ a) and spin with the vorticity (Ω_y = γ̇/2 within 1 %);
//   - the particle stress (stresslets + lubrication virial, Batchelor 1970) over the volume the
//     centres fill gives η_r − 1 = 2.5 φ (Einstein) + the pair term, which must be small and
//     O(φ²) (Batchelor & Green 1972: 5.2 φ² with the far field, which a near-field model lacks);
//   - a power-law matrix (n = 0.5): with the `secant` stresslet viscosity the same 2.5φ relative
//     to μ(γ̇); with the default `homogenized` one Chateau, Ovarlez & Trung's dilute limit
//     (0.75 + 1.75 n)φ = 1.625φ (J. Rheol. 52 (2008) 489; near_field.cpp).
// The relative viscosity is η_r = 1 + σ_p,xz / (μ(γ̇) γ̇), the fluid part being μ(γ̇) γ̇ (the
// Fast-Lubrication-Dynamics form of the stress, docs/hydrodynamics.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "coupling_test_support.hpp"
#include "near_field_test_support.hpp"
#include "rheosim/core/config.hpp"
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/dem/engine.hpp"

namespace rheosim::coupling {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double a = 1e-4, rho = 1000.0, rate = 100.0;

struct DiluteResult {
  double phi = 0.0;
  double relative_viscosity = 0.0;
  double lubrication_part = 0.0;  // η_r contribution of the lubrication virial
  double max_slip = 0.0;          // max |U − u∞| / (γ̇ a) at the end, isolated particles
  double mean_spin = 0.0;         // mean Ω_y / γ̇, all particles
  double max_spin_error = 0.0;    // max |Ω_y/γ̇ − 1/2|, isolated particles
};

DiluteResult run_dilute(double phi_target, std::shared_ptr<const core::Rheology> matrix, std::uint64_t seed,
                        StressletViscosity stresslet_viscosity = StressletViscosity::homogenized) {
  testing::RunFolder folder;
  const double length = 20 * a, height = 20 * a;
  const int n = static_cast<int>(std::lround(phi_target * length * length * height / (4.0 / 3.0 * pi * a * a * a)));
  // Random non-overlapping centres (gap > 0.1 a), z in [0, height], periodic in x and y.
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(0.0, length), uz(0.0, height);
  std::vector<testing::Sphere> spheres;
  const double zc = 0.5 * height;
  while (static_cast<int>(spheres.size()) < n) {
    const testing::Sphere s{.x = ux(rng), .y = ux(rng), .z = uz(rng), .radius = a, .density = rho};
    bool ok = true;
    for (const auto& o : spheres) {
      double dx = s.x - o.x, dy = s.y - o.y;
      dx -= length * std::round(dx / length);
      dy -= length * std::round(dy / length);
      const double dz = s.z - o.z;
      if (dx * dx + dy * dy + dz * dz < std::pow(2.1 * a, 2)) ok = false;
    }
    if (ok) spheres.push_back(s);
  }
  for (auto& s : spheres) s.vx = rate * (s.z - zc);  // start in the shear profile

  const double mu = matrix->viscosity(rate);
  dem::Engine engine({.run_directory = folder.path()});
  testing::make_sphere_box(engine,
                           {.low = {0, 0, -3 * a},
                            .high = {length, length, height + 3 * a},
                            .periodic = {true, true, false},
                            .time_step = 1e-6},
                           spheres);
  NearFieldSettings settings;
  settings.terms = {.lubrication = true, .single_particle = true, .stokes_drag = true};
  settings.stresslet_viscosity = stresslet_viscosity;
  NearFieldScene scene;
  scene.periodic = {true, true, false};
  scene.box_high = {length, length, 0.0};
  const AmbientFlow shear = [zc](const Vector3& x) {
    AmbientSample s;
    s.velocity = {rate * (x[2] - zc), 0.0, 0.0};
    s.velocity_gradient[2] = rate;
    return s;
  };
  NearFieldStepHook hook(engine, make_near_field_model(settings, std::move(matrix)), scene, shear);
  engine.run(5000);  // strain 0.5: spin-up (the torque relaxes in ~1e-6 s, lubrication pairs settle)
  (void)hook.take_means();
  engine.run(15000);  // strain 1.5 of measurement
  const auto means = hook.take_means();

  DiluteResult out;
  const double volume = length * length * height;
  out.phi = n * 4.0 / 3.0 * pi * a * a * a / volume;
  out.relative_viscosity = 1.0 + means.particle_stress[4] / (volume * mu * rate);
  out.lubrication_part = means.lubrication_virial[4] / (volume * mu * rate);
  const auto x = engine.positions(), v = engine.velocities(), w = engine.angular_velocities();
  const std::size_t count = engine.particle_count();
  EXPECT_EQ(static_cast<int>(count), n) << "particles were lost";
  // Slip and spin of the isolated particles (no other surface within the lubrication cutoff
  // a/2: paired particles rightly leave the affine flow, they orbit each other).
  std::size_t isolated = 0;
  for (std::size_t i = 0; i < count; ++i) {
    double nearest = 1e300;
    for (std::size_t j = 0; j < count; ++j) {
      if (j == i) continue;
      double dx = x[3 * j] - x[3 * i], dy = x[3 * j + 1] - x[3 * i + 1];
      dx -= length * std::round(dx / length);
      dy -= length * std::round(dy / length);
      nearest = std::min(nearest, std::sqrt(dx * dx + dy * dy + std::pow(x[3 * j + 2] - x[3 * i + 2], 2)) - 2 * a);
    }
    out.mean_spin += w[3 * i + 1] / rate / static_cast<double>(count);
    if (nearest < 0.5 * a) continue;
    ++isolated;
    const double slip = std::hypot(v[3 * i] - rate * (x[3 * i + 2] - zc), v[3 * i + 1], v[3 * i + 2]);
    out.max_slip = std::max(out.max_slip, slip / (rate * a));
    out.max_spin_error = std::max(out.max_spin_error, std::abs(w[3 * i + 1] / rate - 0.5));
  }
  EXPECT_GT(isolated, count / 4);
  return out;
}

void report(const char* label, const DiluteResult& r) {
  std::printf(
      "%s: φ = %.4f, η_r = %.5f (Einstein %.5f), lubrication part %.2e, max slip/(γ̇a) %.2e, "
      "mean Ω_y/γ̇ %.5f\n",
      label, r.phi, r.relative_viscosity, 1.0 + 2.5 * r.phi, r.lubrication_part, r.max_slip, r.mean_spin);
}

TEST(ValidateStressletDilute, NewtonianMatrixGivesEinstein) {
  for (const double phi : {0.02, 0.05}) {
    const DiluteResult r = run_dilute(phi, testing::newtonian(1.0), 3);
    report("newtonian", r);
    // Einstein within the O(φ²) pair part, which must itself be small and non-negative on average.
    EXPECT_NEAR(r.relative_viscosity - 1.0 - r.lubrication_part, 2.5 * r.phi, 1e-3 * 2.5 * r.phi);
    EXPECT_LT(std::abs(r.lubrication_part), 5.2 * r.phi * r.phi * 2.0);
    EXPECT_NEAR(r.relative_viscosity, 1.0 + 2.5 * r.phi, 0.1 * 2.5 * r.phi);
    // Force- and torque-free: the particles follow the flow and spin with the vorticity.
    EXPECT_LT(r.max_slip, 0.01);
    EXPECT_NEAR(r.mean_spin, 0.5, 0.02);
    EXPECT_LT(r.max_spin_error, 0.01);
  }
}

// The stresslet part (η_r − 1 − lubrication part) is exact for the imposed flow; with n = 0.5
// the secant stresslet gives 2.5φ and the homogenised one (0.3 + 0.7n) · 2.5φ = 1.625φ.
TEST(ValidateStressletDilute, PowerLawMatrixSecantAndHomogenizedStresslet) {
  const auto doc = core::Document::from_string("model: power_law\nconsistency: 3.0\nindex: 0.5\n", "rheology");
  const auto matrix = core::make_rheology(doc.root());
  for (const auto& [mode, intrinsic] :
       {std::pair{StressletViscosity::secant, 2.5}, std::pair{StressletViscosity::homogenized, 0.75 + 1.75 * 0.5}}) {
    const DiluteResult r = run_dilute(0.03, matrix, 5, mode);
    report(mode == StressletViscosity::secant ? "power_law n = 0.5, secant" : "power_law n = 0.5, homogenized", r);
    EXPECT_NEAR(r.relative_viscosity - 1.0 - r.lubrication_part, intrinsic * r.phi, 1e-3 * intrinsic * r.phi);
    EXPECT_NEAR(r.relative_viscosity, 1.0 + intrinsic * r.phi, 0.1 * intrinsic * r.phi);
    EXPECT_NEAR(r.mean_spin, 0.5, 0.02);
    EXPECT_LT(r.max_slip, 0.01);
  }
}

}  // namespace
}  // namespace rheosim::coupling
