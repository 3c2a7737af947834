#pragma once
// Turns LIGGGHTS' fatal errors into C++ exceptions (private to dem/).
//
// How LIGGGHTS 3.8 stops on an error: every check calls a member of LAMMPS_NS::Error
// (error.h): all() when every rank found the problem, one() when a single rank did, plus
// fix_error(), compute_error(), universe_all(), universe_one() and done() (the `quit`
// command). Each prints "ERROR: ..." and then ends the process with exit(1), MPI_Finalize
// or MPI_Abort. There is no exception mode in this version. (Error::cg is left alone: it only
// warns or calls all(), through the PLT like every other call.)
//
// Mechanism: liggghts_error_hook.cpp defines those members itself. libliggghts.so is not
// linked with -Bsymbolic (no DT_SYMBOLIC / FLAGS SYMBOLIC in `readelf -d`), and all of its
// ~5400 internal calls to them go through the PLT (checked with objdump: no direct calls), so
// the dynamic linker binds them to the first definition in the global search order: ours, in
// the executable or in a library loaded before libliggghts.so. Our definitions write
// "ERROR: ..." to LIGGGHTS' log (rank 0, flushed) and throw LiggghtsFailure instead of ending
// the process. Engine catches it at the lammps_open / lammps_command boundary.
//
// is_error_hook_active() checks at run time that the interposition really happened (the
// definition the dynamic linker resolves is in the same object as this file), so a link that
// loses it (e.g. libliggghts linked ahead of rheosim_dem into a shared object) fails loudly
// at Engine construction instead of exiting on the first LIGGGHTS error.
//
// Consequences, documented on Engine: the exception leaves LIGGGHTS' state half-updated
// (whatever the failing command had done so far), so the instance is unusable afterwards.
#include <stdexcept>
#include <string>

namespace rheosim::dem::detail {

// Thrown from inside LIGGGHTS in place of its error exit.
class LiggghtsFailure : public std::runtime_error {
 public:
  LiggghtsFailure(std::string message, std::string source_file, int source_line, bool collective);
  [[nodiscard]] const std::string& message() const { return message_; }
  // LIGGGHTS source file and line that raised it (e.g. "../modify.cpp", 688).
  [[nodiscard]] const std::string& source_file() const { return source_file_; }
  [[nodiscard]] int source_line() const { return source_line_; }
  // True for Error::all-like errors (raised on every rank of the communicator), false for
  // Error::one-like errors (this rank only).
  [[nodiscard]] bool is_collective() const { return collective_; }

 private:
  std::string message_;
  std::string source_file_;
  int source_line_ = 0;
  bool collective_ = true;
};

// True if LIGGGHTS' calls to LAMMPS_NS::Error::all resolve to our definition.
[[nodiscard]] bool is_error_hook_active();

}  // namespace rheosim::dem::detail
