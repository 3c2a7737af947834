// Relative viscosity of a sheared suspension with near-field hydrodynamics:
// dem::ShearCellScene (periodic in x and y between plates, top plate sliding at γ̇ H) with the
// near-field hook in an imposed linear ambient flow u∞ = γ̇ z e_x — Fast-Lubrication-Dynamics
// style (docs/hydrodynamics.md): Stokes drag and torque on u∞, stresslets, pair and plate
// lubrication, Hertz contacts with friction from LIGGGHTS; the fluid part of the stress is
// μ(γ̇) γ̇. Stress on the top plate = fluid + contact (the scene's mesh stress) + plate
// lubrication; the particle virial (stresslets + lubrication + contact virial from LIGGGHTS'
// `compute pressure ... virial` + plate contacts) cross-checks it.
//
// The test (~1 min): at φ = 0.3 the stress bookkeeping of the LIGGGHTS-hooked near field adds
// up, drag only stays near η_r = 1 and the near field lifts η_r well above it. The predictive
// η_r(φ) against measured suspensions is validated on the Lees–Edwards box
// (tests/rheometer/validate_suspension_box.cpp, docs/suspension-box.md). The same cell checks
// the coupled CFD-DEM cell (solved fluid column) like for like (~2 min).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "coupling_test_support.hpp"
#include "rheosim/core/case.hpp"
#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/coupling/shear_cell_point.hpp"
#include "rheosim/dem/contact.hpp"
#include "rheosim/dem/engine.hpp"
#include "rheosim/dem/shear_cell_scene.hpp"

