#include <gtest/gtest.h>

#include <cmath>

#include "inhap/core/error.hpp"
#include "inhap/surface/compare.hpp"
#include "surface/sphere_points.hpp"

using namespace inhap;

namespace {
/// Ellipsoid with three different axes (no rotational symmetry: ICP has one answer).
TriMesh ellipsoid(double a, double b, double c) {
  TriMesh m = test::icosphere(4, 1.0);
  for (Vec3& p : m.positions) p = Vec3(a * p.x(), b * p.y(), c * p.z());
  m.compute_normals();
  return m;
}
}  // namespace

TEST(Compare, ConcentricSpheresDifferByTheirRadii) {
  const TriMesh a = test::icosphere(5, 20.0), b = test::icosphere(5, 21.5);
  const CompareResult r = compare_surfaces(a, b);
  // Chords of the fine icospheres sit at most ~0.002 mm inside the true spheres.
  EXPECT_NEAR(r.hausdorff, 1.5, 0.01);
  EXPECT_NEAR(r.mean, 1.5, 0.01);
  EXPECT_NEAR(r.rms, 1.5, 0.01);
  EXPECT_NEAR(r.a_to_b.max, 1.5, 0.01);
  EXPECT_NEAR(r.b_to_a.max, 1.5, 0.01);
  ASSERT_EQ(r.a_vertex_error.size(), a.num_vertices());
  for (double e : r.a_vertex_error) EXPECT_NEAR(e, 1.5, 0.01);
  EXPECT_GT(r.a_to_b.samples, a.num_vertices());
}

TEST(Compare, IcpUndoesARigidMotion) {
  const TriMesh b = ellipsoid(30, 20, 12);
  TriMesh a = b;
  const Mat3 R = Mat3(Eigen::AngleAxisd(0.12, Vec3(1, 2, 3).normalized()));
  const Vec3 t(1.5, -2.0, 0.7);
  for (Vec3& p : a.positions) p = R * p + t;
  a.compute_normals();
  EXPECT_GT(compare_surfaces(a, b).hausdorff, 1.0);
  CompareOptions o;
  o.icp = true;
  const CompareResult r = compare_surfaces(a, b, o);
  EXPECT_LT(r.hausdorff, 0.01);
  EXPECT_LT((r.transform.R * R - Mat3::Identity()).norm(), 1e-3);
  EXPECT_LT((r.transform.R * t + r.transform.t).norm(), 1e-2);
}

TEST(Compare, OverlapOnlyComparesAPatchWithTheWholeSphere) {
  const double radius = 25.0;
  const TriMesh sphere = test::icosphere(5, radius);
  // The patch: the sphere's faces within 40 degrees of +z, pushed out by 0.3 mm.
  TriMesh patch;
  std::vector<std::int32_t> remap(sphere.num_vertices(), -1);
  for (const Tri& t : sphere.triangles) {
    bool in = true;
    for (auto v : t) in = in && sphere.positions[v].normalized().z() > std::cos(40 * M_PI / 180);
    if (!in) continue;
    Tri nt;
    for (int k = 0; k < 3; ++k) {
      auto& r = remap[t[k]];
      if (r < 0) {
        r = static_cast<std::int32_t>(patch.positions.size());
        patch.positions.push_back(sphere.positions[t[k]] * (radius + 0.3) / radius);
      }
      nt[k] = r;
    }
    patch.triangles.push_back(nt);
  }
  patch.compute_normals();
  // Everything: the far side of the sphere is ~2 R from the patch.
  EXPECT_GT(compare_surfaces(patch, sphere).hausdorff, 40.0);
  CompareOptions o;
  o.exclude_boundary = true;
  const CompareResult r = compare_surfaces(patch, sphere, o);
  EXPECT_NEAR(r.hausdorff, 0.3, 0.01);
  EXPECT_NEAR(r.mean, 0.3, 0.01);
  // A region of points limits both sides too; samples of the sphere just past the rim (within
  // 0.5 mm of a rim vertex) are up to sqrt(0.3^2 + 0.5^2) mm from the patch.
  CompareOptions reg;
  reg.region = patch.positions;
  reg.region_radius = 0.5;
  const double h = compare_surfaces(patch, sphere, reg).hausdorff;
  EXPECT_GE(h, 0.3 - 1e-3);
  EXPECT_LE(h, std::hypot(0.3, 0.5) + 1e-3);
}

TEST(Compare, EmptyInputOrEmptyRegionIsAnError) {
  const TriMesh s = test::icosphere(2, 5.0);
  EXPECT_THROW(compare_surfaces(TriMesh{}, s), Error);
  CompareOptions o;
  o.region = {Vec3(100, 0, 0)};
  o.region_radius = 1.0;
  EXPECT_THROW(compare_surfaces(s, s, o), Error);
}

TEST(Compare, SamplesCoverTheAreaUniformly) {
  const TriMesh s = test::icosphere(3, 10.0);
  const SurfaceSamples smp = sample_surface(s, 2.0, 1);
  double area = 0, weights = 0;
  for (std::size_t f = 0; f < s.num_triangles(); ++f) area += s.face_area(f);
  for (double w : smp.weights) weights += w;
  EXPECT_NEAR(weights, area, 1e-9 * area);
  EXPECT_GE(smp.points.size(), s.num_vertices() + static_cast<std::size_t>(2.0 * area));
  for (const Vec3& p : smp.points) EXPECT_LE(p.norm(), 10.0 + 1e-9);
}
