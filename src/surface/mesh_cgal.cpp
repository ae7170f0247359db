// Manifold repair and sqrt(3) subdivision with CGAL (Polygon_mesh_processing, Surface_mesh,
// Subdivision_method_3). One of the three CGAL translation units of the surface module.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>

#include <array>
#include <vector>

#include "inhap/core/error.hpp"
#include "inhap/surface/mesh_ops.hpp"

namespace inhap {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using SMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

TriMesh from_surface_mesh(const SMesh& sm) {
  TriMesh out;
  std::vector<std::int32_t> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), -1);
  for (auto v : sm.vertices()) {
    index[v.idx()] = static_cast<std::int32_t>(out.positions.size());
    const Point& p = sm.point(v);
    out.positions.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : sm.faces()) {
    Tri t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      if (k < 3) t[static_cast<std::size_t>(k)] = index[v.idx()];
      ++k;
    }
    if (k == 3) out.triangles.push_back(t);
  }
  out.compute_normals();
  return out;
}

SMesh to_surface_mesh(const TriMesh& mesh) {
  // (used by sqrt3_subdivide and fill_small_holes)
  std::vector<Point> pts;
  pts.reserve(mesh.positions.size());
  for (const Vec3& p : mesh.positions) pts.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::array<std::size_t, 3>> faces;
  faces.reserve(mesh.triangles.size());
  for (const Tri& t : mesh.triangles)
    faces.push_back({static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                     static_cast<std::size_t>(t[2])});
  SMesh sm;
  if (!PMP::is_polygon_soup_a_polygon_mesh(faces))
    throw Error("mesh operation: expected a manifold, consistently oriented mesh");
  PMP::polygon_soup_to_polygon_mesh(pts, faces, sm);
  return sm;
}

}  // namespace

TriMesh make_manifold(const TriMesh& soup, bool keep_largest, ManifoldReport* report,
                      std::size_t min_component_faces) {
  ManifoldReport rep;
  std::vector<Point> pts;
  pts.reserve(soup.positions.size());
  for (const Vec3& p : soup.positions) pts.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::vector<std::size_t>> faces;
  faces.reserve(soup.triangles.size());
  for (const Tri& t : soup.triangles)
    faces.push_back({static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                     static_cast<std::size_t>(t[2])});
  const std::size_t faces_in = faces.size();
  PMP::repair_polygon_soup(pts, faces);
  const std::size_t points_before = pts.size();
  PMP::orient_polygon_soup(pts, faces);
  rep.duplicated_vertices = pts.size() - points_before;
  SMesh sm;
  if (!faces.empty()) PMP::polygon_soup_to_polygon_mesh(pts, faces, sm);

  auto fcc = sm.add_property_map<SMesh::Face_index, std::size_t>("f:cc", 0).first;
  rep.components = faces.empty() ? 0 : PMP::connected_components(sm, fcc);
  if (keep_largest && rep.components > 1) {
    PMP::keep_largest_connected_components(sm, 1);
    sm.collect_garbage();
  } else if (min_component_faces > 1 && rep.components > 1) {
    PMP::keep_large_connected_components(sm, min_component_faces);
    sm.collect_garbage();
  }
  rep.kept_components = rep.components;
  if (rep.components > 1) {
    auto kept = sm.add_property_map<SMesh::Face_index, std::size_t>("f:cc2", 0).first;
    rep.kept_components = PMP::connected_components(sm, kept);
  }
  if (!faces.empty() && CGAL::is_closed(sm) && !PMP::is_outward_oriented(sm))
    PMP::reverse_face_orientations(sm);
  TriMesh out = from_surface_mesh(sm);
  rep.dropped_faces = faces_in - out.triangles.size();
  if (report) *report = rep;
  return out;
}

std::size_t fill_small_holes(TriMesh& mesh, std::size_t max_edges, double max_fraction) {
  if (mesh.triangles.empty()) return 0;
  SMesh sm = to_surface_mesh(mesh);
  // Collect one border halfedge per loop first (filling changes the border).
  std::vector<SMesh::Halfedge_index> loops;
  std::vector<char> seen(sm.number_of_halfedges(), 0);
  for (auto h : sm.halfedges()) {
    if (!sm.is_border(h) || seen[h.idx()]) continue;
    std::size_t n = 0;
    for (auto g : CGAL::halfedges_around_face(h, sm)) {
      seen[g.idx()] = 1;
      ++n;
    }
    if (n <= max_edges &&
        static_cast<double>(n) <= max_fraction * static_cast<double>(sm.number_of_vertices()))
      loops.push_back(h);
  }
  std::size_t filled = 0;
  for (auto h : loops) {
    if (!sm.is_border(h)) continue;
    std::vector<SMesh::Face_index> faces;
    PMP::triangulate_hole(sm, h, std::back_inserter(faces));
    filled += faces.empty() ? 0 : 1;
  }
  if (filled) mesh = from_surface_mesh(sm);
  return filled;
}

TriMesh sqrt3_subdivide(const TriMesh& mesh, std::size_t iterations) {
  if (iterations == 0 || mesh.triangles.empty()) return mesh;
  SMesh sm = to_surface_mesh(mesh);
  CGAL::Subdivision_method_3::Sqrt3_subdivision(
      sm, CGAL::parameters::number_of_iterations(static_cast<int>(iterations)));
  return from_surface_mesh(sm);
}

}  // namespace inhap
