// Definitions of LIGGGHTS' terminating LAMMPS_NS::Error members that throw instead of
// exiting; see liggghts_error_hook.hpp for why this works and how it is checked.
#include "liggghts_error_hook.hpp"

#include <dlfcn.h>
#include <mpi.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

// LIGGGHTS headers, private to dem/.
#include <compute.h>
#include <error.h>
#include <fix.h>
#include <universe.h>

namespace rheosim::dem::detail {

LiggghtsFailure::LiggghtsFailure(std::string message, std::string source_file, int source_line, bool collective)
    : std::runtime_error(message),
      message_(std::move(message)),
      source_file_(std::move(source_file)),
      source_line_(source_line),
      collective_(collective) {}

namespace {

// Any object in this file: its address tells dladdr which loaded object holds our code.
const int marker_in_this_object = 0;

// Itanium-mangled names of the members defined below (the ones LIGGGHTS calls most).
constexpr const char* hooked_symbols[] = {
    "_ZN9LAMMPS_NS5Error3allEPKciS2_",                    // Error::all
    "_ZN9LAMMPS_NS5Error3oneEPKciS2_",                    // Error::one
    "_ZN9LAMMPS_NS5Error9fix_errorEPKciPNS_3FixES2_S2_",  // Error::fix_error (5 args)
};

std::string or_empty(const char* text) { return text != nullptr ? std::string(text) : std::string(); }

// "ERROR: <message> (<file>:<line>)" into LIGGGHTS' screen and log, flushed, so the log
// shows why the run stopped even though the process goes on.
void record(std::FILE* screen, std::FILE* logfile, const std::string& prefix, const std::string& message,
            const char* file, int line) {
  for (std::FILE* out : {screen, logfile}) {
    if (out == nullptr) continue;
    std::fprintf(out, "%s%s (%s:%d)\n", prefix.c_str(), message.c_str(), file != nullptr ? file : "?", line);
    std::fflush(out);
  }
}

bool is_rank0(MPI_Comm comm) {
  int me = 0;
  MPI_Comm_rank(comm, &me);
  return me == 0;
}

}  // namespace

bool is_error_hook_active() {
  Dl_info own{};
  if (dladdr(&marker_in_this_object, &own) == 0) return false;
  for (const char* symbol : hooked_symbols) {
    void* resolved = dlsym(RTLD_DEFAULT, symbol);
    Dl_info where{};
    if (resolved == nullptr || dladdr(resolved, &where) == 0 || where.dli_fbase != own.dli_fbase) return false;
  }
  return true;
}

}  // namespace rheosim::dem::detail

namespace LAMMPS_NS {

using rheosim::dem::detail::LiggghtsFailure;
using rheosim::dem::detail::or_empty;
using rheosim::dem::detail::record;

// Called by every rank of the world: all ranks throw together, rank 0 writes the message.
void Error::all(const char* file, int line, const char* str) {
  const std::string message = or_empty(str);
  if (rheosim::dem::detail::is_rank0(world)) record(screen, logfile, "ERROR: ", message, file, line);
  throw LiggghtsFailure(message, or_empty(file), line, true);
}

// Called by a single rank: only that rank throws. Under mpirun -np > 1 the other ranks may be
// left waiting in a collective call; the caller must then end the job (MpiSession::abort_all).
void Error::one(const char* file, int line, const char* str) {
  const std::string message = or_empty(str);
  record(screen, logfile, "ERROR on this rank: ", message, file, line);
  throw LiggghtsFailure(message, or_empty(file), line, false);
}

void Error::universe_all(const char* file, int line, const char* str) {
  const std::string message = or_empty(str);
  if (universe != nullptr && universe->me == 0)
    record(universe->uscreen, universe->ulogfile, "ERROR: ", message, file, line);
  throw LiggghtsFailure(message, or_empty(file), line, true);
}

void Error::universe_one(const char* file, int line, const char* str) {
  const std::string message = or_empty(str);
  if (universe != nullptr) record(universe->uscreen, nullptr, "ERROR on this rank: ", message, file, line);
  throw LiggghtsFailure(message, or_empty(file), line, false);
}

void Error::fix_error(const char* file, int line, Fix* fix, const char* str) {
  fix_error(file, line, fix, fix != nullptr ? fix->style : nullptr, str);
}

void Error::fix_error(const char* file, int line, Fix* fix, const char* fixstylestr, const char* str) {
  // LIGGGHTS passes a short placeholder (e.g. "") for a plain syntax error.
  const std::string style = or_empty(fixstylestr);
  const std::string id = fix != nullptr ? or_empty(fix->id) : std::string();
  const std::string detail = or_empty(str);
  const std::string message = detail.size() > 2 ? "Fix " + style + " (id " + id + "): " + detail
                                                : "Illegal fix " + style + " (id " + id + ") command";
  if (rheosim::dem::detail::is_rank0(world)) record(screen, logfile, "ERROR: ", message, file, line);
  throw LiggghtsFailure(message, or_empty(file), line, true);
}

void Error::compute_error(const char* file, int line, Compute* compute, const char* str) {
  const std::string style = compute != nullptr ? or_empty(compute->style) : std::string();
  const std::string id = compute != nullptr ? or_empty(compute->id) : std::string();
  const std::string detail = or_empty(str);
  const std::string message = detail.size() > 2 ? "Compute " + style + " (id " + id + "): " + detail
                                                : "Illegal compute " + style + " (id " + id + ") command";
  if (rheosim::dem::detail::is_rank0(world)) record(screen, logfile, "ERROR: ", message, file, line);
  throw LiggghtsFailure(message, or_empty(file), line, true);
}

// `quit` (and LIGGGHTS' own -help/-restart shortcuts): shut down without an error message.
void Error::done() { throw LiggghtsFailure("LIGGGHTS was asked to shut down (quit)", std::string(), 0, true); }

}  // namespace LAMMPS_NS
