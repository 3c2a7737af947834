#include "rheosim/rheometer/openfoam.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>
#include <ostream>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/units.hpp"
#include "rheosim/core/version.hpp"
#include "rheosim/rheometer/plate.hpp"

namespace rheosim::rheometer {

namespace {

constexpr int max_cells = 100000;  // per direction; far beyond anything a 2-core machine runs

void check_mesh(const OpenFoamMesh& mesh, double core_fraction) {
  const auto check = [](int n, const char* what) {
    if (n < 1 || n > max_cells)
      core::throw_config_error("", std::string("--mesh ") + what,
                               fmt::format("{} cells is not in [1, {}]", n, max_cells), "a positive number of cells");
  };
  check(mesh.radial_cells, "radial_cells");
  check(mesh.azimuthal_cells, "azimuthal_cells");
  check(mesh.axial_cells, "axial_cells");
  if (!(core_fraction >= 0.2 && core_fraction <= 0.65))
    core::throw_config_error("", "core_fraction", fmt::format("{} is not in [0.2, 0.65]", core_fraction),
                             "half-width of the O-grid's core square as a fraction of R");
}

}  // namespace

// ----------------------------------------------------------------------------------------- mesh

OpenFoamMesh OpenFoamMesh::preset(std::string_view name) {
  std::string upper(name);
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char ch) { return std::toupper(ch); });
  if (upper == "M1") return m1();
  if (upper == "M2") return m2();
  if (upper == "M3") return m3();
  core::throw_config_error("", "--mesh", fmt::format("'{}' is not a mesh preset", name),
                           "M1 (15×30×4), M2 (30×60×8) or M3 (60×120×16), CD §2.3");
}

OpenFoamRim parse_openfoam_rim(std::string_view name) {
  for (const OpenFoamRim rim : {OpenFoamRim::shear_free, OpenFoamRim::slip})
    if (name == name_of(rim)) return rim;
  core::throw_config_error("", "--rim", fmt::format("'{}' is not a rim condition", name),
                           "shear_free (τ_rθ = 0, rheosim's rim) or slip (OpenFOAM's ∂u_t/∂n = 0)");
}

long long OpenFoamMesh::cell_count() const {
  const long long nr = radial_cells, nq = azimuthal_cells, nz = axial_cells;
  return (nq * nq + 4 * nr * nq) * nz;
}

