#pragma once
// dem::Engine: one LIGGGHTS instance in this process. The rest of rheosim
// talks to LIGGGHTS only through this class; liggghts/*.h and mpi.h stay in dem/src/.
//
// Lifetime and output
//   The constructor opens LIGGGHTS with lammps_open on MPI_COMM_WORLD (or a given
//   communicator), starting MPI first if nobody did (MpiSession::ensure). LIGGGHTS' screen
//   goes to the null device (`-screen none` would crash LIGGGHTS' STL reader, which writes to
//   the screen unchecked) and its log goes to <run_directory>/<log_file_name> (written by rank
//   0), so nothing reaches stdout; citations (log.cite) are off, and the harmless style-collision
//   warnings that LIGGGHTS prints to std::cerr when a second instance opens go to the log,
//   too. Nothing is written to the working directory. The destructor closes the instance
//   (lammps_close), which closes the log.
//
// Errors
//   Every LIGGGHTS error (Error::all/one/fix_error/..., which would exit or MPI_Abort the
//   process), and the `quit` command, becomes an EngineError carrying the failing command and
//   LIGGGHTS' message; LIGGGHTS also writes "ERROR: ..." into its log. See
//   dem/src/liggghts_error_hook.hpp for the mechanism. The instance is then *failed*: the
//   failing command stopped half-way and LIGGGHTS' state is not consistent any more, so
//   every later call except the queries has_failed() / failure() throws an EngineError that
//   names the original failure. A failed instance is abandoned, not destroyed: its log is
//   flushed and closed, but lammps_close is not called (destructors could run over the
//   half-updated state and crash), so its memory stays allocated until the process exits.
//   Open a new Engine to continue. Under mpirun -np > 1 an EngineError that is not
//   is_collective() was raised on this rank only; the other ranks may wait forever, so the
//   application should end the job (MpiSession::abort_all). One case stays fatal: an error
//   raised inside a LIGGGHTS destructor while a healthy instance closes (destructors are
//   noexcept, so the exception ends in std::terminate); LIGGGHTS' destructors do not check.
//
// External force and torque (for the coupling)
//   Choice: LIGGGHTS' `fix external pf/callback 1 1` (fix_external.h), not the couple/cfd
//   fixes. couple/cfd (+ couple/cfd/force) is CFDEMcoupling's protocol: it needs a data
//   coupling model (`file`, or `mpi` driven by CFDEMcoupling's push/pull of named global
//   arrays every couple_every steps) and pulls forces from the CFD side on its own schedule.
//   fix external is LIGGGHTS' hook for a driver program in the same process: it calls back
//   into our code in post_force on every step, after contact forces and before the final
//   integration, with the particles in their current order. That keeps the exchange in our
//   hands (our types, our schedule) and would also allow per-step re-evaluation later.
//   It carries force only, so the callback also adds the torque to LIGGGHTS' per-particle
//   torque at the same point (fix nve/sphere integrates it in final_integrate).
//   Storage: the values are kept in a `fix property/atom` (6 values per particle, default 0),
//   which LIGGGHTS moves with each particle when it sorts or migrates particles between ranks
//   and which is 0 for particles inserted later. set_external_forces() creates both fixes on
//   first use (ids rheosim_external and rheosim_external_store; the box must exist).
//
// Per-step force hook (near-field hydrodynamics)
//   set_step_force_callback(f) makes the same fix external callback call f on every DEM step
//   (in post_force: positions x^(n+1), velocities at the half step v^(n+1/2) of velocity
//   Verlet, contact forces of this step already summed) and in the setup of each run. f sees
//   the current LIGGGHTS arrays (StepState) and writes force and torque spans (zeroed before
//   the call), which are added on that step to the stored external forces of
//   set_external_forces(). StepState::forces/torques hold every force known at that point
//   (contacts, other fixes defined before ours, the stored external load), so an implicit
//   model can predict v^(n+3/2) = v^(n+1/2) + δt (F_known + F_callback)/m. Exceptions thrown by
//   f fail the run like a LIGGGHTS error (the Engine becomes unusable).
//
// Runs
//   run(N) issues `run N` after any command, else `run N pre no post no`, which skips
//   LIGGGHTS' setup and timing summary, as CFD-DEM couplings that run in short pieces do.
//
// Views
//   positions() etc. are views into LIGGGHTS' arrays for the particles owned by this rank
//   (LIGGGHTS' local order, which changes between runs). They stay valid until the next
//   command(), commands(), run(), set_external_forces() or the end of the Engine; copy them
//   to keep them.
//
// Example
//   dem::Engine engine({.run_directory = out / "dem"});
//   engine.commands({"atom_style granular", "units si", ...});
//   engine.run(1000);
//   auto x = engine.positions();          // [x0 y0 z0 x1 y1 z1 ...] in m
//   engine.set_external_forces(forces);  // [fx0 fy0 fz0 ...] in N, same order as x
//   engine.run(100);
//
// Not thread-safe; use an Engine from one thread. Copying and moving are disabled: an Engine
// is the identity of its LIGGGHTS instance.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "rheosim/core/error.hpp"

