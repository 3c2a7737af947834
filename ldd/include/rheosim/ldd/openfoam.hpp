#pragma once
// An LDD dam break as an OpenFOAM v1912 interFoam case: the independent reference for the
// free-surface runs (docs/ldd.md, "Dam break against interFoam"). Only text files are written;
// running blockMesh, setFields and interFoam is the caller's (bench/ldd_dam_break_interfoam.sh).
//
// The case (the LDD scene's own geometry and parameters):
//   mesh     system/blockMeshDict: one block, x from the reservoir's back wall −L to the channel's
//            end wall, y from the floor to the fluid's height H plus air_height, square cells of
//            the LDD spacing Δ (rounded to whole cells), one cell thick (empty front and back).
//   phases   water = the case's fluid (ρ and its law mapped by core::openfoam_transport: a yield-
//            stress law becomes HerschelBulkley with the cap ν₀ = μ(0)/ρ), air = ρ 1 kg/m³,
//            ν 1.48e-5 m²/s; surface tension 0 (the LDD solver has none).
//   start    system/setFieldsDict: α = 1 in [−L, 0] × [0, H] (the reservoir; the gate at x = 0 is
//            gone at t = 0), at rest; p_rgh = 0.
//   walls    floor and both end walls noSlip (as the LDD walls); the top is open to the
//            atmosphere (totalPressure p0 = 0, pressureInletOutletVelocity, inletOutlet α).
//   time     the case's end time; the step adapts to maxCo = maxAlphaCo = max_courant, starting
//            from min(δt, 0.01 Δ/√(gH)) (a first step at δt jolts the air; openfoam.cpp).
//   front    system/controlDict samples α at the cell centres of the lowest three cell rows at
//            every probe interval (sets `front`, raw): postProcessing/front/<t>/row*_alpha.water.xy.
//            The mass front is the largest x with α >= 0.5 plus Δ/2, as the LDD front is the
//            largest x of a fluid node plus Δ/2.
//   rheosim.json  the case's name and hash, the cell size and counts, the front's files and
//            definition: what a comparison reads back.
#include <filesystem>
#include <string>
#include <vector>

#include "rheosim/core/openfoam.hpp"
#include "rheosim/ldd/case.hpp"

namespace rheosim::ldd {

struct InterFoamExportOptions {
  double max_courant = 0.5;  // maxCo and maxAlphaCo, in (0, 1]
  double air_height = 0;     // [m] of air above the fluid's height H; 0: H/2
};

struct InterFoamExport {
  std::filesystem::path directory;
  std::vector<std::filesystem::path> files;  // relative to directory, in writing order
  core::OpenFoamTransport transport;         // the fluid's ("water") transport model
  int cells_x = 0, cells_y = 0;              // the block's cells
  double cell_size = 0;                      // [m]
  std::string commands;                      // the shell commands that run the case
};

// Writes the interFoam case of a 2D dam break into dir. A ConfigError names the key for another
// scene, a 3D case, an option out of range or a law without an OpenFOAM model.
[[nodiscard]] InterFoamExport export_interfoam(const Case& c, const std::filesystem::path& dir,
                                               const InterFoamExportOptions& options = {});

}  // namespace rheosim::ldd
