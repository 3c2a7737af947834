#pragma once
// MPI for the whole process, without mpi.h in public headers.
//
// LIGGGHTS needs MPI to be initialised before an instance is opened, and MPI can be
// initialised and finalised only once per process. So:
//   - an application that runs under `mpirun` creates one MpiSession at the top of main();
//     it initialises MPI (unless someone already did) and finalises it when main() returns;
//   - dem::Engine calls MpiSession::ensure(): if MPI is not running yet, it starts a
//     process-wide session that finalises MPI at process exit. Engines can therefore be
//     opened and closed any number of times in one process (tests do).
// A session finalises MPI only if it initialised it, and never after MPI_Finalize was
// already called by someone else.
//
// Threads: MPI is initialised with MPI_THREAD_FUNNELED (only the main thread calls MPI; other
// modules may run OpenMP regions in between).
namespace rheosim::dem {

class MpiSession {
 public:
  // Initialises MPI unless it is already initialised. Throws core::RunError if MPI was
  // already finalised (it cannot be restarted) or MPI_Init fails.
  MpiSession();
  // Finalises MPI if this session initialised it and MPI is still running.
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  // True if this object called MPI_Init (and will call MPI_Finalize).
  [[nodiscard]] bool owns_mpi() const { return owns_mpi_; }

  // Makes sure MPI is running: if it is not initialised yet, starts a process-wide session
  // (finalised at process exit). Throws core::RunError if MPI was already finalised.
  static void ensure();
  // MPI initialised and not yet finalised.
  [[nodiscard]] static bool is_running();
  // Rank in and size of MPI_COMM_WORLD; MPI must be running.
  [[nodiscard]] static int world_rank();
  [[nodiscard]] static int world_size();
  // Ends every rank with exit_code (MPI_Abort on MPI_COMM_WORLD). For a rank-local failure
  // under `mpirun -np N`, N > 1, after which the other ranks could wait forever.
  [[noreturn]] static void abort_all(int exit_code);

 private:
  bool owns_mpi_ = false;
};

}  // namespace rheosim::dem
