#pragma once
// Rheometer and sweep cases (docs/case-files.md), read from the Section of a core::CaseFile:
// the plates, the liquid(s), the rim shear rates, the fluid solver's grid, and the particles,
// whose DEM keys dem reads and whose hydrodynamic keys coupling reads. Solvers take these
// structs and never see YAML.
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rheosim/core/case.hpp"
#include "rheosim/coupling/suspended_particles.hpp"

namespace rheosim::rheometer {

struct NamedFluid {
  std::string name;  // from `fluids: [{name: ...}]`; "fluid" for a single `fluid:`
  core::FluidProperties properties;
};

// solver: — numerical settings of the fluid solver (all optional).
struct FluidSolverSettings {
  int radial_cells = 40;          // N_r
  int axial_cells = 8;            // N_z
  double radial_grading = 1.0;    // last/first radial cell width (< 1 refines at the rim)
  double axial_stretching = 0.0;  // β of the tanh clustering of axial cells towards both plates (0: uniform)
  bool inertia = true;            // false: creeping (Stokes) limit, where the closed forms hold
  // With inertia: solve each point on half the cells first and report the Richardson torque
  // T + (T − T_2h)/3 (second order in r and z); needs even cell counts >= 8.
  bool extrapolate = false;
  double tolerance = 1e-10;  // relative change per Picard iteration
  int max_iterations = 500;
};

struct RheometerCase {  // kind: rheometer
  core::PlateGeometry geometry;
  core::FluidProperties fluid;                            // the first (or only) fluid
  std::vector<NamedFluid> fluids;                         // every fluid; single phase may list several
  std::vector<double> shear_rates;                        // γ̇_R = ΩR/H [1/s], increasing
  std::optional<coupling::SuspendedParticles> particles;  // absent: single phase
  FluidSolverSettings solver;
  // model: which scene computes a suspension point: the Lees–Edwards box (bulk stress of a
  // periodic box of spheres with lubrication and frictional contacts, the local flow curve
  // integrated over the plate), the walled box (the same spheres between the two plates at the
  // case's gap), the full disk (CFD-DEM of the whole gap), the periodic shear cell (CFD-DEM of a
  // slab of the gap), or auto (the program picks the faithful one and logs why).
  enum class SuspensionModel { automatic, lees_edwards, walled_box, full_disk, shear_cell };
  SuspensionModel suspension_model = SuspensionModel::automatic;
};

// Its YAML name ("auto", "lees_edwards", …), the one mapping for the reader and describe().
[[nodiscard]] const char* name_of(RheometerCase::SuspensionModel model);

struct SweepCase {                       // kind: sweep — every (φ, γ̇_R) of volume_fractions × shear_rates
  RheometerCase rheometer;               // particles hold everything but φ
  std::vector<double> volume_fractions;  // φ [-], increasing; 0 is single phase
};

// A rheometer or sweep case (an LDD case is an ldd::Case, rheosim/ldd/case.hpp).
struct Case : core::CaseHeader {
  std::variant<RheometerCase, SweepCase> spec;
};

// The sweep a case runs as: a sweep case itself; a rheometer case over φ ∈ {0} (the liquid
// alone) or, with particles at φ > 0, {0, φ} (the liquid is the reference of the torque increase).
// Every rheometer and sweep case runs through one pipeline (sweep.hpp): stored points, resume,
// analysis, report.
[[nodiscard]] Case as_sweep(const Case& c);

// Reads a rheometer or sweep case; throws ConfigError naming file:line:col, key, expectation and fix.
[[nodiscard]] Case read_case(const core::CaseFile& file);
[[nodiscard]] Case load_case(const std::string& path);
[[nodiscard]] Case parse_case(std::string_view text, const std::string& name);

// A human-readable listing of a validated case: every value with its SI unit.
[[nodiscard]] std::string describe(const Case& c);

}  // namespace rheosim::rheometer
