#pragma once
// What `aggkit scan` and `aggkit sweep` share to spread independent runs over MPI ranks and resume after an
// interruption: a folder DIR/points/ that holds one small file per finished run, each written atomically
// (a killed command leaves finished files whole and never a half-written one under a final name), a
// fingerprint of everything the results depend on (results of another scene are not reused), and the
// unfinished runs computed over the ranks of MPI_COMM_WORLD, each rank drawing the next one when it is free
// (mpi_ranks.hpp).
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace aggkit {

// The whole text of a file; "" if it is missing or unreadable.
std::string read_text_file(const std::filesystem::path& file);

// A record file of one CSV row under a header (the scan's points, its Hopf and criticality caches): the
// row's fields (a trailing comma gives a trailing empty field), or nullopt unless the text is exactly the
// header line, one row and nothing after it — a damaged, truncated or foreign file is not a record, and its run
// is done again.
std::optional<std::vector<std::string>> one_row_record(const std::string& text, const std::string& header);

// A record's number field: the whole field read as a double ("" is NaN where `empty_is_nan`); nullopt for
// anything else (trailing characters, out of range, empty).
std::optional<double> record_number(const std::string& field, bool empty_is_nan = false);

// Every rank: creates `points` (under the output folder `out`) and checks that every rank can write files
// there; otherwise InputError (key "--out") on every rank.
void prepare_points_folder(const std::filesystem::path& out, const std::filesystem::path& points);

// Rank 0: if points/fingerprint.toml differs from `fingerprint`, removes the earlier results (files whose
// extension is `extension`, e.g. ".csv"), says so on `progress` with `command` ("aggkit scan") and `why`,
// and records the new fingerprint.
void check_points_fingerprint(const std::filesystem::path& points, const std::string& fingerprint,
                              const std::string& extension, const std::string& command, const std::string& why,
                              std::ostream* progress);

struct DistributedRuns {
  std::size_t runs = 0;      // asked for
  std::size_t reused = 0;    // finished earlier (found finished by every rank alike)
  std::size_t computed = 0;  // by this rank
  std::size_t failed = 0;    // over all ranks
};

// Every rank, collectively: runs i < count for which finished(i) is false are listed (the same list on every
// rank: finished() must read the shared points folder), then computed over the ranks, each drawing the next
// unfinished run when it is free, by compute(i, number, count) — `number` its 1-based place in the batch of
// `count`, after the runs finished earlier (a resumed batch counts on: "8/9") — which returns false for a
// failed run (not written: a rerun retries it). Returns when every rank has finished, with a
// progress line on rank 0: "<command>: <what>: N runs, F finished earlier, T to compute on K ranks".
DistributedRuns compute_unfinished_runs(std::size_t count, const std::function<bool(std::size_t)>& finished,
                                        const std::function<bool(std::size_t i, std::size_t number, std::size_t count)>& compute,
                                        const std::string& command, const std::string& what, std::ostream* progress);

// A task drawn first with a batch of runs and run whole by one rank (the scan's converged Hopf curve), so
// that it runs beside them: finished() reads the shared points folder, compute() returns false if it failed.
struct SerialTask {
  std::function<bool()> finished, compute;
};

}  // namespace aggkit
