#include "inhap/friction/mesh_rim.hpp"

#include <algorithm>
#include <limits>

#include "inhap/core/error.hpp"

namespace inhap::friction {

MeshRim::MeshRim(const TriMesh& mesh)
    : tris_(mesh.triangles), edge_out_(mesh.triangles.size()), vertex_out_(mesh.positions.size()) {
  if (mesh.triangles.empty()) throw Error("shape mesh: expected at least one triangle");
  index_ = MeshIndex(mesh);
  const MeshAdjacency adj = build_adjacency(mesh);
  const auto& x = mesh.positions;
  for (std::size_t f = 0; f < tris_.size(); ++f) {
    const Tri& t = tris_[f];
    const Vec3 n = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
    for (int e = 0; e < 3; ++e) {
      edge_out_[f][e] = Vec3::Zero();
      if (adj.face_neighbors[f][e] != -1) continue;
      ++boundary_edges_;
      const Vec3 p0 = x[t[e]], p1 = x[t[(e + 1) % 3]], third = x[t[(e + 2) % 3]];
      Vec3 out = (p1 - p0).cross(n);
      if (!(out.norm() > 0)) continue;  // a degenerate face: no direction
      out.normalize();
      if (out.dot(third - p0) > 0) out = -out;
      edge_out_[f][e] = out;
      vertex_out_[t[e]].push_back(out);
      vertex_out_[t[(e + 1) % 3]].push_back(out);
    }
  }
}

double MeshRim::beyond_mm(const Vec3& p) const {
  if (boundary_edges_ == 0 || !p.allFinite()) return 0.0;
  const ClosestPoint cp = index_.closest_point(p);
  if (!cp.valid()) return 0.0;
  constexpr double kOnFeature = 1e-9;  // a barycentric weight that counts as zero
  const Tri& t = tris_[cp.triangle];
  int zeros = 0, nonzero = 0, zero = 0;
  for (int i = 0; i < 3; ++i)
    if (cp.bary[i] <= kOnFeature)
      ++zeros, zero = i;
    else
      nonzero = i;
  const Vec3 d = p - cp.point;
  if (zeros == 1)  // on the edge opposite vertex `zero`: edge (zero + 1) % 3
    return std::max(0.0, d.dot(edge_out_[cp.triangle][(zero + 1) % 3]));
  if (zeros == 2) {  // at vertex `nonzero`
    double best = 0.0;
    for (const Vec3& out : vertex_out_[t[nonzero]]) best = std::max(best, d.dot(out));
    return best;
  }
  return 0.0;  // inside the face
}

}  // namespace inhap::friction
