// Sliding yield surface geometry and barycentric interpolation over reference points.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/friction/reference_mesh.hpp"
#include "inhap/friction/yield_surface.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::friction {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<double> eight_angles() {
  std::vector<double> a;
  for (int k = 0; k < 8; ++k) a.push_back(k * kPi / 4);
  return a;
}

// Coulomb cone: radius = c * level in every direction, measured at levels 1, 3, 5.
YieldSurface cone(double c) {
  std::vector<double> lv, r;
  for (double l : {1.0, 3.0, 5.0})
    for (int k = 0; k < 8; ++k) {
      lv.push_back(l);
      r.push_back(c * l);
    }
  return YieldSurface::make(eight_angles(), 3, lv, r);
}

TEST(YieldSurface, IsotropicConeIsExactEverywhere) {
  const YieldSurface s = cone(0.4);
  Rng rng(3);
  for (int i = 0; i < 200; ++i) {
    const double l = rng.uniform(0.0, 8.0), th = rng.uniform(-10.0, 10.0);
    EXPECT_NEAR(s.radius_at(l, th), 0.4 * l, 1e-12);  // beyond level 5: same cone
  }
  EXPECT_EQ(s.radius_at(-1.0, 0.3), 0.0);
  EXPECT_TRUE(s.inside(Vec3(0.39, 0.0, 1.0)));
  EXPECT_FALSE(s.inside(Vec3(0.0, 0.41, 1.0)));
  EXPECT_TRUE(s.inside(Vec3(0.8 * std::cos(1.0), 0.8 * std::sin(1.0), 2.001)));
  EXPECT_FALSE(s.inside(Vec3(0.01, 0.0, -0.1)));  // above the surface: no elastic range
}

