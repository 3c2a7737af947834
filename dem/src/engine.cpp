// dem::Engine on LIGGGHTS 3.8 (see engine.hpp for the design). Besides the C library
// interface (library.h) this file reads a few public members of LIGGGHTS' classes (LAMMPS,
// Atom, Update, Modify, Fix, FixExternal) through the installed headers, which have no
// configuration #ifdefs inside those classes, so their layout is the library's.
#include "rheosim/dem/engine.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "liggghts_error_hook.hpp"
#include "rheosim/dem/mpi_session.hpp"

// LIGGGHTS, private to dem/.
#include <atom.h>
#include <fix.h>
#include <fix_external.h>
#include <lammps.h>
#include <library.h>
#include <modify.h>
#include <universe.h>
#include <update.h>

namespace rheosim::dem {

static_assert(std::is_same_v<ParticleId, LAMMPS_NS::tagint>, "ParticleId must be LIGGGHTS' tagint");

namespace {

namespace fs = std::filesystem;

// Our fixes (see engine.hpp, "External force and torque").
constexpr const char* external_fix_id = "rheosim_external";
constexpr const char* store_fix_id = "rheosim_external_store";
// fx fy fz tx ty tz per particle, not written to restart files, not sent to ghosts.
constexpr const char* store_fix_command =
    "fix rheosim_external_store all property/atom rheosimExternalLoad vector no no no 0 0 0 0 0 0";
constexpr const char* external_fix_command = "fix rheosim_external all external pf/callback 1 1";
constexpr std::size_t store_width = 6;
constexpr const char* null_device = "/dev/null";

void check_params(const Engine::Params& p) {
  if (p.run_directory.empty())
    throw std::invalid_argument("Engine::Params::run_directory is empty, expected the folder for LIGGGHTS' output");
  const fs::path log(p.log_file_name);
  if (p.log_file_name.empty() || log.filename() != log || p.log_file_name == "." || p.log_file_name == "..")
    throw std::invalid_argument(
        fmt::format("Engine::Params::log_file_name = '{}', expected a plain file name (it is placed in run_directory)",
                    p.log_file_name));
}

void check_finite(std::span<const double> values, std::string_view name) {
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw std::invalid_argument(fmt::format("{}[{}] = {} is not finite", name, i, values[i]));
}

// Every LIGGGHTS instance after the first re-registers its granular contact styles in a
// process-wide table and reports each duplicate on std::cerr ("WARNING! Style collision
// detected!", utils.h), about 30 lines; the entries are identical, so this is harmless. The
// text is caught while the instance opens and written to its log instead of the terminal.
// (std::cerr is shared with libliggghts through libstdc++; Engines are used from one thread.)
class CerrRedirect {
 public:
  explicit CerrRedirect(std::ostringstream& sink) : previous_(std::cerr.rdbuf(sink.rdbuf())) {}
  ~CerrRedirect() { std::cerr.rdbuf(previous_); }
  CerrRedirect(const CerrRedirect&) = delete;
  CerrRedirect& operator=(const CerrRedirect&) = delete;

 private:
  std::streambuf* previous_;
};

std::string describe_source(const detail::LiggghtsFailure& failure) {
  if (failure.source_file().empty()) return {};
  return fmt::format("{}:{}", fs::path(failure.source_file()).filename().string(), failure.source_line());
}

}  // namespace

EngineError::EngineError(std::string message, Details details, std::source_location origin)
    : core::RunError(message, origin), details_(std::move(details)) {}

class Engine::Impl {
 public:
  explicit Impl(Params params);
  ~Impl();
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  void execute(std::string_view line);
  void set_equal_variable(std::string_view name, double value);
  void run(std::int64_t steps);

  [[nodiscard]] int local_count(const char* caller) const;
  [[nodiscard]] std::span<const double> vectors(const char* name, const char* caller) const;
  [[nodiscard]] std::span<const double> scalars(const char* name, const char* caller) const;
  [[nodiscard]] std::span<const ParticleId> tags(const char* caller) const;
  [[nodiscard]] std::int64_t total_count(const char* caller) const;
  [[nodiscard]] std::int64_t step(const char* caller) const;
  [[nodiscard]] double time_step(const char* caller) const;
  [[nodiscard]] double time(const char* caller) const;

  [[nodiscard]] double fix_output(std::string_view fix_id, int index);  // index < 0: scalar

