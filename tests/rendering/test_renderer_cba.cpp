// CBA (god-object) against analytic answers: plane, sphere, concave corner. Units: mm, N, N/mm.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "inhap/core/device.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/rendering/renderer.hpp"
#include "rendering/render_fixtures.hpp"
#include "support/meshes.hpp"

using namespace inhap;
using rendering::Algorithm;

namespace {

// Moves the HIP from `from` to `to` in `n` equal ticks; returns the last force.
Vec3 move(const rendering::Model& m, rendering::State& st, const Vec3& from, const Vec3& to, int n,
          Algorithm alg = Algorithm::kCBA) {
  Vec3 f = Vec3::Zero();
  for (int i = 1; i <= n; ++i)
    f = rendering::step(m, st, from + (double(i) / n) * (to - from), alg);
  return f;
}

}  // namespace

TEST(RendererModel, InterpolatesStiffnessAndNormalBarycentrically) {
  TriMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  mesh.set_property("stiffness", {0.2, 0.6, 1.0});
  mesh.normals = {Vec3(0, 0, 1), Vec3(1, 0, 1).normalized(), Vec3(0, 1, 1).normalized()};
  rendering::Model m(mesh);
  SurfacePoint q;
  q.triangle = 0;
  q.bary = {0.5, 0.25, 0.25};
  EXPECT_NEAR(m.stiffness(q), 0.5 * 0.2 + 0.25 * 0.6 + 0.25 * 1.0, 1e-12);
  const Vec3 expect =
      (0.5 * Vec3(0, 0, 1) + 0.25 * Vec3(1, 0, 1).normalized() + 0.25 * Vec3(0, 1, 1).normalized())
          .normalized();
  EXPECT_NEAR((m.normal(q) - expect).norm(), 0, 1e-12);
  rendering::Params flat;
  flat.force_shading = false;
  rendering::Model mf(mesh, flat);
  EXPECT_NEAR((mf.normal(q) - Vec3::UnitZ()).norm(), 0, 1e-12);
  // Floor: k never below min_stiffness.
  mesh.set_property("stiffness", {-1.0, 0.0, 0.0});
  rendering::Model m0(mesh);
  EXPECT_DOUBLE_EQ(m0.stiffness(q), rendering::Params{}.min_stiffness);
}