std::string openfoam_block_mesh_dict(const core::PlateGeometry& geometry, const OpenFoamMesh& mesh,
                                     double core_fraction) {
  check_mesh(mesh, core_fraction);
  const double R = geometry.radius;
  const double H = geometry.gap;
  const double s = core_fraction * R;   // half-width of the core square
  const double d = R * std::sqrt(0.5);  // rim points at 45° + k·90°
  // Vertex k (0..3): core corner at 45° + k·90°; 4 + k: rim point at the same angle; +8: z = H.
  const std::array<std::array<double, 2>, 4> core_xy{{{s, s}, {-s, s}, {-s, -s}, {s, -s}}};
  const std::array<std::array<double, 2>, 4> rim_xy{{{d, d}, {-d, d}, {-d, -d}, {d, -d}}};
  const std::array<std::array<double, 2>, 4> arc_mid{{{0, R}, {-R, 0}, {0, -R}, {R, 0}}};  // between k and k+1

  std::string out = core::foam_header("dictionary", "system", "blockMeshDict");
  out += fmt::format(
      "// Parallel-plate gap: radius R = {} m, gap H = {} m. 5-block O-grid: a square core of\n"
      "// half-width {} m and four outer blocks to arcs of radius R. Cells: {} radial (outer\n"
      "// blocks) x {} per quarter of the circumference x {} across the gap = {} cells.\n\n",
      core::foam_number(R), core::foam_number(H), core::foam_number(s), mesh.radial_cells, mesh.azimuthal_cells,
      mesh.axial_cells, mesh.cell_count());
  out += "scale   1;\n\nvertices\n(\n";
  for (int layer = 0; layer < 2; ++layer) {
    const double z = layer == 0 ? 0.0 : H;
    for (int k = 0; k < 4; ++k)
      out += fmt::format("    ({} {} {})  // {}: core corner, z = {}\n", core::foam_number(core_xy[k][0]),
                         core::foam_number(core_xy[k][1]), core::foam_number(z), 8 * layer + k, layer == 0 ? "0" : "H");
    for (int k = 0; k < 4; ++k)
      out +=
          fmt::format("    ({} {} {})  // {}: rim, z = {}\n", core::foam_number(rim_xy[k][0]),
                      core::foam_number(rim_xy[k][1]), core::foam_number(z), 8 * layer + 4 + k, layer == 0 ? "0" : "H");
  }
  out += ");\n\n";

  // Hex vertex order: bottom face counter-clockwise seen from +z, then the top face above it.
  const int nr = mesh.radial_cells, nq = mesh.azimuthal_cells, nz = mesh.axial_cells;
  std::array<std::array<int, 8>, 5> blocks{};
  blocks[0] = {2, 3, 0, 1, 10, 11, 8, 9};  // core: x1 along +x, x2 along +y
  for (int k = 0; k < 4; ++k) {            // outer block k: x1 radial, x2 counter-clockwise
    const int k1 = (k + 1) % 4;
    blocks[k + 1] = {k, 4 + k, 4 + k1, k1, 8 + k, 12 + k, 12 + k1, 8 + k1};
  }
  out += "blocks\n(\n";
  for (int b = 0; b < 5; ++b) {
    const auto& v = blocks[b];
    out += fmt::format("    hex ({} {} {} {} {} {} {} {}) ({} {} {}) simpleGrading (1 1 1)  // {}\n", v[0], v[1], v[2],
                       v[3], v[4], v[5], v[6], v[7], b == 0 ? nq : nr, nq, nz,
                       b == 0 ? std::string("core") : fmt::format("outer {}", b - 1));
  }
  out += ");\n\nedges\n(\n";
  for (int layer = 0; layer < 2; ++layer) {
    const double z = layer == 0 ? 0.0 : H;
    for (int k = 0; k < 4; ++k)
      out += fmt::format("    arc {} {} ({} {} {})\n", 8 * layer + 4 + k, 8 * layer + 4 + (k + 1) % 4,
                         core::foam_number(arc_mid[k][0]), core::foam_number(arc_mid[k][1]), core::foam_number(z));
  }
  out += ");\n\nboundary\n(\n";
  const auto face = [](int a, int b, int c, int e) { return fmt::format("            ({} {} {} {})\n", a, b, c, e); };
  // Faces are listed with outward normals (right-hand rule).
  std::string top, bottom, rim;
  for (const auto& v : blocks) {
    top += face(v[4], v[5], v[6], v[7]);
    bottom += face(v[0], v[3], v[2], v[1]);
  }
  for (int b = 1; b < 5; ++b) rim += face(blocks[b][1], blocks[b][2], blocks[b][6], blocks[b][5]);
  out += "    top     // z = H, rotating plate\n    {\n        type wall;\n        faces\n        (\n" + top +
         "        );\n    }\n";
  out += "    bottom  // z = 0, fixed plate\n    {\n        type wall;\n        faces\n        (\n" + bottom +
         "        );\n    }\n";
  out += "    rim     // r = R, flat shear-free meniscus\n    {\n        type patch;\n        faces\n        (\n" +
         rim + "        );\n    }\n";
  out += ");\n\nmergePatchPairs\n(\n);\n";
  out += core::foam_footer;
  return out;
}

// --------------------------------------------------------------------------------------- export

