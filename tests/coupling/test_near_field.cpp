// coupling::NearFieldModel: the term registry and settings checks, the single-particle
// torque and stresslet against Stokes' closed forms, the implicit update of the stiff squeeze
// against the quasi-static two-sphere trajectory (at a δt far beyond the explicit limit), the
// periodic cell-list neighbour search against brute force, and the plate bookkeeping.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "coupling_test_support.hpp"
#include "rheosim/core/config.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/coupling/suspended_particles.hpp"

namespace rheosim::coupling {
namespace {

constexpr double pi = std::numbers::pi;
using testing::newtonian;

std::unique_ptr<const NearFieldModel> model(NearFieldTerms terms, double mu = 1.0) {
  NearFieldSettings s;
  s.terms = terms;
  return make_near_field_model(s, newtonian(mu));
}

AmbientFlow simple_shear(double rate) {
  return [rate](const Vector3& x) {
    AmbientSample s;
    s.velocity = {rate * x[2], 0.0, 0.0};
    s.velocity_gradient[2] = rate;  // ∂u_x/∂z
    return s;
  };
}

// The model's name lists the terms on in one order (the case reader turns the case file's names
// into these flags; its unknown-term error is tested below with the case keys).
TEST(NearFieldRegistry, NamesTheTermsItCombines) {
  EXPECT_EQ(model({.lubrication = true, .single_particle = true})->name(), "lubrication+stresslet");
  EXPECT_EQ(model({.lubrication = true, .stokes_drag = true, .repulsion = false})->name(), "lubrication+stokes_drag");
  EXPECT_EQ(model({})->name(), "none");
  EXPECT_EQ((NearFieldTerms{.lubrication = true, .repulsion = true}.name()), "lubrication+repulsion");
  EXPECT_FALSE(NearFieldTerms{}.any());
}

TEST(NearFieldRegistry, ChecksRanges) {
  NearFieldSettings s;
  s.roughness = 0.0;
  EXPECT_THROW((void)make_near_field_model(s, newtonian(1.0)), std::invalid_argument);
  s.roughness = 1e-3;
  s.lubrication_cutoff = 2.0;
  EXPECT_THROW((void)make_near_field_model(s, newtonian(1.0)), std::invalid_argument);
  s.lubrication_cutoff = 0.5;
  EXPECT_THROW((void)make_near_field_model(s, nullptr), std::invalid_argument);
  // Repulsion needs the lubrication gap list, a force, and a length that has decayed by the cutoff.
  s.terms = {.repulsion = true};
  s.repulsion_force = 1e-9;
  EXPECT_THROW((void)make_near_field_model(s, newtonian(1.0)), std::invalid_argument);
  s.terms = {.lubrication = true, .repulsion = true};
  EXPECT_NO_THROW((void)make_near_field_model(s, newtonian(1.0)));
  s.repulsion_force = 0.0;
  EXPECT_THROW((void)make_near_field_model(s, newtonian(1.0)), std::invalid_argument);
  s.repulsion_force = 1e-9;
  s.repulsion_length = 0.2;  // > cutoff/5
  EXPECT_THROW((void)make_near_field_model(s, newtonian(1.0)), std::invalid_argument);
  // Without the term its settings do not bind: a short cutoff is fine with the default length.
  NearFieldSettings short_cutoff;
  short_cutoff.terms = {.lubrication = true, .single_particle = true};
  short_cutoff.lubrication_cutoff = 0.1;
  EXPECT_NO_THROW((void)make_near_field_model(short_cutoff, newtonian(1.0)));
}

constexpr double plate_gap = 5e-4;  // [m]

// A `particles:` section with the given hydrodynamics block, read by coupling's own reader as
// the rheometer case reader does; every key must have been asked for.
SuspendedParticles particles_with(const std::string& block) {
  const core::Document doc = core::Document::from_string(
      "particles:\n  volume_fraction: 0.1\n  diameter: 2.0e-4\n  density: 1000\n" + block, "case.yaml");
  SuspendedParticles out =
      read_suspended_particles(doc.root().section({"particles", "the particles", "-"}), plate_gap, true);
  doc.check_all_keys_known();
  return out;
}

TEST(NearFieldCaseKeys, ParsesTheHydrodynamicsBlock) {
  const SuspendedParticles p =
      particles_with("  hydrodynamics: {model: lubrication+stresslet, roughness: 2.0e-3, lubrication_cutoff: 0.4}\n");
  EXPECT_TRUE(p.hydrodynamics_given);
  const NearFieldSettings& s = p.hydrodynamics;
  EXPECT_TRUE(s.terms.lubrication);
  EXPECT_TRUE(s.terms.single_particle);
  EXPECT_FALSE(s.terms.stokes_drag);
  EXPECT_EQ(s.terms.name(), "lubrication+stresslet");
  EXPECT_DOUBLE_EQ(s.roughness, 2e-3);
  EXPECT_DOUBLE_EQ(s.lubrication_cutoff, 0.4);
  EXPECT_EQ(make_near_field_model(s, newtonian(1.0))->name(), "lubrication+stresslet");
  EXPECT_NE(describe(p, plate_gap).find("near-field hydrodynamics: lubrication stresslet"), std::string::npos);
  // Absent: drag only.
  const SuspendedParticles plain = particles_with("");
  EXPECT_FALSE(plain.hydrodynamics_given);
  EXPECT_FALSE(plain.hydrodynamics.terms.any());
  // `none` is given but switches nothing on: the seed's drag-only model.
  const SuspendedParticles none = particles_with("  hydrodynamics: {model: none}\n");
  EXPECT_TRUE(none.hydrodynamics_given);
  EXPECT_FALSE(none.hydrodynamics.terms.any());
}

TEST(NearFieldCaseKeys, RejectsUnknownTermsAndOutOfRangeValues) {
  const auto error_of = [](const std::string& block) -> std::string {
    try {
      (void)particles_with(block);
    } catch (const core::ConfigError& e) {
      return e.what();
    }
    return "";
  };
  const std::string unknown = error_of("  hydrodynamics: {model: lubrication+stresslett}\n");
  EXPECT_NE(unknown.find("stresslett"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("case.yaml:"), std::string::npos) << unknown;
  EXPECT_NE(error_of("  hydrodynamics: {model: lubrication, roughness: 0.5}\n").find("roughness"), std::string::npos);
  EXPECT_NE(error_of("  hydrodynamics: {model: lubrication, lubrication_cutoff: 1.5}\n").find("lubrication_cutoff"),
            std::string::npos);
  EXPECT_NE(error_of("  hydrodynamics: {model: lubrication, cutoff: 0.5}\n").find("cutoff"), std::string::npos);
  const std::string lonely = error_of("  hydrodynamics: {model: stresslet+repulsion, repulsion_force: 1e-9}\n");
  EXPECT_NE(lonely.find("without lubrication"), std::string::npos) << lonely;
  const std::string no_force = error_of("  hydrodynamics: {model: lubrication+repulsion}\n");
  EXPECT_NE(no_force.find("repulsion_force"), std::string::npos) << no_force;
  const std::string too_long =
      error_of("  hydrodynamics: {model: lubrication+repulsion, repulsion_force: 1e-9, repulsion_length: 0.3}\n");
  EXPECT_NE(too_long.find("repulsion_length"), std::string::npos) << too_long;
}

TEST(NearFieldCaseKeys, ParsesTheRepulsion) {
  const SuspendedParticles p = particles_with(
      "  hydrodynamics: {model: lubrication+stresslet+repulsion, repulsion_force: 2.0e-9, repulsion_length: 0.02}\n");
  const NearFieldSettings& s = p.hydrodynamics;
  EXPECT_TRUE(s.terms.repulsion);
  EXPECT_EQ(s.terms.name(), "lubrication+stresslet+repulsion");
  EXPECT_DOUBLE_EQ(s.repulsion_force, 2e-9);
  EXPECT_DOUBLE_EQ(s.repulsion_length, 0.02);
  EXPECT_NE(describe(p, plate_gap).find("repulsion F_R0 2e-09 N, λ/ā 0.02"), std::string::npos)
      << describe(p, plate_gap);
}

TEST(NearFieldCaseKeys, ParsesTheStressletViscosity) {
  const auto parse = [](const std::string& block) { return particles_with(block).hydrodynamics; };
  EXPECT_EQ(parse("  hydrodynamics: {model: stresslet}\n").stresslet_viscosity, StressletViscosity::homogenized);
  const auto secant = particles_with("  hydrodynamics: {model: stresslet, stresslet_viscosity: secant}\n");
  EXPECT_EQ(secant.hydrodynamics.stresslet_viscosity, StressletViscosity::secant);
  EXPECT_NE(describe(secant, plate_gap).find("stresslet viscosity secant"), std::string::npos);
  try {
    (void)parse("  hydrodynamics: {model: stresslet, stresslet_viscosity: tangent}\n");
    ADD_FAILURE() << "an unknown stresslet_viscosity was accepted";
  } catch (const core::ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("stresslet_viscosity"), std::string::npos) << what;
    EXPECT_NE(what.find("homogenized"), std::string::npos) << what;
    EXPECT_NE(what.find("case.yaml:"), std::string::npos) << what;
  }
}

TEST(NearField, NoneAddsNothing) {
  const auto m = model({});
  const std::vector<double> x{0, 0, 0, 2.0001e-4, 0, 0}, v{0, 0, 1, 0, 0, -1}, w(6, 0.0), r{1e-4, 1e-4};
  NearFieldResult res;
  res.reset(2, 0);
  m->evaluate({.positions = x, .velocities = v, .angular_velocities = w, .radii = r}, {}, simple_shear(1.0), res);
  for (double f : res.forces) EXPECT_EQ(f, 0.0);
  EXPECT_EQ(res.lubricated_pairs, 0U);
}

// Single sphere at rest in simple shear u = γ̇ z e_x: torque 8πμa³ ω∞ with ω∞ = (0, γ̇/2, 0),
// stresslet (20/3)πμ_S a³E∞ with E∞_xz = γ̇/2; μ of a power-law matrix at the ambient γ̇.
// μ_S: `secant` μ; `homogenized` 0.3 μ + 0.7 dτ/dγ̇ = (0.3 + 0.7 n) μ (near_field.hpp).
TEST(NearField, SingleSphereTorqueAndStressletAreStokes) {
  const auto doc = core::Document::from_string("model: power_law\nconsistency: 2.0\nindex: 0.5\n", "rheology");
  for (const auto& [mode, factor] :
       {std::pair{StressletViscosity::secant, 1.0}, std::pair{StressletViscosity::homogenized, 0.3 + 0.7 * 0.5}}) {
    NearFieldSettings s;
    s.terms = {.single_particle = true};
    s.stresslet_viscosity = mode;
    const auto m = make_near_field_model(s, core::make_rheology(doc.root()));
    const double a = 1e-4, rate = 40.0;
    const double mu = 2.0 * std::pow(rate, -0.5);
    const std::vector<double> x{0, 0, 3e-4}, v(3, 0.0), w(3, 0.0), r{a};
    NearFieldResult res;
    res.reset(1, 0);
    m->evaluate({.positions = x, .velocities = v, .angular_velocities = w, .radii = r}, {}, simple_shear(rate), res);
    EXPECT_NEAR(res.torques[1], 8.0 * pi * mu * a * a * a * rate / 2.0, 1e-12 * mu * a * a * a * rate);
    EXPECT_EQ(res.torques[0], 0.0);
    EXPECT_EQ(res.forces[0], 0.0);  // no drag in `stresslet`
    const double s_xz = factor * 20.0 / 3.0 * pi * mu * a * a * a * rate / 2.0;
    EXPECT_NEAR(res.stresslet_sum[4], s_xz, 1e-9 * s_xz);
    EXPECT_NEAR(res.particle_stress[4], s_xz, 1e-9 * s_xz);
    for (int c : {0, 1, 2, 3, 5}) EXPECT_EQ(res.stresslet_sum[static_cast<std::size_t>(c)], 0.0);
  }
}

// A Bingham matrix far above its yield (γ̇ with τ_y ≫ μ_p γ̇): the homogenised stresslet tends to
// 0.3 of the secant one, so the particles add 0.75φ τ_y to the yield stress, not 2.5φ τ_y.
TEST(NearField, HomogenizedStressletOfAPlasticMatrix) {
  const auto doc = core::Document::from_string(
      "model: bingham\nplastic_viscosity: 0.01\nyield_stress: 100.0\nregularization: 1.0e4\n", "rheology");
  const auto matrix = core::make_rheology(doc.root());
  const double a = 1e-4, rate = 10.0;  // Bn = τ_y/(μ_p γ̇) = 1000
  double secant = 0.0, homogenized = 0.0;
  for (const auto mode : {StressletViscosity::secant, StressletViscosity::homogenized}) {
    NearFieldSettings s;
    s.terms = {.single_particle = true};
    s.stresslet_viscosity = mode;
    NearFieldResult res;
    res.reset(1, 0);
    const std::vector<double> x{0, 0, 3e-4}, v(3, 0.0), w(3, 0.0), r{a};
    make_near_field_model(s, matrix)->evaluate({.positions = x, .velocities = v, .angular_velocities = w, .radii = r},
                                               {}, simple_shear(rate), res);
    (mode == StressletViscosity::secant ? secant : homogenized) = res.stresslet_sum[4];
  }
  const double n = 0.01 * rate / (100.0 + 0.01 * rate);  // d ln τ/d ln γ̇
  EXPECT_NEAR(secant, 20.0 / 3.0 * pi * matrix->viscosity(rate) * a * a * a * rate / 2.0, 1e-12 * secant);
  EXPECT_NEAR(homogenized / secant, 0.3 + 0.7 * n, 1e-6);
}

TEST(NearField, StokesDragOnAmbientFlow) {
  const auto m = model({.stokes_drag = true}, 0.5);
  const double a = 2e-4, rate = 3.0;
  const std::vector<double> x{0, 0, 1e-3}, v{0.001, 0.0, 0.002}, w(3, 0.0), r{a};
  NearFieldResult res;
  res.reset(1, 0);
  m->evaluate({.positions = x, .velocities = v, .angular_velocities = w, .radii = r}, {}, simple_shear(rate), res);
  const double k = 6.0 * pi * 0.5 * a;
  EXPECT_NEAR(res.forces[0], k * (rate * 1e-3 - 0.001), 1e-15);
  EXPECT_NEAR(res.forces[2], -k * 0.002, 1e-15);
}

// A free sphere with implicit drag + torque relaxes onto the ambient flow even though
// δt ≫ m/(6πμa) (the explicit relaxation would diverge): U → γ̇ z, Ω → γ̇/2.
TEST(NearField, ImplicitSingleParticleRelaxesOntoTheFlow) {
  const auto m = model({.single_particle = true, .stokes_drag = true}, 1.0);
  const double a = 1e-4, rho = 1000.0, rate = 100.0;
  const double mass = 4.0 / 3.0 * pi * a * a * a * rho;
  const double dt = 20.0 * mass / (6.0 * pi * a);  // 20 × the drag relaxation time
  std::vector<double> x{0, 0, 2e-4}, v(3, 0.0), w(3, 0.0), r{a}, masses{mass}, zero(3, 0.0);
  NearFieldResult res;
  for (int step = 0; step < 5; ++step) {
    res.reset(1, 0);
    m->evaluate({.positions = x,
                 .velocities = v,
                 .angular_velocities = w,
                 .radii = r,
                 .masses = masses,
                 .other_forces = zero,
                 .other_torques = zero,
                 .time_step = dt},
                {}, simple_shear(rate), res);
    const double inertia = 0.4 * mass * a * a;
    for (std::size_t k = 0; k < 3; ++k) {
      v[k] += dt * res.forces[k] / mass;
      w[k] += dt * res.torques[k] / inertia;
    }
    EXPECT_LT(std::abs(v[0]), 1.01 * rate * x[2]);  // no overshoot
  }
  EXPECT_NEAR(v[0], rate * x[2], 1e-3 * rate * x[2]);
  EXPECT_NEAR(w[1], rate / 2.0, 1e-3 * rate);
  EXPECT_EQ(
      m->stable_time_step({.positions = x, .velocities = v, .angular_velocities = w, .radii = r}, rho) < dt / 20.0,
      true);
}

// Two equal spheres pressed together by ±F in quiescent fluid: the quasi-static gap obeys
// dh/dt = −F / (6πμa X^A(ξ)), ξ = (h + δ)/a (leading terms). The implicit update follows it at
// δt = 200 × the explicit stability limit at the final gap.
TEST(NearField, ImplicitSqueezeFollowsQuasiStaticTrajectory) {
  const double a = 1e-4, rho = 1000.0, mu = 1.0, force = 1e-7, roughness = 1e-3;
  const auto m = model({.lubrication = true}, mu);
  const double mass = 4.0 / 3.0 * pi * a * a * a * rho;
  const double h0 = 0.2 * a;
  const auto closing_speed = [&](double h) {
    const double xi = (h + roughness * a) / a;
    return force / (6.0 * pi * mu * a * (0.25 / xi + 9.0 / 40.0 * std::log(1.0 / xi)));
  };
  // Leading term alone: h + δ = (h0 + δ) e^(−t/τ), τ = 6πμa²/(4F); 2.2 τ reaches h ≈ 0.02 a.
  const double t_end = 2.2 * 6.0 * pi * mu * a * a / (4.0 * force);
  // Reference: RK4 on dh/dt = −closing_speed(h).
  double h_ref = h0;
  const int ref_steps = 200000;
  const double dtr = t_end / ref_steps;
  for (int i = 0; i < ref_steps; ++i) {
    const double k1 = -closing_speed(h_ref), k2 = -closing_speed(h_ref + 0.5 * dtr * k1);
    const double k3 = -closing_speed(h_ref + 0.5 * dtr * k2), k4 = -closing_speed(h_ref + dtr * k3);
    h_ref += dtr / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  ASSERT_GT(h_ref, 0.0);
  ASSERT_LT(h_ref, 0.05 * a);  // the test reaches the stiff regime

  std::vector<double> x{0, 0, 0, 2 * a + h0, 0, 0}, v(6, 0.0), w(6, 0.0), r{a, a}, masses{mass, mass};
  const std::vector<double> other{force, 0, 0, -force, 0, 0}, zero(6, 0.0);
  const std::vector<double> x_end{0, 0, 0, 2 * a + h_ref, 0, 0};
  const ParticleSnapshot at_end{.positions = x_end, .velocities = v, .angular_velocities = w, .radii = r};
  const double explicit_limit = m->stable_time_step(at_end, rho);
  const int steps = 400;
  const double dt = t_end / steps;
  EXPECT_GT(dt, 100.0 * explicit_limit);
  NearFieldResult res;
  int max_iterations = 0;
  for (int step = 0; step < steps; ++step) {
    res.reset(2, 0);
    m->evaluate({.positions = x,
                 .velocities = v,
                 .angular_velocities = w,
                 .radii = r,
                 .masses = masses,
                 .other_forces = other,
                 .other_torques = zero,
                 .time_step = dt},
                {}, {}, res);
    max_iterations = std::max(max_iterations, res.solver_iterations);
    for (std::size_t k = 0; k < 6; ++k) {
      v[k] += dt * (other[k] + res.forces[k]) / mass;
      x[k] += dt * v[k];
    }
  }
  const double h = x[3] - x[0] - 2 * a;
  EXPECT_NEAR(h / h_ref, 1.0, 0.01) << "h = " << h << ", reference " << h_ref;
  EXPECT_LT(max_iterations, 50);
  // Symmetric: the pair's centre does not move.
  EXPECT_NEAR(x[0] + x[3], 2 * a + h0, 1e-12 * a);
}

// Brute-force minimum-image count of gaps below the cutoff, against the cell list.
TEST(NearField, PeriodicCellListFindsEveryPair) {
  const double a = 1e-4, length = 2e-3;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, length);
  std::vector<double> x;
  while (x.size() < 3 * 300) {
    const std::array<double, 3> c{u(rng), u(rng), u(rng)};
    bool overlap = false;
    for (std::size_t j = 0; j < x.size() / 3 && !overlap; ++j) {
      double d2 = 0.0;
      for (int k = 0; k < 3; ++k) {
        double d = c[static_cast<std::size_t>(k)] - x[3 * j + static_cast<std::size_t>(k)];
        d -= length * std::round(d / length);
        d2 += d * d;
      }
      overlap = d2 < 4 * a * a;
    }
    if (!overlap) x.insert(x.end(), c.begin(), c.end());
  }
  const std::size_t n = x.size() / 3;
  const std::vector<double> v(3 * n, 0.0), r(n, a);
  NearFieldScene scene;
  scene.periodic = {true, true, true};
  scene.box_high = {length, length, length};
  std::size_t expected = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      double d2 = 0.0;
      for (std::size_t k = 0; k < 3; ++k) {
        double d = x[3 * j + k] - x[3 * i + k];
        d -= length * std::round(d / length);
        d2 += d * d;
      }
      if (std::sqrt(d2) - 2 * a < 0.5 * a) ++expected;
    }
  ASSERT_GT(expected, 10U);
  NearFieldResult res;
  res.reset(n, 0);
  model({.lubrication = true})
      ->evaluate({.positions = x, .velocities = v, .angular_velocities = v, .radii = r}, scene, {}, res);
  EXPECT_EQ(res.lubricated_pairs, expected);
}

// A pair approaching across the periodic boundary feels the squeeze; the repulsive
// lubrication force acts like a compressed contact: negative xx virial −(x_j − x_i) F_j,x.
TEST(NearField, PeriodicPairSqueezesAcrossTheBoundary) {
  const double a = 1e-4, length = 1e-3, h = 1e-6;
  const std::vector<double> x{a + h / 2, 5e-4, 5e-4, length - a - h / 2, 5e-4, 5e-4};
  const std::vector<double> v{-1e-3, 0, 0, 1e-3, 0, 0}, w(6, 0.0), r{a, a};
  NearFieldScene scene;
  scene.periodic = {true, true, false};
  scene.box_high = {length, length, 0.0};
  NearFieldResult res;
  res.reset(2, 0);
  model({.lubrication = true})
      ->evaluate({.positions = x, .velocities = v, .angular_velocities = w, .radii = r}, scene, {}, res);
  EXPECT_EQ(res.lubricated_pairs, 1U);
  EXPECT_GT(res.forces[0], 0.0);  // particle 0 moves −x towards its neighbour's image: pushed back +x
  EXPECT_NEAR(res.forces[0], -res.forces[3], 1e-15);
  EXPECT_LT(res.lubrication_virial[0], 0.0);
}

// Two spheres at rest a gap h apart, no flow: only the repulsion F_R0 e^{−h/λ} acts, along the
// line of centres, equal and opposite, and its virial is −r ⊗ F_j.
TEST(NearField, RepulsionOfAPairAndAPlate) {
  const double a = 1e-4, h = 3e-6, force = 2e-9, length = 0.05;
  NearFieldSettings settings;
  settings.terms = {.lubrication = true, .repulsion = true};
  settings.repulsion_force = force;
  settings.repulsion_length = length;
  const auto m = make_near_field_model(settings, newtonian(1.0));
  const std::vector<double> x{0, 0, 5e-4, 2 * a + h, 0, 5e-4}, v(6, 0.0), w(6, 0.0), r{a, a};
  NearFieldResult res;
  res.reset(2, 0);
  m->evaluate({.positions = x, .velocities = v, .angular_velocities = w, .radii = r}, {}, {}, res);
  const double expected = force * std::exp(-(h / a) / length);
  EXPECT_NEAR(res.forces[0], -expected, 1e-12 * expected);
  EXPECT_NEAR(res.forces[3], expected, 1e-12 * expected);
  EXPECT_NEAR(res.forces[1], 0.0, 1e-24);
  // −(x_j − x_i) ⊗ F_j: xx = −(2a + h) · expected (a repulsive pair pushes the stress negative).
  EXPECT_NEAR(res.lubrication_virial[0], -(2 * a + h) * expected, 1e-12 * a * expected);
  // Overlapping pair: F_R0 (the contact model takes over inside).
  const std::vector<double> touching{0, 0, 5e-4, 2 * a - 1e-7, 0, 5e-4};
  res.reset(2, 0);
  m->evaluate({.positions = touching, .velocities = v, .angular_velocities = w, .radii = r}, {}, {}, res);
  EXPECT_NEAR(res.forces[3], force, 1e-12 * force);
  // A sphere a gap h above the bottom plate is pushed up, the plate down.
  NearFieldScene scene;
  scene.plates.push_back({.z = 0.0, .faces_up = true, .velocity_at = {}});
  const std::vector<double> above{2e-4, 0, a + h}, v1(3, 0.0), r1{a};
  res.reset(1, 1);
  m->evaluate({.positions = above, .velocities = v1, .angular_velocities = v1, .radii = r1}, scene, {}, res);
  EXPECT_NEAR(res.forces[2], expected, 1e-12 * expected);
  EXPECT_NEAR(res.plate_forces[0][2], -expected, 1e-12 * expected);
}

// Sphere just under a top plate that slides in +x: the plate drags it along (+x force on the
// particle), the plate gets the opposite force, and the moment about the origin follows.
TEST(NearField, PlateLubricationForceAndMoment) {
  const double a = 1e-4, H = 1e-3, h = 2e-6, U = 0.05;
  NearFieldScene scene;
  scene.plates.push_back({.z = 0.0, .faces_up = true, .velocity_at = {}});
  scene.plates.push_back({.z = H, .faces_up = false, .velocity_at = [U](const Vector3&) { return Vector3{U, 0, 0}; }});
  const std::vector<double> x{3e-4, -2e-4, H - a - h}, v(3, 0.0), w(3, 0.0), r{a};
  NearFieldResult res;
  res.reset(1, 2);
  model({.lubrication = true})
      ->evaluate({.positions = x, .velocities = v, .angular_velocities = w, .radii = r}, scene, {}, res);
  EXPECT_EQ(res.lubricated_walls, 1U);
  const double xi = (h + 1e-3 * a) / a;
  const double expected = 6.0 * pi * a * (8.0 / 15.0) * std::log(1.0 / xi) * U;
  EXPECT_NEAR(res.forces[0], expected, 1e-12 * expected);
  EXPECT_NEAR(res.plate_forces[1][0], -expected, 1e-12 * expected);
  EXPECT_EQ(res.plate_forces[0][0], 0.0);
  // Moment about the origin of −F e_x at (x, y, H): (0, −H F, y F).
  EXPECT_NEAR(res.plate_moments[1][1], -H * expected, 1e-12 * H * expected);
  EXPECT_NEAR(res.plate_moments[1][2], -2e-4 * expected, 1e-12 * 2e-4 * expected);
  // The force on the sphere acts at its top (+z side) along +x: torque a e_z × F e_x = +a F e_y.
  EXPECT_GT(res.torques[1], 0.0);
  // Virial: −(x_p − x_w) ⊗ F_p, x_p − x_w = −(a + h) e_z: xz component (a + h) F / 2 · 2 sym.
  EXPECT_NEAR(res.lubrication_virial[4], 0.5 * (a + h) * expected, 1e-9 * a * expected);
}

}  // namespace
}  // namespace rheosim::coupling
