// ShapeQuery on a triangle mesh of the undeformed object (the shape model of chapter 3), for
// geometric contact, p_c / n_c and the proxy projection. Units: mm.
//
// With probe_radius = 0 the mesh is taken as the probe-centre surface itself (a shape model
// built from probe-centre contact points, as the thesis does in 4.3.2); with R > 0 it is the
// object's surface and queries answer for its offset by R (the surface the probe centre
// touches). Normals: the barycentric blend of the vertex normals at the closest point (smooth
// across faces) for R = 0; the exact offset-surface normal (p - closest) / |p - closest|, signed
// by the blended normal, for R > 0. Queries are const, allocation-free and exception-free.
#pragma once

#include <vector>

#include "inhap/friction/shape_query.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::friction {

class MeshSurface final : public ShapeQuery {
 public:
  /// Copies what it needs (the mesh may be destroyed afterwards). Throws inhap::Error on an
  /// empty mesh or a negative radius.
  explicit MeshSurface(const TriMesh& mesh, double probe_radius = 0.0);
  using ShapeQuery::closest;
  bool closest(const Vec3& p, Vec3& point, Vec3& normal,
               double max_distance) const noexcept override;
  /// hint: the mesh triangle of the previous answer (MeshIndex::closest_point's warm start).
  bool closest(const Vec3& p, Vec3& point, Vec3& normal, double max_distance,
               std::int32_t& hint) const noexcept override;
  double probe_radius() const { return radius_; }

 private:
  MeshIndex index_;
  std::vector<Tri> tris_;
  std::vector<Vec3> normals_;
  double radius_;
};

}  // namespace inhap::friction
