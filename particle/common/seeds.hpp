#pragma once
// Seeds of independent realizations, shared by the particle engines: SplitMix64 (Steele, Lea & Flood,
// OOPSLA 2014). Run r of an ensemble with master seed S uses the (r+1)-th output of a SplitMix64 stream
// started at S, so consecutive runs and neighbouring master seeds get unrelated streams.
#include <cstdint>

namespace aggkit {

// One step of SplitMix64: advances `state` and returns a well-mixed 64-bit value.
inline std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// The seed of run `run` (0-based) of an ensemble with master seed `master`.
inline std::uint64_t run_seed(std::uint64_t master, std::uint64_t run) {
  std::uint64_t state = master;
  std::uint64_t value = 0;
  for (std::uint64_t r = 0; r <= run; ++r) value = splitmix64(state);
  return value;
}

// Independent streams of one run: the velocities use run_seed(master, run) itself (unchanged since the first
// starts), and each further random ingredient of a start draws from its own stream, seeded by one more
// SplitMix64 step from the run seed offset by a distinct constant. Adding an ingredient therefore never
// changes the velocities, and the radii do not depend on how many positions were tried.
enum class StartStream : std::uint64_t {
  radii = 0x5261646969000001ULL,      // per-particle radii
  masses = 0x4d61737365000002ULL,     // per-particle masses
  positions = 0x506f736974000003ULL,  // random placement (clouds)
};

inline std::uint64_t stream_seed(std::uint64_t run_seed_value, StartStream stream) {
  std::uint64_t state = run_seed_value ^ std::uint64_t(stream);
  return splitmix64(state);
}

}  // namespace aggkit