namespace {

std::string transport_properties(const core::OpenFoamTransport& t, const core::FluidProperties& fluid) {
  std::string out = core::foam_header("dictionary", "constant", "transportProperties");
  out += core::openfoam_viscosity_entries(t, fluid);
  out += core::foam_footer;
  return out;
}

std::string control_dict(const OpenFoamExportOptions& o, double density) {
  std::string out = core::foam_header("dictionary", "system", "controlDict");
  out += fmt::format(
      "application     simpleFoam;\n\n"
      "startFrom       startTime;\n"
      "startTime       0;\n"
      "stopAt          endTime;\n"
      "endTime         {0};       // SIMPLE iterations at most; residualControl stops earlier\n"
      "deltaT          1;\n\n"
      "writeControl    timeStep;\n"
      "writeInterval   {0};\n"
      "purgeWrite      0;\n"
      "writeFormat     ascii;\n"
      "writePrecision  12;\n"
      "writeCompression off;\n"
      "timeFormat      general;\n"
      "timePrecision   8;\n"
      "runTimeModifiable false;\n\n"
      "functions\n"
      "{{\n"
      "    // Force and moment of the fluid on the rotating plate, about the origin, in N and N m\n"
      "    // (kinematic pressure and stress times rhoInf). postProcessing/forces/0/moment.dat:\n"
      "    // the plate's torque is minus the total moment's z component.\n"
      "    forces\n"
      "    {{\n"
      "        type            forces;\n"
      "        libs            (\"libforces.so\");\n"
      "        writeControl    timeStep;\n"
      "        writeInterval   1;\n"
      "        log             false;\n"
      "        patches         (top);\n"
      "        rho             rhoInf;\n"
      "        rhoInf          {1};\n"
      "        CofR            (0 0 0);\n"
      "    }}\n\n"
      "    // The same on the fixed plate: in a converged steady state its moment balances the top's\n"
      "    // (the slip rim carries no torque), a check of convergence and of the rim condition.\n"
      "    forcesBottom\n"
      "    {{\n"
      "        $forces;\n"
      "        patches         (bottom);\n"
      "    }}\n"
      "}}\n",
      o.max_iterations, core::foam_number(density));
  out += core::foam_footer;
  return out;
}

std::string fv_schemes() {
  std::string out = core::foam_header("dictionary", "system", "fvSchemes");
  out +=
      "// Second order in space (CD §2.3: least-squares velocity gradient, linear diffusion,\n"
      "// linear-upwind convection); steady.\n"
      "ddtSchemes\n{\n    default         steadyState;\n}\n\n"
      "gradSchemes\n{\n    default         Gauss linear;\n    grad(U)         leastSquares;\n}\n\n"
      "divSchemes\n{\n    default         none;\n"
      "    div(phi,U)      bounded Gauss linearUpwind grad(U);\n"
      "    div((nuEff*dev2(T(grad(U))))) Gauss linear;\n}\n\n"
      "laplacianSchemes\n{\n    default         Gauss linear corrected;\n}\n\n"
      "interpolationSchemes\n{\n    default         linear;\n}\n\n"
      "snGradSchemes\n{\n    default         corrected;\n}\n";
  out += core::foam_footer;
  return out;
}

std::string fv_solution(const OpenFoamExportOptions& o) {
  std::string out = core::foam_header("dictionary", "system", "fvSolution");
  out += fmt::format(
      "solvers\n{{\n"
      "    p\n    {{\n        solver          GAMG;\n        smoother        GaussSeidel;\n"
      "        tolerance       1e-12;\n        relTol          0.01;\n    }}\n\n"
      "    U\n    {{\n        solver          smoothSolver;\n        smoother        symGaussSeidel;\n"
      "        tolerance       1e-14;\n        relTol          0.01;\n    }}\n}}\n\n"
      "// SIMPLEC; the domain is closed (walls and a slip rim), so the pressure level is pinned.\n"
      "SIMPLE\n{{\n"
      "    nNonOrthogonalCorrectors 1;\n"
      "    consistent      yes;\n"
      "    pRefCell        0;\n"
      "    pRefValue       0;\n\n"
      "    residualControl\n    {{\n        p               {0};\n        U               {0};\n    }}\n}}\n\n"
      "relaxationFactors\n{{\n    equations\n    {{\n        U               0.9;\n    }}\n}}\n",
      core::foam_number(o.residual_tolerance));
  out += core::foam_footer;
  return out;
}

// partialSlip valueFraction f = −d/(R_f − d) for every rim face, in blockMesh's order: outer
// block 0..3 (as listed in the rim patch), then axial layer, then azimuthal index (checked
// against blockMesh's face centres). d is estimated from the block geometry: the rim cell spans
// the last 1/N_r of the straight line from the core square's side to the arc at the same
// parametric position, so d ≈ (L/(2N_r)) (û·n̂). blockMesh's transfinite interpolation moves
// the true centre by < 1 % of d (measured on M1).
std::vector<double> rim_value_fractions(const core::PlateGeometry& g, const OpenFoamMesh& mesh, double core_fraction) {
  const double R = g.radius;
  const double s = core_fraction * R;
  const int nq = mesh.azimuthal_cells;
  const double half_step = core::units::pi / (4.0 * nq);  // half the angle of one rim face
  const double face_radius = R * std::cos(half_step);     // the face centre lies on the chord
  const std::array<std::array<double, 2>, 4> corner{{{s, s}, {-s, s}, {-s, -s}, {s, -s}}};
  std::vector<double> f;
  f.reserve(static_cast<std::size_t>(4 * nq * mesh.axial_cells));
  for (int b = 0; b < 4; ++b) {
    const auto& c0 = corner[b];
    const auto& c1 = corner[(b + 1) % 4];
    for (int k = 0; k < mesh.axial_cells; ++k) {
      for (int j = 0; j < nq; ++j) {
        const double t = (j + 0.5) / nq;
        const double angle = core::units::pi / 4.0 + core::units::pi / 2.0 * (b + t);
        const double nx = std::cos(angle), ny = std::sin(angle);
        const double sx = c0[0] + t * (c1[0] - c0[0]), sy = c0[1] + t * (c1[1] - c0[1]);
        const double lx = face_radius * nx - sx, ly = face_radius * ny - sy;
        const double length = std::hypot(lx, ly);
        const double d = length / (2.0 * mesh.radial_cells) * (lx * nx + ly * ny) / length;
        f.push_back(-d / (face_radius - d));
      }
    }
  }
  return f;
}

std::string velocity_field(double omega, const core::PlateGeometry& g, const OpenFoamExportOptions& o) {
  std::string rim;
  if (o.rim == OpenFoamRim::slip) {
    rim =
        "    rim         // OpenFOAM's slip: du_t/dn = 0, i.e. du_theta/dr = 0, so tau_r_theta = -mu u_theta/R\n"
        "    {\n        type            slip;\n    }\n";
  } else {
    const auto f = rim_value_fractions(g, o.mesh, o.core_fraction);
    rim = fmt::format(
        "    // Flat shear-free meniscus (as rheosim's solver): u_r = 0 and tau_r_theta = 0, i.e.\n"
        "    // du_theta/dr = u_theta/r. partialSlip's face value (1 - f) u_t,cell with f = -d/(R_f - d)\n"
        "    // (d: cell centre to face) gives (u_f - u_cell)/d = u_f/R_f. OpenFOAM's plain slip would\n"
        "    // impose du_theta/dr = 0 instead, a rim drag of -mu u_theta/R.\n"
        "    rim\n    {{\n        type            partialSlip;\n"
        "        valueFraction   nonuniform List<scalar> {}\n(\n",
        f.size());
    for (std::size_t i = 0; i < f.size(); ++i)
      rim += fmt::format("{:.9g}{}", f[i], (i % 8 == 7 || i + 1 == f.size()) ? "\n" : " ");
    rim += ");\n        value           uniform (0 0 0);\n    }\n";
  }
  std::string out = core::foam_header("volVectorField", "0", "U");
  out += fmt::format(
      "dimensions      [0 1 -1 0 0 0 0];\n\n"
      "internalField   uniform (0 0 0);\n\n"
      "boundaryField\n{{\n"
      "    top         // rotates at Omega = gammaDot_R H / R about +z: u = Omega (e_z x r)\n"
      "    {{\n        type            rotatingWallVelocity;\n        origin          (0 0 0);\n"
      "        axis            (0 0 1);\n        omega           {};\n        value           uniform (0 0 0);\n"
      "    }}\n"
      "    bottom\n    {{\n        type            noSlip;\n    }}\n"
      "{}"
      "}}\n",
      core::foam_number(omega), rim);
  out += core::foam_footer;
  return out;
}

std::string pressure_field() {
  std::string out = core::foam_header("volScalarField", "0", "p");
  out +=
      "dimensions      [0 2 -2 0 0 0 0];   // kinematic pressure p/rho\n\n"
      "internalField   uniform 0;\n\n"
      "boundaryField\n{\n"
      "    top\n    {\n        type            zeroGradient;\n    }\n"
      "    bottom\n    {\n        type            zeroGradient;\n    }\n"
      "    rim\n    {\n        type            zeroGradient;\n    }\n"
      "}\n";
  out += core::foam_footer;
  return out;
}

}  // namespace

