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

}  // namespace inhap
