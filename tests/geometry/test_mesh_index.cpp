// MeshIndex against brute force over all triangles with independent reference routines
// (Moeller-Trumbore segment test, plane projection + edge clamping for closest points), exact
// edge/vertex cases for watertightness, and a counting allocator for the no-allocation promise.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <optional>
#include <thread>
#include <vector>

#include "geometry/reference_distance.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "support/alloc_counter.hpp"
#include "support/meshes.hpp"

using namespace inhap;

namespace test_mesh_index {

// --- independent references ------------------------------------------------------------------
struct RefHit {
  double t;
  Vec3 bary;
};

// Moeller-Trumbore, t in [0, 1].
std::optional<RefHit> ref_segment(const Vec3& a, const Vec3& b, const Vec3& v0, const Vec3& v1,
                                  const Vec3& v2) {
  const Vec3 d = b - a, e1 = v1 - v0, e2 = v2 - v0;
  const Vec3 pv = d.cross(e2);
  const double det = e1.dot(pv);
  if (det == 0) return std::nullopt;
  const Vec3 tv = a - v0;
  const double u = tv.dot(pv) / det;
  if (u < 0 || u > 1) return std::nullopt;
  const Vec3 qv = tv.cross(e1);
  const double v = d.dot(qv) / det;
  if (v < 0 || u + v > 1) return std::nullopt;
  const double t = e2.dot(qv) / det;
  if (t < 0 || t > 1) return std::nullopt;
  return RefHit{t, Vec3(1 - u - v, u, v)};
}

using test::ref_distance2;

const Vec3& P(const TriMesh& m, std::int32_t f, int c) {
  return m.positions[m.triangles[f][c]];
}

std::optional<RefHit> ref_tri(const TriMesh& m, std::int32_t f, const Vec3& a, const Vec3& b) {
  return ref_segment(a, b, P(m, f, 0), P(m, f, 1), P(m, f, 2));
}
double ref_d2(const TriMesh& m, std::int32_t f, const Vec3& p) {
  return ref_distance2(p, P(m, f, 0), P(m, f, 1), P(m, f, 2));
}

Vec3 random_in(Rng& rng, const Vec3& lo, const Vec3& hi) {
  Vec3 p;
  for (int k = 0; k < 3; ++k) p[k] = rng.uniform(lo[k], hi[k]);
  return p;
}
Vec3 random_unit(Rng& rng) {
  Vec3 v;
  do {
    for (int k = 0; k < 3; ++k) v[k] = rng.uniform(-1, 1);
  } while (v.squaredNorm() > 1 || v.squaredNorm() < 1e-6);
  return v.normalized();
}

double bumpy(double x, double y) {
  return 0.3 * std::sin(1.3 * x) * std::cos(0.9 * y) + 0.05 * x;
}

struct Case {
  const char* name;
  TriMesh mesh;
};

std::vector<Case> cases() {
  return {{"soup", test::random_soup(2000, 7)},
          {"icosphere", test::make_sphere(10.0, 3)},
          {"bumpy_grid", test::make_grid_mesh(31, 31, 0.25, bumpy)}};
}

// A uniformly random point on a random triangle, and that triangle's unit normal.
std::pair<Vec3, Vec3> random_surface_point(Rng& rng, const TriMesh& m) {
  const auto f = static_cast<std::int32_t>(rng.below(m.num_triangles()));
  double u = rng.uniform(), v = rng.uniform();
  if (u + v > 1) {
    u = 1 - u;
    v = 1 - v;
  }
  const Vec3 s = (1 - u - v) * P(m, f, 0) + u * P(m, f, 1) + v * P(m, f, 2);
  return {s, m.face_normal(f)};
}

// Three kinds, in turn: long random segments (up to the box diagonal), short ones (up to 5 %)
// anywhere in the box grown by 20 %, and short ones near the surface heading roughly against
// the normal, about half of them crossing it.
std::pair<Vec3, Vec3> random_segment(Rng& rng, const TriMesh& m, int i) {
  const Box3 box = m.bbox();
  const double diag = box.size().norm();
  if (i % 3 == 2) {
    const auto [s, n] = random_surface_point(rng, m);
    const Vec3 d = (-n + 0.5 * random_unit(rng)).normalized();
    const double len = diag * rng.uniform(0.005, 0.05);
    const Vec3 a = s - rng.uniform(-0.5, 1.5) * len * d;
    return {a, a + len * d};
  }
  const Vec3 pad = 0.2 * box.size() + Vec3::Constant(1e-3);
  const Vec3 a = random_in(rng, box.min - pad, box.max + pad);
  const double len = (i % 3 ? 0.05 : 1.0) * diag * rng.uniform(0.01, 1.0);
  return {a, a + len * random_unit(rng)};
}

// Half anywhere in the box grown by 30 %, half within 5 % of the diagonal of the surface.
Vec3 random_point(Rng& rng, const TriMesh& m, int i) {
  const Box3 box = m.bbox();
  if (i % 2) {
    const auto [s, n] = random_surface_point(rng, m);
    return s + 0.05 * box.size().norm() * rng.uniform(-1, 1) * n;
  }
  return random_in(rng, box.min - 0.3 * box.size(), box.max + 0.3 * box.size());
}

// ---------------------------------------------------------------------------------------------
// The index's storage honours its element types' alignment (its records are 64- and 128-byte
// aligned): with a fixed 64-byte alignment a 128-byte record was stored at an address that is
// not a multiple of 128 (undefined behaviour; UBSan: "store to misaligned address").
TEST(MeshIndex, StorageIsAlignedForEveryElementType) {
  struct alignas(128) Wide {
    double x[16];
  };
  detail::IndexAllocator<Wide> wide;
  std::vector<std::pair<Wide*, std::size_t>> held;
  for (std::size_t n = 1; n <= 64; ++n) {
    Wide* p = wide.allocate(n);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % alignof(Wide), 0u) << n << " records";
    held.emplace_back(p, n);
  }
  for (auto [p, n] : held) wide.deallocate(p, n);
  detail::IndexAllocator<Wide> big;  // the huge-page path (2 MiB alignment) above 1 MiB
  Wide* q = big.allocate((std::size_t{3} << 20) / sizeof(Wide));
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(q) % (std::size_t{2} << 20), 0u);
  big.deallocate(q, (std::size_t{3} << 20) / sizeof(Wide));
}

