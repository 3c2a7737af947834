// Dry granular shear in the rheometer scene reaches a steady, positive contact torque that
// grows with Ω, measured the way a rheometer point is: a time average over a
// strain window after the start-up transient.
//
// Physics. Without a fluid, gravity or a confining load, the particles only touch the plates
// if something presses them there. A loose packing (φ = 0.5 is below random close packing)
// between smooth plates has no steady state of its own: an agitated start-up gas cools
// (e = 0.9) and particles on a plate end up rolling with it (see test_rheometer_scene.cpp),
// so the torque first decays. In the rotating gap, though, every particle dragged round by
// the top plate feels the centrifugal force m ω² r and drifts outwards; the frictionless rim
// stops it, and after a strain γ = γ̇_R t of about 15 the particles form a dense annulus at the
// rim that spans the gap and is pressed against the rim by its own centrifugal load. That
// annulus is sheared between the rotating and the fixed plate and carries a steady torque.
// With rigid particles its only stress scale is ρ_p (Ω R)², so T ∝ Ω² (Bagnold scaling): the
// torque is positive and grows with Ω, quadratically. A gravity or a uniform body force would
// not help here: it presses the packing against one plate only (φ = 0.5 fills 0.83 H at most).
//
// Scene: small disk R = 1 mm, H = 0.25 mm = 2.5 d (the CD §4 ratio H/d), d = 0.1 mm, φ = 0.5
// (750 particles), CD §4 material, no gravity, start from a granular gas at half the rim
// speed. γ̇_R = 8000 and 16000 1/s (rim speed 2 and 4 m/s; ~1300 and 650 steps per unit
// strain at δt = 0.3 t_R); average over strains 20–40 in 8 batches (the standard error is
// that of the batch means). Measured (2026-11-23): 1.13e-7 ± 0.09e-7 N·m and 4.22e-7 ±
// 0.23e-7 N·m (1 s.e.), ratio 3.7, close to the 4 of Ω². Runs ~10 s on one core.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include <fmt/format.h>

#include "rheosim/dem/contact.hpp"
#include "rheosim/dem/mpi_session.hpp"
#include "rheosim/dem/rheometer_scene.hpp"

namespace rheosim::dem {
namespace {

namespace fs = std::filesystem;

struct SteadyTorque {
  double mean = 0.0;            // [N·m]
  double standard_error = 0.0;  // [N·m]
};

SteadyTorque steady_torque(double rate, const fs::path& dir) {
  constexpr double radius = 1e-3;
  constexpr double gap = 2.5e-4;
  constexpr double start_strain = 20.0;
  constexpr double end_strain = 40.0;
  constexpr int batches = 8;
  RheometerScene::Params p{.geometry = {.radius = radius, .gap = gap},
                           .particles = {.volume_fraction = 0.5, .diameter = 1e-4, .density = 1000.0},
                           .rim_shear_rate = rate,
                           .gravity = std::nullopt,
                           .seed = 3,
                           .run_directory = dir,
                           .initial_speed = 0.5 * rate * gap};
  // 20 torque samples per unit strain.
  const double dt = p.time_step_fraction * rayleigh_time({.radius = 0.5 * p.particles.diameter,
                                                          .density = p.particles.density,
                                                          .youngs_modulus = p.particles.youngs_modulus,
                                                          .poisson_ratio = p.particles.poisson_ratio});
  p.torque_sample_interval = std::max<std::int64_t>(1, std::llround(1.0 / (20.0 * rate * dt)));
  RheometerScene scene(p);
  const auto steps_per_strain = 1.0 / (rate * scene.time_step());
  scene.advance(static_cast<std::int64_t>(std::ceil(end_strain * steps_per_strain)));
  std::vector<double> window;
  for (const auto& s : scene.torque_series())
    if (s.time * rate > start_strain) window.push_back(s.torque);
  const std::size_t per_batch = window.size() / batches;
  std::vector<double> means;
  for (std::size_t b = 0; b < batches; ++b) {
    double sum = 0.0;
    for (std::size_t k = 0; k < per_batch; ++k) sum += window[b * per_batch + k];
    means.push_back(sum / static_cast<double>(per_batch));
  }
  SteadyTorque t;
  for (const double m : means) t.mean += m / batches;
  double var = 0.0;
  for (const double m : means) var += (m - t.mean) * (m - t.mean) / (batches - 1);
  t.standard_error = std::sqrt(var / batches);
  return t;
}

TEST(DryShear, SteadyTorqueIsPositiveAndGrowsWithOmega) {
  MpiSession::ensure();
  if (MpiSession::world_size() > 1) GTEST_SKIP() << "single-rank test (tests/dem/mpi_scene.cpp runs it on 2 ranks)";
  const fs::path dir = fs::temp_directory_path() / fmt::format("rheosim_validate_dry_shear_{}", ::getpid());
  const auto slow = steady_torque(8000.0, dir / "slow");
  const auto fast = steady_torque(16000.0, dir / "fast");
  fs::remove_all(dir);
  RecordProperty("torque_8000", fmt::format("{:.3e} +- {:.1e}", slow.mean, slow.standard_error));
  RecordProperty("torque_16000", fmt::format("{:.3e} +- {:.1e}", fast.mean, fast.standard_error));
  RecordProperty("ratio", fmt::format("{:.2f}", fast.mean / slow.mean));
  // Positive and resolved: the mean is many standard errors above zero.
  EXPECT_GT(slow.mean, 4.0 * slow.standard_error);
  EXPECT_GT(fast.mean, 4.0 * fast.standard_error);
  // Grows with Ω, about as Ω² (ratio 4 for doubling Ω); the bounds leave room for the noise.
  EXPECT_GT(fast.mean / slow.mean, 2.0);
  EXPECT_LT(fast.mean / slow.mean, 8.0);
}

}  // namespace
}  // namespace rheosim::dem
