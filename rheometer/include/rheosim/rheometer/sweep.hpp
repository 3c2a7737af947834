#pragma once
// `kind: sweep`: every (fluid, φ, γ̇_R) of fluids × volume_fractions × shear_rates,
// resumable after any kill, then the flow-curve analysis and the report.
//
// Who computes a point is injected: a PointRunner is any callable that turns one SweepPoint into
// a PointResult. run_sweep takes two, one for single-phase points (φ = 0) and one for suspension
// points (φ > 0), so the CFD-DEM coupling plugs in by passing its runner — the sweep, the store,
// the analysis and the report do not change:
//
//   auto runners = rheometer::default_point_runners(sweep_case.rheometer);
//   runners.suspension = [&](const SweepPoint& p, const PointProgressCallback& progress) {
//     ...  // build the scene at p.volume_fraction, advance, call progress({strain, target}) now
//     ...  // and then, stop at steady state
//     return PointResult{...};  // torque (fluid + contact) with its steady-state error bar
//   };
//   rheometer::run_sweep(c, out_dir, log, runners);
//
// default_point_runners records suspension points as failed with the reason; the CLI plugs in
// make_coupled_suspension_runner (CFD-DEM). A failed point never stops the sweep.
//
// The run folder:
//   case.yaml         the input deck as given
//   points/point_NNNN.h5   one HDF5 file per finished point, written atomically (temporary file,
//                     fsync, rename) the moment the point finishes; root attributes hold the
//                     point's numbers and the deck's sha256, datasets its fields (if any; a
//                     liquid point: ω, p, u_r, u_z, μ, γ̇ and the cell centres of its (r, z) grid)
//   points/point_NNNN.failed.h5   a failed point's last iterate and reason (not resumed from)
//   sweep.h5          all points as columns, written at the end
//   summary.json, torque.csv, …, report.html   see rheometer/report.hpp and docs/report.md
//
// Every rheometer case runs as a sweep (rheometer::as_sweep in case.hpp).
//
// Resuming: started again on the same folder, a sweep reads points/ and computes only the points
// without a file there. Failed points are not stored, so they are tried again. A points/ folder
// written from a different input deck (another sha256) is refused with a message: results of two
// decks are never mixed.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "rheosim/core/log.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/rheometer/case.hpp"