  void store_external(std::span<const double> load);  // store_width values per local particle
  void clear_external(const char* caller);
  void set_step_callback(StepForceCallback callback);

  // Throws EngineError if the instance failed earlier; function(argument) names the call.
  void require_usable(std::string_view function, std::string_view argument = {}) const;

  std::optional<EngineError> failure;
  fs::path log_path;

 private:
  // Runs f (which calls into LIGGGHTS); a LIGGGHTS error turns into EngineError and the
  // instance into a failed one.
  template <class F>
  void guarded(std::string_view command, F&& f);
  [[noreturn]] void fail(std::string_view command, std::string message, std::string source, bool collective);
  void abandon();
  void ensure_external_fixes();
  [[nodiscard]] LAMMPS_NS::Fix* store_fix() const;
  void replace_stored(std::span<const double> load);  // store_width values per local particle
  static void apply_external(void* self, LAMMPS_NS::bigint step, int nlocal, int* tags, double** x, double** fexternal);

  void call_step_callback(LAMMPS_NS::bigint step, int nlocal, double** load, double** fexternal);

  Params params_;
  StepForceCallback step_callback_;
  // Scratch for the step callback (reused every step).
  std::vector<double> known_forces_, known_torques_, callback_forces_, callback_torques_;
  MPI_Comm comm_ = MPI_COMM_NULL;
  LAMMPS_NS::LAMMPS* lmp_ = nullptr;
  bool setup_needed_ = true;
};

Engine::Impl::Impl(Params params) : params_(std::move(params)) {
  check_params(params_);
  MpiSession::ensure();
  comm_ = params_.communicator_fortran_handle ? MPI_Comm_f2c(*params_.communicator_fortran_handle) : MPI_COMM_WORLD;
  if (comm_ == MPI_COMM_NULL)
    throw std::invalid_argument("Engine::Params::communicator_fortran_handle names MPI_COMM_NULL");
  if (!detail::is_error_hook_active())
    throw core::RunError(
        "LIGGGHTS' error exits are not intercepted in this binary: the dynamic linker resolves "
        "LAMMPS_NS::Error::all to libliggghts, not to rheosim_dem. Link rheosim_dem ahead of "
        "libliggghts (and do not link libliggghts with -Bsymbolic).");

  std::error_code ec;
  fs::create_directories(params_.run_directory, ec);
  if (!fs::is_directory(params_.run_directory))
    throw core::RunError(fmt::format("cannot create the DEM run directory '{}': {}", params_.run_directory.string(),
                                     ec ? ec.message() : "not a directory"));
  log_path = params_.run_directory / params_.log_file_name;

  // The screen goes to the null device rather than `-screen none`: LIGGGHTS writes to its
  // screen without checking for "none" in places (e.g. InputMeshTri::meshtrifile, reached by
  // every fix mesh/surface with an STL file), which would dereference a null FILE*.
  std::vector<std::string> args{
      "liggghts", "-screen", null_device, "-log", log_path.string(), "-echo", params_.echo_commands ? "log" : "none",
      "-nocite"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::string command = "lammps_open";
  for (std::size_t i = 1; i < args.size(); ++i) command += " " + args[i];

  void* handle = nullptr;
  std::ostringstream cerr_text;
  try {
    const CerrRedirect redirect(cerr_text);
    lammps_open(static_cast<int>(args.size()), argv.data(), comm_, &handle);
  } catch (const detail::LiggghtsFailure& e) {
    // The half-built instance is unreachable; nothing to abandon.
    throw EngineError(fmt::format("LIGGGHTS could not start ({}): {}", command, e.message()),
                      {.command = command,
                       .liggghts_message = e.message(),
                       .liggghts_source = describe_source(e),
                       .collective = e.is_collective()});
  }
  lmp_ = static_cast<LAMMPS_NS::LAMMPS*>(handle);
  if (const std::string text = cerr_text.str(); !text.empty() && lmp_->logfile != nullptr) {
    std::fprintf(lmp_->logfile, "rheosim: LIGGGHTS wrote this to std::cerr while opening:\n%s", text.c_str());
    std::fflush(lmp_->logfile);
  }
}

Engine::Impl::~Impl() {
  if (lmp_ == nullptr) return;  // never opened, or abandoned after a failure
  try {
    lammps_close(lmp_);
  } catch (...) {
    // A LIGGGHTS error while closing a healthy instance: nothing sensible is left to do.
  }
}

void Engine::Impl::require_usable(std::string_view function, std::string_view argument) const {
  if (!failure) return;
  const auto& first = failure->details();
  throw EngineError(fmt::format("dem::Engine::{}({}): the LIGGGHTS instance failed earlier on command '{}' ({}) and is "
                                "unusable; open a new Engine",
                                function, argument, first.command, first.liggghts_message),
                    first);
}

template <class F>
void Engine::Impl::guarded(std::string_view command, F&& f) {
  try {
    std::forward<F>(f)();
  } catch (const detail::LiggghtsFailure& e) {
    fail(command, e.message(), describe_source(e), e.is_collective());
  } catch (const std::exception& e) {
    fail(command, fmt::format("C++ exception inside LIGGGHTS: {}", e.what()), {}, false);
  } catch (...) {
    fail(command, "unknown C++ exception inside LIGGGHTS", {}, false);
  }
}

void Engine::Impl::fail(std::string_view command, std::string message, std::string source, bool collective) {
  EngineError error(fmt::format("LIGGGHTS error in command '{}': {}{}. The LIGGGHTS instance is unusable now.", command,
                                message, source.empty() ? std::string() : " (" + source + ")"),
                    {.command = std::string(command),
                     .liggghts_message = message,
                     .liggghts_source = source,
                     .collective = collective});
  failure = error;
  abandon();
  throw error;
}

// Leaves the instance allocated (see engine.hpp) but closes its output files.
void Engine::Impl::abandon() {
  if (lmp_ == nullptr) return;
  std::FILE* log = lmp_->logfile;
  std::FILE* screen = lmp_->screen;
  if (log != nullptr) {
    std::fprintf(log, "rheosim: LIGGGHTS instance abandoned after the error above\n");
    std::fclose(log);
  }
  if (screen != nullptr && screen != stdout && screen != stderr && screen != log) std::fclose(screen);
  lmp_->logfile = nullptr;
  lmp_->screen = nullptr;
  if (lmp_->universe != nullptr) {
    if (lmp_->universe->ulogfile == log) lmp_->universe->ulogfile = nullptr;
    if (lmp_->universe->uscreen == screen) lmp_->universe->uscreen = nullptr;
  }
  lmp_ = nullptr;
}

void Engine::Impl::execute(std::string_view line) {
  require_usable("command", line);
  if (line.find_first_of("\r\n") != std::string_view::npos)
    throw std::invalid_argument(fmt::format("dem::Engine::command takes one line, got '{}'; use commands()", line));
  const std::string text(line);
  setup_needed_ = true;
  guarded(text, [&] { lammps_command(lmp_, text.c_str()); });
}

void Engine::Impl::set_equal_variable(std::string_view name, double value) {
  const bool valid_name = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
  if (!valid_name)
    throw std::invalid_argument(
        fmt::format("set_equal_variable: name = '{}', expected letters, digits and underscores only", name));
  if (!std::isfinite(value))
    throw std::invalid_argument(fmt::format("set_equal_variable: {} = {} is not finite", name, value));
  const bool setup_was_needed = setup_needed_;
  execute(fmt::format("variable {} equal {:.17g}", name, value));
  setup_needed_ = setup_was_needed;  // a new constant needs no setup of the run
}

void Engine::Impl::run(std::int64_t steps) {
  if (steps < 0 || steps > std::numeric_limits<int>::max())
    throw std::invalid_argument(
        fmt::format("run: steps = {}, expected 0 <= steps <= {}", steps, std::numeric_limits<int>::max()));
  require_usable("run", std::to_string(steps));
  const std::string text = setup_needed_ ? fmt::format("run {}", steps) : fmt::format("run {} pre no post no", steps);
  guarded(text, [&] { lammps_command(lmp_, text.c_str()); });
  setup_needed_ = false;
}

int Engine::Impl::local_count(const char* caller) const {
  require_usable(caller);
  return lmp_->atom->nlocal;
}

std::span<const double> Engine::Impl::vectors(const char* name, const char* caller) const {
  const auto n = static_cast<std::size_t>(local_count(caller));
  if (n == 0) return {};
  auto* array = static_cast<double**>(lammps_extract_atom(lmp_, name));
  if (array == nullptr || array[0] == nullptr)
    throw core::RunError(
        fmt::format("dem::Engine::{}: LIGGGHTS has no per-particle '{}' (atom_style granular needed)", caller, name));
  return {array[0], 3 * n};
}

std::span<const double> Engine::Impl::scalars(const char* name, const char* caller) const {
  const auto n = static_cast<std::size_t>(local_count(caller));
  if (n == 0) return {};
  auto* array = static_cast<double*>(lammps_extract_atom(lmp_, name));
  if (array == nullptr)
    throw core::RunError(
        fmt::format("dem::Engine::{}: LIGGGHTS has no per-particle '{}' (atom_style granular needed)", caller, name));
  return {array, n};
}

std::span<const ParticleId> Engine::Impl::tags(const char* caller) const {
  const auto n = static_cast<std::size_t>(local_count(caller));
  if (n == 0) return {};
  auto* array = static_cast<ParticleId*>(lammps_extract_atom(lmp_, "id"));
  if (array == nullptr) throw core::RunError(fmt::format("dem::Engine::{}: LIGGGHTS has no particle ids", caller));
  return {array, n};
}

std::int64_t Engine::Impl::total_count(const char* caller) const {
  require_usable(caller);
  return lmp_->atom->natoms;
}

std::int64_t Engine::Impl::step(const char* caller) const {
  require_usable(caller);
  return lmp_->update->ntimestep;
}

double Engine::Impl::time_step(const char* caller) const {
  require_usable(caller);
  return lmp_->update->dt;
}

double Engine::Impl::time(const char* caller) const {
  require_usable(caller);
  return lmp_->update->get_cur_time();
}

double Engine::Impl::fix_output(std::string_view fix_id, int index) {
  const bool scalar = index < 0;
  const std::string what = scalar ? fmt::format("f_{}", fix_id) : fmt::format("f_{}[{}]", fix_id, index + 1);
  require_usable(scalar ? "fix_scalar" : "fix_vector", what);
  const std::string id(fix_id);
  LAMMPS_NS::Fix* fix = lmp_->modify->find_fix_id(id.c_str());
  if (fix == nullptr) throw std::invalid_argument(fmt::format("{}: there is no LIGGGHTS fix '{}'", what, fix_id));
  if (scalar && fix->scalar_flag == 0)
    throw std::invalid_argument(fmt::format("{}: fix '{}' ({}) has no global scalar", what, fix_id, fix->style));
  if (!scalar && (fix->vector_flag == 0 || index >= fix->size_vector))
    throw std::invalid_argument(fmt::format("{}: fix '{}' ({}) has no global vector element {} (size {})", what, fix_id,
                                            fix->style, index, fix->vector_flag != 0 ? fix->size_vector : 0));
  double value = 0.0;
  guarded(what, [&] { value = scalar ? fix->compute_scalar() : fix->compute_vector(index); });
  return value;
}

LAMMPS_NS::Fix* Engine::Impl::store_fix() const {
  return lmp_->modify->find_fix_id_style(store_fix_id, "property/atom");
}

// Creates our two fixes unless they exist (a `clear` removes them), and (re)attaches the
// callback.
void Engine::Impl::ensure_external_fixes() {
  if (lmp_->modify->find_fix_id(store_fix_id) == nullptr) {
    execute(store_fix_command);
    // The constructor already set every particle to the defaults (0). Without this, LIGGGHTS
    // would set them to the defaults once more in the setup of the next run
    // (Modify::setup, for fixes still marked just_created), wiping values stored before it.
    if (LAMMPS_NS::Fix* store = store_fix(); store != nullptr) store->just_created = 0;
  }
  if (lmp_->modify->find_fix_id(external_fix_id) == nullptr) execute(external_fix_command);
  auto* external = lmp_->modify->find_fix_id_style(external_fix_id, "external");
  if (external == nullptr || store_fix() == nullptr)
    throw core::RunError(
        fmt::format("dem::Engine: fix ids '{}' and '{}' are reserved for external forces but are "
                    "used by fixes of another style",
                    external_fix_id, store_fix_id));
  static_cast<LAMMPS_NS::FixExternal*>(external)->set_callback(&Impl::apply_external, this);
}

void Engine::Impl::store_external(std::span<const double> load) {
  ensure_external_fixes();
  replace_stored(load);
}

void Engine::Impl::clear_external(const char* caller) {
  const auto n = static_cast<std::size_t>(local_count(caller));
  if (store_fix() == nullptr) return;
  const std::vector<double> zero(store_width * n, 0.0);
  replace_stored(zero);
}

// Writes the new values and corrects LIGGGHTS' pending force and torque (computed at the end
// of the last step with the old values) by new − old. Velocity Verlet's first half-kick of the
// next run uses that pending force when the run skips setup (pre no), so without the
// correction a change would act half a step late. A run with setup recomputes it anyway.
void Engine::Impl::replace_stored(std::span<const double> load) {
  double** store = store_fix()->array_atom;
  double** force = lmp_->atom->f;
  double** torque = lmp_->atom->torque;
  const std::size_t n = load.size() / store_width;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < store_width; ++k) {
      const double change = load[store_width * i + k] - store[i][k];
      if (k < 3 && force != nullptr) force[i][k] += change;
      if (k >= 3 && torque != nullptr) torque[i][k - 3] += change;
      store[i][k] = load[store_width * i + k];
    }
  }
}

