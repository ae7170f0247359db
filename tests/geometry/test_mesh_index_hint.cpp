// MeshIndex::closest_point with a warm-start hint: same answer as brute force whatever the hint
// (right, wrong, far, invalid), and less work along a servo-like path. Units: mm.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "geometry/reference_distance.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "support/meshes.hpp"

using namespace inhap;

namespace test_mesh_index_hint {

constexpr double kInf = std::numeric_limits<double>::infinity();

double brute_d2(const TriMesh& m, const Vec3& p) {
  double best = kInf;
  for (const Tri& t : m.triangles)
    best = std::min(
        best, test::ref_distance2(p, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]));
  return best;
}

double tri_d2(const TriMesh& m, std::int32_t f, const Vec3& p) {
  const Tri& t = m.triangles[f];
  return test::ref_distance2(p, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]);
}

double bumpy(double x, double y) {
  return 0.4 * std::sin(1.1 * x) * std::cos(0.7 * y);
}

TEST(MeshIndexHint, AnyHintGivesTheBruteForceAnswer) {
  const TriMesh meshes[] = {test::make_torus(20, 6, 60, 30), test::random_soup(1500, 3),
                            test::make_grid_mesh(41, 41, 0.25, bumpy)};
  for (const TriMesh& m : meshes) {
    const MeshIndex index(m);
    const auto nt = static_cast<std::int32_t>(m.num_triangles());
    const Vec3 lo = m.bbox().min, size = m.bbox().size();
    Rng rng(21);
    for (int i = 0; i < 1500; ++i) {
      Vec3 p;
      for (int k = 0; k < 3; ++k) p[k] = lo[k] + size[k] * rng.uniform(-0.2, 1.2);
      const double ref = brute_d2(m, p);
      const std::int32_t right = index.closest_point(p).triangle;
      const std::int32_t hints[] = {
          right, static_cast<std::int32_t>(rng.below(nt)), (right + 1) % nt, -1, nt, -7};
      for (const std::int32_t h : hints) {
        const ClosestPoint cp = index.closest_point(p, kInf, h);
        ASSERT_TRUE(cp.valid()) << "hint " << h;
        EXPECT_NEAR(std::sqrt(cp.distance2), std::sqrt(ref), 1e-9 * std::sqrt(ref) + 1e-14)
            << "point " << i << " hint " << h;
        EXPECT_NEAR(std::sqrt(tri_d2(m, cp.triangle, p)), std::sqrt(ref),
                    1e-9 * std::sqrt(ref) + 1e-14);
        EXPECT_LT((p - cp.point).squaredNorm() - cp.distance2, 1e-12 * (1 + cp.distance2));
      }
    }
  }
}

TEST(MeshIndexHint, MaxDistanceStillCutsOffWithAHint) {
  const TriMesh m = test::make_grid_mesh(11, 11, 1.0);  // plane z = 0
  const MeshIndex index(m);
  const Vec3 p(4.3, 5.6, 2.0);
  const std::int32_t right = index.closest_point(p).triangle;
  EXPECT_FALSE(index.closest_point(p, 1.99, right).valid());  // the hint is 2 mm away
  const ClosestPoint cp = index.closest_point(p, 2.01, right);
  ASSERT_TRUE(cp.valid());
  EXPECT_NEAR(cp.distance2, 4.0, 1e-12);
  EXPECT_FALSE(index.closest_point(p, -1.0, right).valid());
  EXPECT_FALSE(index.closest_point(Vec3(std::nan(""), 0, 0), kInf, right).valid());
}

// A probe moving 0.1 mm per tick around a torus while its distance to the surface swings
// between -3 and 3 mm: hinting with the previous tick's triangle gives the same distances and
// does markedly fewer point-triangle tests (the hint bounds the search from the root on).
TEST(MeshIndexHint, PreviousTickHintSavesWork) {
  const TriMesh m = test::make_torus(40, 15, 400, 200);
  MeshIndexOptions tree_only;  // the hint's effect on the tree's descent
  tree_only.seed_shell = 0;
  const MeshIndex index(m, tree_only);
  MeshIndex::QueryStats cold, warm;
  std::int32_t prev = -1;
  const double step = 0.1 / 55.0;  // rad per tick on the outer equator (radius 55 mm)
  for (int i = 0; i < 3000; ++i) {
    const double u = i * step, v = 0.3 * std::sin(i * 0.01);
    const Vec3 n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
    const Vec3 s((40 + 15 * std::cos(v)) * std::cos(u), (40 + 15 * std::cos(v)) * std::sin(u),
                 15 * std::sin(v));
    const Vec3 p = s + 3.0 * std::sin(2 * std::numbers::pi * i / 700.0) * n;
    const ClosestPoint a = index.closest_point_counted(p, kInf, cold);
    const ClosestPoint b = index.closest_point_counted(p, kInf, warm, prev);
    ASSERT_TRUE(a.valid() && b.valid());
    EXPECT_NEAR(std::sqrt(b.distance2), std::sqrt(a.distance2), 1e-9);
    prev = b.triangle;
  }
  std::printf(
      "[ hint ] per query: nodes %.1f / %.1f, point-triangle tests %.1f / %.1f (cold / hinted)\n",
      cold.nodes / 3000.0, warm.nodes / 3000.0, cold.exact / 3000.0, warm.exact / 3000.0);
  // Measured: about 13 % less work in all (25 % fewer triangle tests); an ignored hint gives
  // slightly *more* (the hint's own test).
  EXPECT_LT(static_cast<double>(warm.nodes + warm.exact), 0.92 * (cold.nodes + cold.exact));
  EXPECT_LT(warm.exact, 0.85 * cold.exact);
}
}  // namespace test_mesh_index_hint
