// Di Felice drag (CD eqs. 30–33) through the DragModel interface and the registry: low-Re
// limit, direction, voidage correction against hand-computed values, β consistency, zero slip.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "rheosim/core/config.hpp"
#include "rheosim/core/error.hpp"
#include "rheosim/coupling/drag.hpp"
#include "rheosim/coupling/forces.hpp"

namespace rheosim::coupling {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

constexpr double pi = std::numbers::pi;
// CD §4: particle diameter 200 µm in a Newtonian fluid with ρ = 1000 kg/m³, η = 1 mPa·s.
constexpr double diameter = 200e-6;
constexpr double density = 1000.0;
constexpr double viscosity = 1e-3;

std::unique_ptr<const DragModel> di_felice() {
  const auto doc = core::Document::from_string("model: di_felice\n", "drag.yaml");
  return make_drag_model(doc.root());
}

DragInput particle_with_slip(Vector3 slip, double void_fraction, Vector3 particle_velocity = {0.01, -0.02, 0.005}) {
  DragInput in;
  in.particle_velocity = particle_velocity;
  for (std::size_t k = 0; k < 3; ++k) in.fluid_velocity[k] = in.particle_velocity[k] + slip[k];
  in.void_fraction = void_fraction;
  in.diameter = diameter;
  in.fluid_density = density;
  in.fluid_viscosity = viscosity;
  return in;
}

// A particle at rest in a flow along x giving the wanted Re_p = ε ρ d |w| / η.
DragInput particle_at_reynolds(double reynolds, double void_fraction) {
  return particle_with_slip({reynolds * viscosity / (void_fraction * density * diameter), 0.0, 0.0}, void_fraction,
                            {0.0, 0.0, 0.0});
}

double norm(const Vector3& v) { return std::hypot(v[0], v[1], v[2]); }

TEST(Drag, RegistryHasDiFeliceAndSchillerNaumann) {
  EXPECT_THAT(builtin_drag_models().names(), ElementsAre("di_felice", "schiller_naumann"));
  EXPECT_EQ(di_felice()->name(), "di_felice");
}

// Every law a case file can name (DragLaw) is registered under that name, and the disk's
// force list carries it in place of di_felice.
TEST(Drag, EveryCaseFileLawIsRegistered) {
  for (const DragLaw law : {DragLaw::di_felice, DragLaw::schiller_naumann}) {
    EXPECT_EQ(make_drag_model(law)->name(), name_of(law));
    EXPECT_EQ(force_models(law).front(), name_of(law));
    EXPECT_EQ(make_force_model(force_models(law).front())->name(), name_of(law));
  }
  EXPECT_EQ(force_models(DragLaw::di_felice), seed_force_models());
}

TEST(Drag, UnknownModelNameListsTheValidOnes) {
  const auto doc = core::Document::from_string("model: di_feliche\n", "drag.yaml");
  try {
    (void)make_drag_model(doc.root());
    FAIL() << "expected a ConfigError";
  } catch (const core::ConfigError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("di_felice"));
  }
}

// Di Felice's C_d → 23.04/Re_p at low Re, so the drag tends to 23.04/24 = 0.96 × Stokes 3πηd(u−v).
TEST(Drag, LowReynoldsLimitIsPointNineSixStokes) {
  const auto model = di_felice();
  for (const double reynolds : {1e-10, 1e-8, 1e-6}) {
    const DragInput in = particle_at_reynolds(reynolds, 1.0);
    EXPECT_NEAR(particle_reynolds_number(in), reynolds, 1e-12 * reynolds);
    const double stokes = 3.0 * pi * viscosity * diameter * slip_speed(in);
    const double ratio = norm(model->force(in)) / stokes;
    EXPECT_NEAR(ratio, 0.96, 0.01 * 0.96) << reynolds;  // the 1% the design asks for ...
    EXPECT_NEAR(ratio, 0.96, 1e-3 * 0.96) << reynolds;  // ... and it is in fact within 0.1%
  }
}

