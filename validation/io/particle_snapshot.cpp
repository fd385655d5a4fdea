#include "validation/io/particle_snapshot.hpp"

#include <bit>
#include <charconv>
#include <cstdlib>
#include <limits>
#include <string>
#include <system_error>
#include <type_traits>
#include <vector>

#include "analysis/input_error.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/io/child_process.hpp"
#include "validation/io/python_plotter.hpp"

namespace aggkit {

namespace {

constexpr std::chrono::seconds picture_timeout{300};

void check_sizes(const ParticleConfiguration& config, std::span<const std::uint32_t> cluster,
                 std::span<const std::array<double, 3>> velocity, std::span<const double> radius = {},
                 std::span<const std::array<double, 3>> angular_velocity = {}) {
  check_configuration(config);
  const std::size_t n = config.positions.size();
  if (cluster.size() != n)
    throw InputError("cluster", std::to_string(cluster.size()) + " labels",
                     "needs one label per particle (" + std::to_string(n) + ")");
  if (!velocity.empty() && velocity.size() != n)
    throw InputError("velocity", std::to_string(velocity.size()) + " vectors",
                     "needs one velocity per particle (" + std::to_string(n) + ") or none");
  if (!radius.empty() && radius.size() != n)
    throw InputError("radius", std::to_string(radius.size()) + " radii",
                     "needs one radius per particle (" + std::to_string(n) + ") or none");
  if (!angular_velocity.empty() && angular_velocity.size() != n)
    throw InputError("angular_velocity", std::to_string(angular_velocity.size()) + " vectors",
                     "needs one angular velocity per particle (" + std::to_string(n) + ") or none");
  for (std::uint32_t label : cluster)
    if (label > std::uint32_t(std::numeric_limits<std::int32_t>::max()))
      throw InputError("cluster", std::to_string(label), "labels are written as Int32 (at most 2^31 - 1)");
}

// One DataArray in VTK's inline binary form [VTKFileFormats]: format="binary", its content the base64 encoding
// (RFC 4648, '=' padded) of one byte stream: the byte count of the data as a UInt64 (header_type="UInt64")
// followed by the values, both little-endian (byte_order="LittleEndian") — one encoding of header and data
// together, as VTK's own writer does for uncompressed arrays.
class BinaryArray {
 public:
  template <class T>
  void add(T value) {
    static_assert(std::is_arithmetic_v<T>);
    using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t,
                 std::conditional_t<sizeof(T) == 4, std::uint32_t, std::conditional_t<sizeof(T) == 2, std::uint16_t, std::uint8_t>>>;
    append_little_endian(bytes_, std::bit_cast<Bits>(value));
  }
  // Writes the element, header included, and clears the values.
  void write(std::ostream& out, const char* type, const char* name, int components) {
    out << "        <DataArray type=\"" << type << "\"";
    if (*name) out << " Name=\"" << name << "\"";
    if (components > 1) out << " NumberOfComponents=\"" << components << "\"";
    out << " format=\"binary\">\n          ";
    std::vector<unsigned char> stream;
    stream.reserve(8 + bytes_.size());
    append_little_endian(stream, std::uint64_t(bytes_.size()));
    stream.insert(stream.end(), bytes_.begin(), bytes_.end());
    base64(stream, out);
    out << "\n        </DataArray>\n";
    bytes_.clear();
  }

