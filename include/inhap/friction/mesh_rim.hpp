// Where a probe lies beyond the rim of an open shape mesh. A shape modelled from taps covers the
// tapped area only; a probe beyond its rim gets its proxy on the rim, which is not where the
// object is (issue 18: the proxy error grows from 0.14 to 1.95 mm there). `inhap sys proxy`
// counts such samples and warns. Units: mm.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::friction {

class MeshRim {
 public:
  /// Copies what it needs (the mesh may be destroyed afterwards). Throws inhap::Error on an
  /// empty mesh.
  explicit MeshRim(const TriMesh& mesh);
  /// How far p lies beyond the rim, mm, when its closest mesh point is on a boundary edge (the
  /// component of p - closest along the edge's outward normal in the plane of its face) or a
  /// boundary vertex (the largest such component over the vertex's boundary edges); 0 when the
  /// closest point is inside the mesh or p lies straight above or below the rim. A closed mesh
  /// has no rim: always 0.
  double beyond_mm(const Vec3& p) const;
  bool has_rim() const { return boundary_edges_ > 0; }

 private:
  MeshIndex index_;
  std::vector<Tri> tris_;
  /// Per face and edge e = (t[e], t[(e+1)%3]): the outward unit normal of a boundary edge in the
  /// face's plane (zero for an interior edge).
  std::vector<std::array<Vec3, 3>> edge_out_;
  std::vector<std::vector<Vec3>> vertex_out_;  ///< outward normals of a vertex's boundary edges
  std::size_t boundary_edges_ = 0;
};

}  // namespace inhap::friction
