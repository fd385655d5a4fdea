#include "validation/runs/mpi_ranks.hpp"

#include <algorithm>
#include <cstdint>
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
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    initialised_here_ = true;
  }
}

MpiSession::~MpiSession() {
  finalize_petsc();  // PETSc runs on MPI: it must end before MPI does
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

SharedCounter::SharedCounter() {
  if (!mpi_active() || mpi_world().size == 1) return;
  auto* window = new MPI_Win;
  const bool owner = mpi_world().rank == 0;
  MPI_Win_allocate(owner ? MPI_Aint(sizeof(long)) : 0, sizeof(long), MPI_INFO_NULL, MPI_COMM_WORLD, &base_, window);
  if (owner) {  // the first value, stored in an exclusive epoch (valid in the separate and unified memory models)
    MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, *window);
    *base_ = 0;
    MPI_Win_unlock(0, *window);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  window_ = window;
}

SharedCounter::~SharedCounter() {
  if (!window_) return;
  auto* window = static_cast<MPI_Win*>(window_);
  if (mpi_active()) MPI_Win_free(window);
  delete window;
}

std::size_t SharedCounter::next() {
  if (!window_) return std::size_t(local_++);
  const MPI_Win window = *static_cast<MPI_Win*>(window_);
  const long one = 1;
  long drawn = 0;
  MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, window);
  MPI_Fetch_and_op(&one, &drawn, MPI_LONG, 0, 0, MPI_SUM, window);
  MPI_Win_unlock(0, window);
  return std::size_t(drawn);
}
}  // namespace aggkit

namespace aggkit {

std::string mpirun_variable() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (const char* value = std::getenv(variable); value && *value) return std::string(variable) + "=" + value;
  return "";
}

namespace {
constexpr int realization_tag = 2707;               // the messages of MpiRanks::gather
constexpr std::size_t piece = std::size_t(1) << 30;  // bytes per message (MPI counts are int)

void send_bytes(const std::string& bytes, int to) {
  std::uint64_t n = bytes.size();
  MPI_Send(&n, 1, MPI_UINT64_T, to, realization_tag, MPI_COMM_WORLD);
  for (std::size_t at = 0; at < bytes.size(); at += piece)
    MPI_Send(bytes.data() + at, int(std::min(piece, bytes.size() - at)), MPI_CHAR, to, realization_tag, MPI_COMM_WORLD);
}

std::string receive_bytes(int from) {
  std::uint64_t n = 0;
  MPI_Recv(&n, 1, MPI_UINT64_T, from, realization_tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::string bytes(n, '\0');
  for (std::size_t at = 0; at < bytes.size(); at += piece)
    MPI_Recv(bytes.data() + at, int(std::min(piece, bytes.size() - at)), MPI_CHAR, from, realization_tag, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
  return bytes;
}
}  // namespace

MpiRanks::MpiRanks() : world_(mpi_world()) {}

std::vector<std::string> MpiRanks::gather(const std::string& mine) const {
  if (world_.size == 1) return {mine};
  if (world_.rank != 0) {
    send_bytes(mine, 0);
    return {};
  }
  std::vector<std::string> all{mine};
  for (int k = 1; k < world_.size; ++k) all.push_back(receive_bytes(k));
  return all;
}

std::string MpiRanks::broadcast(const std::string& message) const {
  if (world_.size == 1) return message;
  std::uint64_t n = message.size();
  MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  std::string bytes = world_.rank == 0 ? message : std::string(n, '\0');
  for (std::size_t at = 0; at < bytes.size(); at += piece)
    MPI_Bcast(bytes.data() + at, int(std::min(piece, bytes.size() - at)), MPI_CHAR, 0, MPI_COMM_WORLD);
  return bytes;
}

}  // namespace aggkit
