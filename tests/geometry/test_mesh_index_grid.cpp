// MeshIndex's seed grid (docs/spatial-queries.md, "Seed grid"): seeded closest-point queries
// equal brute force over all triangles (independent reference routine) in and around the shell,
// on cell faces and corners, with hints and max_distance; the prism bound never exceeds the true
// distance and is exact above a triangle's interior; cells that would need too many clusters
// fall back to the tree; options are checked.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <limits>
#include <string>
#include <vector>

#include "../../src/geometry/bvh_closest.hpp"
#include "geometry/index_test_meshes.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "support/meshes.hpp"

using namespace inhap;

namespace test_mesh_index_grid {

constexpr double kInf = std::numeric_limits<double>::infinity();

using test::brute_force_d2;
using test::bumpy;
using test::ref_d2;
using test::translated;

struct Case {
  std::string name;
  TriMesh mesh;
  double shell;  // mm
};

std::vector<Case> grid_cases() {
  return {{"torus", test::make_torus(40.0, 15.0, 60, 30), 5.0},
          {"bumpy_grid", test::make_grid_mesh(41, 41, 0.25, bumpy), 1.0},
          {"bumpy_grid_far_away",
           translated(test::make_grid_mesh(41, 41, 0.25, bumpy), Vec3(1.0e4, -3.0e3, 2.0e3)), 1.0},
          {"soup_with_degenerates", test::soup_with_degenerates(5, 1500, 300), 0.2},
          {"sphere", test::make_sphere(2.0, 4), 3.0}};
}

// A prism bound record with the fields make_prism_bound fills (as MeshIndex::TriBound).
struct Bound {
  float n[3], o;
  float m[3][4];
};

MeshIndexOptions grid_options(double shell) {
  MeshIndexOptions o;
  o.seed_shell = shell;
  o.seed_min_triangles = 0;
  return o;
}

// Query points: on and off the surface up to 1.3 shells, anywhere in the grid, and exactly on
// cell corners, edges and faces.
std::vector<Vec3> query_points(const TriMesh& m, const MeshIndex::SeedGridInfo& g, double shell,
                               Rng& rng) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 1500; ++i) {
    const std::size_t f = rng.below(m.num_triangles());
    const auto& t = m.triangles[f];
    double u = rng.uniform(), v = rng.uniform();
    if (u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    const Vec3 x = (1 - u - v) * m.positions[t[0]] + u * m.positions[t[1]] + v * m.positions[t[2]];
    Vec3 n = m.face_normal(f);
    if (!n.allFinite() || n.norm() < 0.5) n = Vec3::UnitZ();
    pts.push_back(x + rng.uniform(-1.3, 1.3) * shell * n);
  }
  const Vec3 size = m.bbox().max - m.bbox().min + Vec3::Constant(2 * shell);
  for (int i = 0; i < 500; ++i) {
    const Vec3 r(rng.uniform(), rng.uniform(), rng.uniform());
    pts.push_back(m.bbox().min - Vec3::Constant(shell) + size.cwiseProduct(r));
  }
  for (int i = 0; i < 500; ++i) {  // cell corners (i % 4 == 0), edges and faces (half cells)
    const Vec3 x = pts[rng.below(1500)] - g.origin;
    Vec3 k;
    for (int a = 0; a < 3; ++a) k[a] = std::round(x[a] / g.cell) + (a < i % 4 ? 0.5 : 0.0);
    pts.push_back(g.origin + g.cell * k);
  }
  return pts;
}