namespace rheosim::dem {

// LIGGGHTS' particle id (its `tagint`, a 32-bit int in the Debian build).
using ParticleId = int;

// A LIGGGHTS error, or a call on an Engine whose instance failed earlier.
class EngineError : public core::RunError {
 public:
  struct Details {
    std::string command;           // the LIGGGHTS command that failed (or "lammps_open ...")
    std::string liggghts_message;  // LIGGGHTS' own error text
    std::string liggghts_source;   // where in LIGGGHTS it was raised, e.g. "modify.cpp:850" (may be empty)
    bool collective = true;        // raised on every rank (Error::all) or on this rank only (Error::one)
  };
  EngineError(std::string message, Details details, std::source_location origin = std::source_location::current());
  [[nodiscard]] const Details& details() const { return details_; }
  [[nodiscard]] const std::string& command() const { return details_.command; }
  [[nodiscard]] const std::string& liggghts_message() const { return details_.liggghts_message; }
  [[nodiscard]] bool is_collective() const { return details_.collective; }

 private:
  Details details_;
};

// What the per-step callback sees (views into LIGGGHTS' arrays, valid during the call only;
// this rank's particles in LIGGGHTS' local order, interleaved xyz, SI).
struct StepState {
  std::int64_t step = 0;                       // LIGGGHTS step number
  double time = 0.0;                           // simulated time [s]
  double time_step = 0.0;                      // δt [s]
  std::span<const double> positions;           // x^(n+1) [m], 3n
  std::span<const double> velocities;          // v^(n+1/2) [m/s], 3n (full-step v during a run's setup)
  std::span<const double> angular_velocities;  // [rad/s], 3n
  std::span<const double> radii;               // [m], n
  std::span<const double> masses;              // [kg], n
  std::span<const ParticleId> ids;             // n
  std::span<const double> forces;              // known force on this step [N], 3n (see above)
  std::span<const double> torques;             // known torque on this step [N·m], 3n
  [[nodiscard]] std::size_t size() const { return radii.size(); }
};
// forces/torques: 3n each, zero on entry; what the callback adds on this step.
using StepForceCallback = std::function<void(const StepState&, std::span<double> forces, std::span<double> torques)>;

class Engine {
 public:
  struct Params {
    // Folder for LIGGGHTS' output; created if missing. Required.
    std::filesystem::path run_directory{};
    // LIGGGHTS' log inside run_directory: a plain file name.
    std::string log_file_name = "liggghts.log";
    // Echo every command into the log (LIGGGHTS' -echo log).
    bool echo_commands = true;
    // Fortran handle (MPI_Comm_c2f) of the communicator LIGGGHTS runs on; empty means
    // MPI_COMM_WORLD. Every rank of it must construct its Engine collectively.
    std::optional<int> communicator_fortran_handle = std::nullopt;
  };

  // Opens LIGGGHTS. Throws std::invalid_argument for bad params, EngineError if LIGGGHTS
  // refuses to start, core::RunError if MPI cannot be started or LIGGGHTS' error exits could
  // not be intercepted (the binary must link rheosim_dem ahead of libliggghts).
  explicit Engine(Params params);
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;
  Engine(Engine&&) = delete;
  Engine& operator=(Engine&&) = delete;

