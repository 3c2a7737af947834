// coupling::run_shear_cell_point: without particles the fluid column is plane
// Couette flow, so the wall stress is exactly μ(γ̇) γ̇ for any generalized-Newtonian law and the
// same on both plates; settings are checked; a near-field model runs on every DEM step and its
// plate load, stresslet and couple reach the wall stress; the near-field scene describes the box.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"
#include "rheosim/coupling/shear_cell_point.hpp"

namespace rheosim::coupling {
namespace {

namespace fs = std::filesystem;

core::FluidProperties fluid(const std::string& rheology_yaml) {
  const auto doc = core::Document::from_string(rheology_yaml, "rheology");
  return {.density = 1000.0, .rheology = core::make_rheology(doc.root())};
}

ShearCellPointSettings settings(core::FluidProperties f, double rate, double phi) {
  ShearCellPointSettings s;
  s.gap = 5e-4;
  s.cell_length = s.cell_width = 1.2e-3;
  s.fluid = std::move(f);
  s.particles = {.volume_fraction = phi, .diameter = 2e-4, .density = 1000.0};
  s.shear_rate = rate;
  s.axial_cells = 4;
  s.steady = {.strain_window = 0.5, .relative_tolerance = 0.01, .min_strain = 1.0, .max_strain = 2.0};
  s.run_directory = fs::temp_directory_path() / fmt::format("rheosim_test_cell_point_{}", ::getpid());
  return s;
}

TEST(ShearCellPoint, WithoutParticlesTheColumnIsExactCouette) {
  for (const std::string law :
       {"model: newtonian\nviscosity: 1.0e-3\n", "model: power_law\nconsistency: 0.01\nindex: 0.5\n"}) {
    for (const double rate : {10.0, 100.0}) {
      const auto s = settings(fluid(law), rate, 0.0);
      const auto point = run_shear_cell_point(s);
      const double exact = couette_stress(s.fluid, rate);
      EXPECT_NEAR(point.stress, exact, 1e-12 * exact) << law << rate;
      EXPECT_NEAR(point.stress_fluid, exact, 1e-12 * exact);
      EXPECT_NEAR(point.bottom_stress, exact, 1e-12 * exact);
      EXPECT_EQ(point.stress_contact, 0.0);
      EXPECT_TRUE(point.converged);
      EXPECT_EQ(point.particles, 0);
    }
  }
  EXPECT_NEAR(couette_stress(fluid("model: newtonian\nviscosity: 1.0e-3\n"), 50.0), 0.05, 1e-15);
}

TEST(ShearCellPoint, ChecksItsSettings) {
  auto s = settings(fluid("model: newtonian\nviscosity: 1.0e-3\n"), 10.0, 0.0);
  s.shear_rate = 0.0;
  EXPECT_THROW((void)run_shear_cell_point(s), std::invalid_argument);
  s.shear_rate = 10.0;
  s.axial_cells = 0;
  EXPECT_THROW((void)run_shear_cell_point(s), std::invalid_argument);
}

// Adds nothing to the particles; puts a fixed load on the top plate and a fixed stresslet and
// rotation torque into the bookkeeping, and counts its calls.
class CountingNearField final : public NearFieldModel {
 public:
  static constexpr double plate_load = -2e-9;    // x force on the top plate [N]
  static constexpr double stresslet_xz = 3e-13;  // Σ S_xz [N·m]
  static constexpr double torque_y = 4e-13;      // Σ T_y [N·m]
  [[nodiscard]] std::string_view name() const override { return "counting"; }
  void evaluate(const ParticleSnapshot& p, const NearFieldScene& scene, const AmbientFlow& ambient,
                NearFieldResult& r) const override {
    ++calls;
    particles = p.size();
    r.plate_forces.at(1)[0] += plate_load;
    r.stresslet_sum[4] += stresslet_xz;
    r.particle_stress[4] += stresslet_xz;
    r.rotation_torque_sum[1] += torque_y;
    plates = scene.plates.size();
    // The column's ambient flow: Couette at the start, slope γ̇ in the middle of the gap.
    middle_slope = ambient(Vector3{0.0, 0.0, 2.5e-4}).velocity_gradient[2];
  }
  [[nodiscard]] double stable_time_step(const ParticleSnapshot&, double) const override { return INFINITY; }
  mutable long calls = 0;
  mutable std::size_t particles = 0, plates = 0;
  mutable double middle_slope = 0.0;
};

TEST(ShearCellPoint, NearFieldRunsOnEveryDemStepAndReachesTheWallStress) {
  auto s = settings(fluid("model: newtonian\nviscosity: 1.0e-3\n"), 100.0, 0.1);
  s.particles.youngs_modulus = 3e6;
  s.coupling_interval = 4;
  s.steady = {.strain_window = 0.1, .relative_tolerance = 1e-12, .min_strain = 0.2, .max_strain = 0.2};
  const auto model = std::make_shared<CountingNearField>();
  s.near_field = model;
  const auto p = run_shear_cell_point(s);
  fs::remove_all(s.run_directory);
  const auto dem_steps = static_cast<long>(p.series.size()) * s.coupling_interval;
  EXPECT_GE(model->calls, dem_steps);  // every step (plus LIGGGHTS' setup calls)
  EXPECT_LE(model->calls, dem_steps + static_cast<long>(p.series.size()) + 1);
  EXPECT_EQ(model->particles, static_cast<std::size_t>(p.particles));
  EXPECT_EQ(model->plates, 2U);
  EXPECT_NEAR(model->middle_slope, 100.0, 20.0);
  const double area = s.cell_length * s.cell_width, volume = area * s.gap;
  EXPECT_NEAR(p.stress_lubrication, -CountingNearField::plate_load / area, 1e-9);
  EXPECT_NEAR(p.stress_stresslet, CountingNearField::stresslet_xz / volume, 1e-9);
  EXPECT_NEAR(p.stress_couple, 0.5 * CountingNearField::torque_y / volume, 1e-9);
  EXPECT_GT(p.cost.near_field, 0.0);
}

TEST(ShearCellPoint, NearFieldSceneDescribesTheBox) {
  const auto dir = fs::temp_directory_path() / fmt::format("rheosim_test_cell_nf_{}", ::getpid());
  dem::ShearCellScene scene({.gap = 5e-4,
                             .cell_length = 1.2e-3,
                             .cell_width = 1e-3,
                             .particles = {.volume_fraction = 0.1, .diameter = 2e-4, .density = 1000.0},
                             .shear_rate = 40.0,
                             .run_directory = dir});
  const auto nf = make_near_field_scene(scene);
  ASSERT_EQ(nf.plates.size(), 2U);
  EXPECT_EQ(nf.plates[0].z, 0.0);
  EXPECT_TRUE(nf.plates[0].faces_up);
  EXPECT_FALSE(nf.plates[1].faces_up);
  EXPECT_DOUBLE_EQ(nf.plates[1].z, 5e-4);
  EXPECT_DOUBLE_EQ(nf.plates[1].velocity_at({0.0, 0.0, 5e-4})[0], 40.0 * 5e-4);
  EXPECT_TRUE(nf.periodic[0] && nf.periodic[1] && !nf.periodic[2]);
  EXPECT_DOUBLE_EQ(nf.box_high[0], 1.2e-3);
  EXPECT_DOUBLE_EQ(nf.box_high[1], 1e-3);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rheosim::coupling
