// Near-field hydrodynamics inside the coupled CFD-DEM scenes: the periodic
// shear cell (solved fluid column) and the full disk (transient 3D fluid), both with
// `lubrication+stresslet` on every DEM step and the solved fluid as the ambient flow.
//  - stresslet part: Σ S_xz / V for the cell and (1/H) Σ (x S_yz − y S_xz) for the disk must
//    give the Einstein increment 2.5 φ of the liquid's stress/torque (isolated-sphere stresslet
//    (20/3)πμa³E∞, n (10/3)πa³ = 2.5 φ), up to how far the solved ambient strain rate near the
//    plates departs from the mean one; this checks the ambient gradient (the disk's cylindrical
//    metric terms included) and the bookkeeping;
//  - the total is above drag only (which gives μγ̇ at φ = 0.1, validate_shear_cell_point);
//  - stress cross-check (item 3): in the cell the bulk stress from the particle virial (pair and
//    plate contacts, near-field virial, the fluid forces' offsets, the column's mean fluid
//    stress) must match the top-plate reading (fluid + contact + plate lubrication + stresslet),
//    and top and bottom plates must carry the same total stress.
// Soft contacts (E = 3 MPa) keep the DEM step large; the near field is implicit, so it does not
// limit the step.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string_view>

#include <fmt/format.h>

#include "coupling_test_support.hpp"
#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/coupling/shear_cell_point.hpp"
#include "rheosim/coupling/suspension_point.hpp"
#include "rheosim/dem/contact.hpp"

