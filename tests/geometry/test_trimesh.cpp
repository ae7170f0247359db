#include <gtest/gtest.h>

#include <cmath>

#include "inhap/core/error.hpp"
#include "inhap/geometry/trimesh.hpp"

using namespace inhap;

namespace {
// Unit cube, 12 triangles, outward orientation.
TriMesh cube() {
  TriMesh m;
  for (int i = 0; i < 8; ++i) m.positions.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}
}  // namespace

TEST(TriMesh, CubeIsClosedOrientedAndNormalsPointOut) {
  TriMesh m = cube();
  m.validate("cube");
  m.compute_normals();
  const Vec3 c(0.5, 0.5, 0.5);
  for (std::size_t v = 0; v < 8; ++v) {
    // Angle-weighted normal at a cube corner is the diagonal direction (three right angles).
    Vec3 expect = (m.positions[v] - c).normalized();
    EXPECT_NEAR(m.normals[v].dot(expect), 1.0, 1e-12) << v;
  }
  for (std::size_t f = 0; f < m.num_triangles(); ++f) EXPECT_NEAR(m.face_area(f), 0.5, 1e-15);
  auto adj = build_adjacency(m);
  auto topo = analyze_topology(m, adj);
  EXPECT_EQ(topo.edges, 18u);
  EXPECT_TRUE(topo.watertight());
  EXPECT_TRUE(topo.oriented());
  EXPECT_EQ(topo.boundary_loops, 0u);
  EXPECT_EQ(topo.components, 1u);
  for (std::size_t f = 0; f < m.num_triangles(); ++f)
    for (int e = 0; e < 3; ++e) EXPECT_GE(adj.face_neighbors[f][e], 0);
  std::size_t total = 0;
  for (int v = 0; v < 8; ++v) total += adj.faces_of_vertex(v).size();
  EXPECT_EQ(total, 36u);
}

TEST(TriMesh, DetectsFlippedFaceNonManifoldEdgeAndBoundary) {
  TriMesh m = cube();
  std::swap(m.triangles[0][0], m.triangles[0][1]);
  auto topo = analyze_topology(m, build_adjacency(m));
  EXPECT_EQ(topo.inconsistent_edges, 3u);
  EXPECT_FALSE(topo.oriented());

  TriMesh open = cube();
  open.triangles.pop_back();
  auto t2 = analyze_topology(open, build_adjacency(open));
  EXPECT_EQ(t2.boundary_edges, 3u);
  EXPECT_EQ(t2.boundary_loops, 1u);
  EXPECT_FALSE(t2.watertight());

  TriMesh fin = cube();
  fin.positions.emplace_back(0.5, -1, 0.5);
  fin.triangles.push_back({0, 1, 8});  // third face on edge 0-1
  auto t3 = analyze_topology(fin, build_adjacency(fin));
  EXPECT_EQ(t3.nonmanifold_edges, 1u);
  EXPECT_FALSE(t3.manifold());
}

TEST(TriMesh, ValidateRejectsBadIndicesAndNaN) {
  TriMesh m = cube();
  m.triangles[3][1] = 8;
  EXPECT_THROW(m.validate("x"), Error);
  m = cube();
  m.positions[2].y() = std::nan("");
  EXPECT_THROW(m.validate("x"), Error);
  m = cube();
  m.triangles[0] = {1, 1, 2};
  EXPECT_THROW(m.validate("x"), Error);
  m = cube();
  EXPECT_THROW(m.set_property("k", {1.0}), Error);
}

TEST(TriMesh, AppendKeepsPropertiesAndShiftsIndices) {
  TriMesh a = cube(), b = cube();
  a.set_property("stiffness", std::vector<double>(8, 0.5));
  b.transform(2.0, Vec3(0, 0, 0));
  a.append(b, 1.0);
  EXPECT_EQ(a.num_vertices(), 16u);
  EXPECT_EQ(a.triangles.back()[0], 3 + 8);
  EXPECT_EQ(a.property("stiffness")[15], 1.0);
  EXPECT_EQ(a.bbox().max, Vec3(2, 2, 2));
  a.validate("appended");
}
