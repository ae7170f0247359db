// Bounding-volume hierarchy over a triangle mesh: binned SAH build, allocation-free queries.
// Units: mm. See docs/spatial-queries.md for the algorithms and their guarantees.
#include "inhap/geometry/mesh_index.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <utility>

#include "bvh_build.hpp"
#include "bvh_closest.hpp"
#include "bvh_obb.hpp"
#include "inhap/core/error.hpp"

// The watertight segment/triangle test needs a shared edge's edge function to be the exact
// negation in both triangles; FMA would round the two differently, so CMakeLists.txt compiles
// this file with -ffp-contract=off (a pragma would stop GCC from inlining Eigen here).

namespace inhap {

namespace {

// The build keeps the depth below kBvhMaxDepth, so a fixed stack never overflows.
constexpr int kStackSize = detail::kBvhMaxDepth + 8;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Ize (2013): relative error bound of a slab-test parameter, 2 * gamma(3).
constexpr double kSlabSlack = 2.0 * 3.0 * std::numeric_limits<double>::epsilon();

// Binary build nodes (left child = self + 1) -> nodes holding the boxes of both children, inner
// nodes numbered in the same depth-first order. Empty when the root is a leaf.
template <class N>
detail::IndexVector<N> to_child_box_nodes(const std::vector<detail::BvhBuildNode>& bn) {
  std::vector<std::int32_t> id(bn.size(), -1);
  std::int32_t inner = 0;
  for (std::size_t i = 0; i < bn.size(); ++i)
    if (bn[i].count == 0) id[i] = inner++;
  detail::IndexVector<N> nodes(static_cast<std::size_t>(inner));
  for (std::size_t i = 0; i < bn.size(); ++i) {
    if (bn[i].count != 0) continue;
    N& n = nodes[id[i]];
    const std::size_t kids[2] = {i + 1, static_cast<std::size_t>(bn[i].first)};
    for (int c = 0; c < 2; ++c) {
      const detail::BvhBuildNode& k = bn[kids[c]];
      for (int a = 0; a < 3; ++a) {
        n.lo[a][c] = k.lo[a];
        n.hi[a][c] = k.hi[a];
      }
      n.child[c] = k.count > 0 ? k.first : id[kids[c]];
      n.count[c] = k.count;
    }
  }
  return nodes;
}

// Oriented boxes of the children of every inner node, in the order of to_child_box_nodes.
template <class O>
detail::IndexVector<O> to_child_obb_nodes(const std::vector<detail::BvhBuildNode>& bn,
                                          const std::vector<detail::BvhObb>& obb) {
  detail::IndexVector<O> out;
  out.reserve(bn.size() / 2 + 1);
  for (std::size_t i = 0; i < bn.size(); ++i) {
    if (bn[i].count != 0) continue;
    O& o = out.emplace_back();
    const std::size_t kids[2] = {i + 1, static_cast<std::size_t>(bn[i].first)};
    for (int c = 0; c < 2; ++c) {
      const detail::BvhObb& k = obb[kids[c]];
      auto& d = o.child[c];
      for (int j = 0; j < 4; ++j) d.q[j] = k.q[j];
      for (int a = 0; a < 3; ++a) {
        d.lo[a] = k.lo[a];
        d.hi[a] = k.hi[a];
      }
    }
  }
  return out;
}

// Segment a + t (b - a), prepared for the slab test and the watertight triangle test
// (Woop, Benthin & Wald 2013: translate to the origin, permute so that z is the dominant
// direction axis, shear so that the ray is the +z axis, then 2D edge functions).
struct Ray {
  Vec3 o, inv;
  std::array<bool, 3> flat{};  // direction component ~0: slab test becomes "o inside the slab"
  int kx = 0, ky = 1, kz = 2;
  double sx = 0, sy = 0, sz = 1;

