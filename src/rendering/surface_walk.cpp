// Closest point on a triangle and the local graph search of Ho et al. (1999). Units: mm.
#include "surface_walk.hpp"

#include <cmath>

namespace inhap::rendering::detail {

namespace {

TriPoint on_segment(const Vec3& p, const Vec3& a, const Vec3& b, int ia, int ib, Region edge) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  double u = len2 > 0 ? (p - a).dot(ab) / len2 : 0.0;
  TriPoint r;
  if (!(u > 0)) {
    r.point = a;
    r.bary[ia] = 1;
    r.region = static_cast<Region>(static_cast<int>(Region::kVertex0) + ia);
  } else if (u >= 1) {
    r.point = b;
    r.bary[ib] = 1;
    r.region = static_cast<Region>(static_cast<int>(Region::kVertex0) + ib);
  } else {
    r.point = a + u * ab;
    r.bary[ia] = 1 - u;
    r.bary[ib] = u;
    r.region = edge;
  }
  return r;
}

// Fallback for degenerate (zero-area) triangles: best of the three edges.
TriPoint degenerate(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  TriPoint best = on_segment(p, a, b, 0, 1, Region::kEdge0);
  double d2 = (best.point - p).squaredNorm();
  for (const TriPoint& cand :
       {on_segment(p, b, c, 1, 2, Region::kEdge1), on_segment(p, c, a, 2, 0, Region::kEdge2)}) {
    const double e2 = (cand.point - p).squaredNorm();
    if (e2 < d2) {
      d2 = e2;
      best = cand;
    }
  }
  return best;
}

}  // namespace

TriPoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Voronoi regions tested in order: vertices, edges, interior (the classic formulation, e.g.
  // Ericson, Real-Time Collision Detection, sec. 5.1.5), written with our region labels.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  TriPoint r;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) {
    r.point = a;
    r.bary = {1, 0, 0};
    r.region = Region::kVertex0;
    return r;
  }
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) {
    r.point = b;
    r.bary = {0, 1, 0};
    r.region = Region::kVertex1;
    return r;
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) {
    r.point = c;
    r.bary = {0, 0, 1};
    r.region = Region::kVertex2;
    return r;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double den = d1 - d3;
    if (!(den > 0)) return degenerate(p, a, b, c);
    const double v = d1 / den;
    r.point = a + v * ab;
    r.bary = {1 - v, v, 0};
    r.region = Region::kEdge0;
    return r;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double den = d2 - d6;
    if (!(den > 0)) return degenerate(p, a, b, c);
    const double w = d2 / den;
    r.point = a + w * ac;
    r.bary = {1 - w, 0, w};
    r.region = Region::kEdge2;
    return r;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double den = (d4 - d3) + (d5 - d6);
    if (!(den > 0)) return degenerate(p, a, b, c);
    const double w = (d4 - d3) / den;
    r.point = b + w * (c - b);
    r.bary = {0, 1 - w, w};
    r.region = Region::kEdge1;
    return r;
  }
  const double sum = va + vb + vc;
  if (!(sum > 0) || !std::isfinite(sum)) return degenerate(p, a, b, c);
  const double v = vb / sum, w = vc / sum;
  r.point = a + v * ab + w * ac;
  r.bary = {1 - v - w, v, w};
  r.region = Region::kFace;
  return r;
}

namespace {

struct Candidate {
  std::int32_t face = -1;
  TriPoint tp;
  double d2 = 0;
};

inline TriPoint closest_on_face(const TriMesh& mesh, std::int32_t f, const Vec3& p) {
  const Tri& t = mesh.triangles[static_cast<std::size_t>(f)];
  return closest_on_triangle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
}

// Tries face g as the next triangle; keeps it when it is strictly closer than `best`.
inline void consider(const TriMesh& mesh, std::int32_t g, std::int32_t current, const Vec3& p,
                     Candidate& best) {
  if (g < 0 || g == current) return;
  const TriPoint tp = closest_on_face(mesh, g, p);
  const double d2 = (tp.point - p).squaredNorm();
  // Strict decrease with a relative margin: equal distances (coplanar neighbours, p above a
  // shared edge) never make the walk move, so it cannot cycle.
  if (d2 < best.d2 * (1.0 - 1e-12) - 1e-24) {
    best.face = g;
    best.tp = tp;
    best.d2 = d2;
  }
}

inline void consider_vertex_fan(const TriMesh& mesh, const MeshAdjacency& adj, std::int32_t v,
                                std::int32_t current, const Vec3& p, Candidate& best) {
  for (std::int32_t g : adj.faces_of_vertex(v)) consider(mesh, g, current, p, best);
}

}  // namespace

WalkResult local_closest(const TriMesh& mesh, const MeshAdjacency& adj, std::int32_t start,
                         const Vec3& p, std::uint32_t max_steps) {
  Candidate cur;
  cur.face = start;
  cur.tp = closest_on_face(mesh, start, p);
  cur.d2 = (cur.tp.point - p).squaredNorm();
  WalkResult out;
  for (;;) {
    if (cur.tp.region == Region::kFace) {
      out.converged = true;
      break;
    }
    if (out.steps >= max_steps) break;
    const Tri& t = mesh.triangles[static_cast<std::size_t>(cur.face)];
    Candidate best = cur;
    const int r = static_cast<int>(cur.tp.region);
    if (r <= static_cast<int>(Region::kVertex2)) {
      consider_vertex_fan(mesh, adj, t[r - static_cast<int>(Region::kVertex0)], cur.face, p, best);
    } else {
      const int e = r - static_cast<int>(Region::kEdge0);
      const std::int32_t g = adj.face_neighbors[static_cast<std::size_t>(cur.face)][e];
      if (g >= 0) {
        consider(mesh, g, cur.face, p, best);
      } else if (g == -2) {  // non-manifold edge: every face around its two ends
        consider_vertex_fan(mesh, adj, t[e], cur.face, p, best);
        consider_vertex_fan(mesh, adj, t[(e + 1) % 3], cur.face, p, best);
      }
    }
    if (best.face == cur.face) {
      out.converged = true;
      break;
    }
    cur = best;
    ++out.steps;
  }
  out.q.triangle = cur.face;
  out.q.bary = cur.tp.bary;
  out.q.point = cur.tp.point;
  out.distance2 = cur.d2;
  return out;
}

}  // namespace inhap::rendering::detail
