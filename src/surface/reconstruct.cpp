// The reconstruction pipeline; see include/inhap/surface/reconstruct.hpp.
#include "inhap/surface/reconstruct.hpp"

#include <string>
#include <vector>

#include "inhap/core/error.hpp"
#include "inhap/surface/alpha_shape.hpp"
#include "inhap/surface/mesh_ops.hpp"
#include "inhap/surface/points.hpp"

namespace inhap {

TriMesh reconstruct_surface(std::span<const Vec3> points, const ReconstructOptions& o,
                            ReconstructReport* report) {
  ReconstructReport rep;
  rep.points_in = points.size();
  std::vector<Vec3> pts;
  for (const Vec3& p : points)
    if (all_finite(p)) pts.push_back(p);
  if (o.outlier_k > 0 && pts.size() > o.outlier_k + 1) {
    const std::vector<std::size_t> kept = remove_knn_outliers(pts, o.outlier_k, o.outlier_sigmas);
    std::vector<Vec3> filtered;
    filtered.reserve(kept.size());
    for (std::size_t i : kept) filtered.push_back(pts[i]);
    pts.swap(filtered);
  }
  rep.outliers = rep.points_in - pts.size();
  if (pts.size() < 4)
    throw Error("surface reconstruction: expected at least 4 points, got " +
                std::to_string(pts.size()) + " after outlier removal");
  if (o.jet_k > 0) pts = jet_smooth(pts, o.jet_k);
  if (o.jitter_mm > 0) pts = jitter(pts, o.jitter_mm, o.seed);
  rep.points_used = pts.size();

  AlphaShapeOptions ao;
  ao.alpha = o.alpha;
  AlphaShapeResult as = alpha_shape(pts, ao);
  rep.alpha = as.alpha;
  rep.solid_components = as.solid_components;
  ManifoldReport mr;
  TriMesh mesh = make_manifold(as.mesh, true, &mr);
  rep.duplicated_vertices = mr.duplicated_vertices;
  rep.components_dropped = mr.components > 0 ? mr.components - 1 : 0;
  taubin_smooth(mesh, o.taubin_iterations, o.taubin_lambda, o.taubin_mu);
  mesh = sqrt3_subdivide(mesh, o.subdivisions);
  rep.vertices = mesh.num_vertices();
  rep.faces = mesh.num_triangles();
  if (report) *report = rep;
  return mesh;
}

}  // namespace inhap