TEST(MeshIndex, FirstHitMatchesBruteForce) {
  for (const auto& c : cases()) {
    SCOPED_TRACE(c.name);
    const TriMesh& m = c.mesh;
    const MeshIndex index(m);
    ASSERT_EQ(index.num_triangles(), m.num_triangles());
    Rng rng(11);
    int hits = 0, ties = 0;
    const double scale = m.bbox().size().norm();
    for (int i = 0; i < 10000; ++i) {
      const auto [a, b] = random_segment(rng, m, i);
      std::optional<RefHit> ref;
      std::int32_t ref_f = -1;
      for (std::int32_t f = 0; f < static_cast<std::int32_t>(m.num_triangles()); ++f)
        if (auto h = ref_tri(m, f, a, b); h && (!ref || h->t < ref->t)) {
          ref = h;
          ref_f = f;
        }
      const auto hit = index.first_hit(a, b);
      ASSERT_EQ(hit.has_value(), ref.has_value()) << "segment " << i;
      ASSERT_EQ(index.any_hit(a, b), ref.has_value()) << "segment " << i;
      if (!ref) continue;
      ++hits;
      EXPECT_NEAR(hit->t, ref->t, 1e-9) << "segment " << i;
      if (hit->triangle != ref_f) {  // tie: the reported triangle must be equally near
        ++ties;
        const auto other = ref_tri(m, hit->triangle, a, b);
        const bool same_t = other && std::abs(other->t - ref->t) <= 1e-9;
        EXPECT_TRUE(same_t ||
                    ref_d2(m, hit->triangle, a + ref->t * (b - a)) < 1e-18 * scale * scale)
            << "segment " << i;
      }
      const Vec3 from_bary = hit->bary[0] * P(m, hit->triangle, 0) +
                             hit->bary[1] * P(m, hit->triangle, 1) +
                             hit->bary[2] * P(m, hit->triangle, 2);
      EXPECT_NEAR(hit->bary.sum(), 1.0, 1e-12);
      EXPECT_GE(hit->bary.minCoeff(), -1e-12);
      EXPECT_LT((from_bary - hit->point).norm(), 1e-9 * scale);
      EXPECT_LT((a + hit->t * (b - a) - hit->point).norm(), 1e-9 * scale);
      EXPECT_EQ(hit->entering, (b - a).dot(m.face_normal(hit->triangle)) < 0);
    }
    // The random segments must exercise both outcomes.
    EXPECT_GT(hits, 1000);
    EXPECT_LT(hits, 9000);
    std::printf("[ %s ] %d of 10000 segments hit, %d ties\n", c.name, hits, ties);
  }
}

