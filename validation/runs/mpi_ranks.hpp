#pragma once
// The MPI side of the runs: a scan's points and a sweep's runs are independent and distributed over the ranks
// of MPI_COMM_WORLD (`mpirun -np K aggkit scan ...`, run_store.hpp), and `aggkit run` under mpirun gives its
// ranks (MpiRanks) the realizations. Without mpirun the process is a singleton MPI job of one rank; a library
// user who never initialises MPI gets a serial scan (rank 0 of 1). mpi.h stays out of headers.
#include <cstddef>
#include <string>
#include <vector>

#include "validation/engines/rank_share.hpp"

namespace aggkit {

// RAII for the `aggkit scan`, `sweep` and (under mpirun) `run` commands: initialises MPI unless already
// initialised (threads funneled: only the thread that initialised it calls MPI), and finalises what it
// initialised (after PETSc is finalised).
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

// A counter shared by the ranks of MPI_COMM_WORLD: next() hands out 0, 1, 2, ... each value once, to whichever
// rank asks first, so runs of uneven cost balance over the ranks (a rank that drew a long run draws fewer).
// One-sided MPI atomics (MPI_Fetch_and_op on a window held by rank 0): no other rank has to be inside MPI for
// a rank to draw. A plain counter without MPI. Construction and destruction are collective.
class SharedCounter {
 public:
  SharedCounter();
  ~SharedCounter();
  SharedCounter(const SharedCounter&) = delete;
  SharedCounter& operator=(const SharedCounter&) = delete;
  std::size_t next();

 private:
  long local_ = 0;        // without MPI (or on one rank)
  long* base_ = nullptr;  // the window's memory (rank 0)
  void* window_ = nullptr;  // MPI_Win, kept out of this header
};

// "NAME=value" of the environment variable that shows this process was started by mpirun or srun (Open MPI,
// MPICH/PMI, PMIx), or "" when none is set.
std::string mpirun_variable();

// The ranks of MPI_COMM_WORLD as rank_share.hpp sees them (rank 0 of 1 when MPI is not initialised); bytes go
// point to point between rank 0 and each rank, in pieces of at most 1 GiB.
class MpiRanks final : public RankGroup {
 public:
  MpiRanks();
  int rank() const override { return world_.rank; }
  int size() const override { return world_.size; }
  std::vector<std::string> gather(const std::string& mine) const override;
  std::string broadcast(const std::string& message) const override;

 private:
  MpiWorld world_;
};
}  // namespace aggkit
