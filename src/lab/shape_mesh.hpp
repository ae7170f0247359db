// Internal: triangle-mesh geometry of the virtual lab (kept apart from the analytic shapes).
#pragma once

#include <string>

#include "inhap/lab/shape.hpp"

namespace inhap::lab {

/// Exact distance, sign from the interpolated vertex normal at the closest point.
SurfaceQuery query_mesh(const MeshShape& shape, const Vec3& p);
Box3 mesh_bounds(const MeshShape& shape);
/// Loads a PLY/OBJ mesh named in a scene file (`path` relative to `scene_dir`), placed as
/// described at MeshShape; errors name `scene_file`.
MeshShape load_mesh_shape(const std::string& path, const std::string& scene_dir,
                          const std::string& scene_file, double scale, const Vec3& offset, char up);

}  // namespace inhap::lab