  Ray(const Vec3& a, const Vec3& d) : o(a) {
    for (int k = 0; k < 3; ++k) {
      flat[k] = std::abs(d[k]) < 1e-300;
      inv[k] = flat[k] ? 0.0 : 1.0 / d[k];
    }
    const Vec3 ad = d.cwiseAbs();
    kz = ad.x() > ad.y() ? (ad.x() > ad.z() ? 0 : 2) : (ad.y() > ad.z() ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (d[kz] < 0) std::swap(kx, ky);  // keep the winding
    sx = d[kx] / d[kz];
    sy = d[ky] / d[kz];
    sz = 1.0 / d[kz];
  }
};

// Slab test of child c of node n for the segment, t in [0, tmax]; tnear is the entry parameter.
// Conservative: padded boxes, exit parameter enlarged by its rounding bound (Ize 2013).
template <class N>
inline bool hit_box(const N& n, int c, const Ray& r, double tmax, double& tnear) {
  double t0 = 0, t1 = tmax;
  for (int k = 0; k < 3; ++k) {
    const double lo = n.lo[k][c], hi = n.hi[k][c];
    if (r.flat[k]) {
      if (r.o[k] < lo || r.o[k] > hi) return false;
      continue;
    }
    double a = (lo - r.o[k]) * r.inv[k], b = (hi - r.o[k]) * r.inv[k];
    if (a > b) std::swap(a, b);
    b += kSlabSlack * std::abs(b);
    t0 = a > t0 ? a : t0;
    t1 = b < t1 ? b : t1;
  }
  tnear = t0;
  return t0 <= t1;
}

struct TriHit {
  double t, u, v, w;
};

// Watertight test; accepts t in [0, tmax]. u, v, w are the weights of v0, v1, v2.
template <class T>
inline bool hit_triangle(const T& tri, const Ray& r, double tmax, TriHit& h) {
  const Vec3 A = tri.v0 - r.o, B = tri.v1 - r.o, C = tri.v2 - r.o;
  const double ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
  const double bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
  const double cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
  // Edge functions, all in the form qx * py - qy * px for the directed edge p -> q, so that a
  // shared edge gives exactly opposite values in its two triangles. Zero counts as inside.
  const double u = cx * by - cy * bx;  // edge v1 -> v2
  const double v = ax * cy - ay * cx;  // edge v2 -> v0
  const double w = bx * ay - by * ax;  // edge v0 -> v1
  if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return false;
  const double det = u + v + w;
  if (det == 0 || !std::isfinite(det)) return false;
  const double tt = u * (r.sz * A[r.kz]) + v * (r.sz * B[r.kz]) + w * (r.sz * C[r.kz]);
  const double t = tt / det;
  if (!(t >= 0 && t <= tmax)) return false;
  h = {t, u / det, v / det, w / det};
  return true;
}

// A subtree: inner node `index` (count == 0) or the leaf of triangle slots [index, index+count).
struct Ref {
  std::int32_t index, count;
};

template <class N>
inline Ref child_ref(const N& n, int c) {
  return {n.child[c], n.count[c]};
}

inline void prefetch_line(const void* p) {
#if defined(__GNUC__)
  __builtin_prefetch(p);
#else
  (void)p;
#endif
}

// The oriented box only pays once a best distance is known and it is large against the child's
// size (an axis-aligned box sticks out of a tilted patch by about half its size; for nearer
// queries it is nearly as tight, and reading and evaluating the oriented box costs a cache line
// and ~30 flops per child). Gate: best^2 > kObbGate * (largest box side)^2, best finite.
// Evaluating it always (also during the first descent) made 0.5 mm queries 40 % slower.
constexpr double kObbGate = 0.25;

template <class N>
inline bool obb_pays(const N& n, int c, double best_d2) {
  double e2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double e = double(n.hi[k][c]) - n.lo[k][c];
    e2 = std::max(e2, e * e);
  }
  return best_d2 > kObbGate * e2 && best_d2 < std::numeric_limits<double>::infinity();
}

// Lower bound of the squared distance from p to the triangles under child c of node n: its
// axis-aligned box distance, then, if that still leaves it open and obb_pays, the max with its
// oriented box distance (both are lower bounds: docs/spatial-queries.md, "Oriented bounds").
template <class N, class O, class Open>
inline double child_bound(const N& n, const O& obb, int c, const Vec3& p, double eq, double best_d2,
                          Open&& open) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double lo = n.lo[k][c], hi = n.hi[k][c];
    const double g = std::max(std::max(lo - p[k], p[k] - hi), 0.0);  // branch-free
    d2 += g * g;
  }
  if (!open(d2) || !obb_pays(n, c, best_d2)) return d2;
  return std::max(d2, detail::obb_distance2(obb.child[c], p, eq));
}

// 0 or 1: the child whose box centre is nearer to p.
template <class N>
inline int nearer_centre(const N& n, const Vec3& p) {
  double d0 = 0, d1 = 0;
  for (int k = 0; k < 3; ++k) {
    const double c0 = 0.5 * (double(n.lo[k][0]) + n.hi[k][0]) - p[k];
    const double c1 = 0.5 * (double(n.lo[k][1]) + n.hi[k][1]) - p[k];
    d0 += c0 * c0;
    d1 += c1 * c1;
  }
  return d1 < d0 ? 1 : 0;
}

