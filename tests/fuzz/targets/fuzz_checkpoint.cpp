// libFuzzer target: the checkpoint reader (particle/common/checkpoint.hpp) and the engines' state readers behind
// it (`aggkit run --resume`). The input is taken two ways:
//   * as a checkpoint file, read by read_checkpoint against a fixed expected header: it is refused with a
//     CheckpointError (damaged, truncated, grown, foreign: another format, program, engine or scene), or what
//     comes back is exactly the bytes after the header, as many as the header states, with its checksum;
//   * as an engine's state (and so is the payload of an accepted file), restored into a freshly started small
//     engine of each kind — ED, TS, DEM, a DSMC ensemble of each method (so each engine also reads the others'
//     states). Each state is refused with a CheckpointError, or read to its last byte, and then the restored
//     engine saves a state of the same length which a fresh engine restores again and saves unchanged: nothing
//     half-read, nothing read that save does not write back.
// Any other exception (a length_error from a length taken on trust, a bad_alloc), a sanitizer report or a
// failed check ends the run.
// Seeds: tests/fuzz/corpus/fuzz_checkpoint holds checkpoint files with the expected header (an empty payload, a
// TS state cut short after its particle count, the same under another engine's name) and the seeds written by
// the command below except dsmc-ar.state (274 kB, beyond the fuzzing's -max_len; the fast DSMC state stands for
// the population both methods share): 288 more edges reached from the start than the three files alone.
//   AGGKIT_FUZZ_CHECKPOINT_SEEDS=DIR fuzz_checkpoint   writes further seeds into DIR instead (each engine's state
//   after a few steps, and a checkpoint file of the TS state with the expected header) and exits.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <unistd.h>

#include "particle/common/checkpoint.hpp"
#include "particle/common/initial_state.hpp"
#include "particle/dem/dem.hpp"
#include "particle/dsmc/ensemble.hpp"
#include "particle/ed/event_driven_aggregation.hpp"
#include "particle/ts/time_stepping_aggregation.hpp"
#include "tests/particle/dsmc/dsmc_fixture.hpp"

using namespace aggkit;