TEST(Drag, ZeroSlipGivesZeroForceAndTheFiniteStokesLimitOfBeta) {
  const auto model = di_felice();
  DragInput in = particle_with_slip({0.0, 0.0, 0.0}, 0.6);
  const Vector3 force = model->force(in);
  for (const double component : force) {
    EXPECT_FALSE(std::isnan(component));
    EXPECT_EQ(component, 0.0);
  }
  // β(0) = 2.88 π η d ε^(−2.7) = 2.88π·1e-3·2e-4·0.6^(−2.7) = 7.18727e-6 kg/s (0.6^(−2.7) = 3.97174).
  EXPECT_NEAR(model->exchange_coefficient(in), 7.187270331475977e-06, 1e-12 * 7e-6);
  in.void_fraction = 1.0;
  EXPECT_NEAR(model->exchange_coefficient(in), 0.96 * 3.0 * pi * viscosity * diameter, 1e-12 * 2e-6);
}

TEST(Drag, ForceFollowsTheRelativeVelocity) {
  const auto model = di_felice();
  for (const Vector3 slip : {Vector3{0.1, 0.0, 0.0}, Vector3{0.0, -0.3, 0.0}, Vector3{-0.02, 0.05, 0.07}}) {
    const Vector3 f = model->force(particle_with_slip(slip, 0.7));
    const double cosine = (f[0] * slip[0] + f[1] * slip[1] + f[2] * slip[2]) / (norm(f) * norm(slip));
    EXPECT_NEAR(cosine, 1.0, 1e-14);
    const Vector3 reversed = model->force(particle_with_slip({-slip[0], -slip[1], -slip[2]}, 0.7));
    for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(reversed[k], -f[k], 1e-15 * norm(f));
  }
}

// ε = 0.6 and Re_p = 1, 10, 100 (slip chosen so that ε ρ d |w|/η hits each value):
//   χ = 3.7 − 0.65 exp(−(1.5 − log10 Re)²/2): Re = 1 → 3.4889759; Re = 10, 100 → 3.1263770
//   ε^(2−χ): 2.1395746 and 1.7778099
//   C_d = (0.63 + 4.8/√Re)²: 29.4849, 4.6134455, 1.2321
TEST(Drag, VoidageCorrectionMatchesHandComputedValues) {
  const auto model = di_felice();
  struct Case {
    double reynolds, drag_coefficient, correction, force;
  };
  for (const Case c : {Case{1.0, 29.4849, 2.1395746357971084, 6.881521718869576e-08},
                       Case{10.0, 4.6134455288698355, 1.7778099478845022, 8.946807933487655e-07},
                       Case{100.0, 1.2321, 1.7778099478845022, 2.389398983009246e-05}}) {
    const DragInput in = particle_at_reynolds(c.reynolds, 0.6);
    const double w = slip_speed(in);
    const double without_voidage = c.drag_coefficient * density * pi * diameter * diameter * w * w / 8.0;
    const double f = norm(model->force(in));
    EXPECT_NEAR(f / without_voidage, c.correction, 1e-10 * c.correction) << c.reynolds;
    EXPECT_NEAR(f, c.force, 1e-10 * c.force) << c.reynolds;
  }
}

// The implementation's β = (π/8) η d ε^(1−χ)(4.8 + 0.63√Re)² against eq. 30 (with ε^(2−χ)) written out.
TEST(Drag, MatchesEquationThirtyAcrossReynoldsAndVoidFraction) {
  const auto model = di_felice();
  for (const double eps : {0.35, 0.6, 0.9, 1.0}) {
    for (double reynolds = 1e-3; reynolds < 2e4; reynolds *= 3.7) {
      const DragInput in = particle_at_reynolds(reynolds, eps);
      const double w = slip_speed(in);
      const double cd = std::pow(0.63 + 4.8 / std::sqrt(reynolds), 2);
      const double chi = 3.7 - 0.65 * std::exp(-std::pow(1.5 - std::log10(reynolds), 2) / 2.0);
      const double eq30 = cd * density * pi * diameter * diameter * w * w * std::pow(eps, 2.0 - chi) / 8.0;
      EXPECT_NEAR(norm(model->force(in)), eq30, 1e-12 * eq30) << eps << ", " << reynolds;
    }
  }
}

