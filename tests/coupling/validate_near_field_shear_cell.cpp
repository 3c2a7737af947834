// Relative viscosity of a sheared suspension with near-field hydrodynamics (issue 9 items 3–4):
// dem::ShearCellScene (periodic in x and y between plates, top plate sliding at γ̇ H) with the
// near-field hook in an imposed linear ambient flow u∞ = γ̇ z e_x — Fast-Lubrication-Dynamics
// style (docs/hydrodynamics.md): Stokes drag and torque on u∞, stresslets, pair and plate
// lubrication, Hertz contacts with friction from LIGGGHTS; the fluid part of the stress is
// μ(γ̇) γ̇. Stress on the top plate = fluid + contact (the scene's mesh stress) + plate
// lubrication; the particle virial (stresslets + lubrication + contact virial from LIGGGHTS'
// `compute pressure ... virial` + plate contacts) cross-checks it.
//
// Enabled test (part of `make test`, ~1 min): at φ = 0.3 the bookkeeping adds up, drag only
// stays near η_r = 1 and the near field lifts η_r to the Krieger–Dougherty level (smoke bound).
// Disabled study (bench/near_field_viscosity.sh): φ = 0.1 … 0.45, KD fit of φ_m, rate
// independence, cost against drag-only. Environment overrides: RHEOSIM_NF_PHIS (comma list),
// RHEOSIM_NF_RATES, RHEOSIM_NF_STRAIN, RHEOSIM_NF_CELL (L/d), RHEOSIM_NF_GAP (H/d), RHEOSIM_NF_FRICTION,
// RHEOSIM_NF_PLATE_LUBRICATION (0: no particle–plate lubrication), RHEOSIM_NF_CUTOFF (h_c/ā),
// RHEOSIM_NF_YOUNGS (E, Pa), RHEOSIM_NF_SKIP (strain left out), RHEOSIM_NF_DRAG_ONLY.
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
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/dem/engine.hpp"
#include "rheosim/dem/shear_cell_scene.hpp"

namespace rheosim::coupling {
namespace {

constexpr double pi = std::numbers::pi;

struct CellSettings {
  double phi = 0.3;
  double rate = 100.0;          // γ̇ [1/s]
  double viscosity = 1.0;       // μ [Pa·s] (Newtonian matrix)
  std::string rheology_yaml;    // another matrix law (YAML of `rheology:`); empty: Newtonian μ
  double diameter = 2e-4;       // d [m]
  double gap_over_d = 10.0;     // H/d
  double cell_over_d = 6.0;     // L_x/d = L_y/d
  double strain = 6.0;          // total strain
  double skip_strain = 2.0;     // transient left out of the means
  double friction = 0.3;
  std::vector<std::string> models{"stokes_drag", "stresslet", "lubrication"};
  bool plate_lubrication = true;  // false: the plates bound the cell for contacts only
  double lubrication_cutoff = NearFieldSettings{}.lubrication_cutoff;  // h_c/ā
  double repulsion_ratio = 0.0;  // F_R0 / (6πμa²γ̇); > 0 adds the `repulsion` term (λ = 0.05 ā)
  double repulsion_force = 0.0;  // F_R0 [N] when > 0 (instead of the ratio): fixed over rates
  core::StressletViscosity stresslet_viscosity = core::StressletViscosity::homogenized;
  double youngs_modulus = 1e6;  // [Pa] soft: δt = 0.2 t_R = 3.5e-6 s = 3.5e-4/γ̇; overlaps below 1 % of d
  std::uint64_t seed = 1;
};

struct CellResult {
  double phi = 0.0;
  std::int64_t particles = 0;
  double eta_r = 0.0, eta_r_error = 0.0;  // bulk (Batchelor) stress / μγ̇
  double stresslet = 0.0, pair_lubrication = 0.0, pair_contact = 0.0;  // its particle parts
  double eta_r_plate = 0.0;               // top plate: fluid + contact + lubrication
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
  core::ParticleProperties props;
  props.volume_fraction = c.phi;
  props.diameter = d;
  props.density = 1000.0;
  props.youngs_modulus = c.youngs_modulus;
  props.restitution = 0.5;
  props.friction = c.friction;
  const double H = c.gap_over_d * d, L = c.cell_over_d * d;
  dem::ShearCellScene cell({.gap = H, .cell_length = L, .cell_width = L, .particles = props,
                            .shear_rate = c.rate, .time_step_fraction = 0.2, .seed = c.seed,
                            .run_directory = folder.path(), .stress_sample_interval = 50});
  dem::Engine& engine = cell.engine();
  // Contact virial of the particle pairs (LIGGGHTS' pressure tensor, virial part only).
  engine.commands({"compute rheosim_nf_temp all temp", "compute rheosim_nf_pressure all pressure rheosim_nf_temp virial",
                   "fix rheosim_nf_virial all ave/time 1 50 50 c_rheosim_nf_pressure[5]"});

