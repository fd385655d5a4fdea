#include "solvers/petsc_session.hpp"

#include <petscsys.h>

#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

namespace aggkit {

namespace {
std::mutex session_mutex;
bool initialized_here = false;
bool exit_hook_registered = false;

void finalize_at_exit() { finalize_petsc(); }
}  // namespace

void ensure_petsc_initialized() {
  std::lock_guard lock(session_mutex);
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (initialized) return;
  PetscBool finalized = PETSC_FALSE;
  PetscFinalized(&finalized);
  if (finalized) throw std::runtime_error("PETSc was already finalised in this process; it cannot restart");
  // Every PETSc object of aggkit lives on PETSC_COMM_SELF. Under MPI (scan, sweep, `mpirun aggkit run`) each
  // rank keeps a PETSc of its own, so a rank that solves never waits in PETSc's collectives
  // (PetscInitialize, PetscFinalize) for ranks that do not (under `aggkit run` only rank 0 runs snes).
  int mpi_initialised = 0;
  MPI_Initialized(&mpi_initialised);
  if (mpi_initialised) PETSC_COMM_WORLD = MPI_COMM_SELF;
  // PETSc must not install its signal handler (it would turn a library user's crash into PETSc noise).
  PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr);
  const PetscErrorCode code = PetscInitializeNoArguments();
  if (code != 0) throw std::runtime_error("PetscInitializeNoArguments failed with code " + std::to_string(code));
  // Errors come back as codes that aggkit turns into exceptions; no tracebacks on stderr.
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  if (!exit_hook_registered) std::atexit(finalize_at_exit);  // the user need not call finalize_petsc()
  exit_hook_registered = true;
  initialized_here = true;
}

void finalize_petsc() {
  std::lock_guard lock(session_mutex);
  if (!initialized_here) return;
  PetscBool finalized = PETSC_FALSE;
  PetscFinalized(&finalized);
  if (!finalized) PetscFinalize();
  initialized_here = false;
}

}  // namespace aggkit
