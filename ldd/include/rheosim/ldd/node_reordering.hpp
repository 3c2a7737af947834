#pragma once
// How a cavity run keeps its node cloud ordered after each advection, and how it carries the
// velocity back to the lattice: two choices of the `solver:` block (ldd/case.hpp).

namespace rheosim::ldd {

// How nodes are reordered after the Lagrangian advection (eq. 20), LDD §3.2:
//   lattice — every node goes back to its initial lattice place and its velocity is
//             interpolated there (LatticeInterpolation): the "significant reordering"
//             case of the seed, taken every step. Node spacing is kept exactly, the operators
//             are built once. The default, and the mode validated against Ghia et al.
//   density — position-based dynamics (Macklin & Müller 2013): the nodes stay Lagrangian.
//             pbd_iterations Jacobi sweeps of the density constraint C_i = ρ_i/ρ₀ − 1
//             (ρ_i = Σ_j W_ij + W(0), ρ₀ its median on the initial lattice):
//             Δx_i = s/ρ₀ Σ_j (λ_i + λ_j) ∇W_ij, λ_i = −C_i / Σ_k |∇_k C_i|², plus a
//             minimum-distance push for pairs closer than pbd_min_distance·Δ, each node's shift
//             capped at pbd_max_shift·Δ per sweep; walls do not move; fluid nodes are kept
//             wall_clearance·Δ inside the walls (without velocity into them); velocities follow
//             the shift to first order, u += ⟨∇u⟩·δx. Experimental: at the lid corners of a
//             cavity the cloud opens a void/pile-up within ~0.2 L/U and the run diverges
//             (docs/ldd.md).
enum class Reordering { lattice, density };

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