// Squared distance from p to a float box (lo, hi), branch-free.
inline double box_distance2(const float (&lo)[3], const float (&hi)[3], const Vec3& p) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double g = std::max(std::max(double(lo[k]) - p[k], p[k] - double(hi[k])), 0.0);
    d2 += g * g;
  }
  return d2;
}

// Starts loading n consecutive 64-byte records.
template <class T>
inline void prefetch_lines(const T* first, std::int32_t n) {
  static_assert(sizeof(T) == 64);
  for (std::int32_t k = 0; k < n; ++k) prefetch_line(first + k);
}

// Starts loading all lines of the triangles in slots [r.index, r.index + r.count).
template <class TV>
inline void prefetch_slots(const TV& tris, Ref r) {
  const char* p = reinterpret_cast<const char*>(&tris[r.index]);
  const char* end = reinterpret_cast<const char*>(&tris[r.index] + r.count);
  for (; p < end; p += 64) prefetch_line(p);
}

// Starts loading a subtree that will probably be visited soon (a stack push): an inner node's
// boxes (and its oriented boxes, for distance queries), or all lines of a leaf's triangles.
template <class NV, class TV>
inline void prefetch(const NV& nodes, const TV& tris, Ref r, bool with_obb) {
  if (r.count > 0) {
    prefetch_slots(tris, r);
    return;
  }
  prefetch_line(&nodes[r.index]);
  if (with_obb) prefetch_line(&nodes[r.index].obb);
}

// Starts loading a seed cluster's slots: the triangles' lines and their prism bounds.
template <class TV, class BV>
inline void prefetch_cluster(const TV& tris, const BV& bounds, Ref r) {
  prefetch_slots(tris, r);
  prefetch_lines(&bounds[r.index], r.count);
}

}  // namespace

MeshIndex::MeshIndex(const TriMesh& mesh, const MeshIndexOptions& options) {
  if (!(options.seed_shell >= 0) || !std::isfinite(options.seed_shell))
    throw Error(fmt::format("MeshIndex: seed_shell must be a finite distance >= 0 mm, got {}",
                            options.seed_shell));
  const std::size_t nf = mesh.triangles.size();
  const auto nv = static_cast<std::int64_t>(mesh.positions.size());
  std::vector<detail::BvhBox> boxes(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const std::int32_t i = mesh.triangles[f][c];
      if (i < 0 || i >= nv)
        throw Error(
            fmt::format("MeshIndex: face {}: vertex index {} out of range [0, {})", f, i, nv));
      const Vec3& p = mesh.positions[i];
      if (!p.allFinite())
        throw Error(fmt::format("MeshIndex: face {}: vertex {} is not finite ({}, {}, {})", f, i,
                                p.x(), p.y(), p.z()));
      boxes[f].grow(p);
      bounds_.extend(p);
    }
  }
  detail::BvhBuild bvh = detail::build_bvh(std::move(boxes));
  assert(bvh.max_depth <= detail::kBvhMaxDepth);
  const auto boxes_only = to_child_box_nodes<Node>(bvh.nodes);
  tris_.resize(nf);
  std::vector<Vec3> verts(3 * nf);  // slot order, for the oriented boxes
  for (std::size_t s = 0; s < nf; ++s) {
    const Tri& t = mesh.triangles[bvh.order[s]];
    tris_[s] = {mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]};
    for (int c = 0; c < 3; ++c) verts[3 * s + c] = mesh.positions[t[c]];
  }
  const auto obbs = to_child_obb_nodes<NodeObb>(bvh.nodes, detail::build_obbs(bvh, verts));
  nodes_.resize(boxes_only.size());
  for (std::size_t i = 0; i < nodes_.size(); ++i) nodes_[i] = {boxes_only[i], obbs[i]};
  tri_ids_ = std::move(bvh.order);
  slots_.resize(nf);
  for (std::size_t s = 0; s < nf; ++s) slots_[tri_ids_[s]] = static_cast<std::int32_t>(s);
  build_seed_grid(options);
}

Box3 MeshIndex::bounds() const {
  return bounds_;
}

std::size_t MeshIndex::memory_bytes() const {
  return sizeof(*this) + nodes_.capacity() * sizeof(NodeRec) + tris_.capacity() * sizeof(TriData) +
         (tri_ids_.capacity() + slots_.capacity()) * sizeof(std::int32_t) + seed_grid_info().bytes;
}

