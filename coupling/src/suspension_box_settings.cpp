// The suspension box's settings: their check and the defaults derived from them
// (suspension_box.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "rheosim/coupling/suspension_box.hpp"

namespace rheosim::coupling {

void check_suspension_box_settings(const SuspensionBoxSettings& s) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("suspension box: " + what); };
  if (!(s.volume_fraction > 0.0 && s.volume_fraction <= 0.6))
    fail(fmt::format("volume fraction {} outside (0, 0.6]", s.volume_fraction));
  if (s.particles < 20) fail(fmt::format("{} particles, expected >= 20", s.particles));
  if (s.radii.empty() || s.radii.size() != s.volume_shares.size())
    fail("radii and volume_shares must be non-empty and of equal length");
  double share_sum = 0.0;
  for (std::size_t c = 0; c < s.radii.size(); ++c) {
    if (!(s.radii[c] > 0.0) || !(s.volume_shares[c] >= 0.0)) fail("radii must be > 0 and shares >= 0");
    share_sum += s.volume_shares[c];
  }
  if (std::abs(share_sum - 1.0) > 1e-6) fail(fmt::format("volume shares sum to {}, expected 1", share_sum));
  if (!(s.friction >= 0.0)) fail(fmt::format("friction {} < 0", s.friction));
  if (!(s.stokes_number >= 0.0)) fail(fmt::format("Stokes number {} < 0", s.stokes_number));
  if (!(s.roughness >= 1e-6 && s.roughness <= 0.1)) fail(fmt::format("roughness {} outside [1e-6, 0.1]", s.roughness));
  if (!(s.lubrication_cutoff > s.roughness && s.lubrication_cutoff <= 1.0))
    fail(fmt::format("lubrication cutoff {} outside (roughness, 1]", s.lubrication_cutoff));
  if (!(s.contact_stiffness >= 0.0)) fail("contact stiffness < 0");
  if (!(s.repulsion_force >= 0.0) || !(s.repulsion_length > 0.0)) fail("repulsion force < 0 or length <= 0");
  if (!(s.max_strain > s.warmup_strain + s.min_averaging_strain))
    fail(fmt::format("max strain {} <= warm-up {} + minimum averaging {}", s.max_strain, s.warmup_strain,
                     s.min_averaging_strain));
  if (!(s.block_strain > 0.0) || !(s.relative_tolerance > 0.0)) fail("block strain and tolerance must be > 0");
  if (s.wall_gap != 0.0) {
    const double largest = *std::max_element(s.radii.begin(), s.radii.end());
    if (!(s.wall_gap >= 2.5 * largest) || !std::isfinite(s.wall_gap))
      fail(fmt::format("wall gap {} a outside [2.5 a_max = {:g}, ∞) (0: Lees–Edwards)", s.wall_gap, 2.5 * largest));
  }
}

double default_contact_stiffness(double /*volume_fraction*/) {
  // The practice of LF_DEM (Mari et al. 2014): soft enough that friction acts through sticking
  // contacts, stiff enough that the mean overlap stays below 1 % of a and the largest below 5 %
  // up to φ = 0.5 (measured: mean 0.45 %, largest 3.3 % there). Stiffer contacts slide almost
  // always and lower η_r at φ = 0.5 (−15 % at 3×, −21 % at 6×); at φ <= 0.3 the change is within 1 %
  // (bench/suspension_box_study.sh, docs/suspension-box.md).
  return 2000.0;
}

double default_strain_step(const SuspensionBoxSettings& s) {
  // The springs are implicit, so the step is set by accuracy: a pair approaching at the
  // affine rate (~2a γ̇) closes a tenth of the lubrication range in about 0.025 strain.
  double step = 5e-3;
  if (s.stokes_number > 0.0) {
    const double k = s.contact_stiffness > 0.0 ? s.contact_stiffness : default_contact_stiffness(s.volume_fraction);
    const double smallest = *std::min_element(s.radii.begin(), s.radii.end());
    const double mass = s.stokes_number * smallest * smallest * smallest;
    // Resolve the particle relaxation time m/(6πμa) = St (strain units) ...
    step = std::min(step, 0.5 * s.stokes_number);
    // ... and a contact's oscillation, a tenth of its period 2π√(m_red/k), where it has one: the
    // squeeze at contact, a/(4δ) for equal spheres, damps it unless 2√(k m_red) exceeds it.
    const double damping = smallest / (4.0 * s.roughness);
    if (2.0 * std::sqrt(k * 0.5 * mass) > damping)
      step = std::min(step, 0.1 * 2.0 * std::numbers::pi * std::sqrt(0.5 * mass / k));
  }
  return step;
}

}  // namespace rheosim::coupling
