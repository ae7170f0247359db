// Triangle-mesh geometry of the virtual lab: exact distance through MeshIndex, inside/outside
// from the normal at the closest point (face normal inside a face, angle-weighted vertex
// normals interpolated on edges and at vertices).
#include "shape_mesh.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::lab {

SurfaceQuery query_mesh(const MeshShape& s, const Vec3& p) {
  SurfaceQuery out;
  if (!s.index || !s.mesh) return out;
  const ClosestPoint cp = s.index->closest_point(p);
  if (!cp.valid()) return out;
  const auto f = static_cast<std::size_t>(cp.triangle);
  Vec3 n;
  constexpr double kEdge = 1e-9;
  if (cp.bary.minCoeff() > kEdge) {
    n = s.mesh->face_normal(f);
  } else {
    const Tri& t = s.mesh->triangles[f];
    n = Vec3::Zero();
    for (int k = 0; k < 3; ++k) n += cp.bary[k] * s.mesh->normals[static_cast<std::size_t>(t[k])];
    if (n.squaredNorm() < 1e-24) n = s.mesh->face_normal(f);
  }
  n.normalize();
  const Vec3 d = p - cp.point;
  const double dist = d.norm();
  const bool inside = d.dot(n) < 0;
  out.closest = cp.point;
  out.distance = inside ? -dist : dist;
  out.normal = dist > 1e-9 ? Vec3((inside ? -d : d) / dist) : n;
  return out;
}

Box3 mesh_bounds(const MeshShape& s) {
  return s.index ? s.index->bounds() : Box3{};
}

MeshShape make_mesh_shape(TriMesh mesh, std::string path) {
  mesh.compute_normals();
  MeshShape s;
  s.path = std::move(path);
  s.index = std::make_shared<const MeshIndex>(mesh);
  s.mesh = std::make_shared<const TriMesh>(std::move(mesh));
  return s;
}

MeshShape load_mesh_shape(const std::string& path, const std::string& scene_dir,
                          const std::string& scene_file, double scale, const Vec3& offset,
                          char up) {
  namespace fs = std::filesystem;
  const fs::path full = fs::path(path).is_absolute() ? fs::path(path) : fs::path(scene_dir) / path;
  TriMesh mesh;
  try {
    mesh = read_mesh(full.string());
  } catch (const Error& e) {
    throw ParseError(scene_file, 0,
                     fmt::format("geometry.path: cannot load the mesh: {}", e.what()));
  }
  if (mesh.num_triangles() == 0)
    throw ParseError(scene_file, 0,
                     fmt::format("geometry.path: expected a mesh with triangles, got none in {}",
                                 full.string()));
  for (auto& v : mesh.positions) {
    const Vec3 q = scale * v;
    v = (up == 'y' ? Vec3(q.x(), -q.z(), q.y()) : q) + offset;  // y-up files: +y -> +z
  }
  MeshShape s = make_mesh_shape(std::move(mesh), path);
  s.scale = scale;
  s.offset = offset;
  s.up = up;
  return s;
}

}  // namespace inhap::lab
