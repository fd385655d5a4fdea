#include "validation/harness/run_checkpoint.hpp"

#include <chrono>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "analysis/input_error.hpp"
#include "particle/common/checkpoint.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/io/stop_signal.hpp"
#include "validation/io/version.hpp"

namespace aggkit {

namespace {

void put_record(StateWriter& out, const EngineRecord& record) {
  out.put(record.times);
  out.put(std::uint64_t(record.values.size()));
  for (const auto& row : record.values) out.put(row);
  out.put(std::uint64_t(record.standard_errors.size()));
  for (const auto& row : record.standard_errors) out.put(row);
  out.put(std::uint64_t(record.distributions.size()));
  for (const auto& d : record.distributions) {
    out.put(d.t);
    out.put(d.n);
    out.put(std::uint64_t(d.realizations.size()));
    for (const auto& n : d.realizations) out.put(n);
    out.put(d.sizes);
  }
  out.put(std::uint64_t(record.realization_values.size()));
  for (const auto& series : record.realization_values) {
    out.put(std::uint64_t(series.size()));
    for (const auto& row : series) out.put(row);
  }
  out.put(std::uint64_t(record.finals.size()));
  for (const auto& f : record.finals) {
    out.put(f.name);
    out.put(f.mean);
    out.put(f.standard_error);
  }
  out.put(std::uint64_t(record.statistics.size()));
  for (const auto& s : record.statistics) {
    out.put(s.name);
    out.put(std::uint8_t(s.value.index()));
    std::visit([&](const auto& v) { out.put(v); }, s.value);
  }
  out.put(std::uint64_t(record.warnings.size()));
  for (const auto& w : record.warnings) out.put(w);
  out.put(record.wall_seconds);
  out.put(record.final_mass_leak);
}

template <class Row>
void get_rows(StateReader& in, std::vector<Row>& rows) {
  rows.resize(in.length(sizeof(std::uint64_t)));  // a row: at least its length
  for (auto& row : rows) in.get(row);
}

void get_record(StateReader& in, EngineRecord& record) {
  in.get(record.times);
  get_rows(in, record.values);
  get_rows(in, record.standard_errors);
  record.distributions.resize(in.length(4 * sizeof(std::uint64_t)));  // t, n, two lengths
  for (auto& d : record.distributions) {
    in.get(d.t);
    in.get(d.n);
    get_rows(in, d.realizations);
    in.get(d.sizes);
  }
  record.realization_values.resize(in.length(sizeof(std::uint64_t)));
  for (auto& series : record.realization_values) get_rows(in, series);
  record.finals.resize(in.length(3 * sizeof(std::uint64_t)));  // name length, mean, standard error
  for (auto& f : record.finals) {
    in.get(f.name);
    in.get(f.mean);
    in.get(f.standard_error);
  }
  record.statistics.resize(in.length(sizeof(std::uint64_t) + 1));  // name length, kind
  for (auto& s : record.statistics) {
    in.get(s.name);
    switch (in.read<std::uint8_t>()) {
      case 0: s.value = in.read<std::int64_t>(); break;
      case 1: s.value = in.read<double>(); break;
      case 2: s.value = in.read<std::string>(); break;
      default: throw CheckpointError("the checkpoint's record holds a statistic of an unknown kind");
    }
  }
  get_rows(in, record.warnings);
  in.get(record.wall_seconds);
  in.get(record.final_mass_leak);
}

CheckpointHeader header_of(const Engine& engine, std::uint64_t fingerprint) {
  return {version(), engine.name() + ":" + engine.label(), fingerprint};
}

std::filesystem::path state_file(const std::filesystem::path& folder, const Engine& engine) {
  return folder / (engine.label() + ".state");
}

// The harness's part of a state file and the engine's, as read.
struct SavedEngine {
  bool completed = false;
  EngineRecord record;
  std::string state;
};

std::optional<SavedEngine> read_saved(const std::filesystem::path& folder, const Engine& engine, std::uint64_t fingerprint) {
  const std::filesystem::path file = state_file(folder, engine);
  if (!std::filesystem::exists(file)) return std::nullopt;  // the run stopped before this engine's first checkpoint
  try {
    const std::string payload = read_checkpoint(file, header_of(engine, fingerprint));
    StateReader in(payload);
    SavedEngine saved;
    saved.completed = in.read<std::uint8_t>() != 0;
    get_record(in, saved.record);
    in.get(saved.state);
    in.expect_end();
    return saved;
  } catch (const CheckpointError& e) {
    throw InputError("--resume", folder.parent_path().string(), std::string("a checkpoint this run can continue from; ") + e.what());
  }
}

void write_saved(const std::filesystem::path& folder, const Engine& engine, std::uint64_t fingerprint, bool completed,
                 const EngineRecord& record, std::string_view state) {
  StateWriter out;
  out.put(std::uint8_t(completed));
  put_record(out, record);
  out.put(state);
  write_checkpoint(state_file(folder, engine), header_of(engine, fingerprint), out.bytes());
}

class HarnessCheckpoint final : public EngineCheckpoint {
 public:
  HarnessCheckpoint(std::filesystem::path folder, const Engine& engine, std::uint64_t fingerprint, double interval,
                    std::string resumed, EngineRecord& record, std::mutex& record_lock)
      : folder_(std::move(folder)), engine_(engine), fingerprint_(fingerprint), interval_(interval),
        resumed_(std::move(resumed)), record_(record), record_lock_(record_lock), last_(Clock::now()) {}

