#pragma once
// How a cavity carries the velocity back to the lattice after each advection (its nodes return
// to their lattice places every step, the "significant reordering" of LDD §3.2, so the node
// spacing is kept exactly and the operators are built once): `solver.interpolation` (ldd/case.hpp).

namespace rheosim::ldd {

// How the lattice reordering carries the velocity back to the lattice (lattice_interpolation.hpp):
//   quadratic          — semi-Lagrangian: node i's own quadratic Taylor polynomial evaluated at
//                        its departure point, clamped to the upwind neighbours' range (second
//                        order, no smoothing at zero displacement). The default;
//   shepard            — eq. 12 at X_i over the advected cloud (first order; smooths by O(Δ²)
//                        per step, a numerical viscosity ∝ Δ²/δt);
//   gradient_corrected — eq. 12 plus ⟨∇u⟩_j·(X_i − x'_j), clamped (anti-diffusive ∝ Δ²/δt:
//                        diverged at Re = 1000). Kept for the comparison in docs/ldd.md.
enum class LatticeInterpolation { quadratic, shepard, gradient_corrected };

}  // namespace rheosim::ldd
