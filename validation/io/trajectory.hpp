#pragma once
// A particle run's trajectory for ParaView: one .vtu per frame (particle_snapshot.hpp, VTK's binary form) in
// <folder>/trajectory/, and <folder>/trajectory.pvd, the collection that lists each frame with its time so
// that ParaView (File > Open trajectory.pvd) plays the run as an animation.
#include <cstddef>
#include <filesystem>
#include <vector>

namespace aggkit {

// <folder>/trajectory/frame_<frame, 5 digits>.vtu
std::filesystem::path trajectory_frame(const std::filesystem::path& folder, std::size_t frame);
// Writes <folder>/trajectory.pvd (atomically) listing frame k at times[k], for every k.
void write_trajectory_collection(const std::filesystem::path& folder, const std::vector<double>& times);

}  // namespace aggkit