  NearFieldSettings settings;
  settings.models = c.models;
  settings.lubrication_cutoff = c.lubrication_cutoff;
  settings.stresslet_viscosity = c.stresslet_viscosity;
  if (c.repulsion_force > 0.0 || c.repulsion_ratio > 0.0) {
    settings.models.emplace_back("repulsion");
    settings.repulsion_force =
        c.repulsion_force > 0.0 ? c.repulsion_force : c.repulsion_ratio * 6.0 * pi * c.viscosity * a * a * c.rate;
  }
  NearFieldScene scene;
  scene.periodic = {true, true, false};
  scene.box_low = {0.0, 0.0, 0.0};
  scene.box_high = {L, L, H};
  const double u_top = c.rate * H;
  scene.plates.push_back({.z = 0.0, .faces_up = true, .velocity_at = {}});
  scene.plates.push_back(
      {.z = H, .faces_up = false, .velocity_at = [u_top](const Vector3&) { return Vector3{u_top, 0.0, 0.0}; }});
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

// Least squares in ln η_r over φ_m (golden section on [0.45, 0.9]).
double fit_maximum_packing(const std::vector<double>& phi, const std::vector<double>& eta) {
  const auto cost = [&](double pm) {
    double s = 0.0;
    for (std::size_t i = 0; i < phi.size(); ++i) {
      if (phi[i] >= pm) return 1e300;
      const double e = std::log(eta[i]) - std::log(krieger_dougherty(phi[i], pm));
      s += e * e;
    }
    return s;
  };
  double lo = 0.46, hi = 0.9;
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int i = 0; i < 100; ++i) {
    const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    if (cost(x1) < cost(x2))
      hi = x2;
    else
      lo = x1;
  }
  return 0.5 * (lo + hi);
}

std::vector<double> env_list(const char* name, std::vector<double> fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr) return fallback;
  std::vector<double> out;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) out.push_back(std::stod(item));
  return out;
}
double env_number(const char* name, double fallback) {
  const char* text = std::getenv(name);
  return text == nullptr ? fallback : std::stod(text);
}

void print(const char* label, const CellResult& r) {
  std::printf("%s φ = %.4f (N = %lld): bulk η_r = %.3f ± %.3f (1 + stresslet %.3f + pair lubrication %.3f + pair "
              "contact %.3f); KD(0.6) = %.3f | top plate: η_r = %.3f (fluid 1, contact %.3f, lubrication %.3f), "
              "virial incl. plates %.3f | steps %lld, DEM %.1f s, near field %.1f s, max CG iterations %d\n",
              label, r.phi, static_cast<long long>(r.particles), r.eta_r, r.eta_r_error, r.stresslet,
              r.pair_lubrication, r.pair_contact, krieger_dougherty(r.phi, 0.6), r.eta_r_plate, r.plate_contact,
              r.plate_lubrication, r.eta_r_virial_with_plates, static_cast<long long>(r.steps), r.dem_seconds,
              r.near_field_seconds, r.max_iterations);
  std::fflush(stdout);
}

TEST(ValidateNearFieldShearCell, ModerateConcentrationIsNearKriegerDougherty) {
  CellSettings c;
  c.phi = 0.3;
  c.strain = 3.0;
  c.skip_strain = 1.0;
  const CellResult full = run_cell(c);
  print("lubrication+stresslet", full);
  CellSettings drag_only = c;
  drag_only.models = {"stokes_drag"};
  drag_only.strain = 2.0;
  const CellResult seed_model = run_cell(drag_only);
  print("stokes_drag only", seed_model);
  // Bookkeeping: the bulk parts add up and the stresslets give Einstein's 2.5 φ.
  EXPECT_NEAR(full.eta_r, 1.0 + full.stresslet + full.pair_lubrication + full.pair_contact, 1e-9);
  EXPECT_NEAR(full.stresslet, 2.5 * full.phi, 0.02 * 2.5 * full.phi);
  // Drag only stays near 1 (the seed's under-prediction); the near field lifts η_r to the
  // measured level (× 2.5–3 at φ = 0.3). The η_r(φ) curve and its φ_m fit are the bench study
  // (bench/near_field_viscosity.sh); here a smoke bound of ±60 % around KD(φ_m = 0.6).
  EXPECT_LT(seed_model.eta_r, 1.3);
  EXPECT_GT(full.eta_r, seed_model.eta_r + 1.0);
  EXPECT_NEAR(full.eta_r / krieger_dougherty(full.phi, 0.6), 1.0, 0.6);
}