TEST(MeshIndex, ClosestPointMatchesBruteForce) {
  for (const auto& c : cases()) {
    SCOPED_TRACE(c.name);
    const TriMesh& m = c.mesh;
    const MeshIndex index(m);
    Rng rng(12);
    const double scale = m.bbox().size().norm();
    for (int i = 0; i < 10000; ++i) {
      const Vec3 p = random_point(rng, m, i);
      double ref = std::numeric_limits<double>::infinity();
      for (std::int32_t f = 0; f < static_cast<std::int32_t>(m.num_triangles()); ++f)
        ref = std::min(ref, ref_d2(m, f, p));
      const ClosestPoint cp = index.closest_point(p);
      ASSERT_TRUE(cp.valid());
      EXPECT_NEAR(std::sqrt(cp.distance2), std::sqrt(ref), 1e-9 * std::sqrt(ref) + 1e-14)
          << "point " << i;
      // The reported triangle is (one of) the nearest, and its weights give the point.
      EXPECT_NEAR(std::sqrt(ref_d2(m, cp.triangle, p)), std::sqrt(ref), 1e-9 * std::sqrt(ref));
      const Vec3 from_bary = cp.bary[0] * P(m, cp.triangle, 0) + cp.bary[1] * P(m, cp.triangle, 1) +
                             cp.bary[2] * P(m, cp.triangle, 2);
      EXPECT_NEAR(cp.bary.sum(), 1.0, 1e-12);
      EXPECT_GE(cp.bary.minCoeff(), -1e-12);
      EXPECT_LT((from_bary - cp.point).norm(), 1e-12 * scale);
      EXPECT_NEAR((p - cp.point).squaredNorm(), cp.distance2, 1e-12 * cp.distance2);
    }
  }
}

TEST(MeshIndex, FlatGridClosestPointIsTheVerticalProjection) {
  const TriMesh m = test::make_grid_mesh(11, 11, 1.0);
  const MeshIndex index(m);
  Rng rng(3);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p(rng.uniform(0, 10), rng.uniform(0, 10), rng.uniform(-3, 3));
    const ClosestPoint cp = index.closest_point(p);
    ASSERT_TRUE(cp.valid());
    EXPECT_NEAR(cp.distance2, p.z() * p.z(), 1e-12);
    EXPECT_LT((cp.point - Vec3(p.x(), p.y(), 0)).norm(), 1e-12);
  }
  // Outside the grid: the nearest point is on the boundary, e.g. the corner (10, 10, 0).
  const ClosestPoint corner = index.closest_point(Vec3(13, 14, 0));
  EXPECT_NEAR(corner.distance2, 25.0, 1e-12);
  EXPECT_LT((corner.point - Vec3(10, 10, 0)).norm(), 1e-12);
}

// Watertightness, exactly: vertical segments through every vertex and every edge midpoint
// (horizontal, vertical and diagonal edges) of a flat grid with integer coordinates.
TEST(MeshIndex, FlatGridVerticesAndEdgeMidpointsAreNeverMissed) {
  const int n = 21;
  const TriMesh m = test::make_grid_mesh(n, n, 1.0);
  const MeshIndex index(m);
  int tested = 0, missed = 0, ref_missed = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (const Vec2& off : {Vec2(0, 0), Vec2(0.5, 0), Vec2(0, 0.5), Vec2(0.5, 0.5)}) {
        const double x = i + off.x(), y = j + off.y();
        if (x > n - 1 || y > n - 1) continue;
        for (const double dir : {1.0, -1.0}) {
          const Vec3 a(x, y, dir), b(x, y, -dir);
          ++tested;
          const auto hit = index.first_hit(a, b);
          if (!hit || !index.any_hit(a, b)) {
            ++missed;
            continue;
          }
          EXPECT_EQ(hit->t, 0.5);
          EXPECT_LT((hit->point - Vec3(x, y, 0)).norm(), 1e-12);
          EXPECT_EQ(hit->entering, dir > 0);  // the grid faces +z
          bool ref_hit = false;
          for (std::int32_t f = 0; f < static_cast<std::int32_t>(m.num_triangles()); ++f)
            ref_hit = ref_hit || ref_tri(m, f, a, b).has_value();
          ref_missed += !ref_hit;
        }
      }
  EXPECT_EQ(tested, 2 * (n * n + 3 * (n - 1) * (n - 1) + 2 * (n - 1)));
  EXPECT_EQ(missed, 0);
  std::printf(
      "[ flat grid ] %d exact vertex/edge segments, missed 0 expected, got %d "
      "(Moeller-Trumbore reference missed %d)\n",
      tested, missed, ref_missed);
}

