#include "validation/io/trajectory.hpp"

#include <cstdio>
#include <string>

#include "validation/io/atomic_file.hpp"
#include "analysis/text.hpp"

namespace aggkit {

std::filesystem::path trajectory_frame(const std::filesystem::path& folder, std::size_t frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%05zu.vtu", frame);
  return folder / "trajectory" / name;
}

void write_trajectory_collection(const std::filesystem::path& folder, const std::vector<double>& times) {
  std::string xml = "<?xml version=\"1.0\"?>\n"
                    "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (std::size_t k = 0; k < times.size(); ++k)
    xml += "    <DataSet timestep=\"" + shortest_text(times[k]) + "\" group=\"\" part=\"0\" file=\"trajectory/" +
           trajectory_frame(folder, k).filename().string() + "\"/>\n";
  xml += "  </Collection>\n</VTKFile>\n";
  write_file_atomically(folder / "trajectory.pvd", xml);
}

}  // namespace aggkit
