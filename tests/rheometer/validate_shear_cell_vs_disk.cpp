// Issue 10 item 5: the shear cell's plate torque against CFD-DEM of the whole disk, one φ and two
// rim shear rates. A long study (minutes), so DISABLED_ here and run by
//   bench/shear_cell_vs_disk.sh BUILD_DIR
// (docs/shear-cell.md and docs/performance.md record its output).
//
// Set-up (stated, as the issue allows a smaller disk): the CD §4 liquid and spheres (η = 1 mPa·s,
// d = 0.2 mm, ρ = ρ_p = 1000 kg/m³), gap H = 0.5 mm, φ = 0.1, a disk of R = 5 mm (R/H = 10, the
// smallest disk the automatic choice hands to the cell; about 940 spheres) instead of 15 mm,
// contact stiffness E = 5 MPa (CD: 3 GPa; 5 MPa is the softest the disk scene accepts: LIGGGHTS'
// SI limit without soft_particles) in both models so that the disk runs in minutes — the
// stiffness effect itself is item 3's check. Both models: drag-only Di Felice coupling, divided
// void fraction, 4 fluid cells across the gap (with 2 the disk's torque is grid-dominated,
// docs/coupling.md "Resolution warning"), Δt_CFD <= 1e-5 s, creeping fluid (see below); each
// model's torque is compared as a ratio to its own liquid torque on the same grid.
// Measured (docs/performance.md): NOT within 3 % — the disk gives 1.55–1.60× its liquid at
// φ = 0.1 where the cell gives 1.000×.
// Environment overrides: RHEOSIM_PHI, RHEOSIM_DISK_RADIUS, RHEOSIM_CELL_LENGTH,
// RHEOSIM_YOUNGS_MODULUS, RHEOSIM_MAX_STRAIN, RHEOSIM_AXIAL_CELLS, RHEOSIM_FLUID_STEP, and for the
// disk only (diagnostics) RHEOSIM_DISK_FORCES (e.g. "di_felice,viscous"), RHEOSIM_VOID_FRACTION;
// RHEOSIM_SKIP_DISK=1 runs the cell alone.
// Cell: 1.6 mm × 1.6 mm (the size the seed sweep converged to at φ = 0.1), the same steady-state
// detector.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"
#include "rheosim/coupling/shear_cell_point.hpp"
#include "rheosim/coupling/suspension_point.hpp"
#include "rheosim/dem/contact.hpp"
#include "rheosim/rheometer/plate.hpp"
#include "rheosim/rheometer/shear_cell.hpp"

