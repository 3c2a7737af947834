#include "void_fraction/centre.hpp"

namespace rheosim::coupling {

CentreVoidFraction::Params CentreVoidFraction::Params::from(const core::Section& /*section*/) { return {}; }

void CentreVoidFraction::split(const CellLocator& locator, const ParticleView& particles, ParticleCellMap& out) const {
  out.clear();
  out.offsets.reserve(particles.size() + 1);
  out.shares.reserve(particles.size());
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const CellLocator::Location at = locator.locate(particles.position(p));
    out.mapped_points += at.mapped ? 1 : 0;
    out.shares.push_back({at.cell, sphere_volume_from_radius(particles.radii[p])});
    out.offsets.push_back(out.shares.size());
  }
}

}  // namespace rheosim::coupling