namespace rheosim::coupling {
namespace {

constexpr double pi = std::numbers::pi;

struct CellSettings {
  double phi = 0.3;
  double rate = 100.0;        // γ̇ [1/s]
  double viscosity = 1.0;     // μ [Pa·s] (Newtonian matrix)
  std::string rheology_yaml;  // another matrix law (YAML of `rheology:`); empty: Newtonian μ
  double diameter = 2e-4;     // d [m]
  double gap_over_d = 10.0;   // H/d
  double cell_over_d = 6.0;   // L_x/d = L_y/d
  double strain = 6.0;        // total strain
  double skip_strain = 2.0;   // transient left out of the means
  double friction = 0.3;
  NearFieldTerms terms{.lubrication = true, .single_particle = true, .stokes_drag = true};
  bool plate_lubrication = true;  // false: the plates bound the cell for contacts only
  double lubrication_cutoff = NearFieldSettings{}.lubrication_cutoff;  // h_c/ā
  double repulsion_ratio = 0.0;  // F_R0 / (6πμa²γ̇); > 0 adds the `repulsion` term (λ = 0.05 ā)
  double repulsion_force = 0.0;  // F_R0 [N] when > 0 (instead of the ratio): fixed over rates
  StressletViscosity stresslet_viscosity = StressletViscosity::homogenized;
  double youngs_modulus = 1e6;  // [Pa] soft: δt = 0.2 t_R = 3.5e-6 s = 3.5e-4/γ̇; overlaps below 1 % of d
  std::uint64_t seed = 1;
};

struct CellResult {
  double phi = 0.0;
  std::int64_t particles = 0;
  double eta_r = 0.0, eta_r_error = 0.0;                               // bulk (Batchelor) stress / μγ̇
  double stresslet = 0.0, pair_lubrication = 0.0, pair_contact = 0.0;  // its particle parts
  double eta_r_plate = 0.0;                                            // top plate: fluid + contact + lubrication
  double plate_contact = 0.0, plate_lubrication = 0.0;
  double eta_r_virial_with_plates = 0.0;  // virial including the plate gaps and contacts
  double matrix_stress = 0.0;             // μ(γ̇) γ̇ [Pa]
  double dem_seconds = 0.0, near_field_seconds = 0.0;
  std::int64_t steps = 0;
  int max_iterations = 0;
};

CellResult run_cell(const CellSettings& c) {
  testing::RunFolder folder;
  const double d = c.diameter, a = 0.5 * d;
  dem::ParticleProperties props;
  props.volume_fraction = c.phi;
  props.diameter = d;
  props.density = 1000.0;
  props.youngs_modulus = c.youngs_modulus;
  props.restitution = 0.5;
  props.friction = c.friction;
  const double H = c.gap_over_d * d, L = c.cell_over_d * d;
  dem::ShearCellScene cell({.gap = H,
                            .cell_length = L,
                            .cell_width = L,
                            .particles = props,
                            .shear_rate = c.rate,
                            .time_step_fraction = 0.2,
                            .seed = c.seed,
                            .run_directory = folder.path(),
                            .stress_sample_interval = 50});
  dem::Engine& engine = cell.engine();
  // Contact virial of the particle pairs (LIGGGHTS' pressure tensor, virial part only).
  engine.commands({"compute rheosim_nf_temp all temp",
                   "compute rheosim_nf_pressure all pressure rheosim_nf_temp virial",
                   "fix rheosim_nf_virial all ave/time 1 50 50 c_rheosim_nf_pressure[5]"});

  NearFieldSettings settings;
  settings.terms = c.terms;
  settings.lubrication_cutoff = c.lubrication_cutoff;
  settings.stresslet_viscosity = c.stresslet_viscosity;
  if (c.repulsion_force > 0.0 || c.repulsion_ratio > 0.0) {
    settings.terms.repulsion = true;
    settings.repulsion_force =
        c.repulsion_force > 0.0 ? c.repulsion_force : c.repulsion_ratio * 6.0 * pi * c.viscosity * a * a * c.rate;
  }
  NearFieldScene scene;
  scene.periodic = {true, true, false};
  scene.box_low = {0.0, 0.0, 0.0};
  scene.box_high = {L, L, H};
  const double u_top = c.rate * H;
  scene.plates.push_back({.z = 0.0, .faces_up = true, .velocity_at = {}});
  scene.plates.push_back({.z = H, .faces_up = false, .velocity_at = [u_top](const Vector3&) {
                            return Vector3{u_top, 0.0, 0.0};
                          }});
  // Plate lubrication off: the plates are put far away for the near-field model.
  if (!c.plate_lubrication) {
    scene.plates[0].z = -1.0;
    scene.plates[1].z = 1.0;
  }
  const double rate = c.rate;
  const AmbientFlow shear = [rate](const Vector3& x) {
    AmbientSample s;
    s.velocity = {rate * x[2], 0.0, 0.0};
    s.velocity_gradient[2] = rate;
    return s;
  };
  const auto doc = core::Document::from_string(
      c.rheology_yaml.empty() ? fmt::format("model: newtonian\nviscosity: {:.17g}\n", c.viscosity) : c.rheology_yaml,
      "rheology");
  const auto matrix = core::make_rheology(doc.root());
  NearFieldStepHook hook(engine, make_near_field_model(settings, matrix), scene, shear);

  const double dt = cell.time_step();
  const double block_strain = 0.25;
  const auto block = static_cast<std::int64_t>(std::ceil(block_strain / (c.rate * dt) / 50.0) * 50);
  const int blocks = static_cast<int>(std::ceil(c.strain / (block * dt * c.rate)));
  const int skip = static_cast<int>(std::ceil(c.skip_strain / (block * dt * c.rate)));
  const double area = L * L, volume = L * L * H, box_volume = L * L * (H + 2.0 * d);
  const double fluid_stress = matrix->stress(c.rate);  // μ(γ̇) γ̇
  std::vector<double> bulk_values;
  CellResult r;
  double contact_sum = 0.0, lub_sum = 0.0, virial_sum = 0.0, virial_contact_sum = 0.0, plate_sum = 0.0;
  double stresslet_sum = 0.0, pair_lub_sum = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (int b = 0; b < blocks; ++b) {
    const std::size_t samples_before = cell.stress_series().size();
    cell.advance(block);
    const auto series = cell.stress_series();
    double contact = 0.0, contact_bottom = 0.0;
    for (std::size_t i = samples_before; i < series.size(); ++i) {
      contact += series[i].top_shear;
      contact_bottom += series[i].bottom_shear;
    }
    const auto count = static_cast<double>(series.size() - samples_before);
    contact /= count;
    contact_bottom /= count;
    const auto means = hook.take_means();
    r.max_iterations = std::max(r.max_iterations, means.max_solver_iterations);
    r.near_field_seconds += means.seconds;
    const double lubrication = -means.plate_forces[1][0] / area;
    if (b < skip) continue;
    // Pair contact virial: σ_xz = −P_xz(virial) over the box volume; plate contacts as pairs
    // with the contact point a below/above the centre: a A (τ_top + τ_bottom).
    const double pair_contact = -engine.fix_scalar("rheosim_nf_virial") * box_volume;
    const double plate_contact = a * area * (contact + contact_bottom);
    // Bulk (Batchelor) stress: stresslets + pair lubrication + pair contacts, plates excluded.
    const double bulk = fluid_stress + (means.particle_stress[4] - means.plate_virial[4] + pair_contact) / volume;
    bulk_values.push_back(bulk);
    plate_sum += fluid_stress + contact + lubrication;
    contact_sum += contact;
    lub_sum += lubrication;
    virial_sum += fluid_stress + (means.particle_stress[4] + pair_contact + plate_contact) / volume;
    virial_contact_sum += pair_contact / volume;
    stresslet_sum += means.stresslet_sum[4] / volume;
    pair_lub_sum += (means.lubrication_virial[4] - means.plate_virial[4]) / volume;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto n = static_cast<double>(bulk_values.size());
  double mean = 0.0;
  for (double t : bulk_values) mean += t / n;
  double var = 0.0;
  for (double t : bulk_values) var += (t - mean) * (t - mean) / std::max(1.0, n - 1.0);
  r.phi = cell.volume_fraction();
  r.particles = cell.total_particle_count();
  r.eta_r = mean / fluid_stress;
  r.eta_r_error = std::sqrt(var / n) / fluid_stress;  // blocks of 0.25 strain: treated as independent
  r.stresslet = stresslet_sum / n / fluid_stress;
  r.pair_lubrication = pair_lub_sum / n / fluid_stress;
  r.pair_contact = virial_contact_sum / n / fluid_stress;
  r.eta_r_plate = plate_sum / n / fluid_stress;
  r.plate_contact = contact_sum / n / fluid_stress;
  r.plate_lubrication = lub_sum / n / fluid_stress;
  r.eta_r_virial_with_plates = virial_sum / n / fluid_stress;
  r.matrix_stress = fluid_stress;
  r.steps = static_cast<std::int64_t>(blocks) * block;
  r.dem_seconds = wall - r.near_field_seconds;
  return r;
}

double krieger_dougherty(double phi, double phi_max) { return std::pow(1.0 - phi / phi_max, -2.5 * phi_max); }

void print(const char* label, const CellResult& r) {
  std::printf(
      "%s φ = %.4f (N = %lld): bulk η_r = %.3f ± %.3f (1 + stresslet %.3f + pair lubrication %.3f + pair "
      "contact %.3f); KD(0.6) = %.3f | top plate: η_r = %.3f (fluid 1, contact %.3f, lubrication %.3f), "
      "virial incl. plates %.3f | steps %lld, DEM %.1f s, near field %.1f s, max CG iterations %d\n",
      label, r.phi, static_cast<long long>(r.particles), r.eta_r, r.eta_r_error, r.stresslet, r.pair_lubrication,
      r.pair_contact, krieger_dougherty(r.phi, 0.6), r.eta_r_plate, r.plate_contact, r.plate_lubrication,
      r.eta_r_virial_with_plates, static_cast<long long>(r.steps), r.dem_seconds, r.near_field_seconds,
      r.max_iterations);
  std::fflush(stdout);
}

TEST(ValidateNearFieldShearCell, BookkeepingAddsUpAndTheNearFieldLiftsTheStress) {
  CellSettings c;
  c.phi = 0.3;
  c.strain = 3.0;
  c.skip_strain = 1.0;
  const CellResult full = run_cell(c);
  print("lubrication+stresslet", full);
  CellSettings drag_only = c;
  drag_only.terms = {.stokes_drag = true};
  drag_only.strain = 2.0;
  const CellResult seed_model = run_cell(drag_only);
  print("stokes_drag only", seed_model);
  // Bookkeeping: the bulk parts add up and the stresslets give Einstein's 2.5 φ.
  EXPECT_NEAR(full.eta_r, 1.0 + full.stresslet + full.pair_lubrication + full.pair_contact, 1e-9);
  EXPECT_NEAR(full.stresslet, 2.5 * full.phi, 0.02 * 2.5 * full.phi);
  // Drag only stays near 1 (the seed's under-prediction); the near field lifts η_r above it.
  EXPECT_LT(seed_model.eta_r, 1.3);
  EXPECT_GT(full.eta_r, seed_model.eta_r + 1.0);
}

constexpr double mu = 1e-3;  // water [Pa·s], the seed's liquid

std::shared_ptr<const core::Rheology> newtonian() { return testing::newtonian(mu); }
using testing::lubrication_and_stresslet;

// The seed's particles (d = 200 µm, ρ_p = 1000, E/softening) in water at γ̇ in a coupled shear cell
// with lubrication + stresslet (+ repulsion F_R0 = repulsion_ratio × 6πμa²γ̇, Mari et al.'s stress
// scale), run to a fixed strain: the settings of the like-for-like test below.
struct SeedCell {
  double gap = 5e-4, cell = 1.6e-3, phi = 0.3, rate = 100.0;  // m, m, -, 1/s
  double softening = 1e4, friction = 0.3, axial_cell_over_d = 1.25, strain = 20.0;
  double repulsion_ratio = 0.0, repulsion_length = NearFieldSettings{}.repulsion_length;
  NearFieldSettings hydrodynamics = lubrication_and_stresslet();
  DragLaw drag = DragLaw::di_felice;
};

ShearCellPointSettings seed_cell_settings(const SeedCell& c) {
  ShearCellPointSettings s;
  s.gap = c.gap;
  s.cell_length = s.cell_width = c.cell;
  s.fluid = {.density = 1000.0, .rheology = newtonian()};
  s.particles = {.volume_fraction = c.phi,
                 .diameter = 2e-4,
                 .density = 1000.0,
                 .youngs_modulus = 3.0e9 / c.softening,
                 .poisson_ratio = 0.33,
                 .restitution = 0.9,
                 .friction = c.friction};
  s.drag = c.drag;
  const double dt = 0.3 * dem::rayleigh_time({1e-4, 1000.0, s.particles.youngs_modulus, 0.33});
  s.coupling_interval = std::max(1, static_cast<int>(std::lround(1e-5 / dt)));
  s.shear_rate = c.rate;
  s.axial_cells = std::max(2, static_cast<int>(std::lround(s.gap / (c.axial_cell_over_d * 2e-4))));
  s.steady = {.strain_window = 2.0, .relative_tolerance = 1e-9, .min_strain = c.strain, .max_strain = c.strain};
  auto hydrodynamics = c.hydrodynamics;
  if (c.repulsion_ratio > 0.0) {
    const double a = 0.5 * s.particles.diameter;
    hydrodynamics.terms.repulsion = true;
    hydrodynamics.repulsion_force = c.repulsion_ratio * 6.0 * std::numbers::pi * mu * a * a * s.shear_rate;
    hydrodynamics.repulsion_length = c.repulsion_length;
  }
  s.near_field = make_near_field_model(hydrodynamics, s.fluid.rheology);
  return s;
}

// Like for like: the coupled cell (solved fluid column) against the imposed-flow FLD cell of
// this file (u∞ = γ̇z), the same definition of η_r (stresslet + symmetric pair virial, no
// plates), both run here: φ = 0.3, F_R0 = 10 × 6πμa²γ̇, H = 20 d, 8 d × 8 d, the same particles
// and particle Stokes number (ργ̇a²/μ = 1). With the drag the case files pick for lubricated
// suspensions (particles.drag auto = the isolated sphere) the two must agree within 4 %; Di
// Felice's hindrance on each sphere's slip counts the crowding twice (docs/hydrodynamics.md).
TEST(NearFieldCoupledValidation, ShearCellWithTheIsolatedSphereDragMatchesTheImposedFlowCell) {
  SeedCell c{.gap = 4e-3, .phi = 0.3, .repulsion_ratio = 10.0, .drag = DragLaw::schiller_naumann};
  ShearCellPointSettings s = seed_cell_settings(c);
  testing::RunFolder folder;
  s.run_directory = folder.path();
  const auto p = run_shear_cell_point(s);
  CellSettings imposed;
  imposed.phi = c.phi;
  imposed.rate = c.rate;
  imposed.viscosity = mu;
  imposed.gap_over_d = c.gap / 2e-4;
  imposed.cell_over_d = 8.0;
  imposed.strain = c.strain;
  imposed.skip_strain = 5.0;
  imposed.friction = c.friction;
  imposed.repulsion_ratio = c.repulsion_ratio;
  imposed.stresslet_viscosity = c.hydrodynamics.stresslet_viscosity;
  imposed.youngs_modulus = 3.0e9 / c.softening;
  const CellResult reference = run_cell(imposed);
  print("imposed-flow cell", reference);
  const double liquid = mu * c.rate, imposed_cell = reference.eta_r;
  const double eta_r = p.bulk_parts.imposed_cell_definition() / liquid;
  std::printf("phi %.4f, N %lld: imposed cell's definition %.4f (imposed cell %.3f), plate %.4f +- %.4f, bulk %.4f\n",
              p.volume_fraction, static_cast<long long>(p.particles), eta_r, imposed_cell, p.stress / liquid,
              p.stress_error / liquid, p.bulk_stress / liquid);
  EXPECT_NEAR(eta_r, imposed_cell, 0.04 * imposed_cell);
  // The plate reading adds the wall layers' plate lubrication and the antisymmetric pair part.
  EXPECT_GT(p.stress / liquid, eta_r);
  EXPECT_LT(p.stress / liquid, 1.12 * eta_r);
}

}  // namespace
}  // namespace rheosim::coupling
