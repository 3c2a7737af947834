#pragma once
// stresslet (alias single_particle) and stokes_drag: the single-particle hydrodynamics of a
// rigid sphere of radius a in a linear ambient flow u∞(x) with rate of strain E∞ and vorticity
// ω∞ = ½ ∇×u∞, in a liquid of viscosity μ = μ(√(2E∞:E∞)):
//   torque     T = −8πμa³ (Ω − ω∞)            (Kim & Karrila 1991, §2.4: rotlet of a sphere)
//   stresslet  S = (20/3)πμa³ E∞              (Batchelor & Green, J. Fluid Mech. 56 (1972) 375;
//                                             Einstein: n·S = 2.5 φ · 2μE∞, so η_r = 1 + 2.5φ;
//                                             a shear-thinning matrix: μ → μ_S, near_field.hpp)
//   drag       F = −6πμa (U − u∞(x))          (stokes_drag only: Stokes' law on the ambient
//                                             flow, for cells with an imposed flow and no
//                                             fluid solver; CFD-DEM has Di Felice drag instead)
// The torque makes a free sphere spin with the fluid (Ω = ω∞, e.g. γ̇/2 in simple shear); the
// stresslet is what a force- and torque-free sphere adds to the suspension stress. A sphere
// that does not follow the flow (U ≠ u∞, Ω ≠ ω∞) has no further stresslet in Stokes flow
// (R_SU = 0 for one sphere), so S depends on E∞ only.
#include <array>

#include "rheosim/coupling/near_field.hpp"

namespace rheosim::coupling::single_particle {

struct AmbientAtParticle {
  Vector3 velocity{};
  Vector3 vorticity_half{};       // ω∞ = ½ ∇×u∞ [1/s]
  SymmetricTensor strain_rate{};  // E∞ [1/s], xx yy zz xy xz yz
  double shear_rate = 0.0;        // √(2E∞:E∞) [1/s]
};

[[nodiscard]] AmbientAtParticle decompose(const AmbientSample& sample);

}  // namespace rheosim::coupling::single_particle
