// Alpha shape on CGAL's 3D Delaunay triangulation. One of the three CGAL translation units of
// the surface module.
//
// The regularized alpha solid is the union of the Delaunay tetrahedra whose circumradius is at
// most alpha (Edelsbrunner & Mücke); its boundary is the set of facets between such a
// tetrahedron and one that is larger or infinite. This is what CGAL's Alpha_shape_3 computes
// in REGULARIZED mode; we classify the cells ourselves because the one-component alpha
// (find_optimal_alpha) is then a single union-find sweep over the cells sorted by radius,
// O(n log n), instead of Alpha_shape_3's binary search over component counts (several
// seconds for 30,000 points), and the closed-manifold scan re-extracts the boundary cheaply.
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "inhap/core/error.hpp"
#include "inhap/surface/alpha_shape.hpp"

namespace inhap {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<std::int32_t, K>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<std::int32_t, K,
                                                     CGAL::Delaunay_triangulation_cell_base_3<K>>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds, CGAL::Fast_location>;
using Point = K::Point_3;

/// Finite cells with their squared circumradius and neighbours (-1: infinite).
struct Cells {
  std::vector<Delaunay::Cell_handle> handle;
  std::vector<double> r2;
  std::vector<std::array<std::int32_t, 4>> nb;
  std::vector<std::array<std::int32_t, 4>> vertex;  // input point indices
};

Cells index_cells(Delaunay& dt, const std::vector<double>& scale) {
  Cells c;
  for (auto it = dt.all_cells_begin(); it != dt.all_cells_end(); ++it) it->info() = -1;
  for (auto it = dt.finite_cells_begin(); it != dt.finite_cells_end(); ++it) {
    it->info() = static_cast<std::int32_t>(c.handle.size());
    c.handle.push_back(it);
  }
  const std::size_t n = c.handle.size();
  c.r2.resize(n);
  c.nb.resize(n);
  c.vertex.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& h = c.handle[i];
    c.r2[i] = CGAL::squared_radius(h->vertex(0)->point(), h->vertex(1)->point(),
                                   h->vertex(2)->point(), h->vertex(3)->point());
    double s = 0;
    for (int k = 0; k < 4; ++k) {
      c.nb[i][static_cast<std::size_t>(k)] = h->neighbor(k)->info();
      c.vertex[i][static_cast<std::size_t>(k)] = h->vertex(k)->info();
      if (!scale.empty()) s += 0.25 * scale[static_cast<std::size_t>(h->vertex(k)->info())];
    }
    if (!scale.empty()) c.r2[i] /= s * s;  // radius in units of the local length
  }
  return c;
}

struct UnionFind {
  std::vector<std::int32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::int32_t find(std::int32_t x) {
    while (parent[static_cast<std::size_t>(x)] != x)
      x = parent[static_cast<std::size_t>(x)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    return x;
  }
  bool unite(std::int32_t a, std::int32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent[static_cast<std::size_t>(a)] = b;
    return true;
  }
};

/// Smallest squared alpha at which every point lies on a cell of the solid and the cells form
/// one facet-connected component (CGAL's find_optimal_alpha(1) for REGULARIZED shapes).
double one_component_alpha2(const Cells& c, std::size_t num_points, bool one_component) {
  const std::size_t n = c.r2.size();
  std::vector<double> vmin(num_points, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < n; ++i)
    for (auto v : c.vertex[i])
      vmin[static_cast<std::size_t>(v)] = std::min(vmin[static_cast<std::size_t>(v)], c.r2[i]);
  double solid = 0;
  for (double v : vmin)
    if (std::isfinite(v)) solid = std::max(solid, v);  // points merged as duplicates: +inf
  if (!one_component) return solid;
  std::vector<std::int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return c.r2[a] < c.r2[b]; });
  UnionFind uf(n);
  std::vector<char> in(n, 0);
  std::size_t components = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const auto i = order[k];
    in[static_cast<std::size_t>(i)] = 1;
    ++components;
    for (auto j : c.nb[static_cast<std::size_t>(i)])
      if (j >= 0 && in[static_cast<std::size_t>(j)] && uf.unite(i, j)) --components;
    const double r2 = c.r2[static_cast<std::size_t>(i)];
    const bool last_of_value = k + 1 == n || c.r2[static_cast<std::size_t>(order[k + 1])] > r2;
    if (last_of_value && r2 >= solid && components == 1) return r2;
  }
  return n ? c.r2[static_cast<std::size_t>(order.back())] : 0.0;
}

