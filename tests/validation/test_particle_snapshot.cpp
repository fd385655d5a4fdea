// Particle snapshots: the .vtu parses as VTK XML with the right structure and counts (checked by Python's
// XML parser, an independent reader), and the cluster picture is a PNG. The picture needs matplotlib: test
// cases tagged [needs-matplotlib] fail with a line "SKIPPED: matplotlib ..." where the plot interpreter
// cannot import it, and CTest reports exactly those as skipped (SKIP_REGULAR_EXPRESSION,
// tests/CMakeLists.txt) — never as passed.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdlib>
#include <fstream>

#include "analysis/input_error.hpp"
#include "tests/validation/scene_fixture.hpp"
#include "validation/io/child_process.hpp"
#include "validation/io/particle_snapshot.hpp"
#include "validation/harness/plot.hpp"

using namespace aggkit;

namespace {

ParticleConfiguration five_particles(int dimension) {
  ParticleConfiguration c;
  c.dimension = dimension;
  c.radius = 0.25;
  c.box = {4, 4, 4};
  c.periodic = true;
  c.positions = {{0.5, 0.5, 1}, {1.0, 0.5, 1}, {3.9, 2, 1.5}, {0.1, 2, 1.5}, {2, 3.25, 0.125}};
  return c;
}

// Python's ElementTree and base64 module read the file (an independent reader of the binary form): every
// DataArray must be format="binary", its base64 text one stream of a UInt64 little-endian byte count
// (header_type="UInt64") and exactly that many bytes of little-endian values. The script prints one line per
// DataArray: its name, type, NumberOfComponents, the number of values and every value (integers as such,
// doubles in their shortest round-trip form, ".0" dropped), plus the Piece counts.
const char* vtu_reader = R"(
import sys, base64, struct, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
assert root.tag == 'VTKFile' and root.get('type') == 'UnstructuredGrid', root.attrib
assert root.get('byte_order') == 'LittleEndian' and root.get('header_type') == 'UInt64', root.attrib
piece = root.find('UnstructuredGrid/Piece')
print('piece', piece.get('NumberOfPoints'), piece.get('NumberOfCells'))
codes = {'Int32': 'i', 'Int64': 'q', 'UInt8': 'B', 'Float64': 'd'}
for section in ('PointData', 'Points', 'Cells'):
    for array in piece.find(section).findall('DataArray'):
        assert array.get('format') == 'binary', array.attrib
        raw = base64.b64decode(''.join(array.text.split()), validate=True)
        (size,) = struct.unpack('<Q', raw[:8])
        assert size == len(raw) - 8, (array.get('Name'), size, len(raw))
        code = codes[array.get('type')]
        values = struct.unpack('<%d%s' % (size // struct.calcsize(code), code), raw[8:])
        assert size == len(values) * struct.calcsize(code)
        text = [repr(v)[:-2] if repr(v).endswith('.0') else repr(v) for v in values]
        print(section, array.get('Name', '-'), array.get('type'), array.get('NumberOfComponents', '1'),
              len(values), ' '.join(text))
)";

std::string read_with_python(const std::filesystem::path& vtu) {
  const ProcessOutcome run = run_process({plot_interpreter(), "-c", vtu_reader, vtu.string()}, std::chrono::seconds(60));
  INFO(run.output);
  REQUIRE(run.succeeded());
  return run.output;
}

bool matplotlib_available() {
  return run_process({plot_interpreter(), "-c", "import matplotlib, numpy"}, std::chrono::seconds(60)).succeeded();
}

}  // namespace

TEST_CASE("particle snapshot: the binary .vtu decodes to every value written, one vertex per particle") {
  const auto folder = aggkit::testing::scratch_folder("particle-snapshot-vtu");
  const auto c = five_particles(3);
  const std::vector<std::uint32_t> cluster{0, 0, 1, 1, 2};
  const std::vector<std::array<double, 3>> velocity{{1, 0, 0}, {1, 0, 0}, {-0.5, 0.25, 2}, {-0.5, 0.25, 2}, {0, 0, 0}};
  write_vtu_snapshot(folder / "with-velocity.vtu", c, cluster, velocity);
  CHECK(read_with_python(folder / "with-velocity.vtu") ==
        "piece 5 5\n"
        "PointData cluster Int32 1 5 0 0 1 1 2\n"
        "PointData radius Float64 1 5 0.25 0.25 0.25 0.25 0.25\n"
        "PointData velocity Float64 3 15 1 0 0 1 0 0 -0.5 0.25 2 -0.5 0.25 2 0 0 0\n"
        "Points - Float64 3 15 0.5 0.5 1 1 0.5 1 3.9 2 1.5 0.1 2 1.5 2 3.25 0.125\n"
        "Cells connectivity Int64 1 5 0 1 2 3 4\n"
        "Cells offsets Int64 1 5 1 2 3 4 5\n"
        "Cells types UInt8 1 5 1 1 1 1 1\n");

  // 2-D, no velocity: z is written as 0 and there is no velocity array.
  write_vtu_snapshot(folder / "plain.vtu", five_particles(2), cluster);
  CHECK(read_with_python(folder / "plain.vtu") ==
        "piece 5 5\n"
        "PointData cluster Int32 1 5 0 0 1 1 2\n"
        "PointData radius Float64 1 5 0.25 0.25 0.25 0.25 0.25\n"
        "Points - Float64 3 15 0.5 0.5 0 1 0.5 0 3.9 2 0 0.1 2 0 2 3.25 0\n"
        "Cells connectivity Int64 1 5 0 1 2 3 4\n"
        "Cells offsets Int64 1 5 1 2 3 4 5\n"
        "Cells types UInt8 1 5 1 1 1 1 1\n");
  // Only the two snapshots are there (no temporary files left behind).
  CHECK(std::distance(std::filesystem::directory_iterator(folder), std::filesystem::directory_iterator()) == 2);
}

TEST_CASE("particle snapshot: per-particle radii and angular velocities survive the binary form bit for bit") {
  // Values with no short decimal form (1/3, 0.1 + 0.2, subnormal and huge magnitudes, −0) and labels up to
  // 2^31 − 1: the decoded doubles must print as the same shortest round-trip strings as the ones written.
  const auto folder = aggkit::testing::scratch_folder("particle-snapshot-vtu-exact");
  const auto c = five_particles(3);
  const std::vector<std::uint32_t> cluster{2147483647u, 0, 7, 1, 3};
  const std::vector<double> radius{1.0 / 3, 0.1 + 0.2, 4.9e-324, 1.7976931348623157e308, 0.25};
  const std::vector<std::array<double, 3>> spin{{-0.0, 1e-300, -2.5}, {1.0 / 7, 0, 0}, {0, 0, 0}, {0, 0, 0}, {6.02214076e23, -1, 1}};
  write_vtu_snapshot(folder / "spin.vtu", c, cluster, {}, radius, spin);
  const std::string text = read_with_python(folder / "spin.vtu");
  CHECK_THAT(text, Catch::Contains("PointData cluster Int32 1 5 2147483647 0 7 1 3\n"));
  CHECK_THAT(text, Catch::Contains("PointData radius Float64 1 5 0.3333333333333333 0.30000000000000004 5e-324 1.7976931348623157e+308 0.25\n"));
  CHECK_THAT(text, Catch::Contains("PointData angular_velocity Float64 3 15 -0 1e-300 -2.5 0.14285714285714285 0 0 0 0 0 0 0 0 6.02214076e+23 -1 1\n"));
  CHECK_THAT(text, !Catch::Contains("PointData velocity"));
}

TEST_CASE("particle snapshot: sizes that do not match the particles are an input error") {
  const auto folder = aggkit::testing::scratch_folder("particle-snapshot-bad");
  const auto c = five_particles(2);
  const std::vector<std::uint32_t> short_labels{0, 1};
  CHECK_THROWS_AS(write_vtu_snapshot(folder / "bad.vtu", c, short_labels), InputError);
  const std::vector<std::uint32_t> labels{0, 1, 2, 3, 4};
  const std::vector<std::array<double, 3>> velocity{{1, 0, 0}};
  CHECK_THROWS_WITH(write_vtu_snapshot(folder / "bad.vtu", c, labels, velocity), Catch::Contains("velocity"));
  CHECK_THROWS_AS(write_cluster_picture(folder / "bad.png", c, short_labels), InputError);
  CHECK(std::filesystem::is_empty(folder));
}

TEST_CASE("particle snapshot: the cluster picture is a PNG", "[needs-matplotlib]") {
  const auto folder = aggkit::testing::scratch_folder("particle-snapshot-png");
  const std::vector<std::uint32_t> cluster{0, 0, 1, 1, 2};
  if (!matplotlib_available())
    FAIL("SKIPPED: matplotlib not importable by " << plot_interpreter() << " (another: AGGKIT_PYTHON)");
  for (int dimension : {2, 3}) {
    const auto png = folder / ("clusters-" + std::to_string(dimension) + "d.png");
    std::string error;
    CHECK(write_cluster_picture(png, five_particles(dimension), cluster, &error));
    INFO(error);
    CHECK(error.empty());
    std::ifstream in(png, std::ios::binary);
    char signature[8] = {};
    in.read(signature, 8);
    CHECK(std::string(signature, 8) == "\x89PNG\r\n\x1a\n");
  }
  CHECK(std::distance(std::filesystem::directory_iterator(folder), std::filesystem::directory_iterator()) == 2);
}

TEST_CASE("particle snapshot: a plotter that fails gives a message, not an exception or a file") {
  const auto folder = aggkit::testing::scratch_folder("particle-snapshot-png-failure");
  const std::vector<std::uint32_t> cluster{0, 0, 1, 1, 2};
  ::setenv("AGGKIT_CLUSTER_PLOT_SCRIPT", (folder / "no-such-script.py").c_str(), 1);
  std::string error;
  const bool written = write_cluster_picture(folder / "clusters.png", five_particles(2), cluster, &error);
  ::unsetenv("AGGKIT_CLUSTER_PLOT_SCRIPT");
  CHECK_FALSE(written);
  CHECK_THAT(error, Catch::Contains("no-such-script.py"));
  CHECK(std::filesystem::is_empty(folder));
}
