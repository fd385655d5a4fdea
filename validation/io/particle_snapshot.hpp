#pragma once
// Output formats for the particle engines (ED, TS, DEM):
//  * a VTK XML UnstructuredGrid file (.vtu, for ParaView): one VTK_VERTEX cell per particle, point data
//    "cluster" (Int32), "radius" (Float64: per particle if given, else the configuration's one radius) and,
//    if given, "velocity" and "angular_velocity" (3 components each); every DataArray in VTK's inline binary
//    form (format="binary": base64 of a UInt64 byte count and the little-endian values, header_type="UInt64",
//    as ParaView/VTK read it), written atomically (validation/io/atomic_file.hpp);
//  * a PNG picture of the configuration, particles drawn as discs coloured by cluster (3-D: projected on
//    the x-y plane), drawn by validation/io/plot_clusters.py under the plotting interpreter of
//    validation/io/python_plotter.hpp. A failure to plot is reported (false + message), never thrown: the caller warns.
#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "analysis/particle_configuration.hpp"

namespace aggkit {

// Throws InputError if `cluster` (or a non-empty `velocity`, `radius` or `angular_velocity`) does not have one
// entry per particle, or a label exceeds the Int32 range; std::runtime_error if the file cannot be written.
void write_vtu_snapshot(const std::filesystem::path& path, const ParticleConfiguration& config,
                        std::span<const std::uint32_t> cluster,
                        std::span<const std::array<double, 3>> velocity = {},
                        std::span<const double> radius = {},
                        std::span<const std::array<double, 3>> angular_velocity = {});

// Writes `png` (atomically) and returns true; if plotting fails returns false with the reason in *error
// (bad sizes are still an InputError, as for the .vtu).
// The script is $AGGKIT_CLUSTER_PLOT_SCRIPT, else plot_clusters.py in the source or install tree.
bool write_cluster_picture(const std::filesystem::path& png, const ParticleConfiguration& config,
                           std::span<const std::uint32_t> cluster, std::string* error = nullptr);

}  // namespace aggkit
