#pragma once
// Near-field hydrodynamics evaluated on every DEM step: what an unresolved CFD-DEM
// grid cannot see — pairwise lubrication between close particles and between particles and the
// plates, and the single-particle torque and stresslet in the local ambient flow. Terms are
// selected by name from the case file (`particles: {hydrodynamics: {model:
// lubrication+stresslet}}`) through one explicit name table (near_field.cpp) and combined into
// one model with one implicit solve; "none" keeps the seed's drag-only model.
// docs/hydrodynamics.md has the formulas, the validation and the wiring.
//
// Contract between the scenes (disk, periodic shear cell) and the models:
//   - the scene fills NearFieldScene once (plates, periodic box) and an AmbientFlow each
//     coupling step (the fluid velocity the particles would feel without each other);
//   - the DEM engine calls evaluate() on every DEM step with the current particle state
//     (dem::Engine::set_step_force_callback) and applies result.forces / result.torques on that
//     step (added to the coupling's drag);
//   - result.particle_stress accumulates the particles' stress contribution (pair virial of the
//     lubrication forces + stresslets) for the stress bookkeeping.
//
// Form of the hydrodynamic force (resistance formulation, generalized coordinates V = (U, Ω)
// of all particles): F_H = −R V + F₀, where R (symmetric, positive semi-definite) collects the
// pair and plate lubrication blocks and the single-particle drag/rotation resistances, and F₀
// the parts driven by the ambient flow and the plate velocities. With time_step > 0 the update
// is implicit (backward Euler on the half-step velocities of velocity Verlet): the model solves
//   (M/δt + R) V⁺ = M/δt V* + F₀,   V* = V + δt M⁻¹ F_other,
// by block-Jacobi-preconditioned conjugate gradients and returns F_H = −R V⁺ + F₀, so that
// LIGGGHTS' explicit step with F_other + F_H lands on V⁺. This is unconditionally stable for the
// stiff 1/h squeeze term; δt stays limited by the contact stiffness only. With time_step = 0
// the force is explicit (F_H = −R V + F₀) and stable only below stable_time_step().
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rheosim/core/rheology.hpp"
#include "rheosim/coupling/particles.hpp"
#include "rheosim/dem/engine.hpp"

