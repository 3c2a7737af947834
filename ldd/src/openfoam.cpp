// An LDD dam break as an interFoam case (see openfoam.hpp).
#include "rheosim/ldd/openfoam.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>
#include <utility>
#include <variant>

#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/version.hpp"

namespace rheosim::ldd {

namespace {

using core::foam_footer;
using core::foam_header;
using core::foam_number;

constexpr int front_rows = 3;  // the lowest cell rows the front is sampled on

// The block of the dam break: x from the back wall to the end wall, y from the floor up.
struct Block {
  double x0 = 0, x1 = 0, height = 0;  // [m]
  int nx = 0, ny = 0;
};

std::string block_mesh_dict(const Block& b, double cell) {
  std::string out = foam_header("dictionary", "system", "blockMeshDict");
  out += fmt::format(
      "// x from the reservoir's back wall to the channel's end wall, y from the floor; one cell of\n"
      "// {} m in z (2D). Cells of {} m.\nscale 1;\n\nvertices\n(\n",
      foam_number(cell), foam_number(cell));
  for (const double z : {0.0, cell})
    for (const auto& [x, y] :
         {std::pair{b.x0, 0.0}, std::pair{b.x1, 0.0}, std::pair{b.x1, b.height}, std::pair{b.x0, b.height}})
      out += fmt::format("    ({} {} {})\n", foam_number(x), foam_number(y), foam_number(z));
  out += fmt::format(");\n\nblocks\n(\n    hex (0 1 2 3 4 5 6 7) ({} {} 1) simpleGrading (1 1 1)\n);\n\n", b.nx, b.ny);
  out += "edges\n(\n);\n\nboundary\n(\n";
  const auto patch = [&](std::string_view name, std::string_view type, std::string_view faces) {
    out += fmt::format("    {}\n    {{\n        type {};\n        faces\n        (\n{}        );\n    }}\n", name, type,
                       faces);
  };
  patch("floor", "wall", "            (0 1 5 4)\n");
  patch("backWall", "wall", "            (0 4 7 3)\n");
  patch("endWall", "wall", "            (1 2 6 5)\n");
  patch("atmosphere", "patch", "            (3 7 6 2)\n");
  patch("frontAndBack", "empty", "            (0 3 2 1)\n            (4 5 6 7)\n");
  out += ");\n\nmergePatchPairs\n(\n);\n";
  return out + std::string(foam_footer);
}

std::string set_fields_dict(double length, double height) {
  std::string out = foam_header("dictionary", "system", "setFieldsDict");
  out += fmt::format(
      "// The reservoir [-L, 0] x [0, H] full of the fluid; the gate at x = 0 is gone at t = 0.\n"
      "defaultFieldValues\n(\n    volScalarFieldValue alpha.water 0\n);\n\nregions\n(\n    boxToCell\n    {{\n"
      "        box ({} 0 -1) (0 {} 1);\n        fieldValues\n        (\n            volScalarFieldValue alpha.water 1\n"
      "        );\n    }}\n);\n",
      foam_number(-length), foam_number(height));
  return out + std::string(foam_footer);
}

std::string transport_properties(const core::OpenFoamTransport& t, const core::FluidProperties& fluid) {
  std::string out = foam_header("dictionary", "constant", "transportProperties");
  out += "phases (water air);\n\n// water: the case's fluid\nwater\n{\n";
  out += core::openfoam_viscosity_entries(t, fluid, "    ");
  out += fmt::format("    rho             {};\n}}\n\n", foam_number(fluid.density));
  out += "air\n{\n    transportModel  Newtonian;\n    nu              1.48e-05;\n    rho             1;\n}\n\n";
  out += "// No surface tension: the LDD solver has none.\nsigma           0;\n";
  return out + std::string(foam_footer);
}

std::string gravity(const std::vector<double>& g) {
  std::string out = foam_header("uniformDimensionedVectorField", "constant", "g");
  out += fmt::format("dimensions      [0 1 -2 0 0 0 0];\nvalue           ({} {} 0);\n", foam_number(g.at(0)),
                     foam_number(g.at(1)));
  return out + std::string(foam_footer);
}

// The first step: interFoam's Courant control starts from deltaT, and a first step at the LDD
// run's δt (1e-3 s) jolts the air at the collapsing corner to ~15 m/s, which then caps the step
// at ~6e-5 s. A hundredth of the time a gravity wave takes to cross a cell starts the run
// gently; the step then grows at interFoam's rate (at most 20 % a step) to the Courant limit.
double first_step(const CaseSettings& s, double height) {
  const double g = std::hypot(s.gravity.at(0), s.gravity.at(1));
  return std::min(s.time_step, 0.01 * s.spacing / std::sqrt(g * height));
}

std::string control_dict(const CaseSettings& s, const Block& b, double cell, double max_courant, double first) {
  const double probe = s.output.probe_interval_for(s.end_time);
  const double frame = s.output.frame_interval_for(s.end_time);
  std::string out = foam_header("dictionary", "system", "controlDict");
  out += fmt::format(
      "application     interFoam;\nstartFrom       startTime;\nstartTime       0;\nstopAt          endTime;\n"
      "endTime         {};\ndeltaT          {};\nwriteControl    adjustable;\nwriteInterval   {};\n"
      "purgeWrite      0;\nwriteFormat     ascii;\nwritePrecision  8;\nwriteCompression off;\n"
      "timeFormat      general;\ntimePrecision   6;\nrunTimeModifiable no;\nadjustTimeStep  yes;\n"
      "maxCo           {};\nmaxAlphaCo      {};\nmaxDeltaT       {};\n\n",
      foam_number(s.end_time), foam_number(first), foam_number(frame), foam_number(max_courant),
      foam_number(max_courant), foam_number(probe));
  // α at the cell centres of the lowest three rows, every probe interval: the mass front.
  out += fmt::format(
      "functions\n{{\n    front\n    {{\n        type            sets;\n        libs            (sampling);\n"
      "        writeControl    adjustable;\n        writeInterval   {};\n        setFormat       raw;\n"
      "        interpolationScheme cell;\n        fields          (alpha.water);\n        sets\n        (\n",
      foam_number(probe));
  for (int row = 0; row < front_rows && row < b.ny; ++row) {
    const double y = (row + 0.5) * cell;
    out += fmt::format(
        "            row{}\n            {{\n                type    midPoint;\n                axis    x;\n"
        "                start   ({} {} {});\n                end     ({} {} {});\n            }}\n",
        row, foam_number(b.x0), foam_number(y), foam_number(0.5 * cell), foam_number(b.x1), foam_number(y),
        foam_number(0.5 * cell));
  }
  out += "        );\n    }\n}\n";
  return out + std::string(foam_footer);
}

std::string fv_schemes() {
  return foam_header("dictionary", "system", "fvSchemes") +
         "ddtSchemes\n{\n    default         Euler;\n}\n\ngradSchemes\n{\n    default         Gauss linear;\n}\n\n"
         "divSchemes\n{\n    div(rhoPhi,U)   Gauss linearUpwind grad(U);\n    div(phi,alpha)  Gauss vanLeer;\n"
         "    div(phirb,alpha) Gauss linear;\n    div(((rho*nuEff)*dev2(T(grad(U))))) Gauss linear;\n}\n\n"
         "laplacianSchemes\n{\n    default         Gauss linear corrected;\n}\n\n"
         "interpolationSchemes\n{\n    default         linear;\n}\n\nsnGradSchemes\n{\n    default         "
         "corrected;\n}\n" +
         std::string(foam_footer);
}

// The momentum predictor solves the viscous term implicitly: a yield-stress fluid's capped
// viscosity (ν₀ = μ(0)/ρ, up to 10⁴ times the plastic one) is then stable at the Courant step.
std::string fv_solution() {
  return foam_header("dictionary", "system", "fvSolution") +
         "solvers\n{\n    \"alpha.water.*\"\n    {\n        nAlphaCorr      2;\n        nAlphaSubCycles 1;\n"
         "        cAlpha          1;\n        MULESCorr       yes;\n        nLimiterIter    5;\n"
         "        solver          smoothSolver;\n        smoother        symGaussSeidel;\n"
         "        tolerance       1e-8;\n        relTol          0;\n    }\n\n"
         "    \"pcorr.*\"\n    {\n        solver          PCG;\n        preconditioner  DIC;\n"
         "        tolerance       1e-5;\n        relTol          0;\n    }\n\n"
         "    p_rgh\n    {\n        solver          GAMG;\n        smoother        DIC;\n"
         "        tolerance       1e-7;\n        relTol          0.05;\n    }\n\n"
         "    p_rghFinal\n    {\n        $p_rgh;\n        relTol          0;\n    }\n\n"
         "    \"U.*\"\n    {\n        solver          PBiCGStab;\n        preconditioner  DILU;\n"
         "        tolerance       1e-8;\n        relTol          0;\n    }\n}\n\n"
         "PIMPLE\n{\n    momentumPredictor   yes;\n    nOuterCorrectors    1;\n    nCorrectors         3;\n"
         "    nNonOrthogonalCorrectors 0;\n}\n\nrelaxationFactors\n{\n    equations\n    {\n        \".*\" 1;\n"
         "    }\n}\n" +
         std::string(foam_footer);
}

// A field at rest with the dam break's patches: walls get wall, the top atmosphere.
std::string field(std::string_view cls, std::string_view name, std::string_view dimensions, std::string_view value,
                  std::string_view wall, std::string_view atmosphere) {
  std::string out = foam_header(cls, "0", name);
  out += fmt::format("dimensions      {};\n\ninternalField   uniform {};\n\nboundaryField\n{{\n", dimensions, value);
  for (const char* patch : {"floor", "backWall", "endWall"})
    out += fmt::format("    {}\n    {{\n{}    }}\n", patch, wall);
  out += fmt::format(
      "    atmosphere\n    {{\n{}    }}\n    frontAndBack\n    {{\n        type            empty;\n    }}\n}}\n",
      atmosphere);
  return out + std::string(foam_footer);
}

}  // namespace

InterFoamExport export_interfoam(const Case& c, const std::filesystem::path& dir, const InterFoamExportOptions& o) {
  const CaseSettings& s = c.settings;
  const auto* dam = std::get_if<DamBreakScene>(&s.scene);
  if (dam == nullptr)
    core::throw_config_error(
        c.file, "scene.type", fmt::format("a '{}' scene has no interFoam export", s.scene_type), "dam_break",
        "the interFoam export writes the dam break; the rheometer's simpleFoam export is for kind: rheometer");
  if (s.dimension != 2 || s.gravity.size() != 2)
    core::throw_config_error(c.file, "dimension", fmt::format("{}D", s.dimension), "dimension: 2");
  if (!(o.max_courant > 0 && o.max_courant <= 1))
    core::throw_config_error(c.file, "--max-courant", fmt::format("{} is not in (0, 1]", o.max_courant),
                             "interFoam's maxCo in (0, 1]");
  if (!(o.air_height >= 0) || !std::isfinite(o.air_height))
    core::throw_config_error(c.file, "--air-height", fmt::format("{} is not >= 0", o.air_height),
                             "air above the fluid in m, >= 0");

  const double length = dam->reservoir[0], height = dam->reservoir[1], cell = s.spacing;
  Block b;
  b.x0 = -length;
  b.nx = static_cast<int>(std::lround(dam->channel_length / cell));
  b.x1 = b.x0 + b.nx * cell;
  b.ny = static_cast<int>(std::lround((height + (o.air_height > 0 ? o.air_height : 0.5 * height)) / cell));
  b.height = b.ny * cell;

  InterFoamExport result;
  result.directory = dir;
  result.transport = core::openfoam_transport(s.fluid);
  result.cells_x = b.nx;
  result.cells_y = b.ny;
  result.cell_size = cell;
  result.commands =
      "export WM_PROJECT_DIR=/usr/share/openfoam   # Debian's OpenFOAM v1912: no bashrc needed\n"
      "blockMesh > log.blockMesh && setFields > log.setFields && interFoam > log.interFoam\n"
      "# mass front: largest x with alpha.water >= 0.5 in postProcessing/front/<t>/row*_alpha.water.xy, + dx/2\n";

  const auto write = [&](const std::filesystem::path& rel, const std::string& text) {
    core::write_atomically(dir / rel, [&](std::ostream& os) { os << text; });
    result.files.push_back(rel);
  };
  write("system/blockMeshDict", block_mesh_dict(b, cell));
  write("system/setFieldsDict", set_fields_dict(length, height));
  write("system/controlDict", control_dict(s, b, cell, o.max_courant, first_step(s, height)));
  write("system/fvSchemes", fv_schemes());
  write("system/fvSolution", fv_solution());
  write("constant/transportProperties", transport_properties(result.transport, s.fluid));
  write("constant/g", gravity(s.gravity));
  write("constant/turbulenceProperties", core::foam_laminar_turbulence_properties());
  write("0/U",
        field("volVectorField", "U", "[0 1 -1 0 0 0 0]", "(0 0 0)", "        type            noSlip;\n",
              "        type            pressureInletOutletVelocity;\n        value           uniform (0 0 0);\n"));
  write("0/p_rgh", field("volScalarField", "p_rgh", "[1 -1 -2 0 0 0 0]", "0",
                         "        type            fixedFluxPressure;\n        value           uniform 0;\n",
                         "        type            totalPressure;\n        p0              uniform 0;\n"));
  write("0/alpha.water",
        field("volScalarField", "alpha.water", "[0 0 0 0 0 0 0]", "0", "        type            zeroGradient;\n",
              "        type            inletOutlet;\n        inletValue      uniform 0;\n        value           "
              "uniform 0;\n"));
  write("README",
        fmt::format("OpenFOAM v1912 interFoam case written by rheosim {} from {} (sha256 {}).\n"
                    "Dam break: reservoir {} m x {} m behind a gate at x = 0, floor to x = {} m; {} x {} "
                    "cells of {} m; fluid transportModel {}; end time {} s, maxCo {}.\n"
                    "Run, from this directory:\n{}",
                    core::version, c.file.empty() ? c.name : c.file, c.sha256, foam_number(length), foam_number(height),
                    foam_number(b.x1), b.nx, b.ny, foam_number(cell), result.transport.model, foam_number(s.end_time),
                    foam_number(o.max_courant), result.commands));
  // What the comparison reads back (bench/ldd_dam_break_interfoam.sh, the validation test).
  nlohmann::ordered_json info;
  info["rheosim_version"] = core::version;
  info["case"] = {{"file", c.file}, {"name", c.name}, {"sha256", c.sha256}};
  info["scene"] = "dam_break";
  info["reservoir"] = {length, height};
  info["cell_size"] = cell;
  info["cells"] = {b.nx, b.ny};
  info["domain_x"] = {b.x0, b.x1};
  info["domain_height"] = b.height;
  info["front_rows"] = front_rows;
  info["front_files"] = "postProcessing/front/<time>/row<k>_alpha.water.xy";
  info["front_definition"] = "largest cell-centre x with alpha.water >= 0.5, plus cell_size/2";
  info["max_courant"] = o.max_courant;
  info["openfoam_transport"] = {{"model", result.transport.model}, {"note", result.transport.note}};
  core::write_json(dir / "rheosim.json", info);
  result.files.emplace_back("rheosim.json");
  return result;
}

}  // namespace rheosim::ldd
