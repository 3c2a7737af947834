// Validation: a neutrally buoyant particle released at rest in the sheared gap
// (creeping Couette flow u_θ = Ω r z/H between a fixed and a rotating plate) picks up the fluid
// velocity and then follows the fluid on its circle: drag accelerates it, and the centripetal
// force of its circular path comes from the fluid's radial pressure gradient (CD eq. 34).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "coupling_test_support.hpp"
#include "rheosim/coupling/coupler.hpp"

namespace rheosim::coupling {
namespace {

class Validation : public ::testing::Test {
 protected:
  testing::RunFolder folder_;
};

TEST_F(Validation, NeutrallyBuoyantParticleFollowsTheShearedFluid) {
  const double radius = 0.005, gap = 0.001, rim_shear_rate = 10.0, rho = 1000.0, mu = 1e-3, d = 1e-4;
  const double omega = rim_shear_rate * gap / radius;  // Ω = γ̇_R H / R
  fluid::TransientParams fp;
  fp.grid = {.radius = radius, .gap = gap, .radial_cells = 8, .azimuthal_cells = 16, .axial_cells = 4};
  fp.density = rho;
  fp.rheology = testing::newtonian(mu);
  fp.top_angular_velocity = omega;
  fluid::TransientSolver fluid(fp);
  // Start from the developed Couette profile.
  const fluid::CylindricalGrid& g = fluid.grid();
  const std::size_t nr = g.radial_cells(), nt = g.azimuthal_cells(), nz = g.axial_cells();
  std::vector<double> ur((nr + 1) * nt * nz, 0.0), ut(nr * nt * nz), uz(nr * nt * (nz + 1), 0.0);
  for (std::size_t i = 0; i < nr; ++i)
    for (std::size_t j = 0; j < nt; ++j)
      for (std::size_t k = 0; k < nz; ++k)
        ut[(i * nt + j) * nz + k] = omega * g.radial_centres()[i] * g.axial_centres()[k] / gap;
  fluid.set_velocity(ur, ut, uz);

  const double r0 = 0.003, t0 = 0.3, z0 = 0.55 * gap;
  dem::Engine engine({.run_directory = folder_.path()});
  testing::make_box(engine, radius, gap, 1e-5, 0.0,
                    {{.x = r0 * std::cos(t0), .y = r0 * std::sin(t0), .z = z0, .diameter = d, .density = rho}});
  CouplerSettings settings;
  settings.coupling_interval = 10;
  settings.fluid_time_step = 1e-4;
  settings.particle_density = rho;
  Coupler coupler(settings, engine, fluid);
  coupler.run_until(0.03);  // 54 particle relaxation times t_p = ρ_p d²/(18 μ) = 0.56 ms

  const ParticleSample& s = coupler.samples().at(0);
  const double r = std::hypot(s.position[0], s.position[1]);
  const double azimuthal = (-s.position[1] * s.velocity[0] + s.position[0] * s.velocity[1]) / r;
  const double fluid_speed = std::hypot(s.fluid_velocity[0], s.fluid_velocity[1], s.fluid_velocity[2]);
  const double slip = std::hypot(s.fluid_velocity[0] - s.velocity[0], s.fluid_velocity[1] - s.velocity[1],
                                 s.fluid_velocity[2] - s.velocity[2]);
  const double couette = omega * r * s.position[2] / gap;
  std::printf(
      "sheared particle: r %.6e → %.6e m, z %.6e → %.6e m, u_θ,p = %.6e m/s, fluid there %.6e m/s "
      "(|slip|/|u_f| = %.2e), Couette Ωrz/H = %.6e m/s (error %.3f %%), fluid torque %.4e N·m\n",
      r0, r, z0, s.position[2], azimuthal, fluid_speed, slip / fluid_speed, couette, 100 * (azimuthal / couette - 1),
      coupler.last().record.fluid_torque);
  EXPECT_LT(slip / fluid_speed, 0.01);
  EXPECT_NEAR(azimuthal, couette, 0.02 * couette);
  EXPECT_NEAR(r, r0, 0.01 * r0);
  EXPECT_NEAR(s.position[2], z0, 0.02 * gap);
  EXPECT_GT(coupler.last().record.fluid_torque, 0.0);
}

}  // namespace
}  // namespace rheosim::coupling