  // Runs one LIGGGHTS input line (no line breaks; LIGGGHTS' `&` continuation is not
  // supported here). @post on EngineError the Engine has failed.
  void command(std::string_view line);
  // Defines or redefines the equal-style LIGGGHTS variable `name` as the constant value
  // (`variable name equal value`). Unlike command(), this does not make the next run() set up
  // again: fixes that evaluate the variable every step (e.g. fix move/mesh rotate/variable)
  // see the new value from the next step on, and the run continues as if uninterrupted.
  // name: letters, digits and underscores; value finite (std::invalid_argument otherwise).
  void set_equal_variable(std::string_view name, double value);
  // Runs the lines in order; stops at the first failing one.
  void commands(std::initializer_list<std::string_view> lines);
  void commands(std::span<const std::string> lines);
  // Advances steps >= 0 time steps (see "Runs" above).
  void run(std::int64_t steps);

  // Number of particles owned by this rank, and in the whole simulation.
  [[nodiscard]] std::size_t particle_count() const;
  [[nodiscard]] std::int64_t total_particle_count() const;
  // Current step number, DEM time step [s] and simulated time [s].
  [[nodiscard]] std::int64_t step() const;
  [[nodiscard]] double time_step() const;
  [[nodiscard]] double time() const;

  // Per-particle views, this rank's particles in LIGGGHTS' current local order. Vectors are
  // interleaved: [x0 y0 z0 x1 y1 z1 ...], length 3·particle_count(). SI units.
  [[nodiscard]] std::span<const double> positions() const;           // m
  [[nodiscard]] std::span<const double> velocities() const;          // m/s
  [[nodiscard]] std::span<const double> angular_velocities() const;  // rad/s (needs atom_style granular/sphere)
  [[nodiscard]] std::span<const double> radii() const;               // m, length particle_count()
  [[nodiscard]] std::span<const ParticleId> ids() const;             // length particle_count()

  // Sets an external force [N] and torque [N·m] on each particle of this rank, in the order
  // of positions()/ids() now: forces.size() == 3·particle_count(), torques either empty (no
  // torque) or the same size. The values stay with their particles and are applied on every
  // step of every later run() until set again or cleared. A change acts from the current time
  // on: LIGGGHTS' pending force, which the first half-step of the next run uses, is corrected
  // too. Throws std::invalid_argument for a size mismatch or a non-finite value.
  void set_external_forces(std::span<const double> forces, std::span<const double> torques = {});
  // The same, for the particles named by ids (each owned by this rank, no repeats); the
  // other particles get zero. forces.size() == 3·ids.size().
  void set_external_forces(std::span<const ParticleId> ids, std::span<const double> forces,
                           std::span<const double> torques = {});
  // Zero external force and torque on every particle.
  void clear_external_forces();
  // Installs (or, with an empty function, removes) the per-step force callback (see "Per-step
  // force hook" above). Creates the external-force fixes if needed (the box must exist).
  void set_step_force_callback(StepForceCallback callback);

  // Global output of a LIGGGHTS fix, what an input script calls f_ID and f_ID[index + 1]:
  // e.g. the total force and torque on a mesh (mesh/surface/stress: vector elements 0–2 force,
  // 3–5 torque) or the average of a fix ave/time. The value LIGGGHTS holds now, the same on
  // every rank for reduced quantities. Throws std::invalid_argument if there is no fix fix_id
  // or it has no global scalar / no vector element index.
  [[nodiscard]] double fix_scalar(std::string_view fix_id) const;
  [[nodiscard]] double fix_vector(std::string_view fix_id, int index) const;

  // Failure state (see the header comment).
  [[nodiscard]] bool has_failed() const;
  [[nodiscard]] const std::optional<EngineError>& failure() const;

  // Where LIGGGHTS writes its log.
  [[nodiscard]] const std::filesystem::path& log_path() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rheosim::dem
