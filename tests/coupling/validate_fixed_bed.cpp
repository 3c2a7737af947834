// Validation: a fixed packed bed at ε = 0.4 gives Ergun's pressure drop within
// 10 % through the coupled pieces (void fraction → sampler → Di Felice drag → implicit exchange →
// TransientSolver pressure).
// Set-up: the fluid's closed cylinder (R = H = 10 mm, N_θ = 1, N_r = 2, N_z = 4) filled with a
// frozen bed, ε = 0.4 exactly in every cell (centre scheme, 60 and 180 particles per layer in
// the inner and outer ring, centres random inside the cells; overlaps do not matter for frozen
// particles). A closed container admits no throughflow, so the bed moves instead: every particle
// has velocity −u ẑ (interstitial u = U/ε for superficial U) while its position is frozen — the
// Galilean image of fluid flowing up through a fixed bed. ε stays uniform, the fluid stays at
// rest, and the pressure gradient balances the drag: −ε∇p = n f_d (set II, CD eqs. 27, 29).
// Ergun: ΔP/L = 150 μ (1−ε)² U/(ε³ d²) + 1.75 ρ (1−ε) U²/(ε³ d).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "coupling_test_support.hpp"
#include "rheosim/coupling/exchange.hpp"
#include "rheosim/coupling/forces.hpp"
#include "rheosim/coupling/void_fraction.hpp"

namespace rheosim::coupling {
namespace {

constexpr double pi = std::numbers::pi;

struct Bed {
  double pressure_drop_per_length, ergun, reynolds;
};

Bed fixed_bed(double superficial_reynolds) {
  const double radius = 0.01, gap = 0.01, rho = 1000.0, mu = 1e-3, eps = 0.4;
  fluid::TransientParams fp;
  fp.grid = {.radius = radius, .gap = gap, .radial_cells = 2, .azimuthal_cells = 1, .axial_cells = 4};
  fp.density = rho;
  fp.rheology = testing::newtonian(mu);
  fluid::TransientSolver fluid(fp);
  const fluid::CylindricalGrid& grid = fluid.grid();

  // 60 particles per inner cell, 180 per outer (3× the volume): (1 − ε) of each cell.
  const int inner = 60;
  const double particle_volume = (1.0 - eps) * grid.cell_volume(0, 0) / inner;
  const double d = std::cbrt(6.0 * particle_volume / pi);
  const double superficial = superficial_reynolds * mu / (rho * d);
  const double interstitial = superficial / eps;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0.02, 0.98);
  std::vector<double> positions, velocities, radii;
  for (std::size_t k = 0; k < grid.axial_cells(); ++k)
    for (std::size_t i = 0; i < 2; ++i)
      for (int n = 0; n < (i == 0 ? inner : 3 * inner); ++n) {
        const double r0 = grid.radial_faces()[i], r1 = grid.radial_faces()[i + 1];
        const double r = std::sqrt(r0 * r0 + u01(rng) * (r1 * r1 - r0 * r0)), t = 2 * pi * u01(rng);
        positions.insert(positions.end(),
                         {r * std::cos(t), r * std::sin(t), grid.axial_faces()[k] + u01(rng) * grid.axial_width(k)});
        velocities.insert(velocities.end(), {0.0, 0.0, -interstitial});
        radii.push_back(0.5 * d);
      }
  const ParticleView bed{.positions = positions, .velocities = velocities, .radii = radii};
  VoidFractionField void_fraction(grid, 0.05);
  const VoidFractionReport& report = void_fraction.update(*make_void_fraction_scheme("centre"), bed);
  EXPECT_LT(report.relative_error, 1e-13);
  for (const double e : void_fraction.void_fraction()) EXPECT_NEAR(e, eps, 1e-12);
  fluid.reset_void_fraction(void_fraction.void_fraction());

  FluidSampler sampler(grid);
  MomentumExchange exchange(grid);
  std::vector<std::unique_ptr<const ForceModel>> models;
  for (const std::string& name : seed_force_models()) models.push_back(make_force_model(name));
  std::vector<ParticleSample> samples;
  std::vector<ParticleForce> forces;
  for (int step = 0; step < 20; ++step) {
    sampler.sample(fluid, void_fraction, bed, samples);
    compute_forces(models, {.density = rho}, samples, forces);
    exchange.build(void_fraction.map(), samples, forces);
    fluid.set_momentum_source(exchange.source());
    fluid.advance(1e-3);
  }
  // Mean pressure of the bottom and top layers.
  const auto p = fluid.pressure();
  const std::size_t nz = grid.axial_cells();
  const auto layer = [&](std::size_t k) {
    return (p[k] * grid.cell_volume(0, k) + p[nz + k] * grid.cell_volume(1, k)) /
           (grid.cell_volume(0, k) + grid.cell_volume(1, k));
  };
  const double length = grid.axial_centres()[nz - 1] - grid.axial_centres()[0];
  const double dp = (layer(0) - layer(nz - 1)) / length;
  const double ergun = 150.0 * mu * (1 - eps) * (1 - eps) * superficial / (eps * eps * eps * d * d) +
                       1.75 * rho * (1 - eps) * superficial * superficial / (eps * eps * eps * d);
  return {dp, ergun, superficial_reynolds};
}

TEST(Validation, FixedBedGivesErgunPressureDrop) {
  for (const double reynolds : {0.1, 1.0, 10.0, 100.0}) {
    const Bed b = fixed_bed(reynolds);
    std::printf("fixed bed ε = 0.4, Re = ρUd/μ = %g: ΔP/L = %.6e Pa/m, Ergun %.6e Pa/m, ratio %.4f\n", b.reynolds,
                b.pressure_drop_per_length, b.ergun, b.pressure_drop_per_length / b.ergun);
    EXPECT_NEAR(b.pressure_drop_per_length, b.ergun, 0.10 * b.ergun) << reynolds;
  }
}

}  // namespace
}  // namespace rheosim::coupling
