// Edge-collapse simplification with CGAL (Surface_mesh_simplification, Lindstrom-Turk cost and
// placement), vertex properties carried over from the closest point of the input. The only CGAL
// translation unit of the rendering module. Units: mm; properties keep their own units.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <fmt/format.h>

#include <array>
#include <vector>

#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "inhap/rendering/real_data.hpp"

namespace inhap::rendering {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using SMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;
namespace SMS = CGAL::Surface_mesh_simplification;

}  // namespace

TriMesh simplify_mesh(const TriMesh& mesh, std::size_t target_triangles) {
  if (target_triangles < 4)
    throw Error(
        fmt::format("simplify: expected a target of >= 4 triangles, got {}", target_triangles));
  if (mesh.num_triangles() <= target_triangles) return mesh;
  std::vector<Point> pts;
  pts.reserve(mesh.positions.size());
  for (const Vec3& p : mesh.positions) pts.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::array<std::size_t, 3>> faces;
  faces.reserve(mesh.triangles.size());
  for (const Tri& t : mesh.triangles)
    faces.push_back({std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2])});
  if (!PMP::is_polygon_soup_a_polygon_mesh(faces))
    throw Error("simplify: expected a manifold, consistently oriented mesh");
  SMesh sm;
  PMP::polygon_soup_to_polygon_mesh(pts, faces, sm);
  // Edges of a closed triangle mesh: 3 F / 2 (a mesh with a boundary ends a little below).
  const SMS::Count_stop_predicate<SMesh> stop(target_triangles * 3 / 2);
  SMS::edge_collapse(sm, stop);
  sm.collect_garbage();

  TriMesh out;
  out.positions.reserve(sm.number_of_vertices());
  for (auto v : sm.vertices()) {
    const Point& p = sm.point(v);
    out.positions.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : sm.faces()) {
    Tri t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      if (k < 3) t[std::size_t(k)] = static_cast<std::int32_t>(v.idx());
      ++k;
    }
    if (k == 3) out.triangles.push_back(t);
  }
  // Properties: barycentric interpolation at the closest point of the input surface.
  if (!mesh.properties.empty()) {
    const MeshIndex index(mesh, MeshIndexOptions{.seed_shell = 0});
    std::vector<ClosestPoint> cps;
    cps.reserve(out.positions.size());
    for (const Vec3& p : out.positions) cps.push_back(index.closest_point(p));
    for (const auto& [name, values] : mesh.properties) {
      std::vector<double> v(out.positions.size(), 0.0);
      for (std::size_t i = 0; i < cps.size(); ++i) {
        if (!cps[i].valid()) continue;
        const Tri& t = mesh.triangles[std::size_t(cps[i].triangle)];
        for (int a = 0; a < 3; ++a) v[i] += cps[i].bary[a] * values[std::size_t(t[std::size_t(a)])];
      }
      out.set_property(name, std::move(v));
    }
  }
  out.compute_normals();
  return out;
}

}  // namespace inhap::rendering