TEST(Drag, BetaTimesSlipIsTheForce) {
  const auto model = di_felice();
  for (const Vector3 slip : {Vector3{1e-4, 2e-4, -3e-4}, Vector3{0.5, -0.1, 0.2}, Vector3{0.0, 0.0, 2.0}}) {
    const DragInput in = particle_with_slip(slip, 0.55);
    const double beta = model->exchange_coefficient(in);
    const Vector3 f = model->force(in);
    for (std::size_t k = 0; k < 3; ++k)
      EXPECT_DOUBLE_EQ(f[k], beta * (in.fluid_velocity[k] - in.particle_velocity[k])) << k;
  }
}

TEST(Drag, ArrayFormMatchesScalarForm) {
  const auto model = di_felice();
  const std::vector<DragInput> particles{particle_at_reynolds(0.0, 0.5), particle_at_reynolds(0.3, 0.8),
                                         particle_at_reynolds(40.0, 1.0)};
  std::vector<double> beta(particles.size());
  model->exchange_coefficients(particles, beta);
  for (std::size_t p = 0; p < particles.size(); ++p) EXPECT_EQ(beta[p], model->exchange_coefficient(particles[p]));
  std::vector<double> too_short(2);
  EXPECT_THROW(model->exchange_coefficients(particles, too_short), std::invalid_argument);
}

TEST(Drag, InvalidInputIsRejectedByName) {
  const auto model = di_felice();
  const auto message = [&](DragInput in) -> std::string {
    try {
      (void)model->exchange_coefficient(in);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no exception";
  };
  const DragInput ok = particle_at_reynolds(1.0, 0.6);
  DragInput in = ok;
  in.void_fraction = 0.0;
  EXPECT_THAT(message(in), HasSubstr("void_fraction"));
  in.void_fraction = 1.2;
  EXPECT_THAT(message(in), HasSubstr("(0, 1]"));
  in = ok;
  in.diameter = 0.0;
  EXPECT_THAT(message(in), HasSubstr("diameter"));
  in = ok;
  in.fluid_density = -1.0;
  EXPECT_THAT(message(in), HasSubstr("fluid_density"));
  in = ok;
  in.fluid_viscosity = 0.0;
  EXPECT_THAT(message(in), HasSubstr("fluid_viscosity"));
  in = ok;
  in.fluid_velocity[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(message(in), HasSubstr("fluid_velocity"));
}

// Schiller–Naumann: the isolated sphere, Stokes at low Re, 1 + 0.15 Re^0.687 above, no voidage
// function (the same β at any ε), Newton's C_d = 0.44 beyond Re = 1000.
TEST(Drag, SchillerNaumannIsTheIsolatedSphere) {
  const auto doc = core::Document::from_string("model: schiller_naumann\n", "drag.yaml");
  const auto model = make_drag_model(doc.root());
  EXPECT_EQ(model->name(), "schiller_naumann");
  const double stokes = 3.0 * pi * viscosity * diameter;
  for (const double void_fraction : {1.0, 0.7, 0.4}) {
    // particle_at_reynolds sets ε ρ d |w|/η; the law's Re has no ε.
    const auto at = [&](double reynolds) { return particle_at_reynolds(reynolds * void_fraction, void_fraction); };
    EXPECT_NEAR(model->exchange_coefficient(at(1e-9)), stokes, 1e-6 * stokes) << void_fraction;
    EXPECT_NEAR(model->exchange_coefficient(at(1.0)), 1.15 * stokes, 1e-12 * stokes) << void_fraction;
    EXPECT_NEAR(model->exchange_coefficient(at(100.0)), (1.0 + 0.15 * std::pow(100.0, 0.687)) * stokes, 1e-12 * stokes);
    // Newton's regime: F = (π/8) 0.44 ρ d² w², so β = 0.44 Re/24 × Stokes.
    EXPECT_NEAR(model->exchange_coefficient(at(4000.0)), 0.44 * 4000.0 / 24.0 * stokes, 1e-12 * 100 * stokes);
  }
  EXPECT_EQ(norm(model->force(particle_with_slip({0.0, 0.0, 0.0}, 0.6))), 0.0);
}

}  // namespace
}  // namespace rheosim::coupling
