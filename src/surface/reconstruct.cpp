// The reconstruction pipeline; see include/inhap/surface/reconstruct.hpp.
#include "inhap/surface/reconstruct.hpp"
#include "inhap/core/stats.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "inhap/core/error.hpp"
#include "inhap/surface/alpha_shape.hpp"
#include "inhap/surface/mesh_ops.hpp"
#include "inhap/surface/points.hpp"

namespace inhap {

namespace {

/// Orients PCA normals: by the measured directions when given (the sum over the point and
/// its 12 nearest neighbours: a single contact force can point off at a sharp crest or when
/// the tip slips), else outward of the alpha solid (the boundary's vertex normal at the
/// nearest boundary vertex).
void orient_normals(std::vector<Vec3>& normals, std::span<const Vec3> pts,
                    std::span<const Vec3> directions, double alpha) {
  if (!directions.empty()) {
    const KnnTable t = knn_table(pts, 12);
    for (std::size_t i = 0; i < normals.size(); ++i) {
      // Only neighbours on the point's side: on a thin part sampled on both sides (an ear) the
      // two sides' directions cancel.
      Vec3 ref = directions[i];
      for (std::size_t j = 0; j < t.k; ++j) {
        const Vec3& d = directions[static_cast<std::size_t>(t.index[i * t.k + j])];
        if (d.dot(directions[i]) > 0) ref += d;
      }
      if (normals[i].dot(ref) < 0) normals[i] = -normals[i];
    }
    return;
  }
  AlphaShapeOptions ao;
  ao.alpha = alpha;
  const AlphaShapeResult solid = alpha_shape(pts, ao);
  const NearestSites nn = nearest_sites(solid.mesh.positions, pts);
  for (std::size_t i = 0; i < normals.size(); ++i) {
    if (nn.index[i] < 0) continue;
    if (normals[i].dot(solid.mesh.normals[static_cast<std::size_t>(nn.index[i])]) < 0)
      normals[i] = -normals[i];
  }
}

/// Depth of each point's inner twin: `depth`, but at most `thin_factor` x the distance along its
/// normal to the nearest of its 24 neighbours whose normal is opposite (floored at 0.2 depth).
/// A thin part sampled on both sides (an ear): a twin deeper than about half the thickness lands
/// on or beyond the far side's points, and the outer faces there go missing.
std::vector<double> twin_depths(const std::vector<Vec3>& pts, const std::vector<Vec3>& normals,
                                double depth, double thin_factor) {
  std::vector<double> depths(pts.size(), depth);
  if (!(thin_factor > 0)) return depths;
  const KnnTable t = knn_table(pts, 24);
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (std::size_t j = 0; j < t.k; ++j) {
      const auto m = static_cast<std::size_t>(t.index[i * t.k + j]);
      const double behind = (pts[i] - pts[m]).dot(normals[i]);
      if (normals[m].dot(normals[i]) < 0 && behind > 0)
        depths[i] = std::min(depths[i], std::max(0.2 * depth, thin_factor * behind));
    }
  return depths;
}

/// Local point spacing: each point's mean distance to its 6 nearest neighbours, averaged over
/// the point and those neighbours (mm).
std::vector<double> local_spacing(const std::vector<Vec3>& pts) {
  const std::vector<double> d = knn_mean_distances(pts, 6);
  const KnnTable t = knn_table(pts, 6);
  std::vector<double> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    double s = d[i];
    for (std::size_t j = 0; j < t.k; ++j) s += d[static_cast<std::size_t>(t.index[i * t.k + j])];
    out[i] = s / static_cast<double>(t.k + 1);
  }
  return out;
}

/// Shell mode: alpha shape of the points and their inner twins, faces on points only.
TriMesh shell_surface(const std::vector<Vec3>& pts, std::span<const Vec3> dirs,
                      const ReconstructOptions& o, ReconstructReport& rep) {
  std::vector<Vec3> normals = pca_normals(pts, 12);
  orient_normals(normals, pts, dirs, o.alpha);
  double depth = o.shell_depth;
  if (!(depth > 0)) depth = median(knn_mean_distances(pts, 6), 0.0);
  rep.shell_depth = depth;
  const std::size_t n = pts.size();
  std::vector<Vec3> both(pts);
  const std::vector<double> depths = twin_depths(pts, normals, depth, o.thin_part_depth);
  for (std::size_t i = 0; i < n; ++i) both.push_back(pts[i] - depths[i] * normals[i]);
  AlphaShapeOptions ao;
  ao.alpha = o.alpha;
  ao.one_component = !o.patches;
  // Patches: alpha from the point spacing, patch_alpha_factor times the median 6-NN spacing, so
  // no sheet spans a gap between separately tapped parts wider than about twice that (the
  // hollow between a bunny's ears); points sparser than that stay off the shell.
  if (o.patches && !(o.alpha > 0) && !(o.local_alpha > 0) && o.patch_alpha_factor > 0)
    ao.alpha = o.patch_alpha_factor * median(knn_mean_distances(pts, 6), 0.0);
  if (o.patches && !(o.alpha > 0) && o.local_alpha > 0) {
    const std::vector<double> sp = local_spacing(pts);
    ao.point_scale = sp;
    ao.point_scale.insert(ao.point_scale.end(), sp.begin(), sp.end());
    ao.alpha = o.local_alpha;
  }
  AlphaShapeResult as = alpha_shape(both, ao);
  rep.alpha = as.alpha;
  rep.solid_components = as.solid_components;
  TriMesh soup;
  soup.positions = as.mesh.positions;
  const double min_cos = o.max_face_normal_deg > 0 && o.max_face_normal_deg < 180
                             ? std::cos(o.max_face_normal_deg * 3.14159265358979323846 / 180.0)
                             : -2.0;
  for (const Tri& t : as.mesh.triangles) {
    bool outer = true;
    for (auto v : t)
      outer = outer && as.input_index[static_cast<std::size_t>(v)] < static_cast<std::int32_t>(n);
    if (!outer) continue;
    // A face across a thin part (an ear sampled on both sides) joins points whose normals
    // face away from it: it lies inside the object, not on the sampled surface.
    const Vec3& a = soup.positions[static_cast<std::size_t>(t[0])];
    const Vec3 fn = (soup.positions[static_cast<std::size_t>(t[1])] - a)
                        .cross(soup.positions[static_cast<std::size_t>(t[2])] - a)
                        .normalized();
    bool agrees = true;
    for (auto v : t)
      agrees =
          agrees &&
          fn.dot(normals[static_cast<std::size_t>(as.input_index[static_cast<std::size_t>(v)])]) >=
              min_cos;
    // A face across air: two of its points face each other (opposed contact directions, each
    // pointing toward the other point), e.g. a sheet between two ears.
    bool across_air = false;
    if (o.air_gap_cos > -1 && !dirs.empty())
      for (int k = 0; k < 3; ++k) {
        const auto i = static_cast<std::size_t>(as.input_index[static_cast<std::size_t>(t[k])]);
        const auto j =
            static_cast<std::size_t>(as.input_index[static_cast<std::size_t>(t[(k + 1) % 3])]);
        across_air =
            across_air || faces_each_other(pts[i], dirs[i], pts[j], dirs[j], o.air_gap_cos);
      }
    if (agrees && !across_air) soup.triangles.push_back(t);
  }
  return soup;
}

/// Drops the faces of `mesh` (vertices at points of `pts`) two of whose points face each other
/// across air, and the vertices no face uses any more. Returns true when a face was dropped.
bool drop_faces_across_air(TriMesh& mesh, const std::vector<Vec3>& pts,
                           const std::vector<Vec3>& dirs, double max_cos) {
  if (mesh.positions.empty()) return false;
  const NearestSites ns = nearest_sites(pts, mesh.positions);
  std::vector<Tri> kept;
  for (const Tri& t : mesh.triangles) {
    bool air = false;
    for (int k = 0; k < 3; ++k) {
      const auto i = ns.index[static_cast<std::size_t>(t[k])];
      const auto j = ns.index[static_cast<std::size_t>(t[(k + 1) % 3])];
      if (i < 0 || j < 0) continue;
      air = air ||
            faces_each_other(pts[static_cast<std::size_t>(i)], dirs[static_cast<std::size_t>(i)],
                             pts[static_cast<std::size_t>(j)], dirs[static_cast<std::size_t>(j)],
                             max_cos);
    }
    if (!air) kept.push_back(t);
  }
  if (kept.size() == mesh.triangles.size()) return false;
  TriMesh out;
  std::vector<std::int32_t> remap(mesh.positions.size(), -1);
  for (Tri t : kept) {
    for (auto& v : t) {
      auto& r = remap[static_cast<std::size_t>(v)];
      if (r < 0) {
        r = static_cast<std::int32_t>(out.positions.size());
        out.positions.push_back(mesh.positions[static_cast<std::size_t>(v)]);
      }
      v = r;
    }
    out.triangles.push_back(t);
  }
  out.compute_normals();
  mesh = std::move(out);
  return true;
}

/// Shell: where a twin showed through the outer side a few faces are missing; closes such small
/// holes (the patch's own rim is long and stays open). At most 10 edges: a loop of 16 edges of
/// a whole-object sampling (4-5 mm) is a gap of 20 mm across, and filling it invented a face
/// 5 mm off the bunny's paws (seed 2). The gap left by the faces across air is a small hole
/// too: what the filling puts back across air goes again. Returns the holes filled.
std::size_t close_small_holes(TriMesh& mesh, const std::vector<Vec3>& pts,
                              const std::vector<Vec3>& dirs, const ReconstructOptions& o) {
  const std::size_t filled = fill_small_holes(mesh, 10, 0.1);
  // Dropping faces can pinch a vertex between two fans (a non-manifold vertex, which the
  // subdivision refuses): repaired as after the alpha shape.
  if (!dirs.empty() && o.air_gap_cos >= -1 && drop_faces_across_air(mesh, pts, dirs, o.air_gap_cos))
    mesh = make_manifold(mesh, !o.patches, nullptr, o.patches ? o.min_patch_faces : 0);
  return filled;
}

}  // namespace

