#include "validation/io/particle_snapshot.hpp"

#include <charconv>
#include <cstdlib>
#include <limits>
#include <string>
#include <system_error>
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

// Appends numbers in their shortest round-trip form, separated by spaces.
class NumberWriter {
 public:
  explicit NumberWriter(std::ostream& out) : out_(out) {}
  template <class T>
  void operator()(T value) {
    char buffer[32];
    const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
    out_.write(buffer, end - buffer);
    out_.put(' ');
  }

 private:
  std::ostream& out_;
};

void data_array_open(std::ostream& out, const char* type, const char* name, int components) {
  out << "        <DataArray type=\"" << type << "\"";
  if (*name) out << " Name=\"" << name << "\"";
  if (components > 1) out << " NumberOfComponents=\"" << components << "\"";
  out << " format=\"ascii\">\n";
}

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
  NumberWriter number(out);
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n"
      << "      <PointData Scalars=\"cluster\"" << (velocity.empty() ? "" : " Vectors=\"velocity\"") << ">\n";
  data_array_open(out, "Int32", "cluster", 1);
  for (std::uint32_t label : cluster) number(std::int32_t(label));
  out << "\n        </DataArray>\n";
  data_array_open(out, "Float64", "radius", 1);
  for (std::size_t i = 0; i < n; ++i) number(radius.empty() ? config.radius : radius[i]);
  out << "\n        </DataArray>\n";
  const auto vectors = [&](const char* name, std::span<const std::array<double, 3>> values) {
    if (values.empty()) return;
    data_array_open(out, "Float64", name, 3);
    for (const auto& v : values) number(v[0]), number(v[1]), number(config.dimension == 3 ? v[2] : 0.0);
    out << "\n        </DataArray>\n";
  };
  vectors("velocity", velocity);
  vectors("angular_velocity", angular_velocity);
  out << "      </PointData>\n      <Points>\n";
  data_array_open(out, "Float64", "", 3);
  for (const auto& p : config.positions) number(p[0]), number(p[1]), number(config.dimension == 3 ? p[2] : 0.0);
  out << "\n        </DataArray>\n      </Points>\n      <Cells>\n";
  data_array_open(out, "Int64", "connectivity", 1);
  for (std::size_t i = 0; i < n; ++i) number(std::int64_t(i));
  out << "\n        </DataArray>\n";
  data_array_open(out, "Int64", "offsets", 1);
  for (std::size_t i = 1; i <= n; ++i) number(std::int64_t(i));
  out << "\n        </DataArray>\n";
  data_array_open(out, "UInt8", "types", 1);
  for (std::size_t i = 0; i < n; ++i) out << "1 ";  // VTK_VERTEX
  out << "\n        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
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
