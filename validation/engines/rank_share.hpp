#pragma once
// Realizations over the ranks of a job (`mpirun -np K aggkit run SCENE`): how the particle engines and the
// DSMC engine run their share of the realizations on each rank and bring the results to rank 0, which records
// them in realization order exactly as one process does (so the outputs are those of a one-process run with
// the same seeds, bit for bit).
//   * Rank k of K runs realizations k, k + K, k + 2K, ... (threads within the rank as in one process);
//     realization 0, whose snapshots and trajectory are written, is always on rank 0. A rank with none idles.
//   * The ranks are an interface here, so the engines know no MPI: `aggkit run` hands the harness the MPI one
//     (validation/runs/mpi_ranks.hpp), the harness passes it to the engines that spread their realizations
//     (Engine::spreads_over_ranks) and runs the other ranks' side (harness.hpp, serve_realizations).
//   * A failure on any rank fails the share on every rank after every rank has finished its part, so no rank
//     is left waiting: rank 0 throws it and reports, the others end quietly (ShareAbandoned).
// An engine's run on a rank other than 0 calls gather_shares (or gather_realizations) exactly as often as on
// rank 0 and throws nothing outside them.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "particle/common/checkpoint.hpp"
#include "validation/engines/engine.hpp"

namespace aggkit {

class RankGroup {
 public:
  virtual ~RankGroup() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Every rank's `mine`, in rank order, on rank 0; an empty list on the others. Every rank must call it.
  virtual std::vector<std::string> gather(const std::string& mine) const = 0;
  // Rank 0's `message`, on every rank (the others' argument is ignored). Every rank must call it.
  virtual std::string broadcast(const std::string& message) const = 0;
};

// The ranks that share the realizations: `ranks` if it has more than one, else nullptr (one process runs all).
const RankGroup* shared_ranks(const RankGroup* ranks);

// The realizations of `count` that this rank runs: rank, rank + size, ... ; all of them when `ranks` is null.
std::vector<std::size_t> realizations_of_rank(std::size_t count, const RankGroup* ranks);

// Thrown on the ranks other than 0 when a rank failed a share: rank 0 reports the failure, the others end
// without a word. `input`: the failure was bad input (exit status 2), else a failed run.
struct ShareAbandoned {
  bool input = false;
};

// Runs `work` on every rank and brings each rank's result to rank 0: there, the results in rank order;
// elsewhere an empty list. Without ranks (null): {work()}. If `work` fails on any rank, every rank finishes
// its own first, then rank 0 throws its own exception, or else the first failed rank's again (InputError
// with its key and words, or std::runtime_error with its message, each naming the rank), and the other
// ranks throw ShareAbandoned.
std::vector<std::string> gather_shares(const RankGroup* ranks, const std::function<std::string()>& work);

// The same per realization: `work` gets this rank's realizations (realizations_of_rank) and returns one
// result for each, in that order; rank 0 (or one process) gets the results of all `count` realizations in
// realization order, the other ranks an empty list.
std::vector<std::string> gather_realizations(const RankGroup* ranks, std::size_t count,
                                             const std::function<std::vector<std::string>(const std::vector<std::size_t>& mine)>& work);

// gather_realizations for values of type T: `work` gets this rank's realizations and returns one value for
// each, in that order; `put(StateWriter&, const T&)` writes a value as bytes and `get(StateReader&)` reads it
// back. Rank 0 gets the values of all `count` realizations in realization order, the other ranks an empty
// list. Without ranks (null) it returns work(all realizations) as it is: no bytes are made.
template <class T, class Work, class Put, class Get>
std::vector<T> gather_realization_values(const RankGroup* ranks, std::size_t count, Work&& work, Put&& put, Get&& get) {
  if (!ranks) return work(realizations_of_rank(count, nullptr));
  const std::vector<std::string> gathered = gather_realizations(ranks, count, [&](const std::vector<std::size_t>& mine) {
    std::vector<std::string> payloads;
    for (const T& value : work(mine)) {
      StateWriter out;
      put(out, value);
      payloads.push_back(out.take());
    }
    return payloads;
  });
  std::vector<T> values;
  values.reserve(gathered.size());
  for (const std::string& payload : gathered) {
    StateReader in(payload);
    values.push_back(get(in));
    in.expect_end();
  }
  return values;
}

// A measurement as bytes (for the results a rank sends, and for checkpoints), and back.
void put_measurement(StateWriter& out, const Measurement& m);
Measurement get_measurement(StateReader& in);

}  // namespace aggkit