namespace {

const CheckpointHeader expected{"fuzz", "ts:fuzz", 0x5eedull};

[[noreturn]] void fail(const char* engine, const std::string& what) {
  std::fprintf(stderr, "fuzz_checkpoint: %s: %s\n", engine, what.c_str());
  std::abort();
}

std::unique_ptr<EventDrivenAggregation> start_ed() {
  const std::size_t n = 16;
  const Box box{2, {12, 12, 0}, Boundary::reflecting};
  return std::make_unique<EventDrivenAggregation>(box, 0.5, lattice_positions(box, n, 0.5),
                                                  initial_velocities(2, n, VelocityLaw::fixed_speed, 1.0, 3));
}

std::unique_ptr<TimeSteppingAggregation> start_ts() {
  const std::size_t n = 16;
  const Box box{2, {12, 12, 0}, Boundary::reflecting};
  return std::make_unique<TimeSteppingAggregation>(box, 0.5, lattice_positions(box, n, 0.5),
                                                   initial_velocities(2, n, VelocityLaw::fixed_speed, 1.0, 3), TsSettings{});
}

std::unique_ptr<Dem> start_dem() {
  const std::size_t n = 8;
  const double radius = 0.5, side = box_side_for_volume_fraction(3, n, radius, 0.3);
  const Box box{3, {side, side, side}, Boundary::periodic};
  ParticleStart start;
  start.positions = lattice_positions(box, n, radius);
  start.velocities = initial_velocities(3, n, VelocityLaw::uniform_components, 1.0, 5);
  start.radii.assign(n, radius);
  start.masses.assign(n, 1.0);
  DemSettings settings;
  settings.stiffness = 2000;
  settings.damping = 0.5;
  settings.dt = 0.001;
  settings.friction = 0.5;  // tangential histories in the state
  return std::make_unique<Dem>(box, std::move(start), settings);
}

std::unique_ptr<dsmc::Ensemble> start_dsmc(dsmc::Method method) {
  AggregationModel model = aggkit::testing::dsmc_model(Kernel::ballistic(), 0.1);
  model.truncation = Truncation::cutoff;
  dsmc::Options options;
  options.method = method;
  options.particles = 100;
  options.runs = 2;
  options.bucket = 8;  // sizes above 8 stored one by one: both kinds of storage in the state
  options.threads = 1;
  return std::make_unique<dsmc::Ensemble>(model, options, 1.0);
}

std::unique_ptr<dsmc::Ensemble> start_dsmc_ar() { return start_dsmc(dsmc::Method::acceptance_rejection); }
std::unique_ptr<dsmc::Ensemble> start_dsmc_fast() { return start_dsmc(dsmc::Method::fast); }

template <class Engine>
std::string saved(const Engine& engine) {
  StateWriter out;
  engine.save(out);
  return out.take();
}

// Restores `state` into a fresh engine; true if it was read whole, false if refused with a CheckpointError.
template <class Start>
bool restores(Start start, std::string_view state, std::string& again) {
  auto engine = start();
  StateReader in(state);
  try {
    engine->restore(in);
    in.expect_end();
  } catch (const CheckpointError&) {
    return false;
  }
  again = saved(*engine);
  return true;
}

template <class Start>
void check_engine(const char* name, Start start, std::string_view state) {
  std::string once, twice;
  if (!restores(start, state, once)) return;
  if (once.size() != state.size())
    fail(name, "a state of " + std::to_string(state.size()) + " bytes was accepted, its engine saves " + std::to_string(once.size()));
  if (!restores(start, once, twice)) fail(name, "the engine refuses the state it saved after a restore");
  if (twice != once) fail(name, "a restored engine's state differs from the state it was restored from");
}

void check_file(const std::filesystem::path& file, std::string_view bytes) {
  std::string payload;
  try {
    payload = read_checkpoint(file, expected);
  } catch (const CheckpointError&) {
    return;
  }
  // Accepted: the file is exactly what write_checkpoint writes for the expected header and this payload.
  const std::filesystem::path again = file.string() + "-again";
  write_checkpoint(again, expected, payload);
  std::ifstream in(again, std::ios::binary);
  if (std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()) != bytes)
    fail("read_checkpoint", "accepted a file that is not the expected header and its payload");
  check_engine("ts (from a file)", start_ts, payload);
}

void check_state(std::string_view state) {
  check_engine("ed", start_ed, state);
  check_engine("ts", start_ts, state);
  check_engine("dem", start_dem, state);
  check_engine("dsmc ar", start_dsmc_ar, state);
  check_engine("dsmc fast", start_dsmc_fast, state);
}

void write_seeds(const std::filesystem::path& folder) {
  std::filesystem::create_directories(folder);
  const auto write = [&](const char* name, const std::string& bytes) {
    std::ofstream(folder / name, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  };
  auto ed = start_ed();
  for (int k = 0; k < 20 && ed->step(); ++k) {
  }
  write("ed.state", saved(*ed));
  auto ts = start_ts();
  for (int k = 0; k < 20; ++k) ts->step();
  write("ts.state", saved(*ts));
  write_checkpoint(folder / "ts.checkpoint", expected, saved(*ts));
  auto dem = start_dem();
  for (int k = 0; k < 20; ++k) dem->step();
  write("dem.state", saved(*dem));
  const auto write_dsmc = [&](const char* name, std::unique_ptr<dsmc::Ensemble> ensemble) {
    ensemble->advance_to(0.5);
    write(name, saved(*ensemble));
  };
  write_dsmc("dsmc-ar.state", start_dsmc_ar());
  write_dsmc("dsmc-fast.state", start_dsmc_fast());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* folder = std::getenv("AGGKIT_FUZZ_CHECKPOINT_SEEDS")) {
    write_seeds(folder);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto file = std::filesystem::temp_directory_path() / ("aggkit-fuzz-checkpoint-" + std::to_string(getpid()) + ".state");
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
  check_file(file, bytes);
  check_state(bytes);
  return 0;
}
