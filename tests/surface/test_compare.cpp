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

namespace {
/// Closed box [-10, 10]^2 x [-10, 0], outward (the "reference": an object tapped on its top).
TriMesh box_top_at_zero() {
  TriMesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.emplace_back(i & 1 ? 10 : -10, i & 2 ? 10 : -10, i & 4 ? 0 : -10);
  // Faces as quads a-b-c-d counter-clockwise seen from outside.
  const int quads[6][4] = {{4, 5, 7, 6}, {0, 2, 3, 1}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  m.compute_normals();
  return m;
}

/// Open grid patch over the box top, |x|, |y| <= 9 (1 mm cells): height `h` inside the square
/// |x|, |y| <= 8, rising linearly to h + 1 at the rim (a reconstruction whose rim curls up).
TriMesh curled_patch(double h) {
  TriMesh m;
  for (int j = -9; j <= 9; ++j)
    for (int i = -9; i <= 9; ++i)
      m.positions.emplace_back(i, j, h + std::max(0, std::max(std::abs(i), std::abs(j)) - 8));
  auto v = [](int i, int j) { return (j + 9) * 19 + (i + 9); };
  for (int j = -9; j < 9; ++j)
    for (int i = -9; i < 9; ++i) {
      m.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      m.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  m.compute_normals();
  return m;
}
}  // namespace

TEST(Compare, NormalOverlapDropsTheUntappedWallBelowACurledRim) {
  // The patch lies 0.5 mm above the box top and its rim 1.5 mm above. A wall sample such as
  // (-10, 0, -3.4) is within 5 mm of the rim (-9, 0, 1.5), and its closest point on the patch is
  // the inner corner of the ramp, (-8, 0, 0.5), sqrt(2^2 + 3.9^2) = 4.38 mm away and 1.4 mm from
  // the rim: the rim test keeps it, so the wall (which the patch does not represent) dominates.
  const TriMesh box = box_top_at_zero(), patch = curled_patch(0.5);
  CompareOptions o;
  o.region = patch.positions;
  o.region_radius = 5.0;
  o.exclude_boundary = true;
  o.rim_margin = 1.0;
  const CompareResult rim_only = compare_surfaces(patch, box, o);
  EXPECT_GT(rim_only.b_to_a.max, 4.0);
  const Vec3 at = rim_only.b_to_a.max_at;  // on a wall, below the top
  EXPECT_NEAR(std::max(std::abs(at.x()), std::abs(at.y())), 10.0, 1e-9);
  EXPECT_LT(at.z(), -2.0);
  // With the normal-line test the wall goes (its normal lines pass below the patch); the top
  // stays: the worst is the rim vertices' 1.5 mm over the top, the reference side is between the
  // 0.5 mm of the flat part and the 1.5 mm of the rim, its mean close to 0.5 mm.
  o.normal_overlap = true;
  const CompareResult r = compare_surfaces(patch, box, o);
  EXPECT_NEAR(r.hausdorff, 1.5, 1e-9);
  EXPECT_NEAR(r.a_to_b.max, 1.5, 1e-9);
  EXPECT_GE(r.b_to_a.max, 0.5 - 1e-9);
  EXPECT_LE(r.b_to_a.max, 1.5);
  EXPECT_NEAR(r.b_to_a.max_at.z(), 0.0, 1e-9);  // on the top
  EXPECT_NEAR(r.b_to_a.mean, 0.5, 0.1);
}

TEST(Compare, NormalOverlapKeepsTheSurfaceUnderABridge) {
  // A patch lifted 4 mm over the box top (as a bridge over a groove would be): every top sample
  // below it still counts, 4 mm from it; nothing is hidden by the normal-line test.
  const TriMesh box = box_top_at_zero(), patch = curled_patch(4.0);
  CompareOptions o;
  o.region = {Vec3(0, 0, 0)};
  o.region_radius = 6.0;
  o.exclude_boundary = true;
  o.rim_margin = 1.0;
  const CompareResult without = compare_surfaces(patch, box, o);
  o.normal_overlap = true;
  const CompareResult with = compare_surfaces(patch, box, o);
  EXPECT_NEAR(with.b_to_a.max, 4.0, 1e-9);
  EXPECT_NEAR(with.b_to_a.mean, 4.0, 1e-9);
  EXPECT_EQ(with.b_to_a.samples, without.b_to_a.samples);
  EXPECT_NEAR(with.hausdorff, without.hausdorff, 1e-12);
}

// A partial reconstruction = the top cap (z > 10) of a sphere of radius 20 plus a stray flat
// square 5 mm outside the sphere's side, far from the tapped cap; the reference is the whole
// sphere. Cropped to within 3 mm of the cap's vertices on both sides, the stray part is never
// scored (a -> b stays tiny); with only the reference side cropped (kB) every sample of the
// reconstruction counts and a -> b is the stray square's distance to the sphere, >= 5 mm
// (its corners lie farther: sqrt(25^2 + 2^2 + 2^2) - 20 = 5.16 mm).
TEST(Compare, CroppingOnlyTheReferenceScoresTheWholeReconstruction) {
  const TriMesh sphere = test::icosphere(5, 20.0);
  TriMesh a;
  a.positions = sphere.positions;
  std::vector<Vec3> region;
  for (const Tri& t : sphere.triangles) {
    bool top = true;
    for (auto v : t) top = top && sphere.positions[static_cast<std::size_t>(v)].z() > 10.0;
    if (top) a.triangles.push_back(t);
  }
  for (const Vec3& p : sphere.positions)
    if (p.z() > 10.0) region.push_back(p);
  const auto base = static_cast<std::int32_t>(a.positions.size());
  for (const Vec3& p : {Vec3(25, -2, -2), Vec3(25, 2, -2), Vec3(25, 2, 2), Vec3(25, -2, 2)})
    a.positions.push_back(p);
  a.triangles.push_back({base, base + 1, base + 2});
  a.triangles.push_back({base, base + 2, base + 3});
  a.compute_normals();
  CompareOptions o;
  o.region = region;
  o.region_radius = 3.0;
  const CompareResult both = compare_surfaces(a, sphere, o);
  EXPECT_LT(both.a_to_b.max, 0.1);
  o.crop_sides = CropSides::kB;
  const CompareResult ref_only = compare_surfaces(a, sphere, o);
  EXPECT_GE(ref_only.a_to_b.max, 5.0 - 0.01);
  EXPECT_NEAR(ref_only.a_to_b.max, std::sqrt(25.0 * 25 + 8) - 20.0, 0.02);
  EXPECT_NEAR(ref_only.b_to_a.max, both.b_to_a.max, 1e-12);  // the reference side: unchanged
  EXPECT_EQ(crop_sides_from_string(to_string(CropSides::kA)), CropSides::kA);
  EXPECT_THROW(crop_sides_from_string("c"), Error);
}

// `shape compare --crop-sides auto`: only a closed mesh (the complete reference) is cropped; the
// sides actually cropped follow from the options.
TEST(Compare, AutoCropSidesCropsOnlyTheClosedMesh) {
  const TriMesh sphere = test::icosphere(2, 10.0);  // closed
  TriMesh cap = sphere;                             // the sphere without its faces below z = 0
  std::erase_if(cap.triangles, [&](const Tri& t) { return sphere.positions[t[0]].z() < 0; });
  EXPECT_EQ(auto_crop_sides(cap, sphere), CropSides::kB);
  EXPECT_EQ(auto_crop_sides(sphere, cap), CropSides::kA);
  EXPECT_EQ(auto_crop_sides(sphere, sphere), CropSides::kBoth);
  EXPECT_EQ(auto_crop_sides(cap, cap), CropSides::kBoth);

  CompareOptions o;
  o.crop_sides = CropSides::kB;
  EXPECT_FALSE(cropped_sides(o).a);  // no crop set: nothing is cropped
  EXPECT_FALSE(cropped_sides(o).b);
  o.normal_overlap = true;
  EXPECT_FALSE(cropped_sides(o).a);
  EXPECT_TRUE(cropped_sides(o).b);
  o.crop_sides = CropSides::kBoth;
  EXPECT_TRUE(cropped_sides(o).a);
  EXPECT_TRUE(cropped_sides(o).b);
}
