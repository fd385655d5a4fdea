// Files appear under their final name only when complete.
#include <catch2/catch.hpp>

#include "tests/validation/scene_fixture.hpp"
#include "validation/io/atomic_file.hpp"

using namespace aggkit;

TEST_CASE("harness: an atomic file exists under its name only after commit") {
  const auto folder = aggkit::testing::scratch_folder("atomic-file");
  const auto target = folder / "series.csv";
  {
    AtomicFile file(target);
    file.stream() << "t,M0\n";
    CHECK(std::filesystem::exists(file.temporary_path()));
    CHECK(file.temporary_path().parent_path() == folder);
    CHECK_FALSE(std::filesystem::exists(target));
    file.commit();
    CHECK_FALSE(std::filesystem::exists(file.temporary_path()));
  }
  CHECK(aggkit::testing::read_text(target) == "t,M0\n");
  {
    AtomicFile abandoned(folder / "distribution.csv");
    abandoned.stream() << "half";
  }  // never committed: nothing is left, not even the temporary file
  CHECK(std::distance(std::filesystem::directory_iterator(folder), std::filesystem::directory_iterator()) == 1);
}

TEST_CASE("harness: committing a file nobody wrote is an error") {
  const auto folder = aggkit::testing::scratch_folder("atomic-file-unwritten");
  AtomicFile file(folder / "report.png");
  CHECK_THROWS_AS(file.commit(), std::runtime_error);
  CHECK_FALSE(std::filesystem::exists(folder / "report.png"));
}