TEST(YieldSurface, LinearBetweenLevelsAndDirections) {
  // Direction k has radius (k + 1) * level at level 2, and 10 (k + 1) at level 4.
  std::vector<double> lv, r;
  for (double l : {2.0, 4.0})
    for (int k = 0; k < 8; ++k) {
      lv.push_back(l);
      r.push_back(l == 2.0 ? 2.0 * (k + 1) : 10.0 * (k + 1));
    }
  const YieldSurface s = YieldSurface::make(eight_angles(), 2, lv, r);
  EXPECT_NEAR(s.radius_at(1.0, 0.0), 1.0, 1e-12);           // apex to first vertex
  EXPECT_NEAR(s.radius_at(3.0, 0.0), 6.0, 1e-12);           // between the levels
  EXPECT_NEAR(s.radius_at(8.0, 0.0), 20.0, 1e-12);          // cone beyond the last
  EXPECT_NEAR(s.radius_at(2.0, kPi / 8), 3.0, 1e-12);       // half-way between k=0 and k=1
  EXPECT_NEAR(s.radius_at(2.0, 15 * kPi / 8), 9.0, 1e-12);  // wrap: between k=7 and k=0
  EXPECT_NEAR(s.radius_at(2.0, -kPi / 8), 9.0, 1e-12);
  const Vec3 back = s.radial_return(Vec3(30.0, 0.0, 3.0));
  EXPECT_NEAR(back.x(), 6.0, 1e-12);
  EXPECT_NEAR(back.y(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(back.z(), 3.0);
}

TEST(YieldSurface, RayIntersectionMatchesTheAnalyticCone) {
  const YieldSurface s = cone(0.5);
  // Horizontal ray from the axis at level 2: hits at radius 1.
  auto h = s.intersect_ray(Vec3(0, 0, 2), Vec3(std::cos(0.7), std::sin(0.7), 0), 10.0);
  ASSERT_TRUE(h);
  EXPECT_NEAR(*h, 1.0, 1e-9);
  // Ray going down the axis from outside: x = 1 - s... crossing where |x| = 0.5 z.
  // origin (3, 0, 2), dir (-1, 0, 0): |3 - s| = 1 -> s = 2.
  h = s.intersect_ray(Vec3(3, 0, 2), Vec3(-1, 0, 0), 10.0);
  ASSERT_TRUE(h);
  EXPECT_NEAR(*h, 2.0, 1e-9);
  // Slanted ray from inside: (0,0,2) + s (1, 0, -1): s = 0.5 (2 - s) -> s = 2/3.
  h = s.intersect_ray(Vec3(0, 0, 2), Vec3(1, 0, -1), 10.0);
  ASSERT_TRUE(h);
  EXPECT_NEAR(*h, 2.0 / 3.0, 1e-9);
  // A ray that stays inside never crosses.
  EXPECT_FALSE(s.intersect_ray(Vec3(0, 0, 2), Vec3(0, 0, 1), 10.0));
}

TEST(YieldSurface, BlendIsVertexByVertex) {
  const YieldSurface a = cone(0.2), b = cone(0.6);
  YieldSurface m;
  const YieldSurface* s[] = {&a, &b};
  const double w[] = {0.25, 0.75};
  m.blend(s, w);
  EXPECT_TRUE(m.same_layout(a));
  EXPECT_NEAR(m.radius_at(3.0, 1.0), (0.25 * 0.2 + 0.75 * 0.6) * 3.0, 1e-12);
}

TEST(YieldSurface, MeshIsClosedAndOutwardOriented) {
  const TriMesh m = cone(0.5).to_mesh(2);
  EXPECT_EQ(m.num_vertices(), 1u + 3 * 16 + 1);
  const MeshTopology t = analyze_topology(m, build_adjacency(m));
  EXPECT_TRUE(t.watertight());
  EXPECT_TRUE(t.oriented());
  // Outward: the signed volume is positive (divergence theorem).
  double vol = 0;
  for (const Tri& f : m.triangles)
    vol += m.positions[f[0]].dot(m.positions[f[1]].cross(m.positions[f[2]])) / 6.0;
  EXPECT_GT(vol, 0.0);
}

TEST(YieldSurface, RejectsBadVertices) {
  const auto a = eight_angles();
  std::vector<double> lv(16, 1.0), r(16, 1.0);
  EXPECT_THROW(YieldSurface::make(a, 2, lv, r), Error);  // levels not increasing
  for (int k = 0; k < 8; ++k) lv[8 + k] = 2.0;
  EXPECT_NO_THROW(YieldSurface::make(a, 2, lv, r));
  r[3] = -0.1;
  EXPECT_THROW(YieldSurface::make(a, 2, lv, r), Error);
  r[3] = 1.0;
  std::vector<double> bad_angles = a;
  std::swap(bad_angles[1], bad_angles[2]);
  EXPECT_THROW(YieldSurface::make(bad_angles, 2, lv, r), Error);
}

// --- reference points ------------------------------------------------------------------------

std::vector<Vec3> grid3x3(double z = 0) {
  std::vector<Vec3> p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p.emplace_back(-20.0 + 20.0 * j, -20.0 + 20.0 * i, z);
  return p;
}

double interpolate(const ReferenceMesh& m, const std::vector<double>& f, const Vec3& x) {
  const auto loc = m.locate(x);
  return loc.weight.x() * f[loc.vertex[0]] + loc.weight.y() * f[loc.vertex[1]] +
         loc.weight.z() * f[loc.vertex[2]];
}

TEST(ReferenceMesh, GridTriangulationReproducesALinearFieldExactly) {
  const auto pts = grid3x3(25.0);
  const ReferenceMesh m = ReferenceMesh::build(pts, Vec3::UnitZ());
  EXPECT_EQ(m.triangles().size(), 8u);
  auto field = [](const Vec3& x) { return 0.3 + 0.02 * x.x() - 0.05 * x.y(); };
  std::vector<double> f;
  for (const Vec3& p : pts) f.push_back(field(p));
  Rng rng(11);
  for (int i = 0; i < 500; ++i) {
    // Any height: the location is by projection along the axis.
    const Vec3 x(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(20, 30));
    const auto loc = m.locate(x);
    EXPECT_TRUE(loc.inside);
    EXPECT_GE(loc.weight.minCoeff(), -1e-12);
    EXPECT_NEAR(loc.weight.sum(), 1.0, 1e-12);
    EXPECT_NEAR(interpolate(m, f, x), field(x), 1e-12);
  }
}

TEST(ReferenceMesh, CurvedPointsOnADomeInterpolateLinearlyInProjection) {
  // Points on a sphere cap; the field is linear in the projected coordinates.
  std::vector<Vec3> pts;
  const double R = 50.0;
  for (int i = 0; i < 18; ++i) {
    const double r = i == 0 ? 0.0 : (i < 7 ? 15.0 : 30.0);
    const double a = (i < 7 ? (i - 1) * kPi / 3 : (i - 7) * 2 * kPi / 11);
    const double x = r * std::cos(a), y = r * std::sin(a);
    pts.emplace_back(x, y, std::sqrt(R * R - x * x - y * y));
  }
  const ReferenceMesh m = ReferenceMesh::build(pts, Vec3::UnitZ());
  std::vector<double> f;
  for (const Vec3& p : pts) f.push_back(2.0 * p.x() + p.y());
  Rng rng(5);
  for (int i = 0; i < 200; ++i) {
    const double r = rng.uniform(0, 25), a = rng.uniform(0, 2 * kPi);
    const Vec3 x(r * std::cos(a), r * std::sin(a), std::sqrt(R * R - r * r));
    EXPECT_NEAR(interpolate(m, f, x), 2.0 * x.x() + x.y(), 1e-9);
  }
}

TEST(ReferenceMesh, OutsideTakesTheNearestPointOfTheNearestTriangle) {
  const auto pts = grid3x3();
  const ReferenceMesh m = ReferenceMesh::build(pts, Vec3::UnitZ());
  auto field = [](const Vec3& x) { return 1.0 + x.x() + 2.0 * x.y(); };
  std::vector<double> f;
  for (const Vec3& p : pts) f.push_back(field(p));
  // Beyond the right edge (x = 20): the value of the border point (20, y).
  for (double y : {-15.0, 0.0, 7.5, 19.0}) {
    const auto loc = m.locate(Vec3(35.0, y, 0.0));
    EXPECT_FALSE(loc.inside);
    EXPECT_GE(loc.weight.minCoeff(), 0.0);
    EXPECT_NEAR(interpolate(m, f, Vec3(35.0, y, 0.0)), field(Vec3(20.0, y, 0.0)), 1e-9);
  }
  // Beyond a corner: the corner's value.
  EXPECT_NEAR(interpolate(m, f, Vec3(40.0, 45.0, 3.0)), field(pts[8]), 1e-9);
  // The hint is only a hint.
  const auto a = m.locate(Vec3(5, 5, 0), 0), b = m.locate(Vec3(5, 5, 0), -1);
  EXPECT_EQ(a.triangle, b.triangle);
}

TEST(ReferenceMesh, FewPoints) {
  const std::vector<Vec3> one = {Vec3(1, 2, 3)};
  const ReferenceMesh m1 = ReferenceMesh::build(one, Vec3::UnitZ());
  EXPECT_EQ(m1.locate(Vec3(9, 9, 9)).weight, Vec3(1, 0, 0));
  const std::vector<Vec3> two = {Vec3(0, 0, 0), Vec3(10, 0, 0)};
  const ReferenceMesh m2 = ReferenceMesh::build(two, Vec3::UnitZ());
  const auto loc = m2.locate(Vec3(2.5, 4, 0));
  EXPECT_NEAR(loc.weight.x(), 0.75, 1e-12);
  EXPECT_NEAR(loc.weight.y(), 0.25, 1e-12);
  const std::vector<Vec3> dup = {Vec3(0, 0, 0), Vec3(0, 0, 5)};
  EXPECT_THROW(ReferenceMesh::build(dup, Vec3::UnitZ()), Error);
}

}  // namespace
}  // namespace inhap::friction
