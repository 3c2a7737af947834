#pragma once
// OpenFOAM as the independent peer (docs/openfoam.md): a single-phase `kind: rheometer`
// case at one rim shear rate, written as a complete OpenFOAM v1912 case directory for simpleFoam.
// OpenFOAM is used as a program, not a library (Debian packages no headers): these functions only
// write text files; running blockMesh/simpleFoam is left to the caller (see docs/openfoam.md and
// bench/openfoam_compare.sh).
//
// The case (all lengths in metres, CD §2.3 geometry):
//   mesh   system/blockMeshDict: a 5-block O-grid of the gap 0 <= z <= H, r <= R — a square
//          core of half-width s = core_fraction·R and four outer blocks from the square's sides
//          to arcs of radius R. Counts per OpenFoamMesh below (CD's M1–M3 presets).
//   flow   simpleFoam (steady, laminar, inertia included), SIMPLEC with residual control.
//   walls  top (z = H): rotatingWallVelocity about +z through the origin, Ω = γ̇_R H / R.
//          bottom (z = 0): noSlip. rim (r = R): the flat shear-free meniscus of rheosim's own
//          solver, u_r = 0 and zero shear stress τ_rθ = μ r ∂(u_θ/r)/∂r = 0; p zeroGradient.
//          See OpenFoamRim: OpenFOAM's `slip` is not that condition on a curved rim.
//   torque system/controlDict: a `forces` function object on patch top, CofR (0 0 0),
//          rho rhoInf with the real density, so postProcessing/forces/0/moment.dat holds the
//          moment of the fluid on the top plate in N·m. The plate rotates in +z, so the fluid's
//          moment on it is negative: torque = −(total moment)_z. A second function object,
//          forcesBottom, does the same on the fixed plate (postProcessing/forcesBottom/0/
//          moment.dat, +z): at convergence the two balance, since the slip rim carries no torque.
//   fluid  constant/transportProperties with the rheology in OpenFOAM's kinematic units:
//          ν = μ/ρ, k/ρ, τ₀/ρ (see core::openfoam_transport for each law and where it differs).
//
// OpenFOAM's shear rate is strainRate() = √2 |symm(∇U)| = √(2E:E), the same γ̇ as rheosim's.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rheosim/core/openfoam.hpp"
#include "rheosim/rheometer/case.hpp"

namespace rheosim::rheometer {

// Cell counts of the O-grid, named after CD §2.3 (M#: R × θ × H).
// CD's azimuthal counts (30, 60, 120) are not multiples of 4, so they cannot be the number of
// cells around a 5-block O-grid's circumference. We read them as block counts: each of the four
// outer blocks has `radial_cells` × `azimuthal_cells` × `axial_cells` cells (core edge → rim ×
// along its quarter arc × across the gap), and the square core has `azimuthal_cells`² ×
// `axial_cells`. Around the rim there are 4·azimuthal_cells cells. With the default core
// half-width s = R/2 and azimuthal = 2·radial (all three presets) the cells along the x and y
// axes have the same radial size R/(2·radial_cells) in the core and in the outer blocks.
//   M1 15×30×4: 10 800 cells   M2 30×60×8: 86 400 cells   M3 60×120×16: 691 200 cells
struct OpenFoamMesh {
  int radial_cells = 30;     // per outer block, from the core square to the rim
  int azimuthal_cells = 60;  // per quarter (each outer block's arc, each side of the core)
  int axial_cells = 8;       // across the gap H

  [[nodiscard]] static OpenFoamMesh m1() { return {15, 30, 4}; }
  [[nodiscard]] static OpenFoamMesh m2() { return {30, 60, 8}; }
  [[nodiscard]] static OpenFoamMesh m3() { return {60, 120, 16}; }
  // "M1" | "M2" | "M3" (case-insensitive); anything else is a ConfigError.
  [[nodiscard]] static OpenFoamMesh preset(std::string_view name);

