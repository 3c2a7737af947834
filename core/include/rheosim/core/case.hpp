#pragma once
// Typed, validated case files (docs/case-files.md). CaseFile parses the YAML and reads the header
// every kind shares; the module that owns the kind reads the rest from its Section, validating
// every key (SI units, ranges, cross-key checks) and rejecting unknown ones, and returns plain
// structs. Solvers take these structs and never see YAML. The rheometer and sweep kinds are read
// here (read_case); the LDD kind by the ldd module.
#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"

namespace rheosim::core {

// ------------------------------------------------------------------ shared building blocks

struct FluidProperties {
  double density = 0;                        // ρ [kg/m³]
  std::shared_ptr<const Rheology> rheology;  // μ(γ̇), never null
};

// ------------------------------------------------------------------------ rheometer cases

struct PlateGeometry {  // geometry: {type: parallel_plate, radius, gap}
  double radius = 0;    // R [m]
  double gap = 0;       // H [m], < R
};

// particles.size_distribution: the spread of sphere diameters (absent: all spheres have d).
// Sizes are given as a rheologist reads a particle-size analysis (volume basis): a lognormal
// by its volume-median d50 (= particles.diameter) and geometric standard deviation σ_g, a
// uniform range, or sieve classes with the share of the solid volume in each.
// Trivially copyable on purpose (fixed arrays, no std::vector/optional): GCC 12 reports false
// maybe-uninitialized warnings for such members in designated initialisers of the enclosing
// structs, which -Werror would turn into build failures wherever particles are initialised.
struct SizeDistribution {
  enum class Type { none, uniform, lognormal, discrete };  // none: monodisperse
  static constexpr int max_classes = 16;
  Type type = Type::none;
  double min_diameter = 0;   // [m] uniform: lower bound; lognormal: truncation; discrete: first class
  double max_diameter = 0;   // [m] uniform: upper bound; lognormal: truncation; discrete: last class
  double geometric_std = 1;  // σ_g [-] of the volume-weighted lognormal, in [1, 3]
  int classes = 0;           // discrete: number of classes, [1, max_classes]
  std::array<double, max_classes> diameters{};         // [m] discrete classes, increasing
  std::array<double, max_classes> volume_fractions{};  // [-] discrete: share of the solid volume per class, sum 1
};

// particles.hydrodynamics: near-field hydrodynamics on every DEM step
// (docs/hydrodynamics.md). YAML: `hydrodynamics: {model: lubrication+stresslet, roughness:
// 1.0e-3, lubrication_cutoff: 0.5}`; model is `none` or terms joined by '+': lubrication,
// stresslet (= single_particle), stokes_drag. Absent: none (the seed's drag-only model).
// Trivially copyable, like SizeDistribution (flags instead of a list of names).
// The matrix viscosity in the stresslet (docs/hydrodynamics.md): `homogenized` weights the
// secant and tangent viscosities so that a dilute suspension in a generalized-Newtonian liquid
// follows Chateau, Ovarlez & Trung (J. Rheol. 52 (2008) 489), η ≈ τ(γ̇)(1 + (0.75 + 1.75 n)φ),
// n = d ln τ/d ln γ̇; `secant` is the Newtonian stresslet with μ(γ̇) (2.5φ at any n).
enum class StressletViscosity { homogenized, secant };
// Its YAML name ("homogenized", "secant"), the one mapping for the reader and describe().
[[nodiscard]] constexpr const char* name_of(StressletViscosity v) {
  return v == StressletViscosity::secant ? "secant" : "homogenized";
}

struct Hydrodynamics {
  // The block was given. Absent, a suspension point runs the predictive default (the
  // Lees–Edwards box's near field); `{model: none}` is the seed's drag-only CFD-DEM.
  bool specified = false;
  bool lubrication = false;         // pair and plate lubrication
  bool single_particle = false;     // torque and stresslet in the ambient flow
  bool stokes_drag = false;         // Stokes drag on the imposed ambient flow (cells without a fluid solver)
  bool repulsion = false;           // short-range repulsion F_R0 exp(−h/λ) (needs lubrication)
  double roughness = 1.0e-3;        // δ/ā, in [1e-6, 0.1]
  double lubrication_cutoff = 0.5;  // h_c/ā, in (roughness, 1]
  double repulsion_force = 0.0;     // F_R0 [N], > 0 with repulsion
  double repulsion_length = 0.05;   // λ/ā, in [1e-3, lubrication_cutoff/5]
  StressletViscosity stresslet_viscosity = StressletViscosity::homogenized;  // with the stresslet
  [[nodiscard]] bool any() const { return lubrication || single_particle || stokes_drag || repulsion; }
};

// particles.drag: the fluid–particle drag law of the CFD-DEM coupling (coupling/src/drag/).
// YAML `drag: {model: auto | di_felice | schiller_naumann}`. auto, the default, is di_felice
// (the seed's, CD eqs. 30–33) for drag-only suspensions and schiller_naumann (the isolated
// sphere) when the near field has lubrication: the pair terms then carry the crowding that Di
// Felice's voidage function would add a second time (docs/hydrodynamics.md, "Which drag goes
// with the near field").
enum class DragLaw { di_felice, schiller_naumann };
// Its YAML name, the registry name in coupling::builtin_drag_models().
[[nodiscard]] constexpr const char* name_of(DragLaw d) {
  return d == DragLaw::schiller_naumann ? "schiller_naumann" : "di_felice";
}

struct ParticleProperties {       // particles: (CD §4 defaults)
  double volume_fraction = 0;     // φ [-], [0, 0.5]; a sweep sets it per point
  double diameter = 0;            // d [m], < gap; with a size distribution the representative
                                  // (volume-median) diameter used for H/d, Re_p and St
  double density = 0;             // ρ_p [kg/m³]
  double youngs_modulus = 3.0e9;  // E [Pa]
  double poisson_ratio = 0.33;    // ν [-]
  double restitution = 0.9;       // e [-]
  double friction = 0.3;          // μ_c [-], Coulomb friction coefficient
  // Last, and not a std::optional (see SizeDistribution); type none (the default): monodisperse.
  SizeDistribution size_distribution{};
  Hydrodynamics hydrodynamics{};      // after size_distribution, same reason
  DragLaw drag = DragLaw::di_felice;  // the case reader resolves `auto` (drag_automatic: it did)
  bool drag_automatic = false;
};

struct NamedFluid {
  std::string name;  // from `fluids: [{name: ...}]`; "fluid" for a single `fluid:`
  FluidProperties properties;
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
  PlateGeometry geometry;
  FluidProperties fluid;                        // the first (or only) fluid
  std::vector<NamedFluid> fluids;               // every fluid; single phase may list several
  std::vector<double> shear_rates;              // γ̇_R = ΩR/H [1/s], increasing
  std::optional<ParticleProperties> particles;  // absent: single phase
  FluidSolverSettings solver;
  // model: which scene computes a suspension point: the Lees–Edwards box (bulk stress of a
  // periodic box of spheres with lubrication and frictional contacts, the local flow curve
  // integrated over the plate), the walled box (the same spheres between the two plates at the
  // case's gap), the full disk (CFD-DEM of the whole gap), the periodic shear cell (CFD-DEM of a
  // slab of the gap), or auto (the program picks the faithful one and logs why).
  enum class SuspensionModel { automatic, lees_edwards, walled_box, full_disk, shear_cell };
  SuspensionModel suspension_model = SuspensionModel::automatic;
};

struct SweepCase {                       // kind: sweep — every (φ, γ̇_R) of volume_fractions × shear_rates
  RheometerCase rheometer;               // particles hold everything but φ
  std::vector<double> volume_fractions;  // φ [-], increasing; 0 is single phase
};

// ---------------------------------------------------------------------------- the case

// The part every case file shares, read here: who the case is and which module reads the rest.
struct CaseHeader {
  std::string file;    // path as given
  std::string text;    // the exact input deck
  std::string sha256;  // of text, for reports and resume checks
  std::string name;    // optional `name:`, else the file's stem
  std::string description;
  std::string kind;  // "rheometer" | "sweep" | "ldd"
};

// A parsed case file: its header, and the root Section from which the module that owns the kind
// reads the rest (core::read_case for rheometer and sweep, ldd::read_case for ldd), the way each
// OpenFOAM model reads its own sub-dictionary. The reader ends with check_all_keys_known().
class CaseFile {
 public:
  // Parses the YAML and reads the header; throws ConfigError naming file:line:col and key.
  [[nodiscard]] static CaseFile open(const std::string& path);
  [[nodiscard]] static CaseFile parse(std::string_view text, const std::string& name);