OpenFoamExport export_openfoam(const Case& c, double rim_shear_rate, const std::filesystem::path& dir,
                               const OpenFoamExportOptions& options) {
  const auto* rc = std::get_if<RheometerCase>(&c.spec);
  if (rc == nullptr)
    core::throw_config_error(c.file, "kind", fmt::format("'{}' cannot be exported to OpenFOAM", c.kind),
                             "kind: rheometer (single phase)",
                             "OpenFOAM is rheosim's single-phase peer; sweeps and LDD scenes have no OpenFOAM export");
  if (rc->particles)
    core::throw_config_error(c.file, "particles", "a particle-laden case cannot be exported to OpenFOAM",
                             "a single-phase rheometer case (no particles: section)",
                             "remove particles: to export the suspending fluid alone");
  if (!(rim_shear_rate > 0) || !std::isfinite(rim_shear_rate))
    core::throw_config_error(c.file, "--shear-rate", fmt::format("{} is not a positive rim shear rate", rim_shear_rate),
                             "rim shear rate gammaDot_R = Omega R / H in 1/s, > 0");
  if (options.max_iterations < 1)
    core::throw_config_error(c.file, "max_iterations", fmt::format("{} is not >= 1", options.max_iterations),
                             "number of SIMPLE iterations");
  if (!(options.residual_tolerance > 0))
    core::throw_config_error(c.file, "residual_tolerance", fmt::format("{} is not > 0", options.residual_tolerance),
                             "simpleFoam residualControl tolerance");

  const ParallelPlate plate = ParallelPlate::from(rc->geometry);
  const core::FluidProperties* chosen = &rc->fluid;  // the first (or only) fluid
  if (!options.fluid.empty()) {
    const auto it = std::find_if(rc->fluids.begin(), rc->fluids.end(),
                                 [&](const NamedFluid& f) { return f.name == options.fluid; });
    if (it == rc->fluids.end()) {
      std::string names;
      for (const auto& f : rc->fluids) names += (names.empty() ? "" : ", ") + f.name;
      core::throw_config_error(c.file, "--fluid", fmt::format("the case has no fluid named '{}'", options.fluid),
                               "one of: " + names);
    }
    chosen = &it->properties;
  }
  const core::FluidProperties& fluid = *chosen;
  const double omega = plate.angular_velocity(rim_shear_rate);

  OpenFoamExport result;
  result.directory = dir;
  result.transport = core::openfoam_transport(fluid);
  result.mesh = options.mesh;
  result.cells = options.mesh.cell_count();
  result.rim_shear_rate = rim_shear_rate;
  result.angular_velocity = omega;
  result.gap_reynolds_number =
      plate.gap_reynolds_number(fluid.density, rim_shear_rate, fluid.rheology->viscosity(rim_shear_rate));
  result.closed_form_torque = closed_form_torque(plate, *fluid.rheology, rim_shear_rate);
  result.creeping_torque = creeping_torque(plate, *fluid.rheology, rim_shear_rate);
  result.commands =
      "export WM_PROJECT_DIR=/usr/share/openfoam   # Debian's OpenFOAM v1912: no bashrc needed\n"
      "blockMesh > log.blockMesh && checkMesh > log.checkMesh && simpleFoam > log.simpleFoam\n"
      "tail -n 1 postProcessing/forces/0/moment.dat  # torque on the plate = -(total z), N m\n"
      "tail -n 1 postProcessing/forcesBottom/0/moment.dat  # fixed plate: +(total z) balances it\n";

  const std::string block_mesh = openfoam_block_mesh_dict(rc->geometry, options.mesh, options.core_fraction);

  const auto write = [&](const std::filesystem::path& rel, const std::string& text) {
    core::write_atomically(dir / rel, [&](std::ostream& os) { os << text; });
    result.files.push_back(rel);
  };
  write("system/blockMeshDict", block_mesh);
  write("system/controlDict", control_dict(options, fluid.density));
  write("system/fvSchemes", fv_schemes());
  write("system/fvSolution", fv_solution(options));
  write("constant/transportProperties", transport_properties(result.transport, fluid));
  write("constant/turbulenceProperties", core::foam_laminar_turbulence_properties());
  write("0/U", velocity_field(omega, rc->geometry, options));
  write("0/p", pressure_field());

  const std::string closed =
      result.closed_form_torque ? fmt::format("{:.9g} N m", *result.closed_form_torque) : std::string("none");
  write("README",
        fmt::format(
            "OpenFOAM v1912 case written by rheosim {} from {} (sha256 {}).\n"
            "Parallel plates R = {} m, H = {} m; rim shear rate {} 1/s, Omega = {} rad/s; "
            "{} cells ({}x{}x{}); transportModel {}; rim {}.\n"
            "Creeping-flow torque: closed form {}, quadrature {:.9g} N m; gap Reynolds number "
            "rho Omega H^2/mu(gammaDot_R) = {:.4g} (simpleFoam includes inertia).\n"
            "Run, from this directory:\n{}",
            core::version, c.file.empty() ? c.name : c.file, c.sha256, core::foam_number(plate.radius),
            core::foam_number(plate.gap), core::foam_number(rim_shear_rate), core::foam_number(omega), result.cells,
            options.mesh.radial_cells, options.mesh.azimuthal_cells, options.mesh.axial_cells, result.transport.model,
            options.rim == OpenFoamRim::slip ? "slip (du_t/dn = 0)" : "shear-free (partialSlip, tau_r_theta = 0)",
            closed, result.creeping_torque, result.gap_reynolds_number, result.commands));

  nlohmann::ordered_json info;
  info["rheosim_version"] = core::version;
  info["case"] = {{"file", c.file}, {"name", c.name}, {"sha256", c.sha256}};
  info["radius"] = plate.radius;
  info["gap"] = plate.gap;
  info["density"] = fluid.density;
  nlohmann::ordered_json law;
  law["model"] = std::string(fluid.rheology->name());
  for (const auto& prm : fluid.rheology->parameters()) law[prm.name] = prm.value;
  info["fluid"] =
      !options.fluid.empty() ? options.fluid : (rc->fluids.empty() ? std::string("fluid") : rc->fluids.front().name);
  info["rheology"] = law;
  nlohmann::ordered_json coeffs;
  for (const auto& [key, value] : result.transport.coeffs) coeffs[key] = value;
  info["openfoam_transport"] = {{"model", result.transport.model}, {"coeffs", coeffs}, {"note", result.transport.note}};
  info["mesh"] = {{"radial_cells", options.mesh.radial_cells},
                  {"azimuthal_cells", options.mesh.azimuthal_cells},
                  {"axial_cells", options.mesh.axial_cells},
                  {"core_fraction", options.core_fraction},
                  {"cells", result.cells}};
  info["rim"] = name_of(options.rim);
  info["shear_rate"] = rim_shear_rate;
  info["angular_velocity"] = omega;
  info["gap_reynolds_number"] = result.gap_reynolds_number;
  info["torque_analytic"] =
      result.closed_form_torque ? nlohmann::ordered_json(*result.closed_form_torque) : nlohmann::ordered_json();
  info["torque_creeping"] = result.creeping_torque;
  info["torque_file"] = "postProcessing/forces/0/moment.dat";
  info["torque_sign"] = -1;
  info["torque_file_bottom"] = "postProcessing/forcesBottom/0/moment.dat";  // +z on the fixed plate
  core::write_json(dir / "rheosim.json", info);
  result.files.emplace_back("rheosim.json");
  return result;
}

}  // namespace rheosim::rheometer