namespace rheosim::coupling {

// This rank's particles at one DEM step; interleaved xyz like dem::Engine's views, SI.
struct ParticleSnapshot {
  std::span<const double> positions{};           // [m], 3n
  std::span<const double> velocities{};          // [m/s], 3n (v^(n+1/2) inside a DEM step)
  std::span<const double> angular_velocities{};  // [rad/s], 3n
  std::span<const double> radii{};               // [m], n
  // For the implicit update (time_step > 0); may be empty when time_step == 0.
  std::span<const double> masses{};         // [kg], n (solid spheres: I = (2/5) m a²)
  std::span<const double> other_forces{};   // [N], 3n: every other force on this step (contact, drag, gravity)
  std::span<const double> other_torques{};  // [N·m], 3n
  double time_step = 0.0;                   // DEM δt [s]; > 0: implicit update, 0: explicit forces
  [[nodiscard]] std::size_t size() const { return radii.size(); }
};

// A plate normal to z at height z, moving in its own plane with velocity (vx, vy, 0) — for the
// disk's top plate the velocity is Ω × r, given as a function of position.
struct PlateWall {
  double z = 0.0;                                      // [m]
  bool faces_up = true;                                // fluid on the +z side (the bottom plate)
  std::function<Vector3(const Vector3&)> velocity_at;  // [m/s]; empty = at rest
};

struct NearFieldScene {
  std::vector<PlateWall> plates;
  // Periodic directions (the shear cell: x and y) and the box extents in those directions.
  std::array<bool, 3> periodic{false, false, false};
  Vector3 box_low{0.0, 0.0, 0.0}, box_high{0.0, 0.0, 0.0};
};

// The ambient flow at a point: velocity [m/s] and velocity gradient ∂u_i/∂x_j [1/s] (row i,
// column j). The matrix viscosity of the single-particle terms is evaluated at the ambient
// shear rate √(2E:E), E = ½(∇u + ∇uᵀ); lubrication uses the gap's own shear rate.
struct AmbientSample {
  Vector3 velocity{};
  std::array<double, 9> velocity_gradient{};
};
using AmbientFlow = std::function<AmbientSample(const Vector3&)>;

// Symmetric tensors are stored xx, yy, zz, xy, xz, yz.
using SymmetricTensor = std::array<double, 6>;

struct NearFieldResult {
  std::vector<double> forces;   // [N], 3n, added on this step
  std::vector<double> torques;  // [N·m], 3n
  // Particle contribution to the suspension stress times the volume [N·m] (divide by the
  // volume for a stress), Batchelor (1970): Σ over pairs of −(x_j − x_i) ⊗ F_j (F_j the
  // lubrication force on j from the gap with i; for a plate, x_i is the point of the plate
  // under the particle) plus Σ over particles of the stresslet S_p. Split for the bookkeeping:
  SymmetricTensor particle_stress{};     // lubrication_virial + stresslet_sum
  SymmetricTensor lubrication_virial{};  // pairs and plates
  // The same, not symmetrised, force component first: [3a + b] = Σ −F_j,a (x_j − x_i)_b [N·m].
  // A plate's momentum balance needs this one ([2] = force x, lever z in the shear cell); the
  // symmetric part differs from it by the lubrication torques.
  std::array<double, 9> lubrication_virial_full{};
  SymmetricTensor plate_virial{};  // the plates' part of lubrication_virial
  SymmetricTensor stresslet_sum{};
  // Σ_p (x_p S_yz − y_p S_xz) [N·m²]: the stresslets' r σ_θz about the z axis. The fluid solvers
  // do not receive the stresslet (it is a force dipole, no force on the particle), so a disk adds
  // the torque it transmits, (1/H) ∫ r σ_θz dV = stresslet_axial_moment / H, to the plate torque.
  double stresslet_axial_moment = 0.0;
  // Σ_p of the single-particle rotation torques T_p = −8πμa³(Ω_p − ω∞) [N·m] and Σ_p (x_p T_x +
  // y_p T_y) [N·m²]. Their reaction is a couple density c = −Σ T_p / V on the liquid, which the
  // fluid solvers do not carry either; it makes the antisymmetric stress σ^A_jk = ½ ε_jkm c_m,
  // so the plate reading gains σ^A_xz = ½ Σ T_y / V in the shear cell and
  // (1/H) ∫ r σ^A_θz dV = −Σ (x T_x + y T_y) / (2H) on the disk (for spheres held still in
  // simple shear this is the known +1.5φ of non-rotating spheres).
  Vector3 rotation_torque_sum{};
  double rotation_torque_radial_moment = 0.0;
  // Hydrodynamic near-field force [N] on each plate of the scene (NearFieldScene::plates
  // order) and its moment about the origin [N·m] (the plate torque for the disk is its z part).
  std::vector<Vector3> plate_forces;
  std::vector<Vector3> plate_moments;
  // Diagnostics of this evaluation.
  std::size_t lubricated_pairs = 0;  // particle pairs within the lubrication cutoff
  std::size_t lubricated_walls = 0;  // particle–plate gaps within the cutoff
  double smallest_gap_ratio = 0.0;   // min h/ā over those gaps (h < 0: overlap); 0 when none
  int solver_iterations = 0;         // conjugate-gradient iterations of the implicit update
  void reset(std::size_t particles, std::size_t plates);
};

class NearFieldModel {
 public:
  virtual ~NearFieldModel() = default;
  [[nodiscard]] virtual std::string_view name() const = 0;
  // Adds this model's forces, torques and stress to result (sized by reset()).
  virtual void evaluate(const ParticleSnapshot& particles, const NearFieldScene& scene, const AmbientFlow& ambient,
                        NearFieldResult& result) const = 0;
  // Largest DEM step [s] for which the explicit update (time_step = 0) of this model stays
  // stable for these particles (+inf when it adds nothing stiff). The implicit update
  // (time_step > 0) is stable for any δt; then only the contacts limit the DEM step.
  [[nodiscard]] virtual double stable_time_step(const ParticleSnapshot& particles, double particle_density) const = 0;
};

// The matrix viscosity in the stresslet (docs/hydrodynamics.md): `homogenized` weights the
// secant and tangent viscosities so that a dilute suspension in a generalized-Newtonian liquid
// follows Chateau, Ovarlez & Trung (J. Rheol. 52 (2008) 489), η ≈ τ(γ̇)(1 + (0.75 + 1.75 n)φ),
// n = d ln τ/d ln γ̇; `secant` is the Newtonian stresslet with μ(γ̇) (2.5φ at any n).
enum class StressletViscosity { homogenized, secant };
// Its YAML name ("homogenized", "secant"), the one mapping for the reader and describe().
[[nodiscard]] constexpr const char* name_of(StressletViscosity v) {
  return v == StressletViscosity::secant ? "secant" : "homogenized";
}

// Settings of `particles: {hydrodynamics: {...}}` (read by read_suspended_particles).
// The near-field terms switched on (particles.hydrodynamics.model, terms joined by '+').
struct NearFieldTerms {
  bool lubrication = false;  // pair and plate lubrication (Jeffrey & Onishi 1984, Kim & Karrila 1991)
  // single-particle torque −8πμa³(Ω − ω∞) and stresslet (20/3)πμa³E∞ (stresslet | single_particle)
  bool single_particle = false;
  // −6πμa(U − u∞): drag on the imposed ambient flow, for cells without a fluid solver (with
  // CFD-DEM the coupling's Di Felice drag does this)
  bool stokes_drag = false;
  // short-range repulsion F_R = F_R0 exp(−h/λ) along the line of centres (F_R0 for h < 0), pairs
  // and plates: an electrostatic double layer or a polymer brush (Mari, Seto, Morris & Denn,
  // J. Rheol. 2014). It keeps pairs apart below the stress scale F_R0/(6πa²) (the frictionless
  // branch) and needs `lubrication` (it uses its gap list).
  bool repulsion = false;
  [[nodiscard]] bool any() const { return lubrication || single_particle || stokes_drag || repulsion; }
  // "lubrication+stresslet+stokes_drag+repulsion" for those on, in this order; "none" for none.
  [[nodiscard]] std::string name() const;
};

struct NearFieldSettings {
  NearFieldTerms terms;       // none on: the model adds nothing (drag only)
  double roughness = 1.0e-3;  // δ/ā: the gap is regularised to max(h, 0) + δ, ā = (a_i + a_j)/2, in [1e-6, 0.1]
  double lubrication_cutoff = 0.5;  // h_c/ā: lubrication acts for h < h_c, in (roughness, 1]
  double repulsion_force = 0.0;     // F_R0 [N], > 0 with `repulsion`
  double repulsion_length = 0.05;   // λ/ā, in [1e-3, lubrication_cutoff/5] (the force is cut with the gap list)
  // The matrix viscosity μ_S in the stresslet (20/3)πμ_S a³E∞ (StressletViscosity):
  // homogenized μ_S = μ + 0.7 γ̇ dμ/dγ̇ (0.3 secant + 0.7 tangent), secant μ_S = μ(γ̇).
  StressletViscosity stresslet_viscosity = StressletViscosity::homogenized;
  double solver_tolerance = 1.0e-7;  // residual / |right-hand side| of the implicit solve, in (0, 1e-3]
  int max_solver_iterations = 500;
};

// Builds the combined model (one implicit solve over all enabled terms); matrix is the liquid's
// μ(γ̇). Throws std::invalid_argument for settings out of range. With no term on the model adds
// nothing.
[[nodiscard]] std::unique_ptr<const NearFieldModel> make_near_field_model(const NearFieldSettings& settings,
                                                                          std::shared_ptr<const core::Rheology> matrix);

// Runs a model on every DEM step of a dem::Engine (through Engine::set_step_force_callback,
// implicit update with the engine's δt, masses and known forces) and keeps step means of its
// stress and plate loads for the bookkeeping. The callback is removed when the hook ends;
// the engine must outlive the hook. One MPI rank (the pair search sees this rank's particles).
class NearFieldStepHook {
 public:
  struct Means {
    std::int64_t steps = 0;             // DEM steps averaged
    SymmetricTensor particle_stress{};  // step means of NearFieldResult's sums [N·m]
    SymmetricTensor lubrication_virial{};
    std::array<double, 9> lubrication_virial_full{};
    SymmetricTensor plate_virial{};
    SymmetricTensor stresslet_sum{};
    double stresslet_axial_moment = 0.0;         // [N·m²]
    Vector3 rotation_torque_sum{};               // [N·m]
    double rotation_torque_radial_moment = 0.0;  // [N·m²]
    std::vector<Vector3> plate_forces;           // [N]
    std::vector<Vector3> plate_moments;          // [N·m]
    double mean_lubricated_pairs = 0.0;
    int max_solver_iterations = 0;
    double seconds = 0.0;  // wall time spent in the model
  };
  NearFieldStepHook(dem::Engine& engine, std::shared_ptr<const NearFieldModel> model, NearFieldScene scene,
                    AmbientFlow ambient);
  ~NearFieldStepHook();
  NearFieldStepHook(const NearFieldStepHook&) = delete;
  NearFieldStepHook& operator=(const NearFieldStepHook&) = delete;