std::size_t solid_components(const Cells& c, double alpha2) {
  UnionFind uf(c.r2.size());
  std::size_t comps = 0;
  for (std::size_t i = 0; i < c.r2.size(); ++i) {
    if (c.r2[i] > alpha2) continue;
    ++comps;
    for (auto j : c.nb[i])
      if (j >= 0 && c.r2[static_cast<std::size_t>(j)] <= alpha2 &&
          static_cast<std::size_t>(j) < i && uf.unite(static_cast<std::int32_t>(i), j))
        --comps;
  }
  return comps;
}

/// Boundary facets of the solid {r2 <= alpha2}, oriented away from their interior cell, as
/// triangles over the input point indices.
std::vector<Tri> boundary(const Cells& c, double alpha2) {
  std::vector<Tri> tris;
  for (std::size_t i = 0; i < c.r2.size(); ++i) {
    if (c.r2[i] > alpha2) continue;
    for (int k = 0; k < 4; ++k) {
      const auto j = c.nb[i][static_cast<std::size_t>(k)];
      if (j >= 0 && c.r2[static_cast<std::size_t>(j)] <= alpha2) continue;
      const auto& h = c.handle[i];
      const int a = (k + 1) & 3, b = (k + 2) & 3, d = (k + 3) & 3;
      Tri t{h->vertex(a)->info(), h->vertex(b)->info(), h->vertex(d)->info()};
      if (CGAL::orientation(h->vertex(a)->point(), h->vertex(b)->point(), h->vertex(d)->point(),
                            h->vertex(k)->point()) == CGAL::POSITIVE)
        std::swap(t[1], t[2]);
      tris.push_back(t);
    }
  }
  return tris;
}

/// True when the oriented triangles form one closed 2-manifold: every directed edge is used
/// once and its reverse once, and the faces around every vertex form a single fan.
bool closed_manifold(const std::vector<Tri>& tris, std::size_t num_points, bool one_component) {
  if (tris.empty()) return false;
  // Directed edges sorted: each (a,b) must appear exactly once and (b,a) exactly once.
  std::vector<std::uint64_t> e;
  e.reserve(tris.size() * 3);
  auto key = [](std::int32_t a, std::int32_t b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
  };
  for (const Tri& t : tris)
    for (int k = 0; k < 3; ++k) e.push_back(key(t[k], t[(k + 1) % 3]));
  std::sort(e.begin(), e.end());
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (i + 1 < e.size() && e[i + 1] == e[i]) return false;
    const auto a = static_cast<std::int32_t>(e[i] >> 32), b = static_cast<std::int32_t>(e[i]);
    if (!std::binary_search(e.begin(), e.end(), key(b, a))) return false;
  }
  // Vertex fans: with edges manifold, the link of v is a union of cycles; it must be one. The
  // link edge (b -> c) of face (v, b, c): follow the successor map around v.
  std::vector<std::int32_t> offset(num_points + 1, 0);
  for (const Tri& t : tris)
    for (auto v : t) ++offset[static_cast<std::size_t>(v) + 1];
  for (std::size_t v = 0; v < num_points; ++v) offset[v + 1] += offset[v];
  std::vector<std::int32_t> fill(offset.begin(), offset.end() - 1);
  std::vector<std::pair<std::int32_t, std::int32_t>> link(tris.size() * 3);
  for (const Tri& t : tris)
    for (int k = 0; k < 3; ++k)
      link[static_cast<std::size_t>(fill[static_cast<std::size_t>(t[k])]++)] = {t[(k + 1) % 3],
                                                                                t[(k + 2) % 3]};
  std::vector<std::pair<std::int32_t, std::int32_t>> fan;
  for (std::size_t v = 0; v < num_points; ++v) {
    const auto b = offset[v], en = offset[v + 1];
    if (en == b) continue;
    fan.assign(link.begin() + b, link.begin() + en);
    std::sort(fan.begin(), fan.end());
    std::int32_t start = fan.front().first, cur = start;
    std::size_t steps = 0;
    do {
      auto it = std::lower_bound(fan.begin(), fan.end(), std::make_pair(cur, INT32_MIN));
      if (it == fan.end() || it->first != cur) return false;
      cur = it->second;
      ++steps;
    } while (cur != start && steps <= fan.size());
    if (steps != fan.size()) return false;
  }
  if (!one_component) return true;
  // One component: faces connected through shared vertices.
  UnionFind uf(num_points);
  for (const Tri& t : tris) uf.unite(t[0], t[1]), uf.unite(t[1], t[2]);
  const auto root = uf.find(tris.front()[0]);
  for (const Tri& t : tris)
    if (uf.find(t[0]) != root) return false;
  return true;
}

