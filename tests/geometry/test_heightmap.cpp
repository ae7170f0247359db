#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "inhap/core/error.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;

TEST(Heightmap, GridGives2WHTrianglesAndStiffness) {
  for (auto [w, h] : {std::pair{2, 2}, {5, 3}, {257, 257}}) {
    Grid hg(w, h), kg(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        hg.at(x, y) = 0.1 * x - 0.2 * y;
        kg.at(x, y) = 0.5 + 0.001 * x;
      }
    TriMesh m = grid_to_mesh(hg, 0.5, &kg);
    EXPECT_EQ(m.num_triangles(), 2u * (w - 1) * (h - 1));
    EXPECT_EQ(m.num_vertices(), std::size_t(w) * h);
    ASSERT_TRUE(m.has_property("stiffness"));
    EXPECT_DOUBLE_EQ(m.property("stiffness")[w - 1], 0.5 + 0.001 * (w - 1));
    EXPECT_DOUBLE_EQ(m.positions.back().x(), 0.5 * (w - 1));
    EXPECT_DOUBLE_EQ(m.positions.back().z(), 0.1 * (w - 1) - 0.2 * (h - 1));
    // Plane z = 0.1 x - 0.2 y in grid units -> normal ∝ (-0.1/0.5, 0.2/0.5, 1) in mm.
    Vec3 expect = Vec3(-0.2, 0.4, 1).normalized();
    for (std::size_t f = 0; f < m.num_triangles(); f += 97)
      EXPECT_NEAR(m.face_normal(f).dot(expect), 1.0, 1e-12);
    for (const auto& n : m.normals) EXPECT_NEAR(n.dot(expect), 1.0, 1e-12);
    MeshAdjacency adj = build_adjacency(m);
    MeshTopology topo = analyze_topology(m, adj);
    EXPECT_TRUE(topo.manifold());
    EXPECT_TRUE(topo.oriented());
    EXPECT_EQ(topo.boundary_loops, 1u);
    EXPECT_EQ(topo.components, 1u);
    EXPECT_EQ(topo.boundary_edges, 2u * ((w - 1) + (h - 1)));
  }
}

// The mean of a linear function over a block is its value at the block centre. Column 4 carries
// +100 (inside a block for every factor: adds 100 / f to it); column 10 carries +1000 (in the
// partial last block for f = 2 and 3, which is dropped).
TEST(Heightmap, DownsampleAveragesBlocksOfALinearRamp) {
  auto ramp = [](double x, double y) { return 0.3 * x - 0.2 * y + 1.0; };
  for (int f : {1, 2, 3}) {
    Grid g(11, 8);
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x)
        g.at(x, y) = ramp(x, y) + (x == 4 ? 100.0 : 0.0) + (x == 10 ? 1000.0 : 0.0);
    const Grid d = downsample(g, f);
    EXPECT_EQ(d.width, 11 / f);
    EXPECT_EQ(d.height, 8 / f);
    const double c = 0.5 * (f - 1);
    for (int y = 0; y < d.height; ++y)
      for (int x = 0; x < d.width; ++x) {
        auto covers = [&](int column) { return x * f <= column && column < (x + 1) * f; };
        const double spikes = (covers(4) ? 100.0 : 0.0) + (covers(10) ? 1000.0 : 0.0);
        EXPECT_NEAR(d.at(x, y), ramp(x * f + c, y * f + c) + spikes / f, 1e-12)
            << "f " << f << " at " << x << "," << y;
      }
  }
}

// Bilinear interpolation reproduces a bilinear function exactly: sample (x, y) of the n x n
// result sits at grid coordinates (x (W - 1) / (n - 1), y (H - 1) / (n - 1)).
TEST(Heightmap, ResampleBilinearIsExactOnABilinearFunction) {
  auto fn = [](double x, double y) { return 0.3 * x - 0.2 * y + 0.05 * x * y + 1.0; };
  Grid g(11, 8);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) g.at(x, y) = fn(x, y);
  for (int n : {2, 5, 23}) {
    const Grid r = resample_bilinear(g, n);
    ASSERT_EQ(r.width, n);
    ASSERT_EQ(r.height, n);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        EXPECT_NEAR(r.at(x, y), fn(x * 10.0 / (n - 1), y * 7.0 / (n - 1)), 1e-12)
            << "n " << n << " at " << x << "," << y;
  }
}