TEST(ValidateNearFieldShearCell, DISABLED_ViscosityCurveStudy) {
  const auto phis = env_list("RHEOSIM_NF_PHIS", {0.1, 0.2, 0.3, 0.4, 0.45});
  const auto rates = env_list("RHEOSIM_NF_RATES", {100.0});
  CellSettings base;
  base.strain = env_number("RHEOSIM_NF_STRAIN", 8.0);
  base.skip_strain = 0.3 * base.strain;
  base.cell_over_d = env_number("RHEOSIM_NF_CELL", 6.0);
  base.gap_over_d = env_number("RHEOSIM_NF_GAP", 10.0);
  base.friction = env_number("RHEOSIM_NF_FRICTION", 0.3);
  base.plate_lubrication = env_number("RHEOSIM_NF_PLATE_LUBRICATION", 1.0) != 0.0;
  base.lubrication_cutoff = env_number("RHEOSIM_NF_CUTOFF", base.lubrication_cutoff);
  base.youngs_modulus = env_number("RHEOSIM_NF_YOUNGS", base.youngs_modulus);
  base.skip_strain = env_number("RHEOSIM_NF_SKIP", base.skip_strain);
  base.repulsion_ratio = env_number("RHEOSIM_NF_REPULSION", 0.0);
  // μ sets the particle Stokes number St = ρ_pγ̇a²/μ (1e-3 at μ = 1 Pa·s; the coupled cell's
  // water-like 1e-3 Pa·s gives St = 1).
  base.viscosity = env_number("RHEOSIM_NF_VISCOSITY", base.viscosity);
  for (const double rate : rates) {
    std::vector<double> phi, eta;
    for (const double p : phis) {
      CellSettings c = base;
      c.phi = p;
      c.rate = rate;
      const CellResult r = run_cell(c);
      print(fmt::format("γ̇ = {} 1/s", rate).c_str(), r);
      phi.push_back(r.phi);
      eta.push_back(r.eta_r);
    }
    const double pm = fit_maximum_packing(phi, eta);
    std::printf("γ̇ = %g 1/s: Krieger–Dougherty fit φ_m = %.4f\n", rate, pm);
    for (std::size_t i = 0; i < phi.size(); ++i)
      std::printf("  φ = %.4f  η_r = %.3f  KD(φ_m) = %.3f\n", phi[i], eta[i], krieger_dougherty(phi[i], pm));
    std::fflush(stdout);
  }
  if (std::getenv("RHEOSIM_NF_DRAG_ONLY") != nullptr) {
    for (const double p : phis) {
      CellSettings c = base;
      c.phi = p;
      c.models = {"stokes_drag"};
      print("drag only", run_cell(c));
    }
  }
}

// Yield-stress matrix (Bingham, Papanastasiou-regularised): the suspension's yield stress from a
// two-rate Bingham fit τ = τ_y,s + η_p,s γ̇ at Bingham numbers 100 and 33, against
// Chateau, Ovarlez & Trung (J. Rheol. 52 (2008) 489): τ_y,s/τ_y = √((1 − φ) η_r(φ)), with η_r(φ)
// the same model's Newtonian relative viscosity (RHEOSIM_NF_ETA_R, comma list matching the φs;
// default: the γ̇ = 100 study values of docs/hydrodynamics.md). RHEOSIM_NF_REPULSION = r adds the
// repulsion with F_R0 = r · 6πa² τ(100 1/s), the same force at both rates; RHEOSIM_NF_STRESSLET =
// secant uses the secant viscosity in the stresslet (default: homogenized, docs/hydrodynamics.md).
TEST(ValidateNearFieldShearCell, DISABLED_YieldStressStudy) {
  const auto phis = env_list("RHEOSIM_NF_PHIS", {0.1, 0.2, 0.3});
  const auto eta_r = env_list("RHEOSIM_NF_ETA_R", {1.408, 2.390, 4.211});
  const double yield_stress = 1000.0, plastic_viscosity = 0.1;
  const std::vector<double> rates{100.0, 300.0};
  for (std::size_t k = 0; k < phis.size(); ++k) {
    std::vector<double> stress;
    double phi = 0.0;
    for (const double rate : rates) {
      CellSettings c;
      c.phi = phis[k];
      c.rate = rate;
      c.strain = env_number("RHEOSIM_NF_STRAIN", 3.0);
      c.skip_strain = 0.3 * c.strain;
      c.rheology_yaml = fmt::format("model: bingham\nplastic_viscosity: {}\nyield_stress: {}\nregularization: 1.0e4\n",
                                    plastic_viscosity, yield_stress);
      const double a = 0.5 * c.diameter;
      const char* stresslet = std::getenv("RHEOSIM_NF_STRESSLET");
      if (stresslet != nullptr && std::string(stresslet) == "secant") c.stresslet_viscosity = core::StressletViscosity::secant;
      c.repulsion_force = env_number("RHEOSIM_NF_REPULSION", 0.0) * 6.0 * pi * a * a *
                          (yield_stress + plastic_viscosity * rates.front());
      const CellResult r = run_cell(c);
      print(fmt::format("bingham γ̇ = {} 1/s", rate).c_str(), r);
      stress.push_back(r.eta_r * r.matrix_stress);
      phi = r.phi;
    }
    const double tau_s = (stress[0] * rates[1] - stress[1] * rates[0]) / (rates[1] - rates[0]);
    const double cot = std::sqrt((1.0 - phi) * (k < eta_r.size() ? eta_r[k] : 1.0));
    std::printf("φ = %.4f: τ_y,s/τ_y = %.3f (Chateau–Ovarlez–Trung with this model's η_r: %.3f; with KD φ_m = 0.6: "
                "%.3f)\n",
                phi, tau_s / yield_stress, cot, std::sqrt((1.0 - phi) * krieger_dougherty(phi, 0.6)));
    std::fflush(stdout);
  }
}

}  // namespace
}  // namespace rheosim::coupling