// Watertightness under shear: tilted segments through every interior vertex and interior edge
// midpoint of a bumpy grid (generic, non-representable crossing points).
TEST(MeshIndex, TiltedSegmentsThroughBumpyGridVerticesAndEdgesAreNeverMissed) {
  const int n = 41;
  const TriMesh m = test::make_grid_mesh(n, n, 0.25, bumpy);
  const MeshIndex index(m);
  const MeshAdjacency adj = build_adjacency(m);
  Rng rng(5);
  std::vector<Vec3> targets;
  for (int j = 1; j + 1 < n; ++j)
    for (int i = 1; i + 1 < n; ++i) targets.push_back(m.positions[j * n + i]);
  for (const auto& e : adj.edges)
    if (e.faces == 2) targets.push_back(0.5 * (m.positions[e.a] + m.positions[e.b]));
  int missed = 0, ref_missed = 0;
  for (const Vec3& q : targets)
    for (int k = 0; k < 4; ++k) {
      Vec3 d = random_unit(rng);
      d.z() = (k % 2 ? 1.0 : -1.0) * (std::abs(d.z()) + 1.0);  // steeper than the bumps
      const Vec3 a = q + 0.3 * d, b = q - 0.3 * d;
      missed += !index.first_hit(a, b).has_value();
      missed += !index.any_hit(a, b);
      if (k == 0) {  // for the record: a non-watertight test does miss some of these
        bool ref_hit = false;
        for (std::int32_t f = 0; f < static_cast<std::int32_t>(m.num_triangles()) && !ref_hit; ++f)
          ref_hit = ref_tri(m, f, a, b).has_value();
        ref_missed += !ref_hit;
      }
    }
  EXPECT_EQ(missed, 0) << "of " << 8 * targets.size() << " queries";
  std::printf(
      "[ bumpy grid ] %zu tilted vertex/edge segments: 0 missed (Moeller-Trumbore "
      "reference missed %d of %zu)\n",
      4 * targets.size(), ref_missed, targets.size());
}

TEST(MeshIndex, SegmentsThroughClosedIcosphereEnterFirst) {
  const double R = 10.0;
  const TriMesh m = test::make_sphere(R, 3);
  const MeshIndex index(m);
  Rng rng(9);
  int failures = 0;
  for (int i = 0; i < 10000; ++i) {
    const Vec3 q = 0.8 * R * std::cbrt(rng.uniform()) * random_unit(rng);  // inside
    const Vec3 a = 2.0 * R * random_unit(rng);                             // outside
    const Vec3 b = 2.0 * q - a;                                            // through q
    const auto in = index.first_hit(a, b);
    failures += !(in && in->entering);
    const auto out = index.first_hit(q, a);  // from inside: the first hit exits
    failures += !(out && !out->entering);
  }
  EXPECT_EQ(failures, 0);
  // Aimed exactly at every vertex along the line through the centre (2v -> -2v).
  for (const Vec3& v : m.positions) {
    const auto hit = index.first_hit(2.0 * v, -2.0 * v);
    ASSERT_TRUE(hit.has_value());
    EXPECT_TRUE(hit->entering);
    EXPECT_NEAR(hit->t, 0.25, 1e-12);
    EXPECT_LT((hit->point - v).norm(), 1e-9);
  }
}

TEST(MeshIndex, MaxDistanceCutsOff) {
  const MeshIndex index(test::make_grid_mesh(11, 11, 1.0));
  const Vec3 p(4.3, 5.6, 2.0);
  EXPECT_FALSE(index.closest_point(p, 1.99).valid());
  const ClosestPoint cp = index.closest_point(p, 2.01);
  ASSERT_TRUE(cp.valid());
  EXPECT_NEAR(cp.distance2, 4.0, 1e-12);
  EXPECT_TRUE(index.closest_point(Vec3(4.3, 5.6, 0.0), 0.0).valid());  // on the surface
  EXPECT_FALSE(index.closest_point(p, -1.0).valid());
  EXPECT_FALSE(index.closest_point(p, std::nan("")).valid());
  EXPECT_FALSE(index.closest_point(Vec3(std::nan(""), 0, 0)).valid());
}