TEST(Heightmap, DownsampleRejectsBadFactors) {
  Grid g(6, 6, 1.0);
  EXPECT_THROW(downsample(g, 0), Error);
  EXPECT_THROW(downsample(g, 4), Error);  // 1x1 left
  EXPECT_EQ(downsample(g, 3).width, 2);
}

TEST(Heightmap, StiffnessSizeMismatchIsAnError) {
  Grid hg(4, 4), kg(4, 3);
  EXPECT_THROW(grid_to_mesh(hg, 1.0, &kg), Error);
  EXPECT_THROW(grid_to_mesh(hg, 0.0), Error);
}

TEST(Heightmap, LevelPlaneRemovesTiltExactly) {
  Grid g(30, 20);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 30; ++x)
      g.at(x, y) = 3.0 + 0.7 * x - 1.3 * y + (x == 10 && y == 10 ? 5.0 : 0.0);
  level_plane(g);
  // The bump survives; everything else is flat (a single outlier shifts the fit by a tiny amount).
  double spread = 0;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 30; ++x)
      if (!(x == 10 && y == 10)) spread = std::max(spread, std::abs(g.at(x, y) - g.at(0, 0)));
  EXPECT_LT(spread, 0.2);
  EXPECT_GT(g.at(10, 10) - g.at(0, 0), 4.5);
}

TEST(Heightmap, ReadsCsvAndPgm) {
  test::TempDir dir;
  std::ofstream(dir.path("h.csv")) << "# heights in mm\n0,1,2\n3,4,5\n";
  Grid c = read_grid(dir.path("h.csv"));
  EXPECT_EQ(c.width, 3);
  EXPECT_EQ(c.height, 2);
  EXPECT_EQ(c.at(2, 1), 5);
  {
    std::ofstream f(dir.path("h.pgm"), std::ios::binary);
    f << "P5\n# comment\n3 2\n65535\n";
    const unsigned short px[] = {0, 1, 256, 1000, 65535, 7};
    for (auto v : px) f.put(char(v >> 8)).put(char(v & 0xff));
  }
  Grid p = read_grid(dir.path("h.pgm"));
  EXPECT_EQ(p.width, 3);
  EXPECT_EQ(p.at(2, 0), 256);
  EXPECT_EQ(p.at(1, 1), 65535);
  std::ofstream(dir.path("a.pgm")) << "P2 2 2 255\n0 10\n20 255\n";
  EXPECT_EQ(read_grid(dir.path("a.pgm")).at(1, 1), 255);
}

TEST(Heightmap, BadGridsNameFileAndLine) {
  test::TempDir dir;
  struct Case {
    const char* name;
    std::string text;
    const char* expect;
  };
  const Case cases[] = {
      {"ragged.csv", "1,2,3\n4,5\n", ":2: expected 3 values"},
      {"nan.csv", "1,2\nx,5\n", ":2: column 1: expected a finite number, got 'x'"},
      {"one.csv", "1,2\n", "at least 2x2"},
      {"empty.csv", "", "empty file"},
      {"trunc.pgm", "P5 4 4 65535\n\x01\x02", "truncated PGM data"},
      {"maxval.pgm", "P5 4 4 70000\n", "maxval"},
      {"magic.pgm", "P6 4 4 255\n", "expected a PGM (P2 or P5)"},
  };
  for (const auto& c : cases) {
    auto path = dir.path(c.name);
    std::ofstream(path, std::ios::binary) << c.text;
    try {
      read_grid(path);
      ADD_FAILURE() << c.name << ": no error";
    } catch (const Error& e) {
      std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      EXPECT_NE(what.find(c.expect), std::string::npos) << c.name << ": " << what;
    }
  }
}
