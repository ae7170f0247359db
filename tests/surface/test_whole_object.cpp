// Known-answer tests of the reconstruction rules for whole-object tap sets (issue 22): jet fits
// that stay on their side of a sharp crest, twins no deeper than half a thin part, and no face
// across the air between two separately sampled parts. Units: mm.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "inhap/surface/alpha_shape.hpp"
#include "inhap/surface/points.hpp"
#include "inhap/surface/reconstruct.hpp"
#include "surface/sphere_points.hpp"

using namespace inhap;

namespace {

/// Share of `probes` within `tol` of the mesh.
double share_within(const TriMesh& m, const std::vector<Vec3>& probes, double tol) {
  const MeshIndex index(m);
  std::size_t near = 0;
  for (const Vec3& p : probes) near += index.closest_point(p).distance2 <= tol * tol;
  return static_cast<double>(near) / static_cast<double>(probes.size());
}

}  // namespace

TEST(WholeObject, JetFitKeepsTheSidesOfASharpCrest) {
  // A roof z = -tan(40 deg) |x| (the ridged slab's flanks, a 100 deg crest along y), sampled on a
  // jittered 2.5 mm grid with the true outward normals as contact directions. A jet over
  // neighbours of both flanks (within 90 deg: 80 deg apart) rounds the crest; within 60 deg each
  // point is fitted to its own flank, a plane, and stays on it.
  const double slope = std::tan(40 * std::numbers::pi / 180);
  const Vec3 left = Vec3(-slope, 0, 1).normalized(), right = Vec3(slope, 0, 1).normalized();
  Rng rng(3);
  std::vector<Vec3> pts, dirs;
  for (int i = -8; i <= 8; ++i)
    for (int j = -8; j <= 8; ++j) {
      const double x = 2.5 * i + rng.uniform(-0.5, 0.5), y = 2.5 * j + rng.uniform(-0.5, 0.5);
      pts.emplace_back(x, y, -slope * std::abs(x));
      dirs.push_back(x < 0 ? left : right);
    }
  auto worst = [&](const std::vector<Vec3>& s) {
    double e = 0;
    for (std::size_t i = 0; i < s.size(); ++i)
      if (std::abs(pts[i].y()) < 12)  // away from the sampling's own edge
        e = std::max(e, std::abs(s[i].z() + slope * std::abs(s[i].x())) /
                            std::sqrt(1 + slope * slope));  // distance to the flank
    return e;
  };
  const double sided = worst(jet_smooth(pts, 14, dirs, std::cos(60 * std::numbers::pi / 180)));
  const double both = worst(jet_smooth(pts, 14, dirs, 0.0));
  EXPECT_LT(sided, 0.05);
  EXPECT_GT(both, 0.5);
}

TEST(WholeObject, TwinsOfAThinDiscStayInsideIt) {
  // A disc 40 mm wide and 5 mm thick (ellipsoid 20 x 20 x 2.5 mm) sampled all round with 200
  // points (spacing about 4 mm, the twin depth about 3 mm: more than half the thickness). Twins
  // at full depth land near or beyond the other face and its outer faces fall out of the alpha
  // shape; twins at most 0.4 of the distance to the opposite side keep the faces.
  const Vec3 axes(20, 20, 2.5);
  std::vector<Vec3> pts, dirs, probes;
  for (const Vec3& u : test::fibonacci_sphere(200, 1.0)) {
    pts.push_back(u.cwiseProduct(axes));
    dirs.push_back(u.cwiseQuotient(axes).normalized());
  }
  for (const Vec3& u : test::fibonacci_sphere(4000, 1.0))
    if (std::abs(u.z()) > 0.5) probes.push_back(u.cwiseProduct(axes));  // the two broad faces
  ReconstructOptions deep;
  deep.thin_part_depth = 0;
  const double kept = share_within(reconstruct_surface(pts, dirs, {}), probes, 1.0);
  const double holed = share_within(reconstruct_surface(pts, dirs, deep), probes, 1.0);
  EXPECT_GT(kept, 0.8);  // 0.88 (the rim, 5 mm round, is cut by about a millimetre)
  EXPECT_LT(holed, 0.2);
}

