#pragma once
// Momentum exchange particles → fluid, CD eq. 29 in set II / form A: the fluid gets −Σ f_d/ΔV
// (the drag only; the pressure-gradient and viscous forces on the particles act back on the
// fluid through the ε in −ε∇p + ε∇·τ of CD eq. 27). With the drag implicit (split as in
// fluid::MomentumSource, source f − K u on the fluid):
//   −β_p(u_f − u_p) = β_p u_p − β_p u_f   →   f_c = Σ_p w_pc β_p u_p / V_c   (explicit)
//                                             K_c = Σ_p w_pc β_p / V_c       (implicit, × u^(n+1))
// with w_pc = (volume share of particle p in cell c)/V_p from the void-fraction map, so the
// reaction goes to the cells that carry the particle's volume.
// Basis: the solver takes cylindrical components per cell. For N_θ > 1 a force is projected on
// the basis at the cell centre θ_c, so Σ_c (cell vector rebuilt at θ_c) V_c is exactly the
// Cartesian sum — momentum balance to round-off through the solver's own arrays. For N_θ = 1 (a
// cell spanning 2π) a Cartesian x–y sum has no meaning; the particle's own θ is used and only
// the axial sum is comparable.
// Per-cell consistency (build() with the cell velocities ũ_c): the particle feels β(u_f(x_p) − u_p)
// with u_f interpolated at its centre, but the implicit part acts on the cell velocity, so with
// f_c = Σ β u_p alone a particle moving with the fluid at x_p still pushed its cells by
// β(u_f(x_p) − ũ_c). In a gap of two cell layers the particles sit in the inner halves of the
// layers, so the layers were pulled toward the mid-gap velocity and the wall gradients
// steepened. build() therefore puts β(u_p − u_f(x_p)) + β ũ_c in the explicit part: the source
// f_c − K_c u^(n+1) equals −Σ f_d per cell whenever u^(n+1) = ũ_c (steady state), and stays
// implicit in K for stability.
// Balance: at the fluid velocity the particles sampled, the fluid's source Σ_c (f_c − K_c ũ_c) V_c
// equals −Σ_p f_d,p to round-off; the implicit part then only adds K(ũ − u^(n+1)), which vanishes
// when the cell velocity equals the sampled one.
#include <span>
#include <vector>

#include "rheosim/coupling/fluid_fields.hpp"
#include "rheosim/coupling/forces.hpp"
#include "rheosim/coupling/void_fraction.hpp"
#include "rheosim/fluid/transient.hpp"

namespace rheosim::coupling {

struct ExchangeBalance {
  Vector3 drag_on_particles{};      // Σ_p β_p(u_f − u_p) [N]
  Vector3 drag_to_fluid{};          // Σ_c (f_c − K_c ũ_c) V_c from the solver arrays [N]
  Vector3 pressure_on_particles{};  // Σ_p −V_p∇p [N] (reaction carried by ε, form A)
  Vector3 viscous_on_particles{};   // Σ_p V_p∇·τ [N] (reaction carried by ε, form A)
  double relative_error = 0.0;      // |on + to| / Σ_p |f_d,p| (components compared: x, y, z or z only)
  bool axial_only = false;          // N_θ = 1
};

class MomentumExchange {
 public:
  explicit MomentumExchange(const fluid::CylindricalGrid& grid);

  // Rebuilds f and K from this step's forces (same particle order as the map and samples).
  // cell_velocity: the fluid's cell-centre velocity (FluidCellFields::velocity) for per-cell
  // consistency (header comment); nullptr: the plain split f_c = Σ β u_p.
  void build(const ParticleCellMap& map, std::span<const ParticleSample> samples, std::span<const ParticleForce> forces,
             const CellVectorField* cell_velocity = nullptr);

  // View of the arrays for TransientSolver::set_momentum_source (valid until the next build()).
  [[nodiscard]] fluid::MomentumSource source() const;
  [[nodiscard]] std::span<const double> radial() const { return radial_; }                      // f_r [N/m³]
  [[nodiscard]] std::span<const double> azimuthal() const { return azimuthal_; }                // f_θ [N/m³]
  [[nodiscard]] std::span<const double> axial() const { return axial_; }                        // f_z [N/m³]
  [[nodiscard]] std::span<const double> drag_coefficient() const { return drag_coefficient_; }  // K [kg/(m³·s)]

  // The action–reaction ledger of the last build().
  [[nodiscard]] ExchangeBalance balance(const ParticleCellMap& map, std::span<const ParticleSample> samples,
                                        std::span<const ParticleForce> forces) const;

 private:
  [[nodiscard]] double basis_angle(std::size_t cell, const ParticleSample& particle) const;

  const fluid::CylindricalGrid* grid_;
  std::vector<double> radial_, azimuthal_, axial_, drag_coefficient_, cell_volume_, cell_theta_;
  CellVectorField cell_velocity_;  // ũ_c of the last build() (empty without)
};

}  // namespace rheosim::coupling
