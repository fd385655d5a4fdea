#include "validation/runs/run_store.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <sstream>
#include <vector>

#include "analysis/input_error.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/runs/run_folder.hpp"
#include "validation/runs/mpi_ranks.hpp"

namespace aggkit {

std::string read_text_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return "";
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::optional<std::vector<std::string>> one_row_record(const std::string& text, const std::string& header) {
  std::istringstream in(text);
  std::string line, row, rest;
  if (!std::getline(in, line) || line != header) return std::nullopt;
  if (!std::getline(in, row) || std::getline(in, rest)) return std::nullopt;
  std::vector<std::string> fields;
  std::string field;
  std::istringstream cells(row);
  while (std::getline(cells, field, ',')) fields.push_back(field);
  if (!row.empty() && row.back() == ',') fields.emplace_back();
  return fields;
}

std::optional<double> record_number(const std::string& field, bool empty_is_nan) {
  if (field.empty()) return empty_is_nan ? std::optional<double>(std::nan("")) : std::nullopt;
  // strtod, not stod: stod refuses a subnormal number (ERANGE on underflow), and the states the scan caches
  // hold densities of ~1e-318 in their far tails, written exactly by shortest_text. An overflow (±HUGE_VAL
  // with ERANGE) is refused.
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(field.c_str(), &end);
  if (end != field.c_str() + field.size() || (errno == ERANGE && std::isinf(value))) return std::nullopt;
  return value;
}

void prepare_points_folder(const std::filesystem::path& out, const std::filesystem::path& points) {
  // Every rank checks that it can write (they may not share a file system view); a failure anywhere stops
  // all ranks with the same error.
  std::string folder_error;
  try {
    check_writable_folder(points, out, std::to_string(mpi_world().rank));  // a probe per rank
  } catch (const InputError& e) {
    folder_error = e.what();
  }
  if (!mpi_all(folder_error.empty())) {
    if (!folder_error.empty()) throw InputError("--out", out.string(), "an output folder that can be created and written");
    throw InputError("--out", out.string(), "an output folder that every MPI rank can write");
  }
}

void check_points_fingerprint(const std::filesystem::path& points, const std::string& fingerprint,
                              const std::string& extension, const std::string& command, const std::string& why,
                              std::ostream* progress) {
  const std::filesystem::path file = points / "fingerprint.toml";
  std::error_code error;
  const bool exists = std::filesystem::exists(file, error);
  if (exists && read_text_file(file) == fingerprint) return;
  if (exists) {
    std::size_t removed = 0;
    for (const auto& entry : std::filesystem::directory_iterator(points, error))
      if (entry.path().extension() == extension) removed += std::filesystem::remove(entry.path(), error) ? 1 : 0;
    if (progress && removed) *progress << command << ": " << why << ": " << removed << " earlier results discarded\n";
  }
  write_file_atomically(file, fingerprint);
}

DistributedRuns compute_unfinished_runs(std::size_t count, const std::function<bool(std::size_t)>& finished,
                                        const std::function<bool(std::size_t, std::size_t, std::size_t)>& compute,
                                        const std::string& command, const std::string& what, std::ostream* progress) {
  const MpiWorld world = mpi_world();
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < count; ++i)
    if (!finished(i)) todo.push_back(i);
  DistributedRuns runs;
  runs.runs = count;
  runs.reused = count - todo.size();
  mpi_barrier();  // every rank has listed the same unfinished runs before any is written
  if (progress && world.rank == 0)
    *progress << command << ": " << what << ": " << count << " runs, " << runs.reused << " finished earlier, "
              << todo.size() << " to compute on " << world.size << (world.size == 1 ? " rank\n" : " ranks\n") << std::flush;
  // Runs are numbered over the whole batch: after a resume the count continues after the runs finished
  // earlier ("8/9") instead of starting again at 1.
  // Each rank draws the next run from a shared counter, so a rank held up by a long run draws fewer.
  long failed = 0;
  SharedCounter counter;
  for (std::size_t k = counter.next(); k < todo.size(); k = counter.next()) {
    if (compute(todo[k], runs.reused + k + 1, count)) ++runs.computed;
    else ++failed;
  }
  runs.failed = std::size_t(mpi_sum(failed));  // also the barrier after which every result is on disk
  return runs;
}

}  // namespace aggkit
