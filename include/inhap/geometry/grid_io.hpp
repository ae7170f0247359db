// Writing height and stiffness maps in the formats read_grid() reads. Units: as the grid's
// values (heights mm, stiffness N/mm, or raw levels).
#pragma once

#include <string>

#include "inhap/geometry/heightmap.hpp"

namespace inhap {

/// Writes `grid` atomically by the file's extension: .csv (one grid row per line, shortest
/// round-trip digits: read_grid gives the same values back) or .pgm (P5, 16-bit: the values must
/// be integer levels in [0, 65535]). Throws Error naming the file otherwise, IoError when it
/// cannot be written.
void write_grid(const std::string& path, const Grid& grid);

}  // namespace inhap