// fix external's callback, in post_force of every step (and in the setup of each run):
// force into fexternal (which the fix adds to f), torque straight into atom->torque.
void Engine::Impl::apply_external(void* self, LAMMPS_NS::bigint step, int nlocal, int* /*tags*/, double** /*x*/,
                                  double** fexternal) {
  auto* impl = static_cast<Impl*>(self);
  LAMMPS_NS::Fix* store = impl->store_fix();
  double** load = store != nullptr ? store->array_atom : nullptr;
  double** torque = impl->lmp_->atom->torque;
  for (int i = 0; i < nlocal; ++i) {
    for (int k = 0; k < 3; ++k) fexternal[i][k] = load != nullptr ? load[i][k] : 0.0;
    if (load != nullptr && torque != nullptr)
      for (int k = 0; k < 3; ++k) torque[i][k] += load[i][3 + k];
  }
  if (impl->step_callback_) impl->call_step_callback(step, nlocal, load, fexternal);
}

// Hands the current arrays to the step callback and adds what it returns. The torque array
// already holds the stored external torque (added above); the force array f does not hold
// fexternal yet (fix external adds it after this callback), so the known force is f + load.
void Engine::Impl::call_step_callback(LAMMPS_NS::bigint step, int nlocal, double** load, double** fexternal) {
  LAMMPS_NS::Atom* atom = lmp_->atom;
  const auto n = static_cast<std::size_t>(nlocal);
  if (atom->omega == nullptr || atom->radius == nullptr || atom->rmass == nullptr || atom->torque == nullptr)
    throw core::RunError("dem::Engine step force callback: needs atom_style granular (omega, radius, rmass, torque)");
  known_forces_.assign(3 * n, 0.0);
  known_torques_.assign(3 * n, 0.0);
  callback_forces_.assign(3 * n, 0.0);
  callback_torques_.assign(3 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      known_forces_[3 * i + k] = atom->f[i][k] + (load != nullptr ? load[i][k] : 0.0);
      known_torques_[3 * i + k] = atom->torque[i][k];
    }
  const auto view3 = [n](double** array) {
    return n == 0 ? std::span<const double>() : std::span<const double>(array[0], 3 * n);
  };
  const StepState state{.step = step,
                        .time = lmp_->update->get_cur_time(),
                        .time_step = lmp_->update->dt,
                        .positions = view3(atom->x),
                        .velocities = view3(atom->v),
                        .angular_velocities = view3(atom->omega),
                        .radii = std::span<const double>(atom->radius, n),
                        .masses = std::span<const double>(atom->rmass, n),
                        .ids = std::span<const ParticleId>(atom->tag, n),
                        .forces = known_forces_,
                        .torques = known_torques_};
  step_callback_(state, callback_forces_, callback_torques_);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      fexternal[i][k] += callback_forces_[3 * i + k];
      atom->torque[i][k] += callback_torques_[3 * i + k];
    }
}