TEST(MeshIndexGrid, PrismBoundIsALowerBoundAndExactAboveTheInterior) {
  for (const auto& c : grid_cases()) {
    SCOPED_TRACE(c.name);
    const TriMesh& m = c.mesh;
    std::vector<Bound> b(m.num_triangles());
    std::vector<bool> ok(m.num_triangles());
    double slack = 0, scale = 0;
    for (std::size_t f = 0; f < m.num_triangles(); ++f) {
      const auto& t = m.triangles[f];
      double s = 0, k = 0;
      ok[f] = detail::make_prism_bound(m.positions[t[0]], m.positions[t[1]], m.positions[t[2]],
                                       b[f], s, k);
      slack = std::max(slack, s);
      scale = std::max(scale, k);
    }
    Rng rng(3);
    const Box3 box = m.bbox();
    long checked = 0, tight = 0, interior = 0;
    for (int q = 0; q < 200; ++q) {
      const std::size_t f0 = rng.below(m.num_triangles());
      const auto& t0 = m.triangles[f0];
      Vec3 p = (m.positions[t0[0]] + m.positions[t0[1]] + m.positions[t0[2]]) / 3;
      if (q % 2 == 1)
        p = box.min +
            (box.max - box.min).cwiseProduct(Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
      const double h = rng.uniform(-1, 1);
      if (q % 2 == 0 && ok[f0]) {  // straight above the centroid: the bound is h^2
        p += h * m.face_normal(f0);
        const double eq = detail::prism_error(p, scale);
        const double lb = detail::prism_bound(b[f0], p, eq, slack);
        // Exact but for the float rounding of the plane (the centroid is within the slack of
        // the offset, and the slack is subtracted once more) and the 1e-6 factor.
        EXPECT_NEAR(lb, h * h, 2 * std::abs(h) * (2 * slack + eq) + 2e-6 * h * h + 1e-15)
            << "triangle " << f0;
        EXPECT_LT(slack, 1e-6 * (1 + scale));  // float rounding of the offsets only
        ++interior;
      }
      const double eq = detail::prism_error(p, scale);
      for (std::size_t f = 0; f < m.num_triangles(); ++f, ++checked) {
        const double lb = detail::prism_bound(b[f], p, eq, slack), d2 = ref_d2(m, f, p);
        ASSERT_LE(lb, d2) << "triangle " << f << " query " << q << std::setprecision(17)
                          << " bound " << lb << " reference " << d2;
        tight += lb >= 0.5 * d2;
      }
    }
    EXPECT_GT(interior, 20);
    // Nearly exact: most bounds are within a factor 2 of the squared distance.
    EXPECT_GT(double(tight), 0.5 * double(checked));
  }
}

TEST(MeshIndexGrid, PrismBoundOfDegenerateTrianglesIsZero) {
  Bound b;
  double s = -1, k = -1;
  const Vec3 a(1, 2, 3), d(0.1, 0.2, 0.3);
  EXPECT_FALSE(detail::make_prism_bound(a, a, a + d, b, s, k));
  EXPECT_FALSE(detail::make_prism_bound(a, a + d, a + 2 * d, b, s, k));
  EXPECT_EQ(detail::prism_bound(b, Vec3(5, 5, 5), 0.0, 0.0), 0.0);
  EXPECT_EQ(s, -1);  // untouched
}

TEST(MeshIndexGrid, SeededQueriesMatchBruteForce) {
  for (const auto& c : grid_cases()) {
    SCOPED_TRACE(c.name);
    const TriMesh& m = c.mesh;
    const MeshIndex index(m, grid_options(c.shell));
    const auto g = index.seed_grid_info();
    ASSERT_GT(g.covered, 0);
    ASSERT_GT(g.cell, 0);
    EXPECT_GT(g.bytes, 0u);
    EXPECT_LE(g.seeds_per_cell, 120);
    Rng rng(11);
    const auto pts = query_points(m, g, c.shell, rng);
    MeshIndex::QueryStats st;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec3& p = pts[i];
      const ClosestPoint r = index.closest_point_counted(p, kInf, st);
      const double want = brute_force_d2(m, p);
      ASSERT_TRUE(r.valid()) << i;
      ASSERT_NEAR(r.distance2, want, 1e-9 * (1 + want)) << "query " << i;
      // The reported triangle is that near, and its barycentrics give the point.
      EXPECT_NEAR(ref_d2(m, static_cast<std::size_t>(r.triangle), p), want, 1e-9 * (1 + want));
      const auto& t = m.triangles[r.triangle];
      const Vec3 x = r.bary[0] * m.positions[t[0]] + r.bary[1] * m.positions[t[1]] +
                     r.bary[2] * m.positions[t[2]];
      EXPECT_LT((x - r.point).norm(), 1e-9 * (1 + p.norm()));
    }
    // The grid did the work (else this test could not fail for a wrong grid).
    EXPECT_GT(st.seeded, static_cast<std::int64_t>(pts.size() / 2));
  }
}

