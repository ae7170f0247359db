// sort_spatially: the same surface in a cache-friendly order. Known answers: every triangle keeps
// its corners (and their order) and every vertex its normal and properties; on a grid the edges
// join vertices much nearer in memory than in row-major order. Units: mm.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <set>

#include "inhap/geometry/spatial_order.hpp"

using namespace inhap;

namespace {

// n x n grid, row-major, a bump in z, a property that names each vertex's old index.
TriMesh row_major_grid(int n) {
  TriMesh m;
  std::vector<double> old_id;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = i * 0.5, y = j * 0.5;
      m.positions.emplace_back(x, y,
                               3.0 * std::exp(-((x - 10) * (x - 10) + (y - 12) * (y - 12)) / 20));
      old_id.push_back(double(m.positions.size() - 1));
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const std::int32_t a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  m.set_property("old_id", old_id);
  m.compute_normals();
  return m;
}

// Share of a triangle's corner pairs at most `within` entries apart in the vertex arrays: how
// often one triangle's data share a few cache lines.
double share_near(const TriMesh& m, int within) {
  std::size_t near = 0;
  for (const Tri& t : m.triangles)
    for (int k = 0; k < 3; ++k) near += std::abs(t[k] - t[(k + 1) % 3]) <= within;
  return double(near) / (3.0 * double(m.triangles.size()));
}

}  // namespace

TEST(SpatialOrder, KeepsEveryTriangleAndVertexAndOnlyRenumbers) {
  const TriMesh before = row_major_grid(40);
  TriMesh after = before;
  const SpatialOrder order = sort_spatially(after);
  ASSERT_EQ(after.num_vertices(), before.num_vertices());
  ASSERT_EQ(after.num_triangles(), before.num_triangles());
  // Both permutations are permutations.
  EXPECT_EQ(std::set<std::int32_t>(order.vertex_from.begin(), order.vertex_from.end()).size(),
            before.num_vertices());
  EXPECT_EQ(std::set<std::int32_t>(order.face_from.begin(), order.face_from.end()).size(),
            before.num_triangles());
  const auto& ids = after.property("old_id");
  for (std::size_t i = 0; i < after.num_vertices(); ++i) {
    const auto from = static_cast<std::size_t>(order.vertex_from[i]);
    EXPECT_EQ(after.positions[i], before.positions[from]);
    EXPECT_EQ(after.normals[i], before.normals[from]);
    EXPECT_EQ(ids[i], double(from));  // properties move with their vertex
  }
  for (std::size_t f = 0; f < after.num_triangles(); ++f) {
    const Tri& was = before.triangles[static_cast<std::size_t>(order.face_from[f])];
    for (int k = 0; k < 3; ++k)  // same corners in the same order: same orientation
      EXPECT_EQ(after.positions[static_cast<std::size_t>(after.triangles[f][k])],
                before.positions[static_cast<std::size_t>(was[k])]);
  }
  EXPECT_NO_THROW(after.validate("sorted grid"));
}

TEST(SpatialOrder, PutsATrianglesCornersNearerInMemoryThanRowMajor) {
  const TriMesh before = row_major_grid(128);
  TriMesh after = before;
  sort_spatially(after);
  // Row-major: a triangle spans two rows, so two of its three corner pairs lie a row (128
  // entries) apart. Morton order keeps most pairs within a few entries.
  EXPECT_NEAR(share_near(before, 16), 1.0 / 3.0, 1e-9);
  EXPECT_GT(share_near(after, 16), 0.6);
  // Faces too: consecutive faces are near each other on the surface.
  double step = 0;
  for (std::size_t f = 1; f < after.num_triangles(); ++f)
    step += (after.positions[static_cast<std::size_t>(after.triangles[f][0])] -
             after.positions[static_cast<std::size_t>(after.triangles[f - 1][0])])
                .norm();
  EXPECT_LT(step / double(after.num_triangles() - 1), 2.0);  // mm, on a 0.5 mm grid
}

TEST(SpatialOrder, EmptyMeshAndMortonKeyBounds) {
  TriMesh empty;
  const SpatialOrder o = sort_spatially(empty);
  EXPECT_TRUE(o.vertex_from.empty());
  const Vec3 lo(0, 0, 0), ext(10, 10, 10);
  EXPECT_EQ(morton_key(lo, lo, ext), 0u);
  EXPECT_EQ(morton_key(ext, lo, ext), (std::uint64_t(1) << 63) - 1);  // all 63 bits set
  // Interleaving: x is bit 0, y bit 1, z bit 2 of each triple.
  const double cell = 10.0 / double((1u << 21) - 1);
  EXPECT_EQ(morton_key(Vec3(cell * 1.5, 0, 0), lo, ext), 1u);
  EXPECT_EQ(morton_key(Vec3(0, cell * 1.5, 0), lo, ext), 2u);
  EXPECT_EQ(morton_key(Vec3(0, 0, cell * 1.5), lo, ext), 4u);
}