  [[nodiscard]] const CaseHeader& header() const { return header_; }
  [[nodiscard]] Section root() const { return document_.root(); }
  // The case file's directory: relative paths in the case (an STL wall) resolve against it.
  [[nodiscard]] std::filesystem::path directory() const;
  // A reader's first check: `kind` is one it reads, or a ConfigError at `kind` names the reader.
  void require_kind(const std::vector<std::string>& kinds, std::string_view reader) const;
  // After the reader: every key of the file was asked for, or a ConfigError names the stray one.
  void check_all_keys_known() const { document_.check_all_keys_known(); }

 private:
  CaseFile(Document document, CaseHeader header) : document_(std::move(document)), header_(std::move(header)) {}
  Document document_;
  CaseHeader header_;
};

// A rheometer or sweep case (an LDD case is an ldd::Case, rheosim/ldd/case.hpp).
struct Case : CaseHeader {
  std::variant<RheometerCase, SweepCase> spec;
};

// Reads a rheometer or sweep case; throws ConfigError naming file:line:col, key, expectation and fix.
[[nodiscard]] Case read_case(const CaseFile& file);
[[nodiscard]] Case load_case(const std::string& path);
[[nodiscard]] Case parse_case(std::string_view text, const std::string& name);

// `fluid: {density, rheology}` under `section`: the liquid of every kind of case.
[[nodiscard]] FluidProperties read_fluid(const Section& section);

// SHA-256 (FIPS 180-4) of a byte string, lower-case hex.
[[nodiscard]] std::string sha256_hex(std::string_view bytes);

}  // namespace rheosim::core

namespace rheosim::core {
// A human-readable listing of a validated case: every value with its SI unit.
[[nodiscard]] std::string describe(const Case& c);
// The `fluid:` lines of such a listing ("  fluid: density …, rheology …\n").
[[nodiscard]] std::string describe_fluid(const FluidProperties& fluid);
}  // namespace rheosim::core
