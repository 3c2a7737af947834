// The rheometer scene under MPI: `mpirun -np 2 dem_mpi_scene --compare` runs the
// same dry-shear scene on all ranks (MPI_COMM_WORLD) and, on rank 0 alone, on MPI_COMM_SELF,
// and checks that
//   - both hold the same particle count, the per-rank particle arrays partition the particles
//     (local counts sum to the total, every id 1..N exactly once over all ranks), and the
//     placement is the same on every rank;
//   - the steady torque of both runs is statistically equal: the difference of the two means
//     is within 3 combined standard errors (batch means over the averaging window; the runs
//     diverge microscopically because the ranks sum forces in another order, so equality is a
//     statistical statement, not a bitwise one).
// Without --compare it runs the scene once and prints the torque series (for exploring scenes).
//
// Scene (defaults): dry shear of a small disk, R = 1 mm, H = 0.25 mm = 2.5 d (the CD §4 ratio
// H/d), d = 0.1 mm, φ = 0.5 (750 particles, CD §4 material, no gravity), γ̇_R = 16000 1/s (plate
// rim speed 4 m/s), starting from a granular gas at half that speed. The steady state is the
// one of validate_dry_shear.cpp: the sheared particles are flung against the frictionless rim
// and pack there into a dense annulus across the gap, confined by their own centrifugal
// force, which carries a steady torque ∝ Ω²; it is reached after a strain γ = γ̇_R t of about
// 15. The torque is averaged over strains 15–30.
//
// Exit code 0: checks passed (or no --compare); 1: a check failed; 2: bad arguments.
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "rheosim/dem/contact.hpp"
#include "rheosim/dem/mpi_session.hpp"
#include "rheosim/dem/rheometer_scene.hpp"

namespace {

namespace fs = std::filesystem;
using rheosim::dem::RheometerScene;

struct Options {
  double radius = 1e-3;            // R [m]
  double gap = 2.5e-4;             // H [m]
  double diameter = 1e-4;          // d [m]
  double volume_fraction = 0.5;    // φ
  double rate = 16000.0;           // γ̇_R [1/s]
  double transient_strain = 15.0;  // strain before averaging
  double window_strain = 15.0;     // strain averaged over
  int batches = 6;                 // batch means for the standard error
  double initial_speed = -1.0;     // [m/s]; < 0: half the plate's rim speed γ̇_R H
  std::uint64_t seed = 1;
  bool compare = false;
  bool print_series = false;
  fs::path out;  // run folders; default: a temporary folder, removed at the end
};

Options parse(int argc, char** argv) {
  Options o;
  std::map<std::string, std::string> kv;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--compare")
      o.compare = true;
    else if (a == "--print-series")
      o.print_series = true;
    else if (a.rfind("--", 0) == 0 && a.find('=') != std::string::npos)
      kv[a.substr(2, a.find('=') - 2)] = a.substr(a.find('=') + 1);
    else
      throw std::invalid_argument(fmt::format("unknown argument '{}'", a));
  }
  for (const auto& [key, value] : kv) {
    if (key == "radius")
      o.radius = std::stod(value);
    else if (key == "gap")
      o.gap = std::stod(value);
    else if (key == "diameter")
      o.diameter = std::stod(value);
    else if (key == "phi")
      o.volume_fraction = std::stod(value);
    else if (key == "rate")
      o.rate = std::stod(value);
    else if (key == "transient")
      o.transient_strain = std::stod(value);
    else if (key == "window")
      o.window_strain = std::stod(value);
    else if (key == "batches")
      o.batches = std::stoi(value);
    else if (key == "speed")
      o.initial_speed = std::stod(value);
    else if (key == "seed")
      o.seed = std::stoull(value);
    else if (key == "out")
      o.out = value;
    else
      throw std::invalid_argument(fmt::format("unknown option --{}", key));
  }
  if (o.batches < 2) throw std::invalid_argument("--batches must be >= 2");
  return o;
}

struct RunResult {
  std::int64_t total_count = 0;
  bool partition_ok = true;     // local arrays partition ids 1..N
  bool placement_ok = true;     // the same placement on every rank
  double mean = 0.0;            // torque over the window [N·m]
  double standard_error = 0.0;  // from batch means [N·m]
  double wall_seconds = 0.0;
  std::int64_t steps = 0;
  std::vector<rheosim::dem::TorqueSample> series;
};