  [[nodiscard]] long long cell_count() const;
  bool operator==(const OpenFoamMesh&) const = default;
};

// The velocity condition at the rim r = R.
// OpenFOAM's `slip` sets the face's tangential velocity to the cell centre's, i.e. ∂u_t/∂n = 0.
// On the curved rim that is ∂u_θ/∂r = 0, so the shear stress there is τ_rθ = −μ u_θ/R, not 0:
// the rim drags the fluid. In creeping flow this raises the top-plate torque by (4/3)(H/R)² of
// the closed form in the continuum limit (+0.15 % for CD's H/R = 1/30; measured +0.11 % on M2) and
// lowers the bottom plate's by (2/3)(H/R)² — an error that refinement does not remove.
//   shear_free  `partialSlip` with a per-face valueFraction f = −d/(R_f − d) (d: cell-centre to
//               face distance, R_f: face radius). Its face value u_f = (1 − f) u_t,cell makes
//               (u_f − u_cell)/d = u_f/R_f, i.e. ∂u_θ/∂r = u_θ/r: zero τ_rθ, as rheosim's rim.
//               It applies the same gradient to the axial component (∂u_z/∂r = u_z/R instead of
//               0), an O(u_z/R) error confined to the weak secondary flow. The per-face values
//               follow blockMesh's rim face order (block, then axial layer, then azimuth) and an
//               estimate of d within 1 % (enough: the rim term itself is a 0.15 % effect).
//   slip        OpenFOAM's `slip`, for reference.
enum class OpenFoamRim { shear_free, slip };
// "shear_free" | "slip" (the CLI's --rim); anything else is a ConfigError naming both.
[[nodiscard]] OpenFoamRim parse_openfoam_rim(std::string_view name);
// Its name, as parse_openfoam_rim reads it.
[[nodiscard]] constexpr const char* name_of(OpenFoamRim rim) {
  return rim == OpenFoamRim::slip ? "slip" : "shear_free";
}

struct OpenFoamExportOptions {
  OpenFoamMesh mesh = OpenFoamMesh::m2();
  OpenFoamRim rim = OpenFoamRim::shear_free;
  std::string fluid;           // which of the case's `fluids:` (by name); empty: the first
  double core_fraction = 0.5;  // half-width of the core square / R, in (0.2, 0.65)
  int max_iterations = 10000;  // SIMPLE iterations at most (controlDict endTime, deltaT 1)
  // residualControl for p and U: simpleFoam stops when both initial residuals fall below it.
  double residual_tolerance = 1e-7;
};

// system/blockMeshDict for the plate gap (16 vertices, 5 hex blocks, 8 arc edges; patches top,
// bottom, rim). Throws ConfigError for cell counts < 1 or a core_fraction out of range.
[[nodiscard]] std::string openfoam_block_mesh_dict(const core::PlateGeometry& geometry, const OpenFoamMesh& mesh,
                                                   double core_fraction = 0.5);

// What export_openfoam wrote and the numbers a comparison needs.
struct OpenFoamExport {
  std::filesystem::path directory;
  std::vector<std::filesystem::path> files;  // relative to directory, in writing order
  core::OpenFoamTransport transport;
  OpenFoamMesh mesh;
  long long cells = 0;
  double rim_shear_rate = 0;                 // γ̇_R [1/s]
  double angular_velocity = 0;               // Ω = γ̇_R H/R [rad/s]
  double gap_reynolds_number = 0;            // ρΩH²/μ(γ̇_R)
  std::optional<double> closed_form_torque;  // [N·m], creeping flow, unregularised law
  double creeping_torque = 0;                // [N·m], creeping flow, the law as implemented
  std::string commands;                      // the shell commands that run the case
};

// Writes the OpenFOAM v1912 case for `c` (kind: rheometer, no particles; of a case with several
// `fluids:`, the one options.fluid names, else the first) at rim shear rate
// `rim_shear_rate` [1/s] into `dir` (created; existing files of the same names are replaced):
//   system/{blockMeshDict,controlDict,fvSchemes,fvSolution}, constant/{transportProperties,
//   turbulenceProperties}, 0/{U,p}, README (the command sequence) and rheosim.json (geometry,
//   Ω, transport mapping, closed-form and creeping torques, gap Reynolds number).
// Every file is written atomically. Throws ConfigError for a case that cannot be exported
// (another kind, particles, an unknown fluid name, a law without OpenFOAM model, γ̇_R <= 0) and
// RunError on I/O failure.
OpenFoamExport export_openfoam(const Case& c, double rim_shear_rate, const std::filesystem::path& dir,
                               const OpenFoamExportOptions& options = {});

}  // namespace rheosim::rheometer
