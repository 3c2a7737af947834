#pragma once
// The particles of a suspension point: the solid phase the DEM integrates (dem::ParticleProperties)
// and how the liquid acts on it — the drag law and the near-field hydrodynamics. One `particles:`
// section of the case file holds both; dem reads its keys, this reader the hydrodynamic ones.
#include <string>

#include "rheosim/core/config.hpp"
#include "rheosim/coupling/drag.hpp"
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/dem/particles.hpp"

namespace rheosim::coupling {

struct SuspendedParticles : dem::ParticleProperties {
  // particles.hydrodynamics: near-field hydrodynamics on every DEM step (docs/hydrodynamics.md).
  // YAML `hydrodynamics: {model: lubrication+stresslet, roughness: 1.0e-3, lubrication_cutoff:
  // 0.5}`; model is `none` or terms joined by '+': lubrication, stresslet (= single_particle),
  // stokes_drag, repulsion. Absent (hydrodynamics_given false): no terms, and a suspension point
  // runs the predictive default (the Lees–Edwards box's near field); `{model: none}` is the
  // seed's drag-only CFD-DEM.
  bool hydrodynamics_given = false;
  NearFieldSettings hydrodynamics{};
  DragLaw drag = DragLaw::di_felice;  // the reader resolves `auto` (drag_automatic: it did)
  bool drag_automatic = false;
};

// Reads a `particles:` section: dem::read_particles for the solid, then `hydrodynamics` and
// `drag`. gap [m] is the plate gap the spheres must fit in.
[[nodiscard]] SuspendedParticles read_suspended_particles(const core::Section& particles, double gap,
                                                          bool with_volume_fraction);

// The listing lines of `rheosim validate` for these particles ("  particles: …\n", the size
// distribution, the near field and the drag), every value with its SI unit.
[[nodiscard]] std::string describe(const SuspendedParticles& particles, double gap);

}  // namespace rheosim::coupling
