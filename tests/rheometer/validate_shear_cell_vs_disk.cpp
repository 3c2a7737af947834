// the shear cell's plate torque against CFD-DEM of the whole disk, one φ and two
// rim shear rates (about 2 minutes on one core of a quiet machine; docs/shear-cell.md and
// docs/performance.md record it).
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
// Each model runs three placements (seeds) and their means are compared: one run's error bar
// (0.1–0.3 %) understates the scatter between placements (±1.3 % at 100 1/s), because a drag-only
// suspension keeps its arrangement. Measured: docs/shear-cell.md ("Why the disk's excess over
// the cell grew with the rate") and docs/performance.md. Within 3 % only with the cell's
// placement shaken like the disk's (the former layered lattice never let spheres meet and gave
// 1.000×, −1.9 % / −2.8 % against the disk's seed means). Deterministic per seed (one thread).
// Cell: 1.6 mm × 1.6 mm (the size the seed sweep converged to at φ = 0.1), the same steady-state
// detector.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

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

TEST(ShearCellVersusDisk, TorqueWithinThreePercentOfTheDisk) {
  const auto doc = core::Document::from_string("model: newtonian\nviscosity: 1.0e-3\n", "rheology");
  const double density = 1000.0;  // ρ = ρ_p
  const core::FluidProperties fluid{.density = density, .rheology = core::make_rheology(doc.root())};
  const double phi = 0.1;
  const double radius = 5e-3;
  const double gap = 5e-4;
  const double cell_length = 1.6e-3;
  dem::ParticleProperties particles{
      .volume_fraction = phi, .diameter = 2e-4, .density = density, .youngs_modulus = 5e6};
  const coupling::SteadyStateSettings steady{
      .strain_window = 2.0, .relative_tolerance = 0.02, .min_strain = 4.0, .max_strain = 20.0};
  const double dt = 0.3 * dem::rayleigh_time({1e-4, density, particles.youngs_modulus, particles.poisson_ratio});
  const int interval = std::max(1, static_cast<int>(1e-5 / dt));
  const int axial_cells = static_cast<int>(4);
  const fs::path dir = fs::temp_directory_path() / fmt::format("rheosim_cell_vs_disk_{}", ::getpid());

  // Mean and standard error over the placements (seeds): one run's batch-means error (0.1–0.3 %)
  // understates the scatter between placements (±1.3 % at 100 1/s, docs/shear-cell.md).
  const auto mean_and_error = [](const std::vector<double>& v) {
    double m = 0.0, var = 0.0;
    for (const double x : v) m += x / static_cast<double>(v.size());
    for (const double x : v) var += (x - m) * (x - m);
    const double n = static_cast<double>(v.size());
    return std::pair{m, v.size() > 1 ? std::sqrt(var / (n - 1.0) / n) : 0.0};
  };
  const std::vector<std::uint64_t> seeds{1, 2, 3};
  LocalFlowCurve curve;
  std::vector<double> cell_error, disk_torque, disk_error, disk_liquid;
  const std::vector<double> rates{50.0, 100.0};
  for (const double rate : rates) {
    std::vector<double> cell_stress, disk_torques;
    coupling::SuspensionPointSettings d;
    for (const std::uint64_t seed : seeds) {
      coupling::ShearCellPointSettings c;
      c.gap = gap;
      c.cell_length = c.cell_width = cell_length;
      c.fluid = fluid;
      c.particles = particles;
      c.shear_rate = rate;
      c.axial_cells = axial_cells;
      c.coupling_interval = interval;
      c.steady = steady;
      c.seed = seed;
      c.run_directory = dir / fmt::format("cell_{}_{}", rate, seed);
      fs::create_directories(c.run_directory);
      const auto cell = coupling::run_shear_cell_point(c);
      std::printf(
          "cell  rate %g seed %llu: tau %.5g +- %.2g Pa (%.4f x mu rate; fluid %.5g, contact %.5g), N %lld, "
          "strain %.1f, converged %d, %.1f s\n",
          rate, static_cast<unsigned long long>(seed), cell.stress, cell.stress_error, cell.stress / (1e-3 * rate),
          cell.stress_fluid, cell.stress_contact, static_cast<long long>(cell.particles), cell.strain, cell.converged,
          cell.wall_time);
      cell_stress.push_back(cell.stress);

      d.geometry = {.radius = radius, .gap = gap};
      d.fluid = fluid;
      d.particles = particles;
      d.rim_shear_rate = rate;
      // Fluid inertia off: the cell is
      // creeping, and with inertia on the disk at φ = 0.1 did not reach a steady torque by strain
      // 20 (1.57× / 1.43× its liquid, bottom-plate torque above the top's; docs/shear-cell.md).
      // The creeping disk's spheres get the centripetal pressure the fluid's inertia would give
      // (forces.hpp), so they are not flung outward.
      d.inertia = false;
      d.axial_cells = axial_cells;
      d.coupling.coupling_interval = interval;
      d.gravity = true;
      d.seed = seed;
      d.steady = steady;
      d.run_directory = dir / fmt::format("disk_{}_{}", rate, seed);
      fs::create_directories(d.run_directory);
      const auto disk = coupling::run_point(d);
      std::printf(
          "disk  rate %g seed %llu: T %.5g +- %.2g N m (fluid %.5g, contact %.5g, bottom fluid %.5g), N %lld, "
          "strain %.1f, converged %d, %.1f s (dem %.1f)\n",
          rate, static_cast<unsigned long long>(seed), disk.torque, disk.torque_error, disk.torque_fluid,
          disk.torque_contact, disk.bottom_torque_fluid, static_cast<long long>(disk.particles), disk.strain,
          disk.converged, disk.wall_time, disk.cost.dem);
      disk_torques.push_back(disk.torque);
    }
    const auto [cell_mean, cell_se] = mean_and_error(cell_stress);
    curve.shear_rate.push_back(rate);
    curve.stress.push_back(cell_mean);
    cell_error.push_back(cell_se / cell_mean);
    const auto [disk_mean, disk_se] = mean_and_error(disk_torques);
    disk_torque.push_back(disk_mean);
    disk_error.push_back(disk_se);
    // The same disk, grid and time step without particles (run_point runs the fluid alone):
    // the liquid reference that carries the disk's own inertia and grid effects.
    d.particles.volume_fraction = 0.0;
    d.run_directory = dir / fmt::format("disk_liquid_{}", rate);
    fs::create_directories(d.run_directory);
    const auto liquid = coupling::run_point(d);
    std::printf("disk  rate %g, no particles: T %.5g N m\n", rate, liquid.torque);
    disk_liquid.push_back(liquid.torque);
  }
  const ParallelPlate plate{radius, gap};
  for (std::size_t i = 0; i < rates.size(); ++i) {
    const double cell_torque = plate_torque(curve, radius, rates[i]);
    const double liquid = newtonian_torque(plate, 1e-3, rates[i]);
    std::printf("rate %g: cell torque %.5g N m (%.4f +- %.4f x creeping liquid, %zu seeds)\n", rates[i], cell_torque,
                cell_torque / liquid, cell_error[i] * cell_torque / liquid, seeds.size());
    // Compared as torque ratios to each model's own liquid (the cell is creeping; the disk's
    // liquid carries its inertia and grid), and as plain torques; means over the seeds.
    const double difference = (cell_torque / liquid) / (disk_torque[i] / disk_liquid[i]) - 1.0;
    const double error = std::hypot(cell_error[i], disk_error[i] / disk_torque[i]);
    std::printf(
        "rate %g: disk %.5g +- %.2g N m (%.4f +- %.4f x its liquid %.5g): ratio difference %+.2f +- %.2f %%, "
        "plain cell/disk - 1 = %+.2f %%\n",
        rates[i], disk_torque[i], disk_error[i], disk_torque[i] / disk_liquid[i], disk_error[i] / disk_liquid[i],
        disk_liquid[i], 100.0 * difference, 100.0 * error, 100.0 * (cell_torque / disk_torque[i] - 1.0));
    EXPECT_LE(std::abs(difference), 0.03) << rates[i];
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rheosim::rheometer
