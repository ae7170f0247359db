#include "inhap/friction/mesh_surface.hpp"

#include <cmath>

#include "inhap/core/error.hpp"

namespace inhap::friction {

MeshSurface::MeshSurface(const TriMesh& mesh, double probe_radius)
    : index_(mesh), tris_(mesh.triangles), radius_(probe_radius) {
  if (mesh.triangles.empty()) throw Error("shape mesh: expected at least one triangle");
  if (!(probe_radius >= 0) || !std::isfinite(probe_radius))
    throw Error("shape mesh: expected a probe radius >= 0 mm");
  if (mesh.normals.size() == mesh.positions.size()) {
    normals_ = mesh.normals;
  } else {
    TriMesh copy = mesh;
    copy.compute_normals();
    normals_ = copy.normals;
  }
}

bool MeshSurface::closest(const Vec3& p, Vec3& point, Vec3& normal,
                          double max_distance) const noexcept {
  std::int32_t no_hint = -1;
  return closest(p, point, normal, max_distance, no_hint);
}

bool MeshSurface::closest(const Vec3& p, Vec3& point, Vec3& normal, double max_distance,
                          std::int32_t& hint) const noexcept {
  if (!p.allFinite()) return false;
  // The mesh is the offset surface's base: search radius + max_distance around p.
  const ClosestPoint cp = index_.closest_point(p, max_distance + radius_, hint);
  if (!cp.valid()) return false;
  hint = cp.triangle;
  const Tri& t = tris_[cp.triangle];
  Vec3 n =
      cp.bary.x() * normals_[t[0]] + cp.bary.y() * normals_[t[1]] + cp.bary.z() * normals_[t[2]];
  const double nn = n.norm();
  if (!(nn > 0)) return false;
  n /= nn;
  if (radius_ > 0) {
    const Vec3 d = p - cp.point;
    const double dn = d.norm();
    if (dn > 1e-9) n = (d.dot(n) >= 0 ? 1.0 : -1.0) * d / dn;
    point = cp.point + radius_ * n;
  } else {
    point = cp.point;
  }
  normal = n;
  return true;
}

}  // namespace inhap::friction