// Runs the scene on comm (all its ranks call this); the result is the same on every rank.
RunResult run_scene(const Options& o, MPI_Comm comm, const fs::path& dir) {
  int rank = 0;
  int size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  RheometerScene::Params p{
      .geometry = {.radius = o.radius, .gap = o.gap},
      .particles = {.volume_fraction = o.volume_fraction, .diameter = o.diameter, .density = 1000.0},
      .rim_shear_rate = o.rate,
      .gravity = std::nullopt,
      .seed = o.seed,
      .run_directory = dir,
      .initial_speed = o.initial_speed >= 0.0 ? o.initial_speed : 0.5 * o.rate * o.gap,
      .communicator_fortran_handle = MPI_Comm_c2f(comm)};
  // Batches of whole torque samples: the window is batches × per_batch samples.
  const double dt = p.time_step_fraction * rheosim::dem::rayleigh_time({.radius = 0.5 * o.diameter,
                                                                        .density = p.particles.density,
                                                                        .youngs_modulus = p.particles.youngs_modulus,
                                                                        .poisson_ratio = p.particles.poisson_ratio});
  const auto steps_per_strain = static_cast<std::int64_t>(std::ceil(1.0 / (o.rate * dt)));
  p.torque_sample_interval = std::max<std::int64_t>(1, steps_per_strain / 20);
  RheometerScene scene(p);
  const auto transient = static_cast<std::int64_t>(std::ceil(o.transient_strain / (o.rate * dt)));
  const auto window = static_cast<std::int64_t>(std::ceil(o.window_strain / (o.rate * dt)));

  RunResult r;
  r.total_count = scene.total_particle_count();

  // Per-rank arrays: local counts add up to the total and the ids are 1..N, each once.
  const auto ids = scene.engine().ids();
  const auto local = static_cast<long long>(scene.engine().particle_count());
  long long summed = 0;
  MPI_Allreduce(&local, &summed, 1, MPI_LONG_LONG, MPI_SUM, comm);
  std::vector<int> owned(static_cast<std::size_t>(r.total_count), 0);
  for (const int id : ids)
    if (id >= 1 && id <= r.total_count) ++owned[static_cast<std::size_t>(id - 1)];
  MPI_Allreduce(MPI_IN_PLACE, owned.data(), static_cast<int>(owned.size()), MPI_INT, MPI_SUM, comm);
  r.partition_ok = summed == r.total_count && std::all_of(owned.begin(), owned.end(), [](int c) { return c == 1; });
  // The same placement everywhere: compare a checksum of the centres with rank 0's.
  double checksum = 0.0;
  if (const auto& placed = scene.placement())
    for (std::size_t i = 0; i < placed->centres.size(); ++i)
      checksum += placed->centres[i] * static_cast<double>(i % 7 + 1);
  double reference = checksum;
  MPI_Bcast(&reference, 1, MPI_DOUBLE, 0, comm);
  int same = reference == checksum ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &same, 1, MPI_INT, MPI_MIN, comm);
  r.placement_ok = same == 1 && scene.placement().has_value() &&
                   static_cast<std::int64_t>(scene.placement()->count) == r.total_count;

  const auto start = std::chrono::steady_clock::now();
  scene.advance(transient + window);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.steps = transient + window;
  r.series.assign(scene.torque_series().begin(), scene.torque_series().end());

  // Samples inside the window, split into batches.
  std::vector<double> values;
  for (const auto& s : r.series)
    if (s.step > transient) values.push_back(s.torque);
  const std::size_t per_batch = values.size() / static_cast<std::size_t>(o.batches);
  if (per_batch == 0) throw std::runtime_error("too few torque samples in the window");
  std::vector<double> means;
  for (int b = 0; b < o.batches; ++b) {
    double sum = 0.0;
    for (std::size_t k = 0; k < per_batch; ++k) sum += values[static_cast<std::size_t>(b) * per_batch + k];
    means.push_back(sum / static_cast<double>(per_batch));
  }
  double mean = 0.0;
  for (const double m : means) mean += m;
  mean /= static_cast<double>(means.size());
  double var = 0.0;
  for (const double m : means) var += (m - mean) * (m - mean);
  var /= static_cast<double>(means.size() - 1);
  r.mean = mean;
  r.standard_error = std::sqrt(var / static_cast<double>(means.size()));
  (void)size;
  return r;
}

