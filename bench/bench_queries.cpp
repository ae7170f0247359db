// Spatial-query latency of inhap::MeshIndex against CGAL's AABB_tree. Units: mm, microseconds.
// Meshes: (a) a 257 x 257 AFM-like height field (131,072 triangles, 0.39 mm spacing, 100 mm
// wide), (b) a closed torus of 1,000,000 triangles (R = 40 mm, r = 15 mm). For each: build time
// and heap bytes, then per-query latency p50/p99 of servo-like segments (0.5-2 mm near the
// surface, about half crossing it) and of closest-point queries within 5 mm of the surface,
// with the default index (seed grid) and with the tree alone ("inhap tree only").
// Every query is timed on its own with steady_clock into a preallocated vector.
//   build/bench/bench_queries --benchmark_min_time=0.2
#include <benchmark/benchmark.h>
#include <malloc.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <numbers>
#include <string>
#include <vector>

#include "inhap/core/random.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "support/meshes.hpp"

// --- live heap bytes (to measure what a build keeps) -------------------------------------------
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
namespace {
std::atomic<long long> g_live_bytes{0};
void* counted_alloc(std::size_t n) {
  void* p = std::malloc(n ? n : 1);
  if (!p) throw std::bad_alloc();
  g_live_bytes.fetch_add(static_cast<long long>(malloc_usable_size(p)), std::memory_order_relaxed);
  return p;
}
void counted_free(void* p) noexcept {
  if (!p) return;
  g_live_bytes.fetch_sub(static_cast<long long>(malloc_usable_size(p)), std::memory_order_relaxed);
  std::free(p);
}
}  // namespace
void* counted_aligned_alloc(std::size_t n, std::size_t align) {
  void* p = std::aligned_alloc(align, (n + align - 1) / align * align);
  if (!p) throw std::bad_alloc();
  g_live_bytes.fetch_add(static_cast<long long>(malloc_usable_size(p)), std::memory_order_relaxed);
  return p;
}
void* operator new(std::size_t n, std::align_val_t a) {
  return counted_aligned_alloc(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return counted_aligned_alloc(n, static_cast<std::size_t>(a));
}
void operator delete(void* p, std::align_val_t) noexcept {
  counted_free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  counted_free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  counted_free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  counted_free(p);
}
void* operator new(std::size_t n) {
  return counted_alloc(n);
}
void* operator new[](std::size_t n) {
  return counted_alloc(n);
}
void operator delete(void* p) noexcept {
  counted_free(p);
}
void operator delete[](void* p) noexcept {
  counted_free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  counted_free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  counted_free(p);
}

namespace {

using inhap::MeshIndex;
using inhap::MeshIndexOptions;
using inhap::Rng;
using inhap::TriMesh;
using inhap::Vec3;
using Clock = std::chrono::steady_clock;

// --- CGAL ------------------------------------------------------------------------------------
using K = CGAL::Simple_cartesian<double>;
using CTriangle = K::Triangle_3;
using CPrimitive = CGAL::AABB_triangle_primitive<K, std::vector<CTriangle>::const_iterator>;
using CTree = CGAL::AABB_tree<CGAL::AABB_traits<K, CPrimitive>>;
using CSegmentHit = CTree::Intersection_and_primitive_id<K::Segment_3>::Type;

struct CgalIndex {
  std::vector<CTriangle> triangles;  // the tree points into this vector
  CTree tree;
};

K::Point_3 cp(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

std::unique_ptr<CgalIndex> build_cgal(const TriMesh& m) {
  auto c = std::make_unique<CgalIndex>();
  c->triangles.reserve(m.num_triangles());
  for (const auto& t : m.triangles)
    c->triangles.emplace_back(cp(m.positions[t[0]]), cp(m.positions[t[1]]), cp(m.positions[t[2]]));
  c->tree.rebuild(c->triangles.begin(), c->triangles.end());
  c->tree.accelerate_distance_queries();  // builds the KD-tree now, not in the first query
  return c;
}

double distance_from(const K::Point_3& a, const boost::variant<K::Point_3, K::Segment_3>& x) {
  if (const auto* p = boost::get<K::Point_3>(&x)) return std::sqrt(CGAL::squared_distance(a, *p));
  const auto& s = boost::get<K::Segment_3>(x);
  return std::sqrt(
      std::min(CGAL::squared_distance(a, s.source()), CGAL::squared_distance(a, s.target())));
}

// Segment parameter of the first hit via first_intersection(Ray_3), or -1.
double cgal_ray_t(const CTree& tree, const Vec3& a, const Vec3& b) {
  const auto r = tree.first_intersection(K::Ray_3(cp(a), cp(b)));
  if (!r) return -1;
  const double len = (b - a).norm(), d = distance_from(cp(a), r->first);
  return d <= len ? d / len : -1;
}

// Segment parameter of the first hit via all_intersections(Segment_3), or -1.
double cgal_segment_t(const CTree& tree, const Vec3& a, const Vec3& b,
                      std::vector<CSegmentHit>& scratch) {
  scratch.clear();
  tree.all_intersections(K::Segment_3(cp(a), cp(b)), std::back_inserter(scratch));
  double best = std::numeric_limits<double>::infinity();
  for (const auto& h : scratch) best = std::min(best, distance_from(cp(a), h.first));
  return scratch.empty() ? -1 : best / (b - a).norm();
}

// --- scenes ----------------------------------------------------------------------------------
// AFM-like topography: a few smooth bumps of 1-3 mm, wavy ridges, fine texture.
double afm_height(double x, double y) {
  struct Bump {
    double x, y, sigma, amp;
  };
  static const Bump bumps[] = {
      {25, 30, 8, 2.5}, {70, 60, 12, 3.0}, {45, 80, 6, -1.5}, {80, 20, 10, 1.8}, {15, 75, 5, 1.2}};
  double h = 0;
  for (const auto& b : bumps)
    h += b.amp *
         std::exp(-((x - b.x) * (x - b.x) + (y - b.y) * (y - b.y)) / (2 * b.sigma * b.sigma));
  h += 0.5 * std::sin(2 * std::numbers::pi * (x + 3 * std::sin(2 * std::numbers::pi * y / 40)) / 9);
  h += 0.05 * std::sin(2 * std::numbers::pi * x / 1.7) * std::cos(2 * std::numbers::pi * y / 2.3);
  return h;
}

struct Scene {
  std::string name;
  TriMesh mesh;
  std::vector<std::pair<Vec3, Vec3>> segments;  // servo-like
  std::vector<Vec3> points;                     // within 5 mm of the surface
  std::vector<Vec3> near_points;                // within 0.5 mm (contact regime)
  std::vector<Vec3> path;  // servo path: 0.1 mm per query (100 mm/s at 1 kHz), -5..5 mm off
  std::unique_ptr<MeshIndex> ours;       // default options (seed grid)
  std::unique_ptr<MeshIndex> ours_tree;  // seed_shell = 0: the tree alone
  std::unique_ptr<CgalIndex> cgal;
};

constexpr int kQueries = 20000;
constexpr int kChecked = 5000;  // queries compared between inhap and CGAL (untimed)

Vec3 random_unit(Rng& rng) {
  Vec3 v;
  do {
    for (int k = 0; k < 3; ++k) v[k] = rng.uniform(-1, 1);
  } while (v.squaredNorm() > 1 || v.squaredNorm() < 1e-6);
  return v.normalized();
}

void make_queries(Scene& s, std::uint64_t seed) {
  Rng rng(seed);
  const TriMesh& m = s.mesh;
  for (int i = 0; i < kQueries; ++i) {
    const auto f = rng.below(m.num_triangles());
    double u = rng.uniform(), v = rng.uniform();
    if (u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    const auto& t = m.triangles[f];
    const Vec3 p = (1 - u - v) * m.positions[t[0]] + u * m.positions[t[1]] + v * m.positions[t[2]];
    const Vec3 n = m.face_normal(f);
    // Segment of 0.5-2 mm heading roughly into the surface; crosses it when lambda in [0, 1].
    const Vec3 d = (-n + 0.5 * random_unit(rng)).normalized();
    const double len = rng.uniform(0.5, 2.0), lambda = rng.uniform(-0.5, 1.5);
    const Vec3 a = p - lambda * len * d;
    s.segments.emplace_back(a, a + len * d);
    s.points.push_back(p + rng.uniform(-5.0, 5.0) * n);
    s.near_points.push_back(p + rng.uniform(-0.5, 0.5) * n);
  }
}

// A probe stroking the surface at 100 mm/s sampled at 1 kHz (<= 0.1 mm between queries) while
// its distance to the surface swings slowly between -5 and 5 mm (period 700 queries): the query
// sequence the servo loop and the proxy estimator issue. `surface(a, b)` gives the surface point
// and its unit normal for path parameters (a, b); the parameters advance so the step is 0.1 mm.
template <class Surface>
void make_path(Scene& s, Surface&& surface, double wa, double wb) {
  double a = 0.3, b = 0.1;
  for (int i = 0; i < kQueries; ++i) {
    const auto [x, n] = surface(a, b);
    s.path.push_back(x + 5.0 * std::sin(2 * std::numbers::pi * i / 700.0) * n);
    // Step (wa, wb) in parameter space scaled to 0.1 mm on the surface (finite difference).
    const double h = 1e-6;
    const Vec3 da = (surface(a + h, b).first - x) / h, db = (surface(a, b + h).first - x) / h;
    const double len = (wa * da + wb * db).norm();
    a += 0.1 * wa / len;
    b += 0.1 * wb / len;
  }
}

Scene& scene(int which) {
  static std::unique_ptr<Scene> scenes[2];
  if (!scenes[which]) {
    auto s = std::make_unique<Scene>();
    if (which == 0) {
      s->name = "afm_grid_131k";
      s->mesh = inhap::test::make_grid_mesh(257, 257, 0.39, afm_height);
      // Lissajous over the 100 x 100 mm grid, offset along z.
      make_path(
          *s,
          [](double a, double b) {
            const double x = 50 + 45 * std::sin(a), y = 50 + 45 * std::sin(b);
            return std::pair<Vec3, Vec3>(Vec3(x, y, afm_height(x, y)), Vec3::UnitZ());
          },
          1.0, 1.37);
    } else {
      s->name = "torus_1M";
      s->mesh = inhap::test::make_torus(40.0, 15.0, 1000, 500);
      // Winding path over the torus (u around the z axis, v around the tube), offset along
      // the true normal.
      make_path(
          *s,
          [](double u, double v) {
            const double rho = 40.0 + 15.0 * std::cos(v);
            const Vec3 n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
            return std::pair<Vec3, Vec3>(
                Vec3(rho * std::cos(u), rho * std::sin(u), 15.0 * std::sin(v)), n);
          },
          1.0, 2.3);
    }
    make_queries(*s, 42 + which);
    scenes[which] = std::move(s);
  }
  return *scenes[which];
}

MeshIndexOptions tree_only() {
  MeshIndexOptions o;
  o.seed_shell = 0;
  return o;
}
const MeshIndex& ours(Scene& s, bool tree = false) {
  auto& slot = tree ? s.ours_tree : s.ours;
  if (!slot) slot = std::make_unique<MeshIndex>(s.mesh, tree ? tree_only() : MeshIndexOptions{});
  return *slot;
}
const CTree& cgal(Scene& s) {
  if (!s.cgal) s.cgal = build_cgal(s.mesh);
  return s.cgal->tree;
}

// --- result table ----------------------------------------------------------------------------
struct Row {
  double build_ms = NAN, mbytes = NAN, seg_p50 = NAN, seg_p99 = NAN, cp_p50 = NAN, cp_p99 = NAN,
         near_p50 = NAN, near_p99 = NAN, path_p50 = NAN, path_p99 = NAN, hint_p50 = NAN,
         hint_p99 = NAN;
};
std::map<std::string, Row> g_rows;  // "scene / method"

double percentile(std::vector<double>& v, double q) {
  const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// Runs query(i) once per iteration, cycling over the query set, each timed on its own.
template <class Query>
void time_queries(benchmark::State& state, Query&& query, double& p50, double& p99) {
  std::vector<double> us(static_cast<std::size_t>(state.max_iterations));
  std::size_t k = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    benchmark::DoNotOptimize(query(k % kQueries));
    const auto t1 = Clock::now();
    us[k++] = std::chrono::duration<double, std::micro>(t1 - t0).count();
  }
  us.resize(k);
  p50 = percentile(us, 0.50);
  p99 = percentile(us, 0.99);
  state.counters["p50_us"] = p50;
  state.counters["p99_us"] = p99;
}

// --- benchmarks ------------------------------------------------------------------------------
template <class Build>
void bm_build(benchmark::State& state, int which, const char* method, Build&& build) {
  Scene& s = scene(which);
  Row& row = g_rows[s.name + " / " + method];
  for (auto _ : state) {
    const long long before = g_live_bytes.load();
    const auto t0 = Clock::now();
    build(s);
    const auto t1 = Clock::now();
    row.build_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    row.mbytes = static_cast<double>(g_live_bytes.load() - before) / 1e6;
  }
  state.counters["build_ms"] = row.build_ms;
  state.counters["heap_MB"] = row.mbytes;
  state.counters["triangles"] = static_cast<double>(s.mesh.num_triangles());
  if (s.ours && std::string(method) == "inhap")
    state.counters["memory_bytes_MB"] = static_cast<double>(s.ours->memory_bytes()) / 1e6;
}

void bm_build_ours(benchmark::State& state, int which) {
  bm_build(state, which, "inhap", [](Scene& s) {
    s.ours.reset();
    s.ours = std::make_unique<MeshIndex>(s.mesh);
  });
  const auto g = scene(which).ours->seed_grid_info();
  state.counters["grid_cell_mm"] = g.cell;
  state.counters["grid_covered"] = static_cast<double>(g.covered);
  state.counters["grid_seeds_per_cell"] = g.seeds_per_cell;
  state.counters["grid_MB"] = static_cast<double>(g.bytes) / 1e6;
}
void bm_build_ours_tree(benchmark::State& state, int which) {
  bm_build(state, which, "inhap tree only", [](Scene& s) {
    s.ours_tree.reset();
    s.ours_tree = std::make_unique<MeshIndex>(s.mesh, tree_only());
  });
}
void bm_build_cgal(benchmark::State& state, int which, const char* method) {
  bm_build(state, which, method, [](Scene& s) {
    s.cgal.reset();
    s.cgal = build_cgal(s.mesh);
  });
}

void bm_segment_ours(benchmark::State& state, int which) {
  Scene& s = scene(which);
  const MeshIndex& index = ours(s);
  Row& row = g_rows[s.name + " / inhap"];
  time_queries(
      state,
      [&](std::size_t i) { return index.first_hit(s.segments[i].first, s.segments[i].second); },
      row.seg_p50, row.seg_p99);
  int hits = 0;
  for (const auto& [a, b] : s.segments) hits += index.first_hit(a, b).has_value();
  state.counters["hit_fraction"] = static_cast<double>(hits) / kQueries;
}

// Checks CGAL against ours on all queries: number of disagreeing hit/miss, largest |t diff|.
template <class CgalT>
void compare_segments(benchmark::State& state, Scene& s, CgalT&& cgal_t) {
  const MeshIndex& index = ours(s);
  int disagree = 0;
  double max_dt = 0;
  for (int i = 0; i < kChecked; ++i) {
    const auto& [a, b] = s.segments[i];
    const auto h = index.first_hit(a, b);
    const double t = cgal_t(a, b);
    if (h.has_value() != (t >= 0))
      ++disagree;
    else if (h)
      max_dt = std::max(max_dt, std::abs(h->t - t));
  }
  state.counters["disagree"] = disagree;
  state.counters["max_dt"] = max_dt;
}

void bm_segment_cgal_ray(benchmark::State& state, int which) {
  Scene& s = scene(which);
  const CTree& tree = cgal(s);
  Row& row = g_rows[s.name + " / CGAL ray"];
  time_queries(
      state,
      [&](std::size_t i) { return cgal_ray_t(tree, s.segments[i].first, s.segments[i].second); },
      row.seg_p50, row.seg_p99);
  compare_segments(state, s, [&](const Vec3& a, const Vec3& b) { return cgal_ray_t(tree, a, b); });
}

void bm_segment_cgal_all(benchmark::State& state, int which) {
  Scene& s = scene(which);
  const CTree& tree = cgal(s);
  Row& row = g_rows[s.name + " / CGAL segment"];
  std::vector<CSegmentHit> scratch;
  scratch.reserve(64);
  time_queries(
      state,
      [&](std::size_t i) {
        return cgal_segment_t(tree, s.segments[i].first, s.segments[i].second, scratch);
      },
      row.seg_p50, row.seg_p99);
  compare_segments(
      state, s, [&](const Vec3& a, const Vec3& b) { return cgal_segment_t(tree, a, b, scratch); });
}

// Closest-point query sets: random points within 5 mm of the surface, within 0.5 mm (contact
// regime), and the servo path (in order: consecutive queries 0.1 mm apart).
enum Kind { kFar = 0, kNear = 1, kPath = 2 };
const std::vector<Vec3>& points_of(const Scene& s, int kind) {
  return kind == kFar ? s.points : kind == kNear ? s.near_points : s.path;
}
std::pair<double*, double*> row_slots(Row& row, int kind) {
  if (kind == kFar) return {&row.cp_p50, &row.cp_p99};
  if (kind == kNear) return {&row.near_p50, &row.near_p99};
  return {&row.path_p50, &row.path_p99};
}

void bm_closest_ours(benchmark::State& state, int which, int kind, bool tree) {
  Scene& s = scene(which);
  const MeshIndex& index = ours(s, tree);
  const auto& pts = points_of(s, kind);
  const auto slots = row_slots(g_rows[s.name + (tree ? " / inhap tree only" : " / inhap")], kind);
  time_queries(
      state, [&](std::size_t i) { return index.closest_point(pts[i]).distance2; }, *slots.first,
      *slots.second);
  // Work per query (untimed): inner nodes visited, triangles loaded, full point-triangle tests.
  MeshIndex::QueryStats st;
  for (int i = 0; i < kChecked; ++i)
    index.closest_point_counted(pts[i], std::numeric_limits<double>::infinity(), st);
  state.counters["nodes"] = static_cast<double>(st.nodes) / kChecked;
  state.counters["tris"] = static_cast<double>(st.triangles) / kChecked;
  state.counters["exact"] = static_cast<double>(st.exact) / kChecked;
  state.counters["seeded"] = static_cast<double>(st.seeded) / kChecked;
}

// The servo path as a servo loop queries it: each query hinted with the previous answer's
// triangle (MeshIndex::closest_point(p, max_distance, hint)).
void bm_closest_path_hint(benchmark::State& state, int which, bool tree) {
  Scene& s = scene(which);
  const MeshIndex& index = ours(s, tree);
  Row& row = g_rows[s.name + (tree ? " / inhap tree only" : " / inhap")];
  std::int32_t prev = -1;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  time_queries(
      state,
      [&](std::size_t i) {
        const inhap::ClosestPoint c = index.closest_point(s.path[i], kInf, prev);
        prev = c.triangle;
        return c.distance2;
      },
      row.hint_p50, row.hint_p99);
  MeshIndex::QueryStats st;
  prev = -1;
  double max_dd = 0;
  for (int i = 0; i < kChecked; ++i) {
    const inhap::ClosestPoint c = index.closest_point_counted(s.path[i], kInf, st, prev);
    max_dd = std::max(max_dd, std::abs(c.distance2 - index.closest_point(s.path[i]).distance2));
    prev = c.triangle;
  }
  state.counters["nodes"] = static_cast<double>(st.nodes) / kChecked;
  state.counters["exact"] = static_cast<double>(st.exact) / kChecked;
  state.counters["max_distance2_diff"] = max_dd;  // against the unhinted query: must be ~0
}

void bm_closest_cgal(benchmark::State& state, int which, int kind) {
  Scene& s = scene(which);
  const CTree& tree = cgal(s);
  const auto& pts = points_of(s, kind);
  const auto slots = row_slots(g_rows[s.name + " / CGAL ray"], kind);  // same tree as the ray row
  time_queries(
      state, [&](std::size_t i) { return tree.closest_point_and_primitive(cp(pts[i])).first; },
      *slots.first, *slots.second);
  const MeshIndex& index = ours(s);
  double max_dd = 0;
  for (int i = 0; i < kChecked; ++i) {
    const Vec3& p = pts[i];
    const double d_cgal = std::sqrt(CGAL::squared_distance(cp(p), tree.closest_point(cp(p))));
    max_dd = std::max(max_dd, std::abs(std::sqrt(index.closest_point(p).distance2) - d_cgal));
  }
  state.counters["max_distance_diff_mm"] = max_dd;
}

void register_all() {
  for (int w = 0; w < 2; ++w) {
    const std::string n = w == 0 ? "afm_grid_131k" : "torus_1M";
    auto reg = [&](const std::string& what, auto fn) {
      return benchmark::RegisterBenchmark((what + "/" + n).c_str(), fn, w)
          ->Unit(benchmark::kMicrosecond);
    };
    reg("build/inhap", bm_build_ours)->Iterations(1);
    reg("build/inhap_tree", bm_build_ours_tree)->Iterations(1);
    benchmark::RegisterBenchmark(("build/cgal/" + n).c_str(), bm_build_cgal, w, "CGAL ray")
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
    reg("first_hit/inhap", bm_segment_ours);
    reg("first_hit/cgal_ray", bm_segment_cgal_ray);
    reg("first_hit/cgal_segment", bm_segment_cgal_all);
    for (const int kind : {kFar, kNear, kPath}) {
      const std::string what = kind == kFar    ? "closest_5mm/"
                               : kind == kNear ? "closest_0.5mm/"
                                               : "closest_path/";
      benchmark::RegisterBenchmark((what + "inhap/" + n).c_str(), bm_closest_ours, w, kind, false)
          ->Unit(benchmark::kMicrosecond);
      benchmark::RegisterBenchmark((what + "inhap_tree/" + n).c_str(), bm_closest_ours, w, kind,
                                   true)
          ->Unit(benchmark::kMicrosecond);
      benchmark::RegisterBenchmark((what + "cgal/" + n).c_str(), bm_closest_cgal, w, kind)
          ->Unit(benchmark::kMicrosecond);
    }
    for (const bool tree : {false, true})
      benchmark::RegisterBenchmark(
          ((tree ? "closest_path_hint/inhap_tree/" : "closest_path_hint/inhap/") + n).c_str(),
          bm_closest_path_hint, w, tree)
          ->Unit(benchmark::kMicrosecond);
  }
}

void print_table() {
  auto f = [](double v, const char* fmt) {
    static char buf[4][32];
    static int slot = 0;
    char* b = buf[slot++ % 4];
    if (std::isnan(v))
      std::snprintf(b, 32, "%s", "-");
    else
      std::snprintf(b, 32, fmt, v);
    return b;
  };
  std::printf("\n%-28s %8s %8s | %-19s | %-19s | %-19s | %-19s | %-19s\n", "mesh / method",
              "build ms", "heap MB", "first hit p50/p99", "closest 5mm p50/p99",
              "closest .5mm p50/p99", "closest path p50/p99", "path hinted p50/p99");
  for (const auto& [name, r] : g_rows) {
    std::printf("%-28s %8s %8s | ", name.c_str(), f(r.build_ms, "%.0f"), f(r.mbytes, "%.1f"));
    std::printf("%8s / %8s | ", f(r.seg_p50, "%.2f"), f(r.seg_p99, "%.2f"));
    std::printf("%8s / %8s | ", f(r.cp_p50, "%.2f"), f(r.cp_p99, "%.2f"));
    std::printf("%8s / %8s | ", f(r.near_p50, "%.2f"), f(r.near_p99, "%.2f"));
    std::printf("%8s / %8s | ", f(r.path_p50, "%.2f"), f(r.path_p99, "%.2f"));
    std::printf("%8s / %8s\n", f(r.hint_p50, "%.2f"), f(r.hint_p99, "%.2f"));
  }
  std::printf(
      "(latencies in microseconds per query; CGAL closest uses the same tree as CGAL ray)\n");
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  print_table();
  benchmark::Shutdown();
  return 0;
}