namespace rheosim::rheometer {
namespace {

namespace fs = std::filesystem;

double env_or(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v != nullptr ? std::stod(v) : fallback;
}

TEST(ShearCellVersusDisk, DISABLED_TorqueWithinThreePercentOfTheDisk) {
  const auto doc = core::Document::from_string("model: newtonian\nviscosity: 1.0e-3\n", "rheology");
  const core::FluidProperties fluid{.density = 1000.0, .rheology = core::make_rheology(doc.root())};
  const double phi = env_or("RHEOSIM_PHI", 0.1);
  const double radius = env_or("RHEOSIM_DISK_RADIUS", 5e-3);
  const double gap = 5e-4;
  const double cell_length = env_or("RHEOSIM_CELL_LENGTH", 1.6e-3);
  core::ParticleProperties particles{.volume_fraction = phi, .diameter = 2e-4, .density = 1000.0,
                                     .youngs_modulus = env_or("RHEOSIM_YOUNGS_MODULUS", 5e6)};
  const coupling::SteadyStateSettings steady{.strain_window = 2.0, .relative_tolerance = 0.02, .min_strain = 4.0,
                                             .max_strain = env_or("RHEOSIM_MAX_STRAIN", 20.0)};
  const double dt = 0.3 * dem::rayleigh_time({1e-4, 1000.0, particles.youngs_modulus, particles.poisson_ratio});
  const int interval = std::max(1, static_cast<int>(env_or("RHEOSIM_FLUID_STEP", 1e-5) / dt));
  const int axial_cells = static_cast<int>(env_or("RHEOSIM_AXIAL_CELLS", 4));
  const fs::path dir = fs::temp_directory_path() / fmt::format("rheosim_cell_vs_disk_{}", ::getpid());

  LocalFlowCurve curve;
  std::vector<double> disk_torque, disk_error, disk_liquid;
  const std::vector<double> rates{50.0, 100.0};
  for (const double rate : rates) {
    coupling::ShearCellPointSettings c;
    c.gap = gap;
    c.cell_length = c.cell_width = cell_length;
    c.fluid = fluid;
    c.particles = particles;
    c.shear_rate = rate;
    c.axial_cells = axial_cells;
    c.coupling_interval = interval;
    c.steady = steady;
    c.run_directory = dir / fmt::format("cell_{}", rate);
    fs::create_directories(c.run_directory);
    const auto cell = coupling::run_shear_cell_point(c);
    std::printf("cell  rate %g: tau %.5g +- %.2g Pa (fluid %.5g, contact %.5g), N %lld, strain %.1f, converged %d, "
                "%.1f s\n",
                rate, cell.stress, cell.stress_error, cell.stress_fluid, cell.stress_contact,
                static_cast<long long>(cell.particles), cell.strain, cell.converged, cell.wall_time);
    curve.shear_rate.push_back(rate);
    curve.stress.push_back(cell.stress);

    if (env_or("RHEOSIM_SKIP_DISK", 0.0) != 0.0) continue;  // cell only (its own studies)
    coupling::SuspensionPointSettings d;
    d.geometry = {.radius = radius, .gap = gap};
    d.fluid = fluid;
    d.particles = particles;
    d.rim_shear_rate = rate;
    // Fluid inertia off by default (RHEOSIM_DISK_INERTIA=1 switches it on): the cell is creeping,
    // and with inertia on the disk's transient solver stopped on its Courant guard in a cell
    // next to the axis at φ = 0.1 for every Δt tried (9.3e-6, 4.7e-6, 2.3e-6 s), i.e. the
    // velocity there grows without bound. Caveat: without fluid inertia nothing balances the
    // spheres' centrifugal force (with ρ_p = ρ it is the centripetal −V_p∇p).
    d.inertia = env_or("RHEOSIM_DISK_INERTIA", 0.0) != 0.0;
    d.axial_cells = axial_cells;
    d.coupling.coupling_interval = interval;
    if (const char* forces = std::getenv("RHEOSIM_DISK_FORCES")) {  // diagnostics, e.g. "di_felice,viscous"
      d.coupling.forces.clear();
      std::string list = forces;
      for (std::size_t start = 0; start <= list.size();) {
        const std::size_t end = std::min(list.find(',', start), list.size());
        d.coupling.forces.push_back(list.substr(start, end - start));
        start = end + 1;
      }
    }
    if (const char* scheme = std::getenv("RHEOSIM_VOID_FRACTION")) d.coupling.void_fraction = scheme;
    d.steady = steady;
    d.run_directory = dir / fmt::format("disk_{}", rate);
    fs::create_directories(d.run_directory);
    const auto disk = coupling::run_point(d);
    std::printf("disk  rate %g: T %.5g +- %.2g N m (fluid %.5g, contact %.5g), N %lld, strain %.1f, converged %d, "
                "%.1f s (dem %.1f)\n",
                rate, disk.torque, disk.torque_error, disk.torque_fluid, disk.torque_contact,
                static_cast<long long>(disk.particles), disk.strain, disk.converged, disk.wall_time, disk.cost.dem);
    disk_torque.push_back(disk.torque);
    disk_error.push_back(disk.torque_error);
    // The same disk, grid and time step without particles (run_point runs the fluid alone):
    // the liquid reference that carries the disk's own inertia and grid effects.
    d.particles.volume_fraction = 0.0;
    d.run_directory = dir / fmt::format("disk_liquid_{}", rate);
    fs::create_directories(d.run_directory);
    const auto liquid = coupling::run_point(d);
    std::printf("disk  rate %g, no particles: T %.5g N m\n", rate, liquid.torque);
    disk_liquid.push_back(liquid.torque);
  }
  if (env_or("RHEOSIM_SKIP_DISK", 0.0) != 0.0) GTEST_SKIP() << "RHEOSIM_SKIP_DISK: cell only";
  const ParallelPlate plate{radius, gap};
  for (std::size_t i = 0; i < rates.size(); ++i) {
    const double cell_torque = plate_torque(curve, radius, rates[i]);
    const double liquid = newtonian_torque(plate, 1e-3, rates[i]);
    // Compared as torque ratios to each model's own liquid (the cell is creeping; the disk's
    // liquid carries its inertia and grid), and as plain torques.
    const double difference = (cell_torque / liquid) / (disk_torque[i] / disk_liquid[i]) - 1.0;
    std::printf("rate %g: cell torque %.5g N m (%.4f x creeping liquid), disk %.5g +- %.2g N m (%.4f x its liquid "
                "%.5g): ratio difference %+.2f %%, plain cell/disk - 1 = %+.2f %%\n",
                rates[i], cell_torque, cell_torque / liquid, disk_torque[i], disk_error[i],
                disk_torque[i] / disk_liquid[i], disk_liquid[i], 100.0 * difference,
                100.0 * (cell_torque / disk_torque[i] - 1.0));
    EXPECT_LE(std::abs(difference), 0.03) << rates[i];
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rheosim::rheometer
