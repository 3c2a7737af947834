#pragma once
// The liquid's mean velocity u_f(z) across the walled suspension box (suspension_box.hpp,
// mean_flow_coupling): the plane-Couette momentum balance
//   μ(1 + 2.5 r φ(z)) u_f' = τ₀ + ℓ(z)/2 − F(z),   F(z) = ∫₀^z f,   u_f(0) = 0, u_f(H) = γ̇H,
// with f and ℓ the force and couple densities (x and y) the spheres exert on the liquid, φ the
// solid fraction and r the stresslet's viscosity ratio (Einstein's 2.5φ as a local viscosity).
// ℓ/2: a couple L on the liquid is the antisymmetric force dipole D_zx = −D_xz = L/2, of which
// the plane balance carries D_zx. Bins of about ā/4 hold time averages of f, ℓ and φ, each
// sphere spread over its cross-sections π(a² − (z − z_i)²).
#include <cstddef>
#include <vector>

namespace rheosim::coupling {

class BoxMeanFlow {
 public:
  // Units of the box: lengths ā, rates γ̇; area of the plates, the liquid's viscosity.
  BoxMeanFlow(double height, double area, double viscosity, double stresslet_ratio);
  // One sphere's force and couple on the liquid (x and y components), at height z, radius a.
  void add_sphere(double z, double radius, double force, double couple);
  // Blends the spheres added since the last call into the averages with this weight (1: replace)
  // and solves the profile.
  void relax(double weight);
  [[nodiscard]] double velocity(double z) const;
  [[nodiscard]] double shear_rate(double z) const;
  // The plates' mean liquid stress τ₀ − F(H)/2; (F_top − F_bottom)/(2A), the forces the plates
  // exert on the spheres, completes their reading.
  [[nodiscard]] double liquid_stress() const { return tau0_ - 0.5 * total_force_; }
  // Mean u_f' over [from, to].
  [[nodiscard]] double mean_shear_rate(double from, double to) const {
    return (velocity(to) - velocity(from)) / (to - from);
  }

 private:
  [[nodiscard]] std::size_t bin(double z) const;
  double height_, area_, viscosity_, stresslet_ratio_;
  std::size_t bins_;
  double width_;
  std::vector<double> force_, couple_, fraction_, sample_force_, sample_couple_, sample_fraction_, shear_, velocity_;
  double tau0_ = 0.0, total_force_ = 0.0;
};

}  // namespace rheosim::coupling
