#include "validation/scan/scan_mpi.hpp"

#include <cstdlib>

#include <mpi.h>

#include "solvers/petsc_session.hpp"

namespace aggkit {

namespace {
bool mpi_active() {
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  return initialised && !finalised;
}
}  // namespace

MpiSession::MpiSession(int* argc, char*** argv) {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) {
    MPI_Init(argc, argv);
    initialised_here_ = true;
  }
}

MpiSession::~MpiSession() {
  finalize_petsc();  // PETSc runs on MPI_COMM_WORLD: it must end before MPI does
  if (initialised_here_ && mpi_active()) MPI_Finalize();
}

MpiWorld mpi_world() {
  MpiWorld world;
  if (!mpi_active()) return world;
  MPI_Comm_rank(MPI_COMM_WORLD, &world.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &world.size);
  return world;
}

void mpi_barrier() {
  if (mpi_active()) MPI_Barrier(MPI_COMM_WORLD);
}

bool mpi_all(bool value) {
  if (!mpi_active()) return value;
  int local = value ? 1 : 0, global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
  return global != 0;
}

void mpi_abort(int code) {
  if (mpi_active() && mpi_world().size > 1) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

}  // namespace aggkit

namespace aggkit {
long mpi_sum(long value) {
  if (!mpi_active()) return value;
  long global = 0;
  MPI_Allreduce(&value, &global, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  return global;
}
}  // namespace aggkit
