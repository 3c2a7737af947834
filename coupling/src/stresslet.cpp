// Ambient-flow decomposition for the single-particle terms (see stresslet.hpp).
#include "stresslet.hpp"

#include <cmath>

namespace rheosim::coupling::single_particle {

AmbientAtParticle decompose(const AmbientSample& sample) {
  const auto& g = sample.velocity_gradient;  // g[3 i + j] = ∂u_i/∂x_j
  AmbientAtParticle out;
  out.velocity = sample.velocity;
  out.vorticity_half = {0.5 * (g[7] - g[5]), 0.5 * (g[2] - g[6]), 0.5 * (g[3] - g[1])};
  out.strain_rate = {g[0], g[4], g[8], 0.5 * (g[1] + g[3]), 0.5 * (g[2] + g[6]), 0.5 * (g[5] + g[7])};
  const auto& e = out.strain_rate;
  const double e_colon_e = e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + 2.0 * (e[3] * e[3] + e[4] * e[4] + e[5] * e[5]);
  out.shear_rate = std::sqrt(2.0 * e_colon_e);
  return out;
}

}  // namespace rheosim::coupling::single_particle