TEST(WholeObject, FacesAcrossAirJoinPointsThatFaceEachOther) {
  const Vec3 x = Vec3::UnitX(), z = Vec3::UnitZ();
  const double c = ReconstructOptions{}.air_gap_cos;
  // Inner sides of two ears 8 mm apart: each direction points at the other point.
  EXPECT_TRUE(faces_each_other({0, 0, 0}, x, {8, 0, 0}, -x, c));
  EXPECT_TRUE(faces_each_other({0, 0, 0}, Vec3(1, 0, 0.4).normalized(), {8, 0, 1},
                               Vec3(-1, 0.3, -0.2).normalized(), c));
  // The two sides of a thin part 3 mm thick: material between, directions point away.
  EXPECT_FALSE(faces_each_other({0, 0, 0}, -z, {0, 0, 3}, z, c));
  EXPECT_FALSE(faces_each_other({0, 0, 3}, z, {0, 0, 0}, -z, c));
  // Neighbours on one surface and the two flanks of a 100 deg groove are not opposed.
  EXPECT_FALSE(faces_each_other({0, 0, 0}, z, {4, 0, 0}, z, c));
  const double s = std::tan(40 * std::numbers::pi / 180);
  EXPECT_FALSE(faces_each_other({-3, 0, 3 * s}, Vec3(s, 0, 1).normalized(), {3, 0, 3 * s},
                                Vec3(-s, 0, 1).normalized(), c));
}

TEST(WholeObject, TwoBallsAGapApartGiveTwoPiecesAndNoFaceAcrossTheGap) {
  // Two balls of radius 10 mm, 3 mm apart, each sampled with 90 points (spacing about 3.7 mm,
  // as a person taps a 100 mm object 1000 times), contact directions the outward normals: the
  // automatic alpha (set by the spacing) admits tetrahedra across the gap, and their faces
  // join points that face each other across air; they are dropped (and not put back by the
  // hole filling).
  const Vec3 ca(0, 0, 0), cb(23, 0, 0);
  std::vector<Vec3> pts = test::fibonacci_sphere(90, 10.0, ca), dirs;
  for (const Vec3& p : test::fibonacci_sphere(90, 10.0, cb)) pts.push_back(p);
  for (std::size_t i = 0; i < pts.size(); ++i)
    dirs.push_back((pts[i] - (i < 90 ? ca : cb)).normalized());
  auto spanning = [&](const TriMesh& m) {  // faces with vertices on both balls
    std::size_t n = 0;
    for (const Tri& t : m.triangles) {
      int on_a = 0;
      for (auto v : t) on_a += m.positions[static_cast<std::size_t>(v)].x() < 11.5;
      n += on_a == 1 || on_a == 2;
    }
    return n;
  };
  ReconstructReport rep;
  const TriMesh two = reconstruct_surface(pts, dirs, {}, &rep);
  EXPECT_EQ(spanning(two), 0u);
  EXPECT_EQ(rep.components, 2u);
  ReconstructOptions off;
  off.air_gap_cos = -2;  // the rule off
  EXPECT_GT(spanning(reconstruct_surface(pts, dirs, off)), 0u);
}

TEST(WholeObject, LocalAlphaComparesEachCircumradiusWithItsPointsSpacing) {
  // One regular tetrahedron, circumradius 3 mm: with point lengths 2, 2, 4, 4 mm (mean 3) it is
  // solid (4 boundary faces) at a local alpha just above 1 and empty just below; one alpha for
  // all compares 3 mm itself.
  const double a = 3.0 * std::sqrt(8.0 / 3.0);  // edge of a regular tetrahedron of radius 3
  const std::vector<Vec3> tet{{0, 0, 0},
                              {a, 0, 0},
                              {a / 2, a * std::sqrt(3.0) / 2, 0},
                              {a / 2, a * std::sqrt(3.0) / 6, a * std::sqrt(2.0 / 3.0)}};
  AlphaShapeOptions o;
  o.point_scale = {2, 2, 4, 4};
  o.alpha = 1.01;
  EXPECT_EQ(alpha_shape(tet, o).mesh.num_triangles(), 4u);
  o.alpha = 0.99;
  EXPECT_EQ(alpha_shape(tet, o).mesh.num_triangles(), 0u);
  o.point_scale = {1, 1, 1, 1};
  o.alpha = 2.99;
  EXPECT_EQ(alpha_shape(tet, o).mesh.num_triangles(), 0u);
  o.point_scale.clear();
  o.alpha = 3.01;
  EXPECT_EQ(alpha_shape(tet, o).mesh.num_triangles(), 4u);
  o.point_scale = {1, 1, 1};
  EXPECT_THROW(alpha_shape(tet, o), Error);
}