std::optional<SegmentHit> MeshIndex::first_hit(const Vec3& a, const Vec3& b) const {
  if (tris_.empty() || !a.allFinite() || !b.allFinite() || a == b) return std::nullopt;
  const Vec3 d = b - a;
  if (!d.allFinite()) return std::nullopt;
  const Ray ray(a, d);
  struct Entry {
    Ref ref;
    double tnear;
  };
  Entry stack[kStackSize];
  int sp = 0;
  double best_t = 1.0;
  std::int32_t best_slot = -1;
  TriHit best{};
  Ref cur = nodes_.empty() ? Ref{0, static_cast<std::int32_t>(tris_.size())} : Ref{0, 0};
  auto pop = [&] {  // next subtree that can still hold a nearer hit
    while (sp > 0) {
      const Entry& e = stack[--sp];
      if (e.tnear <= best_t) {
        cur = e.ref;
        return true;
      }
    }
    return false;
  };
  for (;;) {
    if (cur.count > 0) {
      for (std::int32_t s = cur.index; s < cur.index + cur.count; ++s) {
        TriHit h;
        if (hit_triangle(tris_[s], ray, best_t, h) && (best_slot < 0 || h.t < best_t)) {
          best = h;
          best_t = h.t;
          best_slot = s;
        }
      }
    } else {
      const Node& n = nodes_[cur.index].node;
      double t[2] = {0, 0};
      const bool h0 = hit_box(n, 0, ray, best_t, t[0]);
      const bool h1 = hit_box(n, 1, ray, best_t, t[1]);
      if (h0 || h1) {
        const int near = h0 && (!h1 || t[0] <= t[1]) ? 0 : 1;
        if (h0 && h1) {  // far child later, near child now
          stack[sp++] = {child_ref(n, 1 - near), t[1 - near]};
          prefetch(nodes_, tris_, stack[sp - 1].ref, false);
        }
        cur = child_ref(n, near);
        continue;
      }
    }
    if (!pop()) break;
  }
  if (best_slot < 0) return std::nullopt;
  const TriData& tri = tris_[best_slot];
  SegmentHit hit;
  hit.triangle = tri_ids_[best_slot];
  hit.bary = Vec3(best.u, best.v, best.w);
  hit.point = best.u * tri.v0 + best.v * tri.v1 + best.w * tri.v2;
  hit.t = best.t;
  hit.entering = d.dot((tri.v1 - tri.v0).cross(tri.v2 - tri.v0)) < 0;
  return hit;
}

bool MeshIndex::any_hit(const Vec3& a, const Vec3& b) const {
  if (tris_.empty() || !a.allFinite() || !b.allFinite() || a == b) return false;
  const Vec3 d = b - a;
  if (!d.allFinite()) return false;
  const Ray ray(a, d);
  Ref stack[kStackSize];
  int sp = 0;
  stack[sp++] = nodes_.empty() ? Ref{0, static_cast<std::int32_t>(tris_.size())} : Ref{0, 0};
  while (sp > 0) {
    const Ref r = stack[--sp];
    if (r.count > 0) {
      for (std::int32_t s = r.index; s < r.index + r.count; ++s) {
        TriHit h;
        if (hit_triangle(tris_[s], ray, 1.0, h)) return true;
      }
      continue;
    }
    const Node& n = nodes_[r.index].node;
    double tnear;
    for (int c = 1; c >= 0; --c)
      if (hit_box(n, c, ray, 1.0, tnear)) stack[sp++] = child_ref(n, c);
  }
  return false;
}

namespace {
struct NoStats {
  void node() {}
  void triangle() {}
  void exact() {}
  void seeded() {}
};
struct CountStats {
  MeshIndex::QueryStats& s;
  void node() { ++s.nodes; }
  void triangle() { ++s.triangles; }
  void exact() { ++s.exact; }
  void seeded() { ++s.seeded; }
};
}  // namespace

