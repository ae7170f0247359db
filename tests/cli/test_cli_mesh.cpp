#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "inhap/geometry/mesh_io.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;
using test::run_cli;

TEST(CliMesh, InfoOnTheStanfordBunny) {
  const std::string bunny = test::shared_data("bunny/bun_zipper.ply");
  if (!std::filesystem::exists(bunny)) GTEST_SKIP() << "absent: " << bunny;
  auto r = run_cli("mesh info " + bunny);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("vertices    35947"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("faces       69451"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("property    confidence in [0, 0.999"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("manifold    yes"), std::string::npos) << r.out;
}

TEST(CliMesh, ConvertScalesCentresAndMapsStiffness) {
  test::TempDir dir;
  {
    std::ofstream f(dir.path("h.csv"));
    f << "0,1,2\n3,4,5\n6,7,9\n";
  }
  auto r = run_cli("mesh heightmap " + dir.path("h.csv") +
                   " --spacing 2 --stiffness-from-height 0.2 1.0 --out " + dir.path("h.ply"));
  ASSERT_EQ(r.status, 0) << r.out;
  TriMesh h = read_mesh(dir.path("h.ply"));
  EXPECT_EQ(h.num_triangles(), 8u);
  EXPECT_DOUBLE_EQ(h.property("stiffness")[8], 1.0);
  EXPECT_DOUBLE_EQ(h.property("stiffness")[0], 0.2);

  // --downsample 2 on a 5x4 grid: 2x2 blocks -> 2x2 pixels, 2 triangles, spacing 2 * 2 mm.
  {
    std::ofstream f(dir.path("big.csv"));
    f << "0,0,2,2,9\n0,0,2,2,9\n4,4,6,6,9\n4,4,6,6,9\n";
  }
  r = run_cli("mesh heightmap " + dir.path("big.csv") + " --spacing 2 --downsample 2 --out " +
              dir.path("d.ply"));
  ASSERT_EQ(r.status, 0) << r.out;
  TriMesh d = read_mesh(dir.path("d.ply"));
  EXPECT_EQ(d.num_triangles(), 2u);
  EXPECT_DOUBLE_EQ(d.bbox().size().x(), 4.0);
  EXPECT_DOUBLE_EQ(d.bbox().max.z(), 6.0);
  EXPECT_DOUBLE_EQ(d.bbox().min.z(), 0.0);

  r = run_cli("mesh convert " + dir.path("h.ply") + " " + dir.path("c.ply") +
              " --scale-to 100 --center --stiffness-from z_missing --k-range 0 1");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.out.find("no vertex property 'z_missing'"), std::string::npos) << r.out;

  r = run_cli("mesh convert " + dir.path("h.ply") + " " + dir.path("c.ply") +
              " --scale-to 100 --center");
  ASSERT_EQ(r.status, 0) << r.out;
  TriMesh c = read_mesh(dir.path("c.ply"));
  Box3 b = c.bbox();
  EXPECT_NEAR(b.size().maxCoeff(), 100.0, 1e-9);
  EXPECT_NEAR(b.center().norm(), 0.0, 1e-9);
  EXPECT_TRUE(c.has_property("stiffness"));
}

TEST(CliMesh, BadInputGivesOneLineErrorAndNonZeroExit) {
  test::TempDir dir;
  std::ofstream(dir.path("bad.ply"))
      << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n2\n";
  auto r = run_cli("mesh info " + dir.path("bad.ply"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.out.find("inhap: error: " + dir.path("bad.ply")), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;

  r = run_cli("mesh heightmap " + dir.path("none.csv") + " --spacing 1 --out " + dir.path("o.ply"));
  EXPECT_EQ(r.status, 1);
  EXPECT_FALSE(std::filesystem::exists(dir.path("o.ply")));

  r = run_cli("mesh heightmap x.csv --spacing -1 --out o.ply");
  EXPECT_EQ(r.status, 2) << r.out;  // a bad flag: exit 2 (docs/architecture.md)
  EXPECT_EQ(r.out.rfind("inhap: error: ", 0), 0u) << r.out;
  r = run_cli("--help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("mm"), std::string::npos);
}
