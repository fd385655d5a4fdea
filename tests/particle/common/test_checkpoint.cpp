// Checkpoint files: a state comes back as written, and a file that is not exactly what was written, or not
// for this program, engine and scene, is refused with the reason — never half-read.
#include <catch2/catch.hpp>

#include <fstream>

#include "particle/common/checkpoint.hpp"
#include "particle/common/vector3.hpp"
#include "tests/validation/scene_fixture.hpp"

using namespace aggkit;

namespace {

const CheckpointHeader header{"1.2.3", "dem:collapse", 0x1234abcdull};

std::string sample_state() {
  StateWriter out;
  out.put(std::uint64_t(42));
  out.put(std::vector<Vector3>{{1, 2, 3}, {-0.5, 1e-300, 7}});
  out.put(std::string("realization 1"));
  out.put(std::vector<bool>{true, false, true});
  out.put(3.25L);
  return out.take();
}

std::string bytes_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}

std::string refusal(const std::filesystem::path& file, const CheckpointHeader& expected) {
  try {
    read_checkpoint(file, expected);
  } catch (const CheckpointError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST_CASE("checkpoint: a state is read back value for value, and its end is checked") {
  const std::string state = sample_state();
  StateReader in(state);
  CHECK(in.read<std::uint64_t>() == 42);
  std::vector<Vector3> v;
  in.get(v);
  CHECK(v == std::vector<Vector3>{{1, 2, 3}, {-0.5, 1e-300, 7}});
  CHECK(in.read<std::string>() == "realization 1");
  std::vector<bool> b;
  in.get(b);
  CHECK(b == std::vector<bool>{true, false, true});
  CHECK(in.read<long double>() == 3.25L);
  CHECK(in.at_end());
  CHECK_NOTHROW(in.expect_end());

  // A reader that wants more than there is, or a length beyond the end, stops with an error.
  StateReader short_state(std::string_view(state).substr(0, 20));
  short_state.read<std::uint64_t>();
  std::vector<Vector3> w;
  CHECK_THROWS_WITH(short_state.get(w), Catch::Contains("length"));
  StateReader unread(state);
  unread.read<std::uint64_t>();
  CHECK_THROWS_WITH(unread.expect_end(), Catch::Contains("bytes more than this engine reads"));

  // A count of elements that take at least 8 bytes each, more than the bytes left hold: refused.
  StateWriter counted;
  counted.put(std::uint64_t(3));
  counted.put(std::uint64_t(7));
  counted.put(std::uint64_t(8));
  StateReader three_of_eight(counted.bytes());
  CHECK_THROWS_WITH(three_of_eight.length(8), Catch::Contains("beyond its end"));
  StateReader three_of_one(counted.bytes());
  CHECK(three_of_one.length(1) == 3);
}

TEST_CASE("checkpoint: a file is written atomically and read back whole") {
  const auto folder = aggkit::testing::scratch_folder("checkpoint-file");
  const auto file = folder / "dem.state";
  write_checkpoint(file, header, sample_state());
  CHECK(read_checkpoint(file, header) == sample_state());
  CHECK_FALSE(std::filesystem::exists(folder / "dem.state.partial"));
  // A second write replaces the first whole.
  write_checkpoint(file, header, "x");
  CHECK(read_checkpoint(file, header) == "x");
}

TEST_CASE("checkpoint: damaged, truncated, grown, foreign and mismatched files are refused with the reason") {
  const auto folder = aggkit::testing::scratch_folder("checkpoint-refused");
  const auto file = folder / "dem.state";
  write_checkpoint(file, header, sample_state());
  const std::string good = bytes_of(file);

  SECTION("one flipped bit of the payload: the checksum") {
    std::string bad = good;
    bad[bad.size() - 5] ^= 0x10;
    write_bytes(file, bad);
    CHECK_THAT(refusal(file, header), Catch::Contains("checksum"));
  }
  SECTION("truncated at every length: never accepted") {
    for (std::size_t n = 0; n < good.size(); ++n) {
      write_bytes(file, good.substr(0, n));
      INFO("truncated to " << n << " of " << good.size() << " bytes");
      CHECK(refusal(file, header) != "accepted");
    }
    write_bytes(file, good.substr(0, good.size() - 1));
    CHECK_THAT(refusal(file, header), Catch::Contains("truncated"));
  }
  SECTION("bytes appended") {
    write_bytes(file, good + "extra");
    CHECK_THAT(refusal(file, header), Catch::Contains("its header says"));
  }
  SECTION("not a checkpoint") {
    write_bytes(file, "name = \"scene\"\n");
    CHECK_THAT(refusal(file, header), Catch::Contains("not an aggkit checkpoint"));
  }
  SECTION("another aggkit version") {
    CheckpointHeader other = header;
    other.aggkit_version = "1.2.4";
    CHECK_THAT(refusal(file, other), Catch::Contains("written by aggkit 1.2.3, this is aggkit 1.2.4"));
  }
  SECTION("another engine") {
    CheckpointHeader other = header;
    other.engine = "dem:other";
    CHECK_THAT(refusal(file, other), Catch::Contains("engine dem:collapse"));
  }
  SECTION("another scene") {
    CheckpointHeader other = header;
    other.scene_fingerprint = 0x1234abceull;
    CHECK_THAT(refusal(file, other), Catch::Contains("the scene changed"));
  }
  SECTION("another format version") {
    std::string bad = good;
    bad[8] = char(checkpoint_format_version + 1);  // the uint32 after the 8-byte magic (little-endian)
    write_bytes(file, bad);
    CHECK_THAT(refusal(file, header), Catch::Contains("checkpoint format " + std::to_string(checkpoint_format_version + 1) +
                                                      ", this aggkit reads format " +
                                                      std::to_string(checkpoint_format_version)));
  }
  SECTION("no file") {
    std::filesystem::remove(file);
    CHECK_THAT(refusal(file, header), Catch::Contains("no checkpoint"));
  }
}

TEST_CASE("checkpoint: the fingerprint is FNV-1a 64") {
  // Published test vectors of FNV-1a 64 (Fowler, Noll, Vo).
  CHECK(fnv1a64("") == 0xcbf29ce484222325ull);
  CHECK(fnv1a64("a") == 0xaf63dc4c8601ec8cull);
  CHECK(fnv1a64("foobar") == 0x85944171f73967e8ull);
}
