// Internal to the renderer: closest point on a triangle with its Voronoi region, and the local
// graph search of Ho, Basdogan & Srinivasan (1999) that keeps the IHIP on the surface.
// Units: mm. Allocation-free, exception-free (servo-ready).
#pragma once

#include <cstdint>

#include "inhap/geometry/mesh_index.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::rendering::detail {

/// Voronoi region of a triangle's closest point: interior, a vertex (its corner 0..2) or an edge
/// (edge e runs from corner e to corner (e+1)%3, the numbering of MeshAdjacency::face_neighbors).
enum class Region : std::uint8_t { kFace, kVertex0, kVertex1, kVertex2, kEdge0, kEdge1, kEdge2 };

struct TriPoint {
  Vec3 point = Vec3::Zero();
  Vec3 bary = Vec3::Zero();
  Region region = Region::kFace;
};

/// Closest point of triangle (a, b, c) to p (Voronoi-region walk). Degenerate triangles give a
/// finite answer (a vertex or edge point).
TriPoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

struct WalkResult {
  SurfacePoint q;           ///< mesh coordinates
  double distance2 = 0;     ///< |q - p|^2, mm^2
  std::uint32_t steps = 0;  ///< triangles moved across
  bool converged = false;   ///< false: the step budget ran out before a local minimum
};

/// Local search from triangle `start`: repeatedly moves to the neighbouring triangle (across the
/// edge, or around the vertex, on which the current closest point lies) that is strictly closer
/// to p, until no neighbour improves. Distances decrease strictly, so it cannot cycle; at most
/// `max_steps` moves. Returns the local minimum of |q - p| over the surface.
WalkResult local_closest(const TriMesh& mesh, const MeshAdjacency& adj, std::int32_t start,
                         const Vec3& p, std::uint32_t max_steps);

}  // namespace inhap::rendering::detail