TEST(MeshIndex, TranslatedMeshIsQueriedWithTranslatedPoints) {
  TriMesh m = test::make_sphere(5.0, 3);
  const MeshIndex index(m);
  const Vec3 shift(3.5, -20.25, 7.0);
  m.transform(1.0, -shift);  // p -> p + shift
  const MeshIndex moved(m);
  Rng rng(4);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p = shift + random_in(rng, Vec3::Constant(-8), Vec3::Constant(8));
    const Vec3 q = p + 6.0 * random_unit(rng);
    EXPECT_NEAR(index.closest_point(p - shift).distance2, moved.closest_point(p).distance2, 1e-9);
    const auto h1 = index.first_hit(p - shift, q - shift), h2 = moved.first_hit(p, q);
    ASSERT_EQ(h1.has_value(), h2.has_value());
    if (h1) {
      EXPECT_NEAR(h1->t, h2->t, 1e-9);
    }
  }
}

TEST(MeshIndex, EmptyAndDegenerateMeshes) {
  const MeshIndex none;
  EXPECT_EQ(none.num_triangles(), 0u);
  EXPECT_TRUE(none.bounds().empty());
  EXPECT_FALSE(none.first_hit(Vec3(0, 0, 1), Vec3(0, 0, -1)));
  EXPECT_FALSE(none.any_hit(Vec3(0, 0, 1), Vec3(0, 0, -1)));
  EXPECT_FALSE(none.closest_point(Vec3::Zero()).valid());
  const MeshIndex empty{TriMesh{}};
  EXPECT_FALSE(empty.closest_point(Vec3::Zero()).valid());

  // Zero-area triangles: collinear, and all three corners coincident.
  TriMesh d;
  d.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0),
                 Vec3(5, 5, 5), Vec3(5, 5, 5), Vec3(5, 5, 5)};
  d.triangles = {{0, 1, 2}, {3, 4, 5}};
  const MeshIndex deg(d);
  EXPECT_FALSE(deg.first_hit(Vec3(1, 0, 1), Vec3(1, 0, -1)));
  const ClosestPoint cp = deg.closest_point(Vec3(1.5, 2, 0));
  ASSERT_TRUE(cp.valid());
  EXPECT_NEAR(cp.distance2, 4.0, 1e-12);
  EXPECT_LT((cp.point - Vec3(1.5, 0, 0)).norm(), 1e-12);
  EXPECT_NEAR(deg.closest_point(Vec3(5, 5, 6)).distance2, 1.0, 1e-12);

  // Degenerate triangles mixed into a valid mesh change nothing.
  TriMesh g = test::make_grid_mesh(5, 5, 1.0);
  g.append(d);
  const MeshIndex mixed(g);
  const auto hit = mixed.first_hit(Vec3(1.25, 2.5, 1), Vec3(1.25, 2.5, -1));
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->t, 0.5);
  EXPECT_FALSE(mixed.first_hit(Vec3(1, 1, 1), Vec3(1, 1, 1)));  // a == b
  EXPECT_FALSE(mixed.first_hit(Vec3(1, 1, 1), Vec3(1, std::nan(""), -1)));
}

TEST(MeshIndex, BadMeshThrows) {
  TriMesh m = test::make_grid_mesh(3, 3, 1.0);
  m.triangles.push_back({0, 1, 9});
  EXPECT_THROW(MeshIndex{m}, Error);
  m = test::make_grid_mesh(3, 3, 1.0);
  m.positions[4].x() = std::nan("");
  EXPECT_THROW(MeshIndex{m}, Error);
}

