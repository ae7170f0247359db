// MeshIndex distance pruning: the oriented node boxes (src/geometry/bvh_obb.hpp) are true lower
// bounds, with their frames computed per query or beforehand (checked against an independent
// point-triangle distance for every node and triangle),
// they are tight on a tilted plane (analytic distance), and closest_point stays exact against
// brute force on hard inputs: degenerate triangles, points exactly on the surface, meshes far
// from the origin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "../../src/geometry/bvh_build.hpp"
#include "../../src/geometry/bvh_obb.hpp"
#include "geometry/index_test_meshes.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "support/meshes.hpp"

using namespace inhap;

namespace test_mesh_index_bounds {

using test::brute_force_d2;
using test::bumpy;
using test::ref_d2;
using test::soup_with_degenerates;
using test::translated;

// A point on triangle f at barycentrics (1 - u - v, u, v), or a vertex / edge midpoint.
Vec3 surface_point(const TriMesh& m, std::size_t f, int kind, Rng& rng) {
  const auto& t = m.triangles[f];
  const Vec3 &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
  if (kind == 0) return a;
  if (kind == 1) return 0.5 * (b + c);
  double u = rng.uniform(), v = rng.uniform();
  if (u + v > 1) {
    u = 1 - u;
    v = 1 - v;
  }
  return (1 - u - v) * a + u * b + v * c;
}

struct Case {
  const char* name;
  TriMesh mesh;
};

std::vector<Case> hard_cases() {
  return {{"soup_with_degenerates", soup_with_degenerates(5)},
          {"torus", test::make_torus(40.0, 15.0, 60, 30)},
          {"bumpy_grid_far_away",
           translated(test::make_grid_mesh(31, 31, 0.25, bumpy), Vec3(1.0e4, -3.0e3, 2.0e3))}};
}

// The hierarchy MeshIndex builds over m, and the oriented box of every node.
std::pair<detail::BvhBuild, std::vector<detail::BvhObb>> build_with_obbs(const TriMesh& m) {
  std::vector<detail::BvhBox> boxes(m.num_triangles());
  for (std::size_t f = 0; f < m.num_triangles(); ++f)
    for (int k = 0; k < 3; ++k) boxes[f].grow(m.positions[m.triangles[f][k]]);
  detail::BvhBuild bvh = detail::build_bvh(boxes);
  std::vector<Vec3> verts;
  for (const std::int32_t f : bvh.order)
    for (int k = 0; k < 3; ++k) verts.push_back(m.positions[m.triangles[f][k]]);
  std::vector<detail::BvhObb> obb = detail::build_obbs(bvh, verts);
  return {std::move(bvh), std::move(obb)};
}

// Every node's oriented box bounds the distance to every triangle below it from below.
TEST(MeshIndexBounds, OrientedBoxesAreLowerBounds) {
  for (const auto& c : hard_cases()) {
    SCOPED_TRACE(c.name);
    const TriMesh& m = c.mesh;
    const auto [bvh, obb] = build_with_obbs(m);
    ASSERT_EQ(obb.size(), bvh.nodes.size());
    // Slot range of every node (children follow their parent).
    const std::size_t n = bvh.nodes.size();
    std::vector<std::int32_t> begin(n), end(n);
    for (std::size_t i = n; i-- > 0;) {
      const auto& b = bvh.nodes[i];
      begin[i] = b.count > 0 ? b.first : begin[i + 1];
      end[i] = b.count > 0 ? b.first + b.count : end[static_cast<std::size_t>(b.first)];
    }
    // The seed grid's builder projects with precomputed frames (obb_rows): the same bound.
    std::vector<Mat3> rows;
    for (const auto& o : obb) rows.push_back(detail::obb_rows(o.q));
    Rng rng(21);
    const Box3 box = m.bbox();
    const double diag = box.size().norm();
    long checked = 0, positive = 0;
    for (int q = 0; q < 300; ++q) {
      // Near the surface, on it, or anywhere around the mesh.
      const std::size_t f = rng.below(m.num_triangles());
      Vec3 p = surface_point(m, f, q % 4, rng);
      if (q % 4 == 3)
        p += 0.02 * diag * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      if (q % 8 == 7)
        p = box.min +
            (box.max - box.min).cwiseProduct(Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
      const double eq = detail::obb_project_error(p);
      for (std::size_t i = 0; i < n; ++i) {
        const double lb = detail::obb_distance2(obb[i], p, eq);
        const double lb_rows = detail::obb_distance2(obb[i], rows[i], p, eq);
        ASSERT_NEAR(lb_rows, lb, 1e-9 * (1 + lb)) << "node " << i << " query " << q;
        positive += lb > 0;
        for (std::int32_t s = begin[i]; s < end[i]; ++s, ++checked) {
          const double d2 = ref_d2(m, static_cast<std::size_t>(bvh.order[s]), p);
          ASSERT_LE(lb, d2) << "node " << i << " slot " << s << " query " << q;
          ASSERT_LE(lb_rows, d2) << "node " << i << " slot " << s << " query " << q;
        }
      }
    }
    std::printf("[ %s ] %ld (node, triangle, point) triples, %ld positive node bounds\n", c.name,
                checked, positive);
    EXPECT_GT(positive, 0);
  }
}

// On a plane tilted to every axis, a point at height h sees every node's oriented bound at
// about h (plus its lateral offset), where axis-aligned boxes would give far less.
TEST(MeshIndexBounds, OrientedBoxesAreTightOnATiltedPlane) {
  TriMesh m = test::make_grid_mesh(41, 41, 0.5);
  const Mat3 rot = (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  for (auto& p : m.positions) p = rot * p + Vec3(3, -2, 5);
  const auto [bvh, obb] = build_with_obbs(m);
  const Vec3 normal = rot * Vec3::UnitZ();
  const double h = 5.0;
  const Vec3 p = rot * Vec3(10.2, 9.9, 0) + Vec3(3, -2, 5) + h * normal;
  const double eq = detail::obb_project_error(p);
  // Root: the whole plane lies under p, so the bound is exactly h up to float rounding.
  // (The int16 quaternion tilts a frame by up to ~3e-5 rad: 5e-4 mm over the 15 mm between p
  // and the farthest nodes.)
  EXPECT_NEAR(std::sqrt(detail::obb_distance2(obb[0], p, eq)), h, 1e-3);
  // Every node's bound is at least h (up to that tilt); the axis-aligned box of the root
  // contains p (bound 0).
  for (std::size_t i = 0; i < obb.size(); ++i)
    EXPECT_GE(std::sqrt(detail::obb_distance2(obb[i], p, eq)), h - 1e-3) << "node " << i;
  const auto& r = bvh.nodes[0];
  EXPECT_TRUE(p.x() > r.lo[0] && p.x() < r.hi[0] && p.y() > r.lo[1] && p.y() < r.hi[1] &&
              p.z() > r.lo[2] && p.z() < r.hi[2]);
}

// Exact against brute force where rounding is hardest; the counted variant gives the same answer.
TEST(MeshIndexBounds, ClosestPointExactOnHardCases) {
  for (const auto& c : hard_cases()) {
    SCOPED_TRACE(c.name);
    const TriMesh& m = c.mesh;
    const MeshIndex index(m);
    Rng rng(33);
    const double diag = m.bbox().size().norm();
    const double coord = m.bbox().min.cwiseAbs().cwiseMax(m.bbox().max.cwiseAbs()).maxCoeff();
    MeshIndex::QueryStats stats;
    int on_surface = 0;
    for (int i = 0; i < 3000; ++i) {
      const std::size_t f = rng.below(m.num_triangles());
      Vec3 p = surface_point(m, f, i % 3, rng);
      const bool exactly_on = i % 2 == 0;  // vertices, edge midpoints, interior points
      if (!exactly_on)
        p += rng.uniform(0.0, 0.1) * diag *
             Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      const double ref = brute_force_d2(m, p);
      const ClosestPoint cp = index.closest_point(p);
      ASSERT_TRUE(cp.valid());
      // Exact: the same distance up to the rounding of the two point-triangle routines, which
      // grows with the size of the coordinates (1e4 mm for the far grid).
      const double tol = 1e-9 * std::sqrt(ref) + 4e-15 * coord;
      EXPECT_NEAR(std::sqrt(cp.distance2), std::sqrt(ref), tol) << "point " << i;
      EXPECT_NEAR(std::sqrt(ref_d2(m, static_cast<std::size_t>(cp.triangle), p)), std::sqrt(ref),
                  tol);
      const ClosestPoint counted = index.closest_point_counted(p, 1e300, stats);
      EXPECT_EQ(counted.triangle, cp.triangle);
      EXPECT_EQ(counted.distance2, cp.distance2);
      on_surface += exactly_on && std::sqrt(ref) <= 1e-12 * coord;
    }
    EXPECT_GT(stats.nodes, 0);
    EXPECT_LE(stats.exact, stats.triangles);
    std::printf(
        "[ %s ] %d points on the surface; mean %.1f nodes, %.1f triangles loaded, %.1f "
        "exact tests per query\n",
        c.name, on_surface, stats.nodes / 3000.0, stats.triangles / 3000.0, stats.exact / 3000.0);
  }
}
}  // namespace test_mesh_index_bounds
