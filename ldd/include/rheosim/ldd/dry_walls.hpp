#pragma once
// What a free-surface run does with the pressure of wall nodes that stand above the fluid ("dry":
// no interior fluid node within h), a choice of the `solver:` block (ldd/case.hpp, docs/ldd.md).

namespace rheosim::ldd {

//   include     — dry wall nodes carry p = p_atm = 0 and count in the fluid nodes' gradients;
//   exclude     — they carry p = 0 and the fluid nodes beside them rebuild their gradients
//                 without them;
//   extrapolate — every active wall node, dry ones too, carries the fluid's pressure extrapolated
//                 with the hydrostatic offset (the PPE's wall rows; after the solve from the
//                 clipped fluid pressures), not clipped at 0: above the surface that is the
//                 hydrostatic field's extension, −ρg·height, and it stays in the gradients. Only
//                 fluid nodes keep the no-tension clip.
enum class DryWalls { include, exclude, extrapolate };

}  // namespace rheosim::ldd
