#include "rheosim/dem/mpi_session.hpp"

#include <mpi.h>

#include <cstdlib>

#include <fmt/format.h>

#include "rheosim/core/error.hpp"

namespace rheosim::dem {
namespace {

bool is_initialized() {
  int flag = 0;
  MPI_Initialized(&flag);
  return flag != 0;
}

bool is_finalized() {
  int flag = 0;
  MPI_Finalized(&flag);
  return flag != 0;
}

void require_running(const char* what) {
  if (!MpiSession::is_running())
    throw core::RunError(fmt::format("{}: MPI is not running (create an MpiSession first)", what));
}

}  // namespace

MpiSession::MpiSession() {
  if (is_finalized()) throw core::RunError("MPI was already finalised in this process and cannot be started again");
  if (is_initialized()) return;
  int provided = 0;
  if (const int rc = MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided); rc != MPI_SUCCESS)
    throw core::RunError(fmt::format("MPI_Init_thread failed with error code {}", rc));
  owns_mpi_ = true;
}

MpiSession::~MpiSession() {
  if (owns_mpi_ && is_initialized() && !is_finalized()) MPI_Finalize();
}

void MpiSession::ensure() {
  if (is_running()) return;
  // Started on first need, finalised during static destruction at process exit.
  static MpiSession process_session;
  if (!is_running()) throw core::RunError("MPI was already finalised in this process and cannot be started again");
}

bool MpiSession::is_running() { return is_initialized() && !is_finalized(); }

int MpiSession::world_rank() {
  require_running("MpiSession::world_rank");
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int MpiSession::world_size() {
  require_running("MpiSession::world_size");
  int size = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

void MpiSession::abort_all(int exit_code) {
  if (is_running()) MPI_Abort(MPI_COMM_WORLD, exit_code);
  std::exit(exit_code);
}

}  // namespace rheosim::dem