bool faces_each_other(const Vec3& a, const Vec3& da, const Vec3& b, const Vec3& db,
                      double max_cos) {
  const Vec3 u = b - a;
  return da.dot(db) < max_cos && da.dot(u) > 0 && db.dot(u) < 0;
}

TriMesh reconstruct_surface(std::span<const Vec3> points, std::span<const Vec3> directions,
                            const ReconstructOptions& o, ReconstructReport* report) {
  if (!directions.empty() && directions.size() != points.size())
    throw Error("surface reconstruction: expected one direction per point, got " +
                std::to_string(directions.size()) + " for " + std::to_string(points.size()));
  ReconstructReport rep;
  rep.points_in = points.size();
  std::vector<Vec3> pts, dirs;
  std::vector<std::size_t> source;  // input index of each point in pts
  for (std::size_t i = 0; i < points.size(); ++i)
    if (all_finite(points[i])) {
      pts.push_back(points[i]);
      source.push_back(i);
      if (!directions.empty()) dirs.push_back(directions[i]);
    }
  if (o.outlier_k > 0 && pts.size() > o.outlier_k + 1) {
    const std::vector<std::size_t> kept = remove_knn_outliers(pts, o.outlier_k, o.outlier_sigmas);
    std::vector<Vec3> fp, fd;
    std::vector<std::size_t> fs;
    for (std::size_t i : kept) {
      fp.push_back(pts[i]);
      fs.push_back(source[i]);
      if (!dirs.empty()) fd.push_back(dirs[i]);
    }
    pts.swap(fp);
    dirs.swap(fd);
    source.swap(fs);
  }
  rep.used.assign(points.size(), 0);
  for (std::size_t i : source) rep.used[i] = 1;
  rep.outliers = rep.points_in - pts.size();
  if (pts.size() < 4)
    throw Error("surface reconstruction: expected at least 4 points, got " +
                std::to_string(pts.size()) + " after outlier removal");
  const double jet_cos = std::cos(o.jet_max_angle_deg * 3.14159265358979323846 / 180.0);
  if (o.jet_k > 0) pts = jet_smooth(pts, o.jet_k, dirs, jet_cos, o.jet_feature_factor);
  if (o.jitter_mm > 0) pts = jitter(pts, o.jitter_mm, o.seed);
  rep.points_used = pts.size();

  TriMesh soup;
  if (o.mode == SurfaceMode::kSolid) {
    AlphaShapeOptions ao;
    ao.alpha = o.alpha;
    AlphaShapeResult as = alpha_shape(pts, ao);
    rep.alpha = as.alpha;
    rep.solid_components = as.solid_components;
    soup = std::move(as.mesh);
  } else {
    soup = shell_surface(pts, dirs, o, rep);
  }
  ManifoldReport mr;
  const bool patches = o.mode == SurfaceMode::kShell && o.patches;
  TriMesh mesh = make_manifold(soup, !patches, &mr, patches ? o.min_patch_faces : 0);
  rep.duplicated_vertices = mr.duplicated_vertices;
  rep.components_dropped = mr.components - mr.kept_components;
  rep.components = mr.kept_components;
  if (o.mode == SurfaceMode::kShell) rep.holes_filled = close_small_holes(mesh, pts, dirs, o);
  taubin_smooth(mesh, o.taubin_iterations, o.taubin_lambda, o.taubin_mu);
  mesh = sqrt3_subdivide(mesh, o.subdivisions);
  if (o.final_projection && o.jet_k > 0 && pts.size() > o.jet_k) {
    const double max_move =
        0.5 * std::max(rep.shell_depth, median(knn_mean_distances(pts, 6), 0.0));
    mesh.positions = project_onto_jets(
        pts, mesh.positions, o.jet_k, max_move,
        o.sided_final_projection ? std::span<const Vec3>(dirs) : std::span<const Vec3>(), jet_cos);
    mesh.compute_normals();
  }
  rep.vertices = mesh.num_vertices();
  rep.faces = mesh.num_triangles();
  if (report) *report = rep;
  return mesh;
}

}  // namespace inhap