// Stress the build: identical triangles (no centroid spread) and geometrically spaced ones
// (deep SAH trees). Every triangle must still be found.
TEST(MeshIndex, PathologicalDistributionsStayCorrect) {
  TriMesh same;
  for (int i = 0; i < 500; ++i) {
    const auto b = static_cast<std::int32_t>(same.positions.size());
    same.positions.insert(same.positions.end(), {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)});
    same.triangles.push_back({b, b + 1, b + 2});
  }
  const MeshIndex si(same);
  ASSERT_TRUE(si.first_hit(Vec3(0.2, 0.2, 1), Vec3(0.2, 0.2, -1)));

  TriMesh geo;
  for (int i = 0; i < 3000; ++i) {
    const double x = std::pow(1.02, i) - 1.0, s = 1e-3 * (x + 1e-3);
    const auto b = static_cast<std::int32_t>(geo.positions.size());
    geo.positions.insert(geo.positions.end(), {Vec3(x, 0, 0), Vec3(x + s, 0, 0), Vec3(x, s, 0)});
    geo.triangles.push_back({b, b + 1, b + 2});
  }
  const MeshIndex gi(geo);
  for (std::int32_t f = 0; f < static_cast<std::int32_t>(geo.num_triangles()); ++f) {
    const Vec3 c = (P(geo, f, 0) + P(geo, f, 1) + P(geo, f, 2)) / 3.0;
    const ClosestPoint cp = gi.closest_point(c + Vec3(0, 0, 1e-6));
    ASSERT_EQ(cp.triangle, f);
    const auto hit = gi.first_hit(c + Vec3(0, 0, 1), c - Vec3(0, 0, 1));
    ASSERT_TRUE(hit.has_value());
    ASSERT_EQ(hit->triangle, f);
  }
}

TEST(MeshIndex, BoundsAndMemory) {
  const TriMesh m = test::make_torus(40, 15, 60, 30);
  ASSERT_EQ(m.num_triangles(), 3600u);
  const MeshIndex index(m);
  EXPECT_EQ(index.bounds().min, m.bbox().min);
  EXPECT_EQ(index.bounds().max, m.bbox().max);
  EXPECT_NEAR(index.bounds().max.x(), 55.0, 1e-12);
  EXPECT_GE(index.memory_bytes(), m.num_triangles() * (9 * sizeof(double) + 4));
  EXPECT_LT(index.memory_bytes(), m.num_triangles() * 200);
}

TEST(MeshIndex, QueriesDoNotAllocate) {
  const TriMesh m = test::make_torus(40, 15, 120, 60);
  const MeshIndex index(m);
  Rng rng(8);
  std::vector<Vec3> pts(20000);
  for (auto& p : pts) p = random_in(rng, Vec3(-60, -60, -20), Vec3(60, 60, 20));
  // The counter must see allocations at all (else this test could not fail).
  const long before_probe = test::heap_allocations();
  { std::vector<double> probe(100); }
  ASSERT_GT(test::heap_allocations(), before_probe);

  MeshIndex::QueryStats stats;
  const long before = test::heap_allocations();
  int hits = 0, any = 0, near = 0;
  double sum = 0;
  for (int i = 0; i < 10000; ++i) {
    const Vec3& a = pts[2 * i];
    const Vec3& b = pts[2 * i + 1];
    if (auto h = index.first_hit(a, b)) {
      sum += h->t;
      ++hits;
    }
    any += index.any_hit(a, b);
    sum += index.closest_point(a).distance2;
    near += index.closest_point(b, 1.0).valid();
    near += index.closest_point(b, 1.0, i % 100).valid();  // warm-started
    index.closest_point_counted(b, std::numeric_limits<double>::infinity(), stats);
  }
  EXPECT_EQ(test::heap_allocations() - before, 0);
  EXPECT_GT(stats.seeded, 1000);  // the seed grid's path was taken too
  EXPECT_GT(hits, 0);
  EXPECT_EQ(any, hits);
  EXPECT_GT(near, 0);
  EXPECT_GT(sum, 0);
}

TEST(MeshIndex, ConcurrentQueriesAgree) {
  const TriMesh m = test::make_sphere(10.0, 4);
  const MeshIndex index(m);
  Rng rng(10);
  std::vector<Vec3> pts(4000);
  for (auto& p : pts) p = random_in(rng, Vec3::Constant(-15), Vec3::Constant(15));
  auto run = [&](std::vector<double>& out) {
    for (std::size_t i = 0; i + 1 < pts.size(); i += 2) {
      auto h = index.first_hit(pts[i], pts[i + 1]);
      out.push_back(h ? h->t : -1.0);
      out.push_back(index.closest_point(pts[i]).distance2);
    }
  };
  std::vector<double> serial, r1, r2;
  run(serial);
  std::thread t1([&] { run(r1); }), t2([&] { run(r2); });
  t1.join();
  t2.join();
  EXPECT_EQ(r1, serial);
  EXPECT_EQ(r2, serial);
}
}  // namespace test_mesh_index
