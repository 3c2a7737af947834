// Fluid fields at cell centres, the force models (CD eqs. 30–35) and the momentum exchange
// (CD eq. 29): action–reaction to round-off, implicit/explicit split, buoyancy from ∇p.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include <fmt/format.h>

#include "rheosim/core/config.hpp"
#include "rheosim/coupling/exchange.hpp"
#include "rheosim/coupling/fluid_fields.hpp"
#include "rheosim/coupling/forces.hpp"

namespace rheosim::coupling {
namespace {

using ::testing::ElementsAre;
constexpr double pi = std::numbers::pi;

std::shared_ptr<const core::Rheology> newtonian(double mu) {
  const auto doc = core::Document::from_string(fmt::format("model: newtonian\nviscosity: {}\n", mu), "rheology");
  return core::make_rheology(doc.root());
}

fluid::CylindricalGrid grid(int n_theta) {
  return fluid::CylindricalGrid(
      {.radius = 0.01, .gap = 0.002, .radial_cells = 8, .azimuthal_cells = n_theta, .axial_cells = 6});
}

std::size_t index(const fluid::CylindricalGrid& g, std::size_t i, std::size_t j, std::size_t k) {
  return (i * g.azimuthal_cells() + j) * g.axial_cells() + k;
}

// Every drag law is also a force model (schiller_naumann is not one of the seed's).
TEST(Forces, RegistryHasTheSeedModels) {
  EXPECT_THAT(builtin_force_models().names(),
              ElementsAre("di_felice", "pressure_gradient", "schiller_naumann", "viscous"));
  EXPECT_EQ(make_force_model("schiller_naumann")->name(), "schiller_naumann");
  for (const std::string& name : seed_force_models()) EXPECT_EQ(make_force_model(name)->name(), name);
  EXPECT_ANY_THROW((void)make_force_model("stokes_drag"));
}

TEST(Forces, PressureGradientAndViscousForcesFollowTheVolumeAndSign) {
  ParticleSample s;
  s.volume = 2e-12;
  s.pressure_gradient = {10.0, -20.0, 9810.0};
  s.stress_divergence = {1.0, 2.0, -3.0};
  std::vector<ParticleForce> f;
  const std::vector<ParticleSample> samples{s};
  std::vector<std::unique_ptr<const ForceModel>> models;
  models.push_back(make_force_model("pressure_gradient"));
  models.push_back(make_force_model("viscous"));
  compute_forces(models, {.density = 1000}, samples, f);
  EXPECT_DOUBLE_EQ(f[0].pressure_gradient[2], -2e-12 * 9810.0);  // CD eq. 34: −V∇p
  EXPECT_DOUBLE_EQ(f[0].viscous[1], 2e-12 * 2.0);  // +V∇·τ (header: the seed's sign is CFDEM's −∇·τ)
  EXPECT_DOUBLE_EQ(f[0].explicit_force[0], -2e-11 + 2e-12);
  EXPECT_EQ(f[0].drag_coefficient, 0.0);
}

TEST(Forces, DragUsesTheLocalViscosityAndVoidFraction) {
  ParticleSample s;
  s.diameter = 2e-4;
  s.volume = pi / 6 * 8e-12;
  s.velocity = {0, 0, -1e-3};
  s.void_fraction = 0.8;
  s.viscosity = 0.05;
  std::vector<ParticleForce> f;
  std::vector<std::unique_ptr<const ForceModel>> models;
  models.push_back(make_force_model("di_felice"));
  compute_forces(models, {.density = 1000}, std::vector<ParticleSample>{s}, f);
  const double re = 0.8 * 1000 * 2e-4 * 1e-3 / 0.05;
  const double chi = 3.7 - 0.65 * std::exp(-std::pow(1.5 - std::log10(re), 2) / 2);
  const double beta = pi / 8 * 0.05 * 2e-4 * std::pow(0.8, 1 - chi) * std::pow(4.8 + 0.63 * std::sqrt(re), 2);
  EXPECT_NEAR(f[0].drag_coefficient, beta, 1e-12 * beta);
  EXPECT_NEAR(f[0].drag[2], beta * 1e-3, 1e-12 * beta * 1e-3);
  EXPECT_NEAR(f[0].total(s)[2], beta * 1e-3, 1e-12 * beta * 1e-3);
}

TEST(FluidFields, GradientOfALinearFieldIsExact) {
  const fluid::CylindricalGrid g = grid(12);
  FluidCellFields fields(g);
  std::vector<double> p(g.cell_count());
  for (std::size_t i = 0; i < g.radial_cells(); ++i)
    for (std::size_t j = 0; j < g.azimuthal_cells(); ++j)
      for (std::size_t k = 0; k < g.axial_cells(); ++k)
        p[index(g, i, j, k)] = 3.0 * g.radial_centres()[i] - 7.0 * g.axial_centres()[k];
  CellVectorField grad;
  grad.resize(g.cell_count());
  fields.gradient(p, grad);
  for (std::size_t c = 0; c < p.size(); ++c) {
    EXPECT_NEAR(grad.radial[c], 3.0, 1e-10);
    EXPECT_NEAR(grad.azimuthal[c], 0.0, 1e-10);
    EXPECT_NEAR(grad.axial[c], -7.0, 1e-10);
  }
}

// u_θ = Ω r z/H (creeping Couette between the plates) has ∇²u = 0: the stress divergence of the
// fluid in the rheometer gap vanishes, up to the rim cell (shear-free rim is exact there too).
TEST(FluidFields, VectorLaplacianOfTheCouetteProfileVanishes) {
  for (const int n_theta : {1, 16}) {
    const fluid::CylindricalGrid g = grid(n_theta);
    FluidCellFields fields(g);
    const double omega = 3.0, gap = g.params().gap;
    CellVectorField u, lap;
    u.resize(g.cell_count());
    lap.resize(g.cell_count());
    for (std::size_t i = 0; i < g.radial_cells(); ++i)
      for (std::size_t j = 0; j < g.azimuthal_cells(); ++j)
        for (std::size_t k = 0; k < g.axial_cells(); ++k)
          u.azimuthal[index(g, i, j, k)] = omega * g.radial_centres()[i] * g.axial_centres()[k] / gap;
    fields.vector_laplacian(u, 0.0, omega, lap);
    // Scale: Ω R/H² = 7500 1/(m·s); the profile is resolved exactly by the finite volumes.
    for (std::size_t c = 0; c < g.cell_count(); ++c) {
      EXPECT_NEAR(lap.azimuthal[c], 0.0, 1e-9 * omega * g.params().radius / (gap * gap)) << n_theta << " " << c;
      EXPECT_NEAR(lap.radial[c], 0.0, 1e-9);
    }
  }
}

// Generalized Newtonian: a power-law fluid in creeping Couette flow has μ varying with r
// (γ̇ = Ωr/H) and still ∇·τ = 0 (τ_rθ = 0, τ_θz uniform in z): the 2E·∇μ path adds nothing spurious.
TEST(FluidFields, PowerLawCouetteHasNoStressDivergence) {
  const auto doc = core::Document::from_string("model: power_law\nconsistency: 0.01\nindex: 0.5\n", "rheology");
  fluid::TransientParams params;
  params.grid = grid(8).params();
  params.density = 1000;
  params.rheology = core::make_rheology(doc.root());
  params.inertia = false;
  params.top_angular_velocity = 2.0;
  fluid::TransientSolver solver(params);
  const fluid::CylindricalGrid& g = solver.grid();
  const std::size_t nr = g.radial_cells(), nt = g.azimuthal_cells(), nz = g.axial_cells();
  std::vector<double> ur((nr + 1) * nt * nz, 0.0), ut(nr * nt * nz), uz(nr * nt * (nz + 1), 0.0);
  for (std::size_t i = 0; i < nr; ++i)
    for (std::size_t j = 0; j < nt; ++j)
      for (std::size_t k = 0; k < nz; ++k)
        ut[index(g, i, j, k)] = 2.0 * g.radial_centres()[i] * g.axial_centres()[k] / g.params().gap;
  solver.set_velocity(ur, ut, uz);
  for (int s = 0; s < 3; ++s) solver.advance(1e-3);
  FluidCellFields fields(g);
  fields.update(solver);
  const auto mu = fields.viscosity();
  EXPECT_GT(mu[index(g, 0, 0, 1)], 1.5 * mu[index(g, nr - 1, 0, 1)]);  // shear thinning: μ falls with r
  // Scale of the individual terms: μ Ω R / H².
  const double scale = mu[index(g, nr - 1, 0, 1)] * 2.0 * g.params().radius / std::pow(g.params().gap, 2);
  for (std::size_t c = 0; c < g.cell_count(); ++c) {
    EXPECT_NEAR(fields.stress_divergence().azimuthal[c], 0.0, 1e-6 * scale) << c;
    EXPECT_NEAR(fields.stress_divergence().radial[c], 0.0, 1e-6 * scale) << c;
    EXPECT_NEAR(fields.stress_divergence().axial[c], 0.0, 1e-6 * scale) << c;
  }
}

// Random particles, fluid velocities and forces: the fluid's source at the sampled velocity is
// exactly minus the drag on the particles (N_θ > 1: all components; N_θ = 1: axial).
TEST(Exchange, ActionReactionToRoundOff) {
  for (const int n_theta : {1, 8}) {
    const fluid::CylindricalGrid g = grid(n_theta);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<double> positions, velocities, radii;
    for (int p = 0; p < 300; ++p) {
      const double r = 0.0101 * u01(rng), t = 2 * pi * u01(rng);
      positions.insert(positions.end(), {r * std::cos(t), r * std::sin(t), 0.002 * u01(rng)});
      velocities.insert(velocities.end(), {u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5});
      radii.push_back(1e-4);
    }
    const ParticleView view{.positions = positions, .velocities = velocities, .radii = radii};
    VoidFractionField field(g, 0.05);
    field.update(*make_void_fraction_scheme("divided"), view);
    std::vector<ParticleSample> samples(radii.size());
    for (std::size_t p = 0; p < samples.size(); ++p) {
      ParticleSample& s = samples[p];
      s.position = view.position(p);
      s.velocity = view.velocity(p);
      s.diameter = 2e-4;
      s.volume = sphere_volume_from_radius(1e-4);
      s.theta = std::atan2(s.position[1], s.position[0]);
      s.fluid_velocity = {u01(rng), u01(rng) - 0.5, 0.1 * u01(rng)};
      s.void_fraction = 0.9;
      s.viscosity = 1e-3;
      s.pressure_gradient = {0, 0, 9810};
    }
    std::vector<std::unique_ptr<const ForceModel>> models;
    for (const std::string& name : seed_force_models()) models.push_back(make_force_model(name));
    std::vector<ParticleForce> forces;
    compute_forces(models, {.density = 1000}, samples, forces);
    MomentumExchange exchange(g);
    exchange.build(field.map(), samples, forces);
    const ExchangeBalance b = exchange.balance(field.map(), samples, forces);
    EXPECT_EQ(b.axial_only, n_theta == 1);
    EXPECT_LT(b.relative_error, 1e-14) << n_theta;
    EXPECT_NEAR(b.drag_on_particles[2], -b.drag_to_fluid[2], 1e-13 * std::abs(b.drag_on_particles[2]));
    if (n_theta > 1) {
      for (std::size_t d = 0; d < 2; ++d)
        EXPECT_NEAR(b.drag_on_particles[d], -b.drag_to_fluid[d], 1e-13 * std::abs(b.drag_on_particles[d]));
    }
    for (const double k : exchange.drag_coefficient()) EXPECT_GE(k, 0.0);
    // Σ K V = Σ β (the implicit coefficient carries every particle's β once).
    double kv = 0.0, beta = 0.0;
    for (std::size_t c = 0; c < g.cell_count(); ++c)
      kv += exchange.drag_coefficient()[c] *
            g.cell_volume(c / (g.azimuthal_cells() * g.axial_cells()), c % g.axial_cells());
    for (const ParticleForce& f : forces) beta += f.drag_coefficient;
    EXPECT_NEAR(kv, beta, 1e-13 * beta);
  }
}

// A fluid at rest under gravity: the solver's hydrostatic pressure gives ∇p = ρ g, and the
// pressure-gradient force is the buoyancy ρ V g upwards (CD eq. 34).
TEST(Sampler, HydrostaticPressureGivesBuoyancy) {
  const fluid::CylindricalGrid g = grid(8);
  fluid::TransientParams params;
  params.grid = g.params();
  params.density = 1000;
  params.rheology = newtonian(1e-3);
  params.axial_gravity = -9.81;
  fluid::TransientSolver solver(params);
  for (int s = 0; s < 3; ++s) solver.advance(1e-4);
  const std::vector<double> positions{0.004, 0.001, 0.0009, -0.002, -0.006, 0.0013};
  const std::vector<double> velocities(6, 0.0), radii{1e-4, 1e-4};
  const ParticleView view{.positions = positions, .velocities = velocities, .radii = radii};
  VoidFractionField field(g, 0.05);
  field.update(*make_void_fraction_scheme("divided"), view);
  FluidSampler sampler(g);
  std::vector<ParticleSample> samples;
  sampler.sample(solver, field, view, samples);
  ASSERT_EQ(samples.size(), 2u);
  for (const ParticleSample& s : samples) {
    EXPECT_NEAR(s.pressure_gradient[2], -9810.0, 1e-6 * 9810.0);
    EXPECT_NEAR(s.pressure_gradient[0], 0.0, 1e-6 * 9810.0);
    EXPECT_NEAR(std::hypot(s.fluid_velocity[0], s.fluid_velocity[1], s.fluid_velocity[2]), 0.0, 1e-12);
    EXPECT_NEAR(s.viscosity, 1e-3, 1e-15);
    EXPECT_NEAR(s.void_fraction, 1.0, 1e-2);  // one small particle in a cell of ~1e-9 m³
  }
}

}  // namespace
}  // namespace rheosim::coupling