MeshIndex::SeedCell MeshIndex::grid_seeds(const Vec3& p) const {
  if (grid_.start.empty()) return {};
  const Vec3 g = (p - grid_.origin) * grid_.inv_cell;
  // Negated comparisons: NaN fails them too.
  if (!(g.x() >= 0 && g.y() >= 0 && g.z() >= 0 && g.x() < double(grid_.n[0]) &&
        g.y() < double(grid_.n[1]) && g.z() < double(grid_.n[2])))
    return {};
  const std::int64_t i[3] = {static_cast<std::int64_t>(g.x()), static_cast<std::int64_t>(g.y()),
                             static_cast<std::int64_t>(g.z())};
  const std::int64_t cell = i[0] + grid_.n[0] * (i[1] + grid_.n[1] * i[2]);
  // The octant: which half of the cell along each axis (g - i is exact; the build allows for
  // the rounding of g across the cell's middle planes as across its faces).
  const int octant = int(g.x() - double(i[0]) >= 0.5) + 2 * int(g.y() - double(i[1]) >= 0.5) +
                     4 * int(g.z() - double(i[2]) >= 0.5);
  const std::uint32_t b = grid_.start[cell], e = grid_.start[cell + 1];
  return {grid_.seeds.data() + b, static_cast<int>(e - b), 1u << (detail::kSeedIdBits + octant)};
}

ClosestPoint MeshIndex::closest_point(const Vec3& p, double max_distance) const {
  NoStats stats;
  return closest_impl(p, max_distance, -1, stats);
}

ClosestPoint MeshIndex::closest_point(const Vec3& p, double max_distance,
                                      std::int32_t hint_triangle) const {
  NoStats stats;
  return closest_impl(p, max_distance, hint_triangle, stats);
}

ClosestPoint MeshIndex::closest_point_counted(const Vec3& p, double max_distance, QueryStats& stats,
                                              std::int32_t hint_triangle) const {
  CountStats counter{stats};
  return closest_impl(p, max_distance, hint_triangle, counter);
}

namespace {
// One closest-point search: the best triangle so far and the subtrees still to visit.
struct Search {
  struct Entry {
    Ref ref;
    double d2;  // lower bound of the squared distance to the subtree
  };
  // A descent of the tree pushes at most its depth, a seeded search at most its cell's clusters.
  Entry stack[std::max(kStackSize, detail::kSeedMaxClusters + 1)];
  int sp = 0;
  double best_d2 = kInf;
  std::int32_t best_slot = -1;
  Vec3 best_bary = Vec3::Zero();
  // A subtree at lower bound d2 can still improve the answer (ties only while none is found).
  bool open(double d2) const { return d2 < best_d2 || (best_slot < 0 && d2 <= best_d2); }
  void offer(std::int32_t slot, const Vec3& bary, double d2) {
    if (!open(d2)) return;
    best_d2 = d2;
    best_slot = slot;
    best_bary = bary;
  }
  // Pushes keeping the stack sorted, nearest on top (for the seeds only: the stack holds them
  // alone).
  void push_sorted(Ref r, double d2) {
    int j = sp++;
    for (; j > 0 && stack[j - 1].d2 < d2; --j) stack[j] = stack[j - 1];
    stack[j] = {r, d2};
  }
};
}  // namespace

template <class S, class Stats>
void MeshIndex::exact_test(const Vec3& p, std::int32_t slot, S& search, Stats& stats) const {
  const TriData& tri = tris_[slot];
  stats.exact();
  const Vec3 w = detail::closest_bary(p, tri);
  search.offer(slot, w, (p - (w[0] * tri.v0 + w[1] * tri.v1 + w[2] * tri.v2)).squaredNorm());
}

// Seeded start (p lies in a covered cell of the seed grid): the cell's clusters hold the answer,
// and the triangle nearest the cell's centre gives the first bound. The clusters that can still
// improve on it go on the stack as leaf-like slot ranges, nearest on top; all lines of the
// nearest two start loading. Clusters not marked for p's octant are skipped unread.
template <class S, class Stats>
void MeshIndex::seed_search(const Vec3& p, const SeedCell& cell, double eq, S& search,
                            Stats& stats) const {
  stats.seeded();
  const std::uint32_t* seeds = cell.first;
  for (int k = 1; k < cell.count; ++k)
    if (seeds[k] & cell.octant) prefetch_line(&grid_.clusters[seeds[k] & detail::kSeedIdMask]);
  exact_test(p, static_cast<std::int32_t>(seeds[0]), search, stats);
  for (int k = 1; k < cell.count; ++k) {
    if (!(seeds[k] & cell.octant)) continue;
    const Cluster& cl = grid_.clusters[seeds[k] & detail::kSeedIdMask];
    stats.node();
    double d2 = box_distance2(cl.lo, cl.hi, p);
    if (!search.open(d2)) continue;
    d2 = std::max(d2, detail::obb_distance2(cl.obb, p, eq));
    if (search.open(d2)) search.push_sorted(Ref{cl.first, cl.count}, d2);
  }
  for (int j = search.sp - 1; j >= 0 && j >= search.sp - 2; --j)
    prefetch_cluster(tris_, tri_bounds_, search.stack[j].ref);
}