  // A new ambient flow from the next DEM step on (each coupling step).
  void set_ambient(AmbientFlow ambient);
  // The result of the last DEM step.
  [[nodiscard]] const NearFieldResult& last() const { return last_; }
  // Means over the steps since the previous call (or the start), then restarts them.
  [[nodiscard]] Means take_means();

 private:
  void on_step(const dem::StepState& state, std::span<double> forces, std::span<double> torques);
  dem::Engine& engine_;
  std::shared_ptr<const NearFieldModel> model_;
  NearFieldScene scene_;
  AmbientFlow ambient_;
  NearFieldResult last_;
  Means sums_;
  double pair_sum_ = 0.0;
};

// Jeffrey & Onishi (1984) / Kim & Karrila (1991) near-contact resistance functions for two
// spheres a1 (this one) and a2 = λ a1, dimensionless gap ξ = 2h/(a1 + a2), ℓ = ln(1/ξ),
// in the normalisation F = 6πμa1 X^A ..., F(Ω) = 4πμa1² Y^B ..., T = 8πμa1³ Y^C ...; for a
// plate (λ → ∞) ξ = h/a1. Leading singular terms only (the O(1) parts are not included).
struct NearContactResistance {
  double squeeze = 0.0;                  // X^A_11 = g1/ξ + g2 ℓ
  double shear = 0.0;                    // Y^A_11 = g4 ℓ
  double rotation_coupling_self = 0.0;   // −Y^B_11 = λ(4+λ)/(5(1+λ)²) ℓ
  double rotation_coupling_other = 0.0;  // the same for the other sphere's rotation, in units of 4πμa1²
  double rotation_self = 0.0;            // Y^C_11 = (2/5) λ/(1+λ) ℓ
  double rotation_other = 0.0;           // Y^C_12 in units of 8πμa1³
};
[[nodiscard]] NearContactResistance sphere_sphere_resistance(double size_ratio, double xi);
[[nodiscard]] NearContactResistance sphere_plate_resistance(double xi);

}  // namespace rheosim::coupling
