#pragma once
// A starting configuration read from a CSV file: a header line naming the columns, then one particle per
// line,
//   2-D: x,y,vx,vy,radius,mass
//   3-D: x,y,z,vx,vy,vz,radius,mass
// every value a finite number, radius and mass > 0. Blank lines are skipped; nothing else is.
// write_start_file writes the same format (shortest round-trip numbers), so a start read back is
// bit-identical to the one written.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "particle/common/particle_start.hpp"

namespace aggkit {

struct StartFile {
  std::filesystem::path path;        // the file read (as resolved by the caller)
  ParticleStart particles;           // positions, velocities, radii and masses of the file
  std::vector<std::size_t> lines;    // the line of each particle in the file (the header is line 1)

  // "<path> line <k>" of particle i, for messages.
  std::string where(std::size_t particle) const;
};

// The header line of a start file (without the newline).
std::string start_file_header(int dimension);

// Reads a start file. Throws InputError (key "initial.file", value the path) naming the line and what is
// wrong: a missing or unreadable file, a wrong header, a wrong number of columns, a value that is not a
// number or not finite, radius or mass <= 0, or no particle at all.
StartFile read_start_file(const std::filesystem::path& path, int dimension);

// Writes `start` as a start file (std::runtime_error when the file cannot be written).
void write_start_file(const std::filesystem::path& path, int dimension, const ParticleStart& start);

}  // namespace aggkit