namespace rheosim::rheometer {

// One point of a sweep.
struct SweepPoint {
  std::size_t index = 0;       // position in the sweep (fluid-major, then φ, then γ̇_R)
  std::string fluid;           // name of the suspending liquid
  double volume_fraction = 0;  // φ [-]
  double rim_shear_rate = 0;   // γ̇_R [1/s]
};

// What a transient point reports while it runs (a steady solve reports nothing).
struct PointProgress {
  double strain = 0;                                                // accumulated rim strain γ̇_R t [-]
  double target_strain = std::numeric_limits<double>::quiet_NaN();  // expected at the end, NaN if unknown
};
using PointProgressCallback = std::function<void(const PointProgress&)>;

// The measured value of one point. NaN means "not available for this kind of point".
struct PointResult {
  bool converged = false;
  std::string failure;  // why the point has no result (empty when converged)
  std::string method;   // how it was computed, e.g. "steady axisymmetric swirl solve"
  double torque = std::numeric_limits<double>::quiet_NaN();          // on the top plate [N·m]
  double torque_fluid = std::numeric_limits<double>::quiet_NaN();    // fluid part [N·m]
  double torque_contact = std::numeric_limits<double>::quiet_NaN();  // particle contacts [N·m]
  // Near-field parts: plate lubrication, and the torque the stresslets and the
  // particles' rotation couples transmit through the liquid [N·m].
  double torque_lubrication = std::numeric_limits<double>::quiet_NaN();
  double torque_stresslet = std::numeric_limits<double>::quiet_NaN();
  double torque_couple = std::numeric_limits<double>::quiet_NaN();
  double torque_std_error = std::numeric_limits<double>::quiet_NaN();  // steady-state error bar [N·m]
  double torque_creeping = std::numeric_limits<double>::quiet_NaN();   // inertia switched off [N·m]
  double torque_analytic = std::numeric_limits<double>::quiet_NaN();   // closed form, when one exists
  // A Richardson-extrapolated swirl torque (solver.extrapolate): this grid's own and its
  // half-grid's torques [N·m] (NaN otherwise).
  double torque_grid = std::numeric_limits<double>::quiet_NaN();
  double torque_half_grid = std::numeric_limits<double>::quiet_NaN();
  double strain = std::numeric_limits<double>::quiet_NaN();  // simulated strain (transient)
  // CFD-DEM wall time per part of the coupling step [s] (NaN for steady solves).
  double cost_dem = std::numeric_limits<double>::quiet_NaN();
  double cost_void_fraction = std::numeric_limits<double>::quiet_NaN();
  double cost_forces = std::numeric_limits<double>::quiet_NaN();
  double cost_fluid = std::numeric_limits<double>::quiet_NaN();
  double cost_near_field = std::numeric_limits<double>::quiet_NaN();
  int iterations = 0;    // nonlinear iterations or time steps
  double wall_time = 0;  // [s]
  // Which scene computed it: "swirl", "full_disk" or "shear_cell", why, and the
  // model's estimated relative error of `torque` (NaN when not estimated).
  std::string model;
  std::string model_reason;
  double estimated_error = std::numeric_limits<double>::quiet_NaN();
  // Normal stresses: the plate's normal force (thrust pushing the plates apart) [N] and the
  // local first and second normal stress differences at the rim rate [Pa] (NaN when the model
  // has none).
  double normal_force = std::numeric_limits<double>::quiet_NaN();
  double n1 = std::numeric_limits<double>::quiet_NaN();
  double n2 = std::numeric_limits<double>::quiet_NaN();
  // Every rule the point's model bent (a fallback, a solve above its tolerance, an unconverged
  // average, a regime it does not model), for the log, summary.json and the report.
  std::vector<std::string> warnings;
  std::vector<core::Hdf5Dataset> fields;  // stored with the point (paths relative, e.g. "fields/viscosity")
};

using PointRunner = std::function<PointResult(const SweepPoint&, const PointProgressCallback&)>;

struct PointRunners {
  PointRunner single_phase;  // φ = 0
  PointRunner suspension;    // φ > 0
};

// φ = 0: the steady swirl solve of the liquid (fluid/swirl.hpp), with inertia as the case's
// `solver.inertia` says plus the creeping solve for comparison, and the closed-form torque.
// Every point starts from the creeping profile (no warm start from a neighbour), so a point's
// result does not depend on which points ran before it in the same process: a resumed sweep
// ends with the same numbers as an uninterrupted one.
[[nodiscard]] PointRunner make_swirl_point_runner(const RheometerCase& rheometer);
// φ > 0 until the CFD-DEM coupling provides a runner: a failed point naming the reason.
[[nodiscard]] PointRunner make_unavailable_suspension_runner();
[[nodiscard]] PointRunners default_point_runners(const RheometerCase& rheometer);
// φ > 0 by CFD-DEM (coupling::run_point): LIGGGHTS' files of point N go to
// work_dir/point_NNNN. The point's torque is fluid + contact, mean ± standard error over the
// last steady strain window; the torque series and the cost split are stored with the point.
// Before starting, a point's DEM cost is estimated (particles × DEM steps to the detector's
// max_strain, at 1.5e7 particle-steps/s per core, docs/performance.md); a point whose estimate
// exceeds `budget_seconds` fails at once with the estimate and what to change, instead of
// running for hours.
// With the case's `model:` this runner dispatches each point: model full_disk runs
// the disk as above; shear_cell runs rheometer::make_shear_cell_suspension_runner
// (shear_cell.hpp); auto asks choose_suspension_model() and records the reason.
// volume_fractions: the sweep's, for the box runner to queue later φ on free cores.
[[nodiscard]] PointRunner make_coupled_suspension_runner(const RheometerCase& rheometer, std::filesystem::path work_dir,
                                                         double budget_seconds,
                                                         std::vector<double> volume_fractions = {});
// The full-disk CFD-DEM runner alone.
[[nodiscard]] PointRunner make_full_disk_suspension_runner(const RheometerCase& rheometer,
                                                           std::filesystem::path work_dir, double budget_seconds);

// Estimated one-core wall time [s] of a CFD-DEM point run to `max_strain` (see above).
struct SuspensionCostEstimate {
  double particles = 0;
  double dem_steps = 0;
  double wall_time = 0;
};
[[nodiscard]] SuspensionCostEstimate estimate_suspension_cost(const RheometerCase& rheometer, double volume_fraction,
                                                              double rim_shear_rate, double max_strain);

// Every point of the case in sweep order.
[[nodiscard]] std::vector<SweepPoint> sweep_points(const SweepCase& sweep);

// The finished points of one run folder (points/point_NNNN.h5).
class PointStore {
 public:
  // Opens (creating) <run_dir>/points for the deck with this sha256. Removes temporary files
  // left by a killed write. Throws core::ConfigError when a stored point comes from another deck.
  PointStore(std::filesystem::path run_dir, std::string input_sha256);

  // The stored result of `point`, if it finished before; throws core::RunError when the file
  // does not describe this point (a corrupted folder).
  [[nodiscard]] std::optional<PointResult> load(const SweepPoint& point) const;
  // Stores a finished point atomically (a kill leaves the old state or the new file, never half).
  // Removes the point's failure file, if any.
  void store(const SweepPoint& point, const PointResult& result) const;
  // Keeps a failed point's last state (its fields and the reason) in failure_file(point), which
  // load() never reads: the point is computed again on resume.
  void store_failure(const SweepPoint& point, const PointResult& result) const;
  [[nodiscard]] std::filesystem::path file(const SweepPoint& point) const;          // point_NNNN.h5
  [[nodiscard]] std::filesystem::path failure_file(const SweepPoint& point) const;  // point_NNNN.failed.h5
  [[nodiscard]] const std::filesystem::path& directory() const { return directory_; }

 private:
  void write(const std::filesystem::path& path, const SweepPoint& point, const PointResult& result) const;

  std::filesystem::path directory_;
  std::string input_sha256_;
};

struct SweepOutcome {
  std::filesystem::path summary;  // summary.json
  int points = 0;                 // in the sweep
  int reused_points = 0;          // read from points/ (finished by an earlier run)
  int computed_points = 0;        // run now (including failures)
  int failed_points = 0;          // no result: the sweep exits non-zero
};

// Runs (or resumes) a `kind: sweep` case into out_dir and writes summary.json, the CSV tables,
// sweep.h5, the plots and report.html. A point that fails is recorded with its reason and the
// sweep goes on. Throws core::ConfigError when out_dir holds points of another deck and
// core::RunError for I/O failures.
SweepOutcome run_sweep(const Case& c, const std::filesystem::path& out_dir, const core::Log& log,
                       const PointRunners& runners);

}  // namespace rheosim::rheometer
