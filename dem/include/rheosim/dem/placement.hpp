#pragma once
// Initial particle positions for the parallel-plate gap: monodisperse spheres of diameter d (or
// spheres of given diameters, see "Polydisperse") at a target volume fraction φ, with no overlaps.
// Pure geometry, no LIGGGHTS: dem::RheometerScene hands the result to LIGGGHTS as a data file.
//
// What φ means
//   φ is the particle volume over the whole gap volume V = π R² H (the volume the fluid solver
//   and the rheometer formulas see), so the count is
//       N = round(φ · π R² H / (π d³ / 6)) = round(6 φ R² H / d³).
//   A sphere must lie inside the gap, so its centre is confined to the "accessible" cylinder
//   r <= R − d/2, d/2 <= z <= H − d/2 (volume π (R − d/2)² (H − d)); the walls thus exclude a
//   layer d/2 thick, and the volume fraction of the core is higher than φ (with few particle
//   layers across the gap, e.g. H = 2.5 d in CD §4, markedly so). The placed spheres' volume is
//   exactly N π d³/6, so the achieved φ differs from the target only by the rounding of N
//   (relative error <= 1/(2N)).
//
// Method: lattice, random subset, hard-sphere Monte Carlo shaking
//   Random sequential addition (RSA) stalls at its jamming limit (about 0.38 in bulk, lower in a
//   thin gap) long before φ = 0.5, and compress/grow schemes need many relaxation steps to reach
//   0.5 without overlaps. Instead:
//   1. Lattice. The densest of a family of layered lattices that fits the accessible cylinder:
//      L layers at equal spacing s = (H − d)/(L − 1) (one layer at H/2 for L = 1), each layer a
//      hexagonal lattice (stacked A-B-C, each layer over the hollows of the one below) or a
//      square lattice (stacked A-B), with the smallest in-plane spacing a that keeps neighbours
//      in the same and adjacent layers at least d apart:
//          hexagonal  a = max(d, √(3 (d² − s²))),  needs 3s >= d when L >= 4 (A over A)
//          square     a = max(d, √(2 (d² − s²))),  needs 2s >= d when L >= 3 (A over A)
//      L runs over every count that fits; the lattice with the most sites per area wins. This
//      family contains the close-packed structures of thin slits (two hexagonal layers, three
//      square layers, ...) and tends to FCC (111) stacking for wide gaps. Its capacity is well
//      above 0.5 as soon as the gap holds a few layers (CD §4: R = 15 mm, H = 0.5 mm, d = 0.2 mm
//      gives three square layers and about 0.62; R = 2 mm, H = 0.5 mm, d = 0.1 mm gives six
//      hexagonal layers and about 0.64). The lattice is turned by a random angle about the axis.
//   2. Stretch and draw. If the densest lattice has fewer sites than N, place_particles throws.
//      Otherwise the layers are spread in-plane (a grows, s stays) until they hold about 1.05 N
//      sites, so neighbouring particles no longer touch (in the densest lattice they do, and
//      hardly any Monte Carlo move would be accepted), and N of the sites are drawn uniformly
//      at random (exact count by construction).
//   3. Shaking. `shake_sweeps` sweeps of hard-sphere Monte Carlo: each particle in turn gets a
//      random displacement in a cube of half-width δ, accepted only if the sphere stays inside
//      the gap and overlaps nobody (cell list); δ adapts after each sweep towards 40 %
//      acceptance (at most d). This removes the lattice order at low and moderate φ (there δ
//      grows to d and particles wander several diameters) and jitters it at high φ, where a
//      layered structure next to flat walls is physical anyway. Overlap-free moves keep the
//      no-overlap property, so it holds for any number of sweeps.
//   Finally every pair and wall distance is checked once more (cell list); a violation would
//   be an internal error (std::logic_error).
//   All distances use d (1 + 1e-9) (a 1e-9 d clearance), so "no overlap" survives the rounding
//   of positions: pair distances >= d, distances to the plates and to the rim >= d/2.
//
// Polydisperse particles (PlacementParams::diameters, e.g. from size_distribution.hpp): the
//   same method with the lattice spaced for the largest diameter d_max; particle i takes the
//   i-th drawn site, and the Monte Carlo moves and the final check use each pair's own contact
//   distance (r_i + r_j)(1 + 1e-9) and each particle's own wall distance. φ is then the given
//   spheres' total volume over π R² H. The price of spacing sites for d_max: the lattice holds
//   at most capacity · (mean d³ / d_max³) of solid, so a wide distribution at high φ in a thin
//   gap may be refused (the error says so).
//
// Randomness: std::mt19937_64 from `seed` with our own conversion to doubles and our own
// shuffle, so a seed gives the same positions with any standard library (and on every MPI rank).
//
// Example
//   const auto p = dem::place_particles({.plate_radius = 2e-3, .gap = 5e-4, .diameter = 1e-4,
//                                        .volume_fraction = 0.3, .seed = 7});
//   p.centres  // [x0 y0 z0 x1 y1 z1 ...] in m, p.centres.size() == 3 · p.count
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rheosim::dem {

struct PlacementParams {
  double plate_radius = 0.0;     // R [m], > 0
  double gap = 0.0;              // H [m], > diameter
  double diameter = 0.0;         // d [m], > 0 and < R
  double volume_fraction = 0.0;  // φ [-], in [0, 0.5], of the whole gap volume π R² H
  std::uint64_t seed = 1;        // random subset, lattice angle and shaking
  int shake_sweeps = 50;         // Monte Carlo sweeps, >= 0 (0: lattice sites only)
  // Polydisperse: the diameter of every particle [m] (e.g. from sample_diameters); then N is
  // their number, diameter and volume_fraction are ignored, and the lattice is spaced for
  // the largest of them (it must be < gap and < plate_radius).
  std::vector<double> diameters{};
};

struct Placement {
  std::vector<double> centres;    // [x0 y0 z0 x1 y1 z1 ...] [m], axis at x = y = 0, bottom plate z = 0
  std::vector<double> diameters;  // [d0 d1 ...] [m], one per particle
  std::size_t count = 0;          // N = round(6 φ R² H / d³), or the number of given diameters
  double volume_fraction = 0.0;   // achieved: Σ π d_i³/6 / (π R² H)
  // The lattice of step 1.
  std::string lattice;                    // "hexagonal" or "square"
  int layers = 0;                         // L
  double layer_spacing = 0.0;             // s [m] (0 for one layer)
  double capacity_volume_fraction = 0.0;  // densest lattice: sites π d³/6 / (π R² H)
  double lattice_spacing = 0.0;           // a [m] after stretching (step 2)
  std::size_t lattice_sites = 0;          // sites of the stretched lattice (>= count)
  // The shaking of step 3.
  double shake_acceptance = 0.0;  // accepted / proposed moves over all sweeps
  double shake_step = 0.0;        // final δ [m]
};

// N = round(φ · π R² H / (π d³/6)). Throws std::invalid_argument for values out of range.
[[nodiscard]] std::size_t target_particle_count(double plate_radius, double gap, double diameter,
                                                double volume_fraction);

// See the header comment. Throws std::invalid_argument naming the field and its range, or
// saying that φ exceeds what the lattice holds for this gap (with that capacity).
[[nodiscard]] Placement place_particles(const PlacementParams& params);

}  // namespace rheosim::dem