// A query reads only the clusters listed for its octant of the cell: on a smooth surface about
// half of the cell's list (the correctness of the masks is SeededQueriesMatchBruteForce's).
TEST(MeshIndexGrid, QueriesReadOnlyTheirOctantsClusters) {
  for (const auto& c : grid_cases()) {
    if (c.name != "torus" && c.name != "bumpy_grid") continue;
    SCOPED_TRACE(c.name);
    const MeshIndex index(c.mesh, grid_options(c.shell));
    const auto g = index.seed_grid_info();
    Rng rng(5);
    MeshIndex::QueryStats st;
    for (int i = 0; i < 2000; ++i) {
      const Box3 box = c.mesh.bbox();
      const Vec3 r(rng.uniform(), rng.uniform(), rng.uniform());
      const Vec3 p = box.min - Vec3::Constant(c.shell) +
                     (box.size() + Vec3::Constant(2 * c.shell)).cwiseProduct(r);
      MeshIndex::QueryStats one;
      index.closest_point_counted(p, kInf, one);
      if (one.seeded) {
        st.seeded += 1;
        st.nodes += one.nodes;
      }
    }
    ASSERT_GT(st.seeded, 200);
    const double read = double(st.nodes) / double(st.seeded);
    std::printf("[ %s ] %.1f clusters read per seeded query, %.1f listed per covered cell\n",
                c.name.c_str(), read, g.seeds_per_cell);
    EXPECT_LT(read, 0.75 * g.seeds_per_cell);
  }
}

TEST(MeshIndexGrid, HintsAndMaxDistanceAgreeWithTheTree) {
  const TriMesh m = test::make_torus(40.0, 15.0, 60, 30);
  const MeshIndex seeded(m, grid_options(5.0)), plain(m, grid_options(0.0));
  ASSERT_EQ(plain.seed_grid_info().cells, 0);
  Rng rng(4);
  MeshIndex::QueryStats st;
  int found = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(rng.uniform(-60, 60), rng.uniform(-60, 60), rng.uniform(-20, 20));
    const double r = rng.uniform(0, 6);
    const auto hint = static_cast<std::int32_t>(rng.below(m.num_triangles() + 10)) - 5;
    const ClosestPoint a = seeded.closest_point_counted(p, r, st, hint);
    const ClosestPoint b = plain.closest_point(p, r, hint);
    ASSERT_EQ(a.valid(), b.valid()) << i;
    if (a.valid()) {
      ++found;
      EXPECT_EQ(a.distance2, b.distance2) << i;
    }
  }
  EXPECT_GT(found, 200);
  EXPECT_GT(st.seeded, 200);
}

TEST(MeshIndexGrid, OverfullCellsFallBackToTheTree) {
  // Every point of a fine sphere is equally near its centre: the cells there would need all
  // clusters, so they stay uncovered and queries there descend the tree (still exact).
  const TriMesh m = test::make_sphere(1.0, 5);
  const MeshIndex index(m, grid_options(2.0));
  const auto g = index.seed_grid_info();
  ASSERT_GT(g.clusters, 120);
  ASSERT_GT(g.covered, 0);
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(0.01, -0.02, 0.005)}) {
    MeshIndex::QueryStats st;
    const ClosestPoint r = index.closest_point_counted(p, kInf, st);
    EXPECT_EQ(st.seeded, 0);
    EXPECT_NEAR(r.distance2, brute_force_d2(m, p), 1e-12);
  }
  MeshIndex::QueryStats near;  // next to the surface the grid is used
  index.closest_point_counted(Vec3(0, 0, 1.3), kInf, near);
  EXPECT_EQ(near.seeded, 1);
}

TEST(MeshIndexGrid, OptionsAreChecked) {
  const TriMesh m = test::make_torus(40.0, 15.0, 60, 30);
  for (const double bad : {-1.0, std::nan(""), kInf}) {
    MeshIndexOptions o;
    o.seed_shell = bad;
    try {
      MeshIndex index(m, o);
      ADD_FAILURE() << "seed_shell " << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("seed_shell"), std::string::npos) << e.what();
    }
  }
  // Default options: a grid from 4096 triangles on, none below.
  EXPECT_EQ(MeshIndex(test::make_torus(40.0, 15.0, 40, 40)).seed_grid_info().cells, 0);  // 3200
  const MeshIndex big(test::make_torus(40.0, 15.0, 64, 32));                             // 4096
  EXPECT_GT(big.seed_grid_info().covered, 0);
  EXPECT_GT(big.memory_bytes(), MeshIndex(m, grid_options(0)).memory_bytes());
}
}  // namespace test_mesh_index_grid
