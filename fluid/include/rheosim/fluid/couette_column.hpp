#pragma once
// The liquid of a plane-Couette gap averaged over the horizontal plane: the fluid of the periodic
// shear cell (CFD-DEM, docs/shear-cell.md). The volume-averaged momentum equation (CD eqs. 26–28)
// averaged over x and y keeps only the horizontal velocity u(z) = (u_x, u_y):
//
//   ρ ε ∂u/∂t = ε ∂z(μ(γ̇) ∂z u) + f − K u,     u(0) = 0,  u(H) = (U, 0),
//
// with ε the void fraction of each layer, f the particles' reaction (explicit) and K its implicit
// coefficient (CD eq. 29's implicit exchange), γ̇ = |∂z u| on the faces. μ is lagged one step; each
// step is one implicit (backward Euler) tridiagonal solve per component. Layers are N_z cells of
// height Δz = H/N_z; a plate is Δz/2 from the nearest layer centre.
#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "rheosim/core/rheology.hpp"

namespace rheosim::fluid {

struct CouetteColumnParams {
  double density = 0;                              // ρ [kg/m³], > 0
  std::shared_ptr<const core::Rheology> rheology;  // μ(γ̇), not null
  double gap = 0;                                  // H [m], > 0
  int layers = 0;                                  // N_z, >= 1
  double plate_speed = 0;                          // U of the top plate along x [m/s]
  double area = 0;                                 // plate area of the column [m²], > 0 (layer volume A Δz)

  void check() const;  // throws std::invalid_argument naming the field and its valid range
};

class CouetteColumn {
 public:
  // Starts from the Couette profile u_x = U z/H, u_y = 0, ε = 1, no sources.
  explicit CouetteColumn(CouetteColumnParams params);

  [[nodiscard]] std::size_t layers() const { return n_; }
  [[nodiscard]] double layer_height() const { return dz_; }
  [[nodiscard]] double layer_volume() const { return volume_; }
  [[nodiscard]] double centre(std::size_t k) const { return (static_cast<double>(k) + 0.5) * dz_; }
  // ε per layer, set by the caller before advance() (1: no particles).
  [[nodiscard]] std::span<double> void_fraction() { return eps_; }

  // u at height z (u_z = 0): linear between layer centres and the plate values.
  [[nodiscard]] std::array<double, 3> velocity_at(double z) const;
  // ∂u_x/∂z, ∂u_y/∂z at height z: the slope of the same piecewise-linear profile.
  [[nodiscard]] std::array<double, 2> slope_at(double z) const;
  // (1/H) ∫ μ ∂u_x/∂z dz over the faces: the liquid's part of the bulk shear stress [Pa].
  [[nodiscard]] double mean_fluid_stress() const;
  [[nodiscard]] double cell_viscosity(std::size_t k) const { return cell_mu_[k]; }
  // ∂z(μ ∂z u) of layer k, x and y [Pa/m] (the viscous force density of CD eq. 35).
  [[nodiscard]] double div_tau_x(std::size_t k) const { return div_tau_x_[k]; }
  [[nodiscard]] double div_tau_y(std::size_t k) const { return div_tau_y_[k]; }

  void clear_sources();
  // The reaction to one particle's share (weighted_beta = w β of the drag law): the explicit force
  // density w β (u_p − ũ)/V with ũ the liquid velocity the particle sampled, made implicit as
  // −K (u^{n+1} − u^n), K += w β / V. At steady state the reaction is exactly minus the drag the
  // particle gets, so sampling ũ at the particle and u at the layer centre makes no momentum.
  void add_reaction(std::size_t k, double weighted_beta, const std::array<double, 3>& sampled_fluid_velocity,
                    const std::array<double, 3>& particle_velocity);

  // One implicit step δt with the sources added since clear_sources(); updates μ and the wall stresses.
  void advance(double dt);
  // μ ∂u_x/∂z on the plates [Pa], from the last advance() (0 before).
  [[nodiscard]] double wall_stress_top() const { return wall_top_; }
  [[nodiscard]] double wall_stress_bottom() const { return wall_bottom_; }

 private:
  [[nodiscard]] double face_spacing(std::size_t face) const { return (face == 0 || face == n_) ? 0.5 * dz_ : dz_; }
  void update_viscosity();
  void solve(std::vector<double>& u, const std::vector<double>& source, double top_value, double dt);

  CouetteColumnParams params_;
  std::size_t n_;
  double dz_, volume_;
  std::vector<double> ux_, uy_, eps_, source_x_, source_y_, implicit_, face_mu_, div_tau_x_, div_tau_y_, cell_mu_;
  std::vector<double> lower_, diag_, upper_, rhs_;  // Thomas work arrays
  double wall_top_ = 0.0, wall_bottom_ = 0.0;
};

}  // namespace rheosim::fluid