 private:
  template <class Bits>
  static void append_little_endian(std::vector<unsigned char>& to, Bits bits) {
    for (std::size_t b = 0; b < sizeof(Bits); ++b) to.push_back(static_cast<unsigned char>(bits >> (8 * b)));
  }
  static void base64(const std::vector<unsigned char>& in, std::ostream& out) {
    static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string text;
    text.reserve((in.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < in.size(); i += 3) {
      const std::size_t left = in.size() - i;
      const std::uint32_t group = std::uint32_t(in[i]) << 16 | (left > 1 ? std::uint32_t(in[i + 1]) << 8 : 0u) | (left > 2 ? in[i + 2] : 0u);
      text += digits[group >> 18 & 63];
      text += digits[group >> 12 & 63];
      text += left > 1 ? digits[group >> 6 & 63] : '=';
      text += left > 2 ? digits[group & 63] : '=';
    }
    out << text;
  }
  std::vector<unsigned char> bytes_;
};

std::filesystem::path cluster_plot_script() {
  return plot_script("AGGKIT_CLUSTER_PLOT_SCRIPT", AGGKIT_CLUSTER_PLOT_SCRIPT_BUILD, AGGKIT_CLUSTER_PLOT_SCRIPT_INSTALL);
}

}  // namespace

void write_vtu_snapshot(const std::filesystem::path& path, const ParticleConfiguration& config,
                        std::span<const std::uint32_t> cluster, std::span<const std::array<double, 3>> velocity,
                        std::span<const double> radius, std::span<const std::array<double, 3>> angular_velocity) {
  check_sizes(config, cluster, velocity, radius, angular_velocity);
  const std::size_t n = config.positions.size();
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n"
      << "      <PointData Scalars=\"cluster\"" << (velocity.empty() ? "" : " Vectors=\"velocity\"") << ">\n";
  BinaryArray array;
  for (std::uint32_t label : cluster) array.add(std::int32_t(label));
  array.write(out, "Int32", "cluster", 1);
  for (std::size_t i = 0; i < n; ++i) array.add(radius.empty() ? config.radius : radius[i]);
  array.write(out, "Float64", "radius", 1);
  const auto vectors = [&](const char* name, std::span<const std::array<double, 3>> values) {
    if (values.empty()) return;
    for (const auto& v : values) array.add(v[0]), array.add(v[1]), array.add(config.dimension == 3 ? v[2] : 0.0);
    array.write(out, "Float64", name, 3);
  };
  vectors("velocity", velocity);
  vectors("angular_velocity", angular_velocity);
  out << "      </PointData>\n      <Points>\n";
  for (const auto& p : config.positions) array.add(p[0]), array.add(p[1]), array.add(config.dimension == 3 ? p[2] : 0.0);
  array.write(out, "Float64", "", 3);
  out << "      </Points>\n      <Cells>\n";
  for (std::size_t i = 0; i < n; ++i) array.add(std::int64_t(i));
  array.write(out, "Int64", "connectivity", 1);
  for (std::size_t i = 1; i <= n; ++i) array.add(std::int64_t(i));
  array.write(out, "Int64", "offsets", 1);
  for (std::size_t i = 0; i < n; ++i) array.add(std::uint8_t(1));  // VTK_VERTEX
  array.write(out, "UInt8", "types", 1);
  out << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  file.commit();
}

bool write_cluster_picture(const std::filesystem::path& png, const ParticleConfiguration& config,
                           std::span<const std::uint32_t> cluster, std::string* error) {
  auto fail = [error](std::string why) {
    if (error) *error = std::move(why);
    return false;
  };
  check_sizes(config, cluster, {});
  try {
    // The particles go to the plotter through a temporary CSV next to the picture (removed afterwards).
    AtomicFile points(png.parent_path() / (png.filename().string() + ".points.csv"));
    std::ostream& out = points.stream();
    out << "x,y,z,cluster\n";
    char buffer[32];
    for (std::size_t i = 0; i < config.positions.size(); ++i) {
      for (int a = 0; a < 3; ++a) {
        const double value = a < config.dimension ? config.positions[i][a] : 0.0;
        out.write(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr - buffer);
        out.put(',');
      }
      out << cluster[i] << '\n';
    }
    out.flush();
    if (!out) return fail("cannot write " + points.temporary_path().string());

    AtomicFile picture(png);
    std::vector<std::string> argv{plot_interpreter(), cluster_plot_script().string(),
                                  "--points", points.temporary_path().string(),
                                  "--output", picture.temporary_path().string(),
                                  "--radius", std::to_string(config.radius),
                                  "--dimension", std::to_string(config.dimension)};
    if (config.periodic) argv.insert(argv.end(), {"--box", std::to_string(config.box[0]), std::to_string(config.box[1])});
    const ProcessOutcome run = run_process(argv, picture_timeout);
    if (!run.succeeded()) {
      std::string why = !run.started ? run.output
                        : run.timed_out ? "the plotter ran longer than " + std::to_string(picture_timeout.count()) + " s"
                                        : last_output_line(run.output);
      if (why.empty()) why = "the plotter exited with status " + std::to_string(run.exit_status);
      return fail(argv[0] + " " + argv[1] + ": " + why);
    }
    picture.commit();
    return true;
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}

}  // namespace aggkit