  double interval() const override { return interval_; }
  const std::string& resumed() const override { return resumed_; }
  bool due() const override {
    if (interval_ <= 0) return false;
    if (stop_signal() != 0) return true;
    std::lock_guard lock(write_lock_);
    return std::chrono::duration<double>(Clock::now() - last_).count() >= interval_;
  }
  void save(std::string state) override {
    if (interval_ <= 0) return;
    {
      std::lock_guard lock(write_lock_);
      EngineRecord record;
      {
        std::lock_guard lock_record(record_lock_);
        record = record_;
      }
      write_saved(folder_, engine_, fingerprint_, false, record, state);
      last_ = Clock::now();
    }
    if (const int signal = stop_signal(); signal != 0) throw RunInterrupted{signal};
  }

 private:
  using Clock = std::chrono::steady_clock;
  std::filesystem::path folder_;
  const Engine& engine_;
  std::uint64_t fingerprint_;
  double interval_;
  std::string resumed_;
  EngineRecord& record_;
  std::mutex& record_lock_;
  mutable std::mutex write_lock_;
  Clock::time_point last_;
};

}  // namespace

CheckpointedRun read_checkpointed_run(const std::filesystem::path& out) {
  const std::filesystem::path file = out / "checkpoint" / "run.json";
  std::ifstream in(file);
  if (!in)
    throw InputError("--resume", out.string(),
                     "a folder of a run with checkpoints (" + file.string() +
                         " is missing: the run finished, or never wrote a checkpoint)");
  try {
    const nlohmann::json json = nlohmann::json::parse(in);
    CheckpointedRun run;
    run.scene = json.at("scene").get<std::string>();
    run.fingerprint = std::stoull(json.at("fingerprint").get<std::string>(), nullptr, 16);
    run.interval = json.at("checkpoint_every").get<double>();
    run.plot = json.at("plot").get<bool>();
    return run;
  } catch (const std::exception& e) {
    throw InputError("--resume", out.string(), "a readable " + file.string() + " (" + e.what() + ")");
  }
}

RunCheckpoints::RunCheckpoints(const std::filesystem::path& out, CheckpointedRun run, bool resume)
    : folder_(out / "checkpoint"), run_(std::move(run)), resume_(resume) {
  if (resume) return;
  std::filesystem::remove_all(folder_);  // a fresh run: an earlier run's states must not be continued
  std::filesystem::create_directories(folder_);
  const nlohmann::json json{{"scene", std::filesystem::absolute(run_.scene).string()},
                            {"fingerprint", fingerprint_text(run_.fingerprint)},
                            {"checkpoint_every", run_.interval},
                            {"plot", run_.plot},
                            {"aggkit", version()}};
  write_file_atomically(folder_ / "run.json", json.dump(2) + "\n");
}

std::optional<EngineRecord> RunCheckpoints::completed(const Engine& engine) const {
  if (!resume_) return std::nullopt;
  std::optional<SavedEngine> saved = read_saved(folder_, engine, run_.fingerprint);
  if (!saved || !saved->completed) return std::nullopt;
  saved->record.label = engine.label();
  saved->record.name = engine.name();
  saved->record.description = engine.describe();
  return std::move(saved->record);
}

std::unique_ptr<EngineCheckpoint> RunCheckpoints::start(const Engine& engine, EngineRecord& record, std::mutex& record_lock) {
  std::string state;
  if (resume_)
    if (std::optional<SavedEngine> saved = read_saved(folder_, engine, run_.fingerprint); saved && !saved->state.empty()) {
      const std::string label = record.label, name = record.name, description = record.description;
      record = std::move(saved->record);
      record.label = label, record.name = name, record.description = description;
      state = std::move(saved->state);
    }
  double interval = run_.interval;
  if (interval <= 0)
    if (const auto it = engine.settings().find("checkpoint_every"); it != engine.settings().end() && it->is_number())
      interval = it->get<double>();
  return std::make_unique<HarnessCheckpoint>(folder_, engine, run_.fingerprint, interval, std::move(state), record, record_lock);
}

void RunCheckpoints::complete(const Engine& engine, const EngineRecord& record) const {
  write_saved(folder_, engine, run_.fingerprint, true, record, {});
}

void RunCheckpoints::finish() const { std::filesystem::remove_all(folder_); }

}  // namespace aggkit
