// Mesh geometry waits for MeshIndex and mesh I/O (geometry module); until then a mesh scene is
// rejected with a clear error.
#include "shape_mesh.hpp"

#include "inhap/core/error.hpp"

namespace inhap::lab {

SurfaceQuery query_mesh(const MeshShape&, const Vec3&) {
  return SurfaceQuery{};
}
Box3 mesh_bounds(const MeshShape&) {
  return Box3{};
}
MeshShape load_mesh_shape(const std::string&, const std::string&, const std::string& scene_file) {
  throw ParseError(scene_file, 0, "geometry.type: mesh geometry is not available in this build");
}

}  // namespace inhap::lab