void print_result(const char* label, const RunResult& r) {
  fmt::print("{}: N = {}, torque = {:.4e} ± {:.2e} N·m (1 s.e.), {} steps in {:.1f} s, partition {}, placement {}\n",
             label, r.total_count, r.mean, r.standard_error, r.steps, r.wall_seconds, r.partition_ok ? "ok" : "BAD",
             r.placement_ok ? "same" : "DIFFERENT");
}

int run(int argc, char** argv) {
  const rheosim::dem::MpiSession session;
  int rank = 0;
  int size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  Options o;
  try {
    o = parse(argc, argv);
  } catch (const std::exception& e) {
    if (rank == 0) fmt::print(stderr, "dem_mpi_scene: {}\n", e.what());
    return 2;
  }
  const bool temporary = o.out.empty();
  if (temporary) {
    // One folder for all ranks: rank 0's pid.
    long long pid = ::getpid();
    MPI_Bcast(&pid, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    o.out = fs::temp_directory_path() / fmt::format("rheosim_dem_mpi_scene_{}", pid);
  }

  const RunResult parallel = run_scene(o, MPI_COMM_WORLD, o.out / fmt::format("np{}", size));
  if (rank == 0) {
    print_result(fmt::format("{} rank(s)", size).c_str(), parallel);
    if (o.print_series)
      for (const auto& s : parallel.series)
        fmt::print("  step {:8d}  strain {:7.3f}  torque {:.4e}\n", s.step, s.time * o.rate, s.torque);
  }
  int failed = parallel.partition_ok && parallel.placement_ok ? 0 : 1;

  if (o.compare) {
    if (rank == 0) {
      const RunResult serial = run_scene(o, MPI_COMM_SELF, o.out / "np1");
      print_result("1 rank   ", serial);
      const double difference = parallel.mean - serial.mean;
      const double combined = std::hypot(parallel.standard_error, serial.standard_error);
      const bool counts_equal = parallel.total_count == serial.total_count;
      const bool torques_equal = std::abs(difference) <= 3.0 * combined;
      // A meaningful comparison: a resolved, positive steady torque in both runs.
      const bool resolved = serial.mean > 0.0 && parallel.mean > 0.0 && serial.standard_error < 0.2 * serial.mean &&
                            parallel.standard_error < 0.2 * parallel.mean;
      fmt::print("particle count: {} vs {} -> {}\n", parallel.total_count, serial.total_count,
                 counts_equal ? "equal" : "DIFFERENT");
      fmt::print("torque difference: {:.3e} N·m = {:.2f} combined s.e. ({:.2f} % of the serial mean) -> {}\n",
                 difference, combined > 0.0 ? difference / combined : 0.0, 100.0 * difference / serial.mean,
                 torques_equal ? "statistically equal (within 3 s.e.)" : "DIFFERENT");
      if (!resolved) fmt::print("torque not resolved: a positive mean with s.e. < 20 % is needed\n");
      if (!(counts_equal && torques_equal && resolved && serial.partition_ok)) failed = 1;
      int done = 1;
      MPI_Request request = MPI_REQUEST_NULL;
      MPI_Ibcast(&done, 1, MPI_INT, 0, MPI_COMM_WORLD, &request);  // matches the other ranks' Ibcast
      MPI_Wait(&request, MPI_STATUS_IGNORE);
    } else {
      // Wait for rank 0 without spinning a core (the machine is shared).
      int done = 0;
      MPI_Request request = MPI_REQUEST_NULL;
      MPI_Ibcast(&done, 1, MPI_INT, 0, MPI_COMM_WORLD, &request);
      int flag = 0;
      while (MPI_Test(&request, &flag, MPI_STATUS_IGNORE) == MPI_SUCCESS && flag == 0)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (temporary && rank == 0 && failed == 0) fs::remove_all(o.out);  // a failed run keeps its folder
  if (rank == 0) fmt::print("{}\n", failed != 0 ? "FAILED" : "PASSED");
  return failed;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    fmt::print(stderr, "dem_mpi_scene: {}\n", e.what());
    rheosim::dem::MpiSession::abort_all(1);
  }
}