void Engine::Impl::set_step_callback(StepForceCallback callback) {
  require_usable("set_step_force_callback");
  if (callback) ensure_external_fixes();
  step_callback_ = std::move(callback);
}

// ---------------------------------------------------------------------------------------------

Engine::Engine(Params params) : impl_(std::make_unique<Impl>(std::move(params))) {}
Engine::~Engine() = default;

void Engine::command(std::string_view line) { impl_->execute(line); }

void Engine::set_equal_variable(std::string_view name, double value) { impl_->set_equal_variable(name, value); }

void Engine::commands(std::initializer_list<std::string_view> lines) {
  for (const auto line : lines) impl_->execute(line);
}

void Engine::commands(std::span<const std::string> lines) {
  for (const auto& line : lines) impl_->execute(line);
}

void Engine::run(std::int64_t steps) { impl_->run(steps); }

std::size_t Engine::particle_count() const { return static_cast<std::size_t>(impl_->local_count("particle_count")); }
std::int64_t Engine::total_particle_count() const { return impl_->total_count("total_particle_count"); }
std::int64_t Engine::step() const { return impl_->step("step"); }
double Engine::time_step() const { return impl_->time_step("time_step"); }
double Engine::time() const { return impl_->time("time"); }

std::span<const double> Engine::positions() const { return impl_->vectors("x", "positions"); }
std::span<const double> Engine::velocities() const { return impl_->vectors("v", "velocities"); }
std::span<const double> Engine::angular_velocities() const { return impl_->vectors("omega", "angular_velocities"); }
std::span<const double> Engine::radii() const { return impl_->scalars("radius", "radii"); }
std::span<const ParticleId> Engine::ids() const { return impl_->tags("ids"); }