template <class Stats>
ClosestPoint MeshIndex::closest_impl(const Vec3& p, double max_distance, std::int32_t hint,
                                     Stats& stats) const {
  ClosestPoint out;
  if (tris_.empty() || !p.allFinite() || !(max_distance >= 0)) return out;
  Search search;
  search.best_d2 = max_distance * max_distance;
  // Warm start: the hint's distance bounds the search from the first node on.
  if (hint >= 0 && static_cast<std::size_t>(hint) < slots_.size())
    exact_test(p, slots_[hint], search, stats);
  const double eq = detail::obb_project_error(p);
  auto open = [&](double d2) { return search.open(d2); };
  Ref cur = nodes_.empty() ? Ref{0, static_cast<std::int32_t>(tris_.size())} : Ref{0, 0};
  const SeedCell cell = grid_seeds(p);
  const bool seeded = cell.count > 0;
  auto pop = [&] {  // next subtree that can still hold a nearer point
    while (search.sp > 0) {
      const Search::Entry& e = search.stack[--search.sp];
      if (open(e.d2)) {
        cur = e.ref;
        // A seeded search's stack holds clusters only, nearest on top: keep the lines of the
        // two after this one loading (seed_search requested the first two), so that each visit
        // finds its lines on the way instead of waiting for them in turn.
        if (seeded && search.sp >= 2 && open(search.stack[search.sp - 2].d2))
          prefetch_cluster(tris_, tri_bounds_, search.stack[search.sp - 2].ref);
        return true;
      }
    }
    return false;
  };
  const double eqb = seeded ? detail::prism_error(p, prism_scale_) : 0.0;  // for prism_bound
  if (seeded) seed_search(p, cell, eq, search, stats);
  bool run = !seeded || pop();
  while (run) {
    if (cur.count > 0) {
      for (std::int32_t s = cur.index; s < cur.index + cur.count; ++s) {
        const TriData& tri = tris_[s];
        stats.triangle();
        // Cheap rejection before the exact test: in a seeded search the prism bound (nearly
        // exact, one more line per triangle), else the triangle's own bounding box (no extra
        // memory traffic; a plane-distance test after it saved only 10 % of the exact tests).
        if (seeded) {
          if (!open(detail::prism_bound(tri_bounds_[s], p, eqb, plane_slack_))) continue;
        } else {
          const Vec3 lo = tri.v0.cwiseMin(tri.v1).cwiseMin(tri.v2);
          const Vec3 hi = tri.v0.cwiseMax(tri.v1).cwiseMax(tri.v2);
          if ((lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm() > search.best_d2) continue;
        }
        exact_test(p, s, search, stats);
      }
      run = pop();
      continue;
    }
    stats.node();
    const Node& n = nodes_[cur.index].node;
    const NodeObb& o = nodes_[cur.index].obb;
    const double d[2] = {child_bound(n, o, 0, p, eq, search.best_d2, open),
                         child_bound(n, o, 1, p, eq, search.best_d2, open)};
    // Nearer bound first; equal (e.g. both 0 near the surface): nearer box centre first.
    const int near = d[0] != d[1] ? (d[1] < d[0] ? 1 : 0) : nearer_centre(n, p);
    if (!open(d[near])) {
      run = pop();
      continue;
    }
    if (open(d[1 - near])) {
      search.stack[search.sp++] = {child_ref(n, 1 - near), d[1 - near]};
      prefetch(nodes_, tris_, search.stack[search.sp - 1].ref, true);
    }
    const Ref next = child_ref(n, near);
    if (next.count > 0)
      prefetch(nodes_, tris_, next, false);  // all lines of the leaf at once
    else if (obb_pays(n, near, search.best_d2))
      prefetch_line(&nodes_[next.index].obb);
    cur = next;  // descend without popping
  }
  if (search.best_slot < 0) return out;
  const TriData& tri = tris_[search.best_slot];
  out.triangle = tri_ids_[search.best_slot];
  out.bary = search.best_bary;
  out.point = out.bary[0] * tri.v0 + out.bary[1] * tri.v1 + out.bary[2] * tri.v2;
  out.distance2 = search.best_d2;
  return out;
}

}  // namespace inhap
