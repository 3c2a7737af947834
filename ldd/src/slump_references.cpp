#include "slump_references.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd {

namespace {

// s′ of a cylinder whose unyielded top is `plug` of its height (z₀/H = σ_y/(ρgH), σ_y the axial
// stress at yield): the rest settles to z₀ ln(H/z₀) below it.
double cylinder_slump(double plug) { return plug < 1.0 ? 1.0 - plug * (1.0 - std::log(plug)) : 0.0; }

// τ₀R⁵ of Roussel & Coussot's pancake of volume Ω: 225ρgΩ²/(128π²), read either way.
double pancake_stress_times_radius5(double volume, double density, double gravity) {
  return 225.0 * density * gravity * volume * volume / (128.0 * std::numbers::pi * std::numbers::pi);
}

}  // namespace

double pashias_slump(double yield_stress_ratio) {
  if (!(yield_stress_ratio > 0)) throw std::invalid_argument("pashias_slump: τ′ must be > 0");
  return cylinder_slump(2.0 * yield_stress_ratio);
}

double von_mises_cylinder_slump(double yield_stress_ratio) {
  if (!(yield_stress_ratio > 0)) throw std::invalid_argument("von_mises_cylinder_slump: τ′ must be > 0");
  return cylinder_slump(std::numbers::sqrt3 * yield_stress_ratio);
}

std::optional<double> pashias_yield_stress_ratio(double slump) {
  if (!(slump > 0 && slump < 1)) return std::nullopt;
  // s′(τ′) decreases strictly on (0, 1/2): bisection to rounding.
  double low = 0, high = 0.5;
  for (int k = 0; k < 200 && high - low > 1e-15; ++k) {
    const double mid = 0.5 * (low + high);
    (pashias_slump(mid) > slump ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

double roussel_coussot_spread(double volume, double yield_stress, double density, double gravity) {
  if (!(volume > 0 && yield_stress > 0 && density > 0 && gravity > 0))
    throw std::invalid_argument("roussel_coussot_spread: volume, yield stress, density and gravity must be > 0");
  return 2.0 * std::pow(pancake_stress_times_radius5(volume, density, gravity) / yield_stress, 0.2);
}

double roussel_coussot_yield_stress(double volume, double spread, double density, double gravity) {
  if (!(volume > 0 && spread > 0 && density > 0 && gravity > 0))
    throw std::invalid_argument("roussel_coussot_yield_stress: volume, spread, density and gravity must be > 0");
  return pancake_stress_times_radius5(volume, density, gravity) / std::pow(0.5 * spread, 5);
}

namespace detail {

void compare_slump(const CaseSettings& l, RunSummary& summary, const core::Log& log) {
  const double yield_stress = l.fluid.rheology->yield_stress();
  if (!(yield_stress > 0) || !summary.final_height || !summary.final_spread) return;
  const auto& scene = std::get<SlumpScene>(l.scene);
  const double g = l.gravity_magnitude();
  const double height = scene.cone_height;
  if (scene.cone_top_diameter == scene.cone_bottom_diameter) {
    const double ratio = yield_stress / (l.fluid.density * g * height);
    const double theory = pashias_slump(ratio);
    const double von_mises = von_mises_cylinder_slump(ratio);
    const double measured = 1.0 - *summary.final_height / height;
    CylinderSlumpComparison entry{ratio, theory, measured, measured - theory, von_mises, std::nullopt};
    if (const auto read = pashias_yield_stress_ratio(measured))
      entry.implied_yield_stress = *read * l.fluid.density * g * height;
    summary.pashias = entry;
    log.info(
        "cylinder slump (Pashias et al. 1996): τ′ = τ₀/(ρgH) = {:.4g}, slump s/H {:.4f} ({:.4f} with the von "
        "Mises criterion); this run {:.4f} ({:+.4f}), which the formula reads as τ₀ = {}",
        ratio, theory, von_mises, measured, measured - theory,
        entry.implied_yield_stress
            ? fmt::format("{:.4g} Pa (the law's {:.4g} Pa)", *entry.implied_yield_stress, yield_stress)
            : std::string("— (no slump in (0, 1))"));
    return;
  }
  const double big = 0.5 * scene.cone_bottom_diameter, small = 0.5 * scene.cone_top_diameter;
  const double volume = std::numbers::pi * height * (big * big + big * small + small * small) / 3.0;
  const double diameter = roussel_coussot_spread(volume, yield_stress, l.fluid.density, g);
  const double error = *summary.final_spread / diameter - 1.0;
  const double implied = roussel_coussot_yield_stress(volume, *summary.final_spread, l.fluid.density, g);
  summary.roussel_coussot = ConeSpreadComparison{diameter, error, implied};
  log.info(
      "yield-stress pancake (Roussel & Coussot 2005): spread {:.4g} m; this run {:.4g} m ({:+.1f} %), which the "
      "formula reads as τ₀ = {:.4g} Pa (the law's {:.4g} Pa)",
      diameter, *summary.final_spread, 1e2 * error, implied, yield_stress);
}

}  // namespace detail
}  // namespace rheosim::ldd