// A 1e5 N/mm map sat at the 6.2 N clamp for the first 182 ms of a stroke's contact: a stiffness
// above kMaxStiffnessNmm, or not finite, in the map or as the default, is refused by name.
TEST(RendererModel, RefusesAStiffnessAboveTheMaximumOrNotFinite) {
  TriMesh mesh = test::flat_plane(2, 2, 1, 0, 0);
  std::vector<double> k(mesh.num_vertices(), 0.5);
  const auto error_of = [](const TriMesh& m, rendering::Params p = {}) -> std::string {
    try {
      rendering::Model model(m, p);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  k[1] = 1e5;
  mesh.set_property("stiffness", k);
  const std::string e = error_of(mesh);
  EXPECT_NE(e.find("vertex 1: stiffness 100000 N/mm"), std::string::npos) << e;
  EXPECT_NE(e.find("at most 100 N/mm"), std::string::npos) << e;
  for (double bad : {std::nan(""), HUGE_VAL, std::nextafter(rendering::kMaxStiffnessNmm, 1e9)}) {
    k[1] = bad;
    mesh.set_property("stiffness", k);
    EXPECT_NE(error_of(mesh).find("vertex 1"), std::string::npos) << bad;
  }
  k[1] = rendering::kMaxStiffnessNmm;  // the maximum itself is allowed
  mesh.set_property("stiffness", k);
  EXPECT_EQ(error_of(mesh), "");
  rendering::Params p;
  p.default_stiffness = 1e5;
  EXPECT_NE(error_of(test::flat_plane(2, 2, 1, 0, 0), p).find("default_stiffness"),
            std::string::npos);
  p.default_stiffness = rendering::kMaxStiffnessNmm;
  EXPECT_EQ(error_of(test::flat_plane(2, 2, 1, 0, 0), p), "");
  // The rationale, as arithmetic: at the maximum, a probe arriving at 20 mm/s (0.02 mm per 1 ms
  // tick) is asked for less than the device's limit on its first tick of contact.
  EXPECT_LT(rendering::kMaxStiffnessNmm * 20.0 * 1e-3, kDeviceForceLimitN);
}

TEST(RendererModel, RejectsEmptyMeshAndBadParams) {
  EXPECT_THROW(rendering::Model(TriMesh{}), Error);
  rendering::Params bad;
  bad.force_limit_n = -1;
  EXPECT_THROW(rendering::Model(test::flat_plane(2, 2, 1, 0, 0), bad), Error);
  rendering::Params nan;
  nan.a_s = std::nan("");
  EXPECT_THROW(rendering::Model(test::flat_plane(2, 2, 1, 0, 0), nan), Error);
}

// The model's spatial index follows Params::index: no seed grid by default (the renderer's
// queries are segments and local walks), one when asked for; a bad shell is refused.
TEST(RendererModel, IndexOptionsReachTheSpatialIndex) {
  const TriMesh plane = test::make_grid_mesh(81, 81, 0.25);  // 12,800 triangles
  EXPECT_EQ(rendering::Model(plane).index().seed_grid_info().cells, 0);
  rendering::Params seeded;
  seeded.index.seed_shell = 2.0;
  EXPECT_GT(rendering::Model(plane, seeded).index().seed_grid_info().covered, 0);
  rendering::Params bad;
  bad.index.seed_shell = -1;
  EXPECT_THROW(rendering::Model(plane, bad), Error);
}

TEST(RendererCba, PlaneProxyIsFootOfPerpendicularAndForceIsKTimesDepth) {
  const double k = 0.5;
  rendering::Model m(test::flat_plane(20, 20, 1.0, -10, -10, k));
  rendering::State st;
  Vec3 f = move(m, st, Vec3(0.3, 0.2, 5), Vec3(0.3, 0.2, -2.0), 70);
  ASSERT_TRUE(st.collision);
  EXPECT_NEAR((st.ihip.point - Vec3(0.3, 0.2, 0)).norm(), 0, 1e-9);
  EXPECT_NEAR((f - Vec3(0, 0, k * 2.0)).norm(), 0, 1e-9);
  // Sliding under the surface: the proxy follows, the force stays normal.
  f = move(m, st, Vec3(0.3, 0.2, -2.0), Vec3(-6.1, 4.7, -3.0), 40);
  ASSERT_TRUE(st.collision);
  EXPECT_NEAR((st.ihip.point - Vec3(-6.1, 4.7, 0)).norm(), 0, 1e-9);
  EXPECT_NEAR((f - Vec3(0, 0, k * 3.0)).norm(), 0, 1e-9);
  // Leaving upwards releases the contact with zero force.
  f = move(m, st, Vec3(-6.1, 4.7, -3.0), Vec3(-6.1, 4.7, 0.5), 10);
  EXPECT_FALSE(st.collision);
  EXPECT_EQ(f, Vec3::Zero());
}

TEST(RendererCba, SphereProxyIsClosestPointAndForceIsRadialKTimesDepth) {
  const double R = 10.0, k = 0.4;
  const TriMesh mesh = test::icosphere(R, 5);  // 20480 faces, edge ~ 0.33 mm
  // Tessellation error bounds: chord sag (gap between faces and sphere) and the largest angle
  // between a face normal and the radius through any of its corners.
  double sag = 0, alpha = 0;
  for (std::size_t f = 0; f < mesh.num_triangles(); ++f) {
    const auto& t = mesh.triangles[f];
    const Vec3 c = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3;
    sag = std::max(sag, R - c.norm());
    for (int i = 0; i < 3; ++i)
      alpha = std::max(
          alpha,
          std::acos(std::min(1.0, mesh.face_normal(f).dot(mesh.positions[t[i]].normalized()))));
  }
  ASSERT_LT(sag, 0.01);
  ASSERT_LT(alpha, 0.03);
  rendering::Params ps;
  ps.default_stiffness = k;
  rendering::Model mk(mesh, ps);
  Rng rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const Vec3 dir = Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
    const double depth = rng.uniform(0.5, 4.0);
    rendering::State st;
    const Vec3 f = move(mk, st, (R + 3) * dir, (R - depth) * dir, 60);
    ASSERT_TRUE(st.collision) << trial;
    const Vec3 p = (R - depth) * dir;
    // Proxy: the closest point of the mesh to p (exactly), hence the analytic one within the sag.
    const ClosestPoint cp = mk.index().closest_point(p);
    EXPECT_NEAR((st.ihip.point - cp.point).norm(), 0, 1e-9) << trial;
    const double tol_q = (R - depth) * std::sin(alpha) + 2 * sag;
    EXPECT_NEAR((st.ihip.point - R * dir).norm(), 0, tol_q) << trial;
    // Force: k * depth along the outward radial direction (force shading: vertex normals of a
    // sphere are radial), within the tessellation error.
    EXPECT_NEAR((f - k * depth * dir).norm(), 0, k * (2 * sag + depth * 3 * alpha)) << trial;
    EXPECT_GT(f.normalized().dot(dir), std::cos(3 * alpha)) << trial;
  }
}

TEST(RendererCba, TorusProxyAndForceMatchTheAnalyticTubeIncludingTheSaddleSide) {
  const double R = 20, r = 6, k = 0.8;
  const TriMesh mesh = test::make_torus(R, r, 256, 96);
  // Analytic closest point and outward normal of the torus for a point p inside the tube.
  auto tube = [&](const Vec3& p, Vec3& normal) {
    const Vec3 c = R * Vec3(p.x(), p.y(), 0).normalized();
    normal = (p - c).normalized();
    return Vec3(c + r * normal);
  };
  double alpha = 0;  // largest angle between a face normal and the torus normal at its corners
  for (std::size_t f = 0; f < mesh.num_triangles(); ++f)
    for (int i = 0; i < 3; ++i) {
      Vec3 n;
      tube(mesh.positions[mesh.triangles[f][i]], n);
      alpha = std::max(alpha, std::acos(std::min(1.0, mesh.face_normal(f).dot(n))));
    }
  ASSERT_LT(alpha, 0.06);
  rendering::Params ps;
  ps.default_stiffness = k;
  rendering::Model m(mesh, ps);
  Rng rng(21);
  for (int trial = 0; trial < 60; ++trial) {
    const double u = rng.uniform(0, 2 * M_PI), v = rng.uniform(0, 2 * M_PI);  // v = pi: saddle
    const Vec3 radial(std::cos(u), std::sin(u), 0);
    const Vec3 c = R * radial, dir = std::cos(v) * radial + std::sin(v) * Vec3::UnitZ();
    const double depth = rng.uniform(0.3, 2.5);
    rendering::State st;
    const Vec3 f = move(m, st, c + (r + 2) * dir, c + (r - depth) * dir, 60);
    ASSERT_TRUE(st.collision) << trial;
    Vec3 n;
    const Vec3 q = tube(c + (r - depth) * dir, n);
    const double tol = (r - depth) * std::sin(alpha) + 0.02;
    EXPECT_NEAR((st.ihip.point - q).norm(), 0, tol) << trial << " v " << v;
    EXPECT_NEAR((f - k * depth * n).norm(), 0, k * (0.02 + depth * 3 * alpha)) << trial;
  }
}

TEST(RendererCba, ConcaveCornerKeepsProxyOnSurfaceWithForceOutOfTheCorner) {
  for (bool shading : {true, false}) {
    rendering::Params ps;
    ps.force_shading = shading;  // (the 6.2 N clamp scales the force, its direction stays)
    rendering::Model m(test::concave_corner(10.0, 8), ps);
    rendering::State st;
    // Come down onto the floor, slide into the corner and push into it.
    move(m, st, Vec3(5, 5, 3), Vec3(5, 5, -0.5), 35);
    ASSERT_TRUE(st.collision);
    move(m, st, Vec3(5, 5, -0.5), Vec3(-1, -1, -1), 60);
    ASSERT_TRUE(st.collision) << shading;
    Vec3 f = st.force;
    // The proxy sits in the corner (all three walls are constraints), on the surface.
    EXPECT_NEAR(st.ihip.point.norm(), 0, 1e-9) << shading;
    EXPECT_GT(f.x(), 0);
    EXPECT_GT(f.y(), 0);
    EXPECT_GT(f.z(), 0);
    EXPECT_GT(f.normalized().dot(Vec3(1, 1, 1).normalized()), 0.999) << shading;
    // Along the edge x = y = 0 below the corner edge: proxy on the edge, force out of it.
    move(m, st, Vec3(-1, -1, -1), Vec3(-0.5, -1.0, 4.0), 40);
    ASSERT_TRUE(st.collision) << shading;
    EXPECT_NEAR((st.ihip.point - Vec3(0, 0, 4.0)).norm(), 0, 1e-9) << shading;
    f = st.force;
    EXPECT_NEAR(f.z(), 0, 1e-9) << shading;
    EXPECT_GT(f.x(), 0);
    EXPECT_GT(f.y(), 0);
    // Every tick of a random scrub keeps the proxy on the walls and the force pointing into
    // the free octant.
    Rng rng(3);
    Vec3 p = Vec3(-0.5, -1.0, 4.0);
    for (int i = 0; i < 300; ++i) {
      const Vec3 next(rng.uniform(-1.5, 4), rng.uniform(-1.5, 4), rng.uniform(-1.5, 4));
      const Vec3 goal = p + 0.3 * (next - p).normalized();
      rendering::step(m, st, goal, Algorithm::kCBA);
      p = goal;
      const bool inside = p.minCoeff() < 0;
      ASSERT_EQ(st.collision, inside) << i << " shading " << shading;
      if (!inside) continue;
      const Vec3 q = st.ihip.point;
      EXPECT_NEAR(q.minCoeff(), 0, 1e-9) << i;  // on a wall
      EXPECT_GE(q.minCoeff(), -1e-9) << i;
      // The proxy is the closest point of the free octant to p (the god-object's answer).
      EXPECT_NEAR((q - p.cwiseMax(0.0)).norm(), 0, 1e-9) << i;
      EXPECT_GE(st.force.minCoeff(), -1e-9) << i;
    }
  }
}