void Engine::set_external_forces(std::span<const double> forces, std::span<const double> torques) {
  const std::size_t n = particle_count();
  if (forces.size() != 3 * n)
    throw std::invalid_argument(fmt::format("set_external_forces: forces.size() = {}, expected 3 · {} particles = {}",
                                            forces.size(), n, 3 * n));
  if (!torques.empty() && torques.size() != 3 * n)
    throw std::invalid_argument(
        fmt::format("set_external_forces: torques.size() = {}, expected 0 (no torque) or 3 · {} particles = {}",
                    torques.size(), n, 3 * n));
  check_finite(forces, "forces");
  check_finite(torques, "torques");
  std::vector<double> load(store_width * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      load[store_width * i + k] = forces[3 * i + k];
      if (!torques.empty()) load[store_width * i + 3 + k] = torques[3 * i + k];
    }
  impl_->store_external(load);
}

void Engine::set_external_forces(std::span<const ParticleId> particle_ids, std::span<const double> forces,
                                 std::span<const double> torques) {
  const std::size_t m = particle_ids.size();
  if (forces.size() != 3 * m)
    throw std::invalid_argument(
        fmt::format("set_external_forces: forces.size() = {}, expected 3 · {} ids = {}", forces.size(), m, 3 * m));
  if (!torques.empty() && torques.size() != 3 * m)
    throw std::invalid_argument(
        fmt::format("set_external_forces: torques.size() = {}, expected 0 (no torque) or 3 · {} ids = {}",
                    torques.size(), m, 3 * m));
  check_finite(forces, "forces");
  check_finite(torques, "torques");
  const auto local_ids = ids();
  std::unordered_map<ParticleId, std::size_t> local_index;
  local_index.reserve(local_ids.size());
  for (std::size_t i = 0; i < local_ids.size(); ++i) local_index.emplace(local_ids[i], i);
  std::vector<double> load(store_width * local_ids.size(), 0.0);
  std::vector<bool> seen(local_ids.size(), false);
  for (std::size_t j = 0; j < m; ++j) {
    const auto it = local_index.find(particle_ids[j]);
    if (it == local_index.end())
      throw std::invalid_argument(
          fmt::format("set_external_forces: particle id {} is not a particle of this rank", particle_ids[j]));
    const std::size_t i = it->second;
    if (seen[i])
      throw std::invalid_argument(fmt::format("set_external_forces: particle id {} is given twice", particle_ids[j]));
    seen[i] = true;
    for (std::size_t k = 0; k < 3; ++k) {
      load[store_width * i + k] = forces[3 * j + k];
      if (!torques.empty()) load[store_width * i + 3 + k] = torques[3 * j + k];
    }
  }
  impl_->store_external(load);
}

double Engine::fix_scalar(std::string_view fix_id) const { return impl_->fix_output(fix_id, -1); }

double Engine::fix_vector(std::string_view fix_id, int index) const {
  if (index < 0) throw std::invalid_argument(fmt::format("fix_vector: index = {}, expected >= 0", index));
  return impl_->fix_output(fix_id, index);
}

void Engine::clear_external_forces() { impl_->clear_external("clear_external_forces"); }

void Engine::set_step_force_callback(StepForceCallback callback) { impl_->set_step_callback(std::move(callback)); }

bool Engine::has_failed() const { return impl_->failure.has_value(); }
const std::optional<EngineError>& Engine::failure() const { return impl_->failure; }
const std::filesystem::path& Engine::log_path() const { return impl_->log_path; }

}  // namespace rheosim::dem