namespace rheosim::coupling {
namespace {

namespace fs = std::filesystem;
constexpr double mu = 1e-3;
constexpr double rate = 100.0;

std::shared_ptr<const core::Rheology> newtonian() { return testing::newtonian(mu); }
using testing::lubrication_and_stresslet;

ShearCellPoint run_cell(const NearFieldSettings& hydrodynamics, const char* label) {
  ShearCellPointSettings s;
  s.gap = 5e-4;
  s.cell_length = s.cell_width = 1.6e-3;
  s.fluid = {.density = 1000.0, .rheology = newtonian()};
  s.particles = {.volume_fraction = 0.1, .diameter = 2e-4, .density = 1000.0, .youngs_modulus = 3.0e6};
  s.coupling_interval = 4;
  s.shear_rate = rate;
  s.axial_cells = 2;
  s.steady = {.strain_window = 2.0, .relative_tolerance = 0.03, .min_strain = 4.0, .max_strain = 8.0};
  s.near_field = make_near_field_model(hydrodynamics, s.fluid.rheology);
  s.run_directory = fs::temp_directory_path() / fmt::format("rheosim_validate_nf_cell_{}", ::getpid());
  const auto p = run_shear_cell_point(s);
  fs::remove_all(s.run_directory);
  std::printf(
      "cell %s, phi %.4f: N %lld, stress %.5g +- %.2g Pa = fluid %.5g + contact %.3g + lubrication %.5g + "
      "stresslet %.5g + couple %.5g; bottom %.5g; bulk (virial) %.5g; eta_r %.4f; strain %.1f, converged %d; DEM "
      "%.1f s, near field %.1f s, max CG %d\n",
      label, p.volume_fraction, static_cast<long long>(p.particles), p.stress, p.stress_error, p.stress_fluid,
      p.stress_contact, p.stress_lubrication, p.stress_stresslet, p.stress_couple, p.bottom_stress, p.bulk_stress,
      p.stress / (mu * rate), p.strain, p.converged, p.cost.dem, p.cost.near_field, p.max_near_field_iterations);
  return p;
}

TEST(NearFieldCoupledValidation, ShearCellStressletGivesEinstein) {
  // Stresslet only: the spheres follow the column and spin with it, so the stresslet part is
  // 2.5 φ μγ̇ and the couple almost vanishes; the rest is drag only, μγ̇ plus the +2–3 % of the
  // occasional collisions (validate_shear_cell_point).
  NearFieldSettings h;
  h.terms.single_particle = true;
  const auto p = run_cell(h, "stresslet");
  const double liquid = mu * rate, einstein = 2.5 * p.volume_fraction * liquid;
  EXPECT_NEAR(p.stress_stresslet, einstein, 0.05 * einstein);
  EXPECT_GT(p.stress, liquid + einstein);
  EXPECT_LT(p.stress, 1.06 * liquid + einstein);
  EXPECT_LT(std::abs(p.stress_couple), 0.1 * einstein);
  EXPECT_NEAR(p.bulk_stress, p.stress, 0.02 * p.stress);
}

TEST(NearFieldCoupledValidation, ShearCellPlateStressEqualsBulkVirial) {
  const auto p = run_cell(lubrication_and_stresslet(), "lubrication+stresslet");
  const double liquid = mu * rate;
  EXPECT_GT(p.stress_lubrication, 0.0);
  EXPECT_GT(p.stress, (1.0 + 2.5 * p.volume_fraction) * liquid);
  EXPECT_LT(p.stress, 3.0 * liquid);  // φ = 0.1: far from the dense regime
  EXPECT_NEAR(p.bottom_stress, p.stress, std::max(0.03 * p.stress, 4.0 * p.stress_error));
  // Item 3: the plates' momentum balance; contacts are few here, so LIGGGHTS' symmetric contact
  // virial costs little.
  EXPECT_NEAR(p.bulk_stress, p.stress, 0.02 * p.stress);
  // The bulk's parts add up to it; a Newtonian column's mean stress is μU/H whatever its profile.
  const auto& b = p.bulk_parts;
  EXPECT_NEAR(b.fluid + b.stresslet + b.couple + b.pair_lubrication + b.pair_lubrication_antisymmetric +
                  b.plate_lubrication + b.pair_contact + b.plate_contact + b.drag,
              p.bulk_stress, 1e-9 * p.bulk_stress);
  EXPECT_NEAR(b.fluid, liquid, 1e-9 * liquid);
  EXPECT_GT(b.pair_lubrication, 0.0);
  EXPECT_GT(p.cost.near_field, 0.0);
  EXPECT_GT(p.max_near_field_iterations, 0);
}

TEST(NearFieldCoupledValidation, DiskTorqueParts) {
  SuspensionPointSettings s;
  s.geometry = {.radius = 1.5e-3, .gap = 5e-4};
  s.fluid = {.density = 1000.0, .rheology = newtonian()};
  s.particles = {.volume_fraction = 0.1, .diameter = 2e-4, .density = 1000.0, .youngs_modulus = 5.0e6};
  s.hydrodynamics = lubrication_and_stresslet();
  s.rim_shear_rate = rate;
  s.radial_cells = 4;
  s.azimuthal_cells = 4;
  s.axial_cells = 2;
  s.inertia = false;
  s.coupling.coupling_interval = 4;
  s.steady = {.strain_window = 0.5, .relative_tolerance = 1e-9, .min_strain = 1.0, .max_strain = 1.5};
  s.run_directory = fs::temp_directory_path() / fmt::format("rheosim_validate_nf_disk_{}", ::getpid());
  fs::create_directories(s.run_directory);
  const auto p = run_point(s);
  fs::remove_all(s.run_directory);
  const double omega = rate * s.geometry.gap / s.geometry.radius;
  const double liquid = std::acos(-1.0) * mu * omega * std::pow(s.geometry.radius, 4) / (2.0 * s.geometry.gap);
  const double disk_volume = std::acos(-1.0) * s.geometry.radius * s.geometry.radius * s.geometry.gap;
  const double phi = static_cast<double>(p.particles) * std::acos(-1.0) / 6.0 * std::pow(2e-4, 3) / disk_volume;
  std::printf(
      "disk phi %.4f: N %lld, torque %.5g = fluid %.5g + contact %.3g + lubrication %.5g + stresslet %.5g + "
      "couple %.5g N m; "
      "T/T_liquid %.4f, stresslet/(2.5 phi T_liquid) %.4f; DEM %.1f s, near field %.1f s, max CG %d\n",
      phi, static_cast<long long>(p.particles), p.torque, p.torque_fluid, p.torque_contact, p.torque_lubrication,
      p.torque_stresslet, p.torque_couple, p.torque / liquid, p.torque_stresslet / (2.5 * phi * liquid), p.cost.dem,
      p.cost.near_field, p.max_near_field_iterations);
  ASSERT_TRUE(std::isfinite(p.torque));
  // The particles sit at r from the axis to R − a: Σ r² over them is below the uniform-disk
  // value by up to (1 − a/R)⁴ ≈ 0.75 for this small disk, hence the wide lower bound.
  EXPECT_GT(p.torque_stresslet, 0.7 * 2.5 * phi * liquid);
  EXPECT_LT(p.torque_stresslet, 1.15 * 2.5 * phi * liquid);
  EXPECT_GT(p.torque_lubrication, 0.0);
  EXPECT_GT(p.torque, liquid);
  EXPECT_GT(p.cost.near_field, 0.0);
}

}  // namespace
}  // namespace rheosim::coupling
