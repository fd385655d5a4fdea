#pragma once
// The MPI side of a scan: points are independent and distributed over the ranks of MPI_COMM_WORLD
// (`mpirun -np K aggkit scan ...`). Without mpirun the process is a singleton MPI job of one rank; a
// library user who never initialises MPI gets a serial scan (rank 0 of 1). mpi.h stays out of headers.
namespace aggkit {

// RAII for the `aggkit scan` command: initialises MPI unless already initialised, and finalises what it
// initialised (after PETSc, which runs on MPI_COMM_WORLD, is finalised).
class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

 private:
  bool initialised_here_ = false;
};

struct MpiWorld {
  int rank = 0, size = 1;
};
// Rank and size of MPI_COMM_WORLD, or {0, 1} when MPI is not initialised.
MpiWorld mpi_world();
// MPI_Barrier on MPI_COMM_WORLD (nothing without MPI).
void mpi_barrier();
// Logical AND of `value` over all ranks.
bool mpi_all(bool value);
// Ends every rank of the job with `code` (MPI_Abort with more than one rank, else std::exit).
[[noreturn]] void mpi_abort(int code);

}  // namespace aggkit

namespace aggkit {
// Sum of `value` over all ranks.
long mpi_sum(long value);
}  // namespace aggkit