TriMesh to_mesh(const std::vector<Tri>& tris, std::span<const Vec3> points,
                std::vector<std::int32_t>& input_index) {
  TriMesh mesh;
  input_index.clear();
  std::vector<std::int32_t> remap(points.size(), -1);
  mesh.triangles.reserve(tris.size());
  for (Tri t : tris) {
    for (auto& v : t) {
      auto& r = remap[static_cast<std::size_t>(v)];
      if (r < 0) {
        r = static_cast<std::int32_t>(mesh.positions.size());
        mesh.positions.push_back(points[static_cast<std::size_t>(v)]);
        input_index.push_back(v);
      }
      v = r;
    }
    mesh.triangles.push_back(t);
  }
  mesh.compute_normals();
  return mesh;
}

}  // namespace

AlphaShapeResult alpha_shape(std::span<const Vec3> points, const AlphaShapeOptions& options) {
  AlphaShapeResult result;
  std::vector<std::pair<Point, std::int32_t>> input;
  input.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    input.emplace_back(Point(points[i].x(), points[i].y(), points[i].z()),
                       static_cast<std::int32_t>(i));
  Delaunay dt(input.begin(), input.end());
  if (dt.dimension() < 3)
    throw Error("alpha shape: expected points spanning 3D, got " + std::to_string(points.size()) +
                " points of dimension " + std::to_string(dt.dimension()));
  if (!options.point_scale.empty()) {
    if (options.point_scale.size() != points.size())
      throw Error("alpha shape: expected one length per point, got " +
                  std::to_string(options.point_scale.size()) + " for " +
                  std::to_string(points.size()));
    for (double v : options.point_scale)
      if (!(v > 0) || !std::isfinite(v))
        throw Error("alpha shape: expected positive finite point lengths");
  }
  const Cells cells = index_cells(dt, options.point_scale);
  double a2 = options.alpha * options.alpha;
  std::vector<Tri> tris;
  if (options.alpha > 0) {
    tris = boundary(cells, a2);
    result.closed_manifold = closed_manifold(tris, points.size(), options.one_component);
  } else {
    const double a0 = one_component_alpha2(cells, points.size(), options.one_component);
    result.alpha_one_component = std::sqrt(a0);
    a2 = a0;
    tris = boundary(cells, a2);
    result.closed_manifold = closed_manifold(tris, points.size(), options.one_component);
    if (options.require_closed_manifold && !result.closed_manifold) {
      // The shape changes only at cell radii: step by (1 + scan_step) when some radius lies in
      // between, else jump to the next radius.
      std::vector<double> radii(cells.r2);
      std::sort(radii.begin(), radii.end());
      const double f =
          (1 + std::max(1e-6, options.scan_step)) * (1 + std::max(1e-6, options.scan_step));
      const double limit = a0 * options.scan_max_factor * options.scan_max_factor;
      double a = a0;
      while (true) {
        auto next = std::upper_bound(radii.begin(), radii.end(), a);
        if (next == radii.end()) break;
        a = *next <= a * f ? a * f : *next;
        if (a > limit) break;
        std::vector<Tri> t = boundary(cells, a);
        if (closed_manifold(t, points.size(), options.one_component)) {
          tris = std::move(t);
          a2 = a;
          result.closed_manifold = true;
          break;
        }
      }
    }
  }
  result.alpha = std::sqrt(a2);
  result.solid_components = solid_components(cells, a2);
  result.mesh = to_mesh(tris, points, result.input_index);
  result.points_on_surface = result.mesh.positions.size();
  return result;
}

}  // namespace inhap
