// Reading a point set for reconstruction: the vertices of a PLY or OBJ file (faces ignored),
// with the PLY's nx,ny,nz as measured outward directions when the file has them.
// Units: mm.
#pragma once

#include <string>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap {

struct PointSet {
  std::vector<Vec3> points;
  std::vector<Vec3> directions;  ///< empty unless the file stores nx,ny,nz
};

/// Throws ParseError / IoError like read_mesh().
PointSet read_points(const std::string& path);

/// Writes the points (and the directions as nx,ny,nz when there are any) as a PLY (binary, or
/// ASCII) or OBJ (points only) file that read_points() reads back exactly, atomically. Throws
/// Error when directions are given for some points only, IoError when it cannot write.
void write_points(const std::string& path, const PointSet& points, bool ascii = false);

}  // namespace inhap
