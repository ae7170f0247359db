// inhap/geometry/mesh_report.hpp (`inhap mesh info|convert|heightmap`) on meshes whose counts and
// topology are known by construction.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_report.hpp"
#include "support/meshes.hpp"

namespace inhap {
namespace {

TEST(MeshReport, MapLinearSendsMinAndMaxToTheRange) {
  EXPECT_EQ(map_linear({2, 4, 6}, 1, 2), (std::vector<double>{1, 1.5, 2}));
  EXPECT_EQ(map_linear({3, 3}, 0.2, 0.8), (std::vector<double>{0.8, 0.8}));  // constant: hi
  EXPECT_TRUE(map_linear({}, 0, 1).empty());
}

TEST(MeshReport, InfoOfAGridPatch) {
  // 3 x 3 vertices, 8 triangles; edges: 6 horizontal + 6 vertical + 4 diagonals = 16, of which
  // the 8 on the border form one boundary loop. One open, manifold, oriented component.
  TriMesh m = test::make_grid_mesh(3, 3, 2.0);
  m.set_property("stiffness", {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9});
  const std::string t = mesh_info_text("g.ply", m);
  EXPECT_NE(t.find("vertices    9\n"), std::string::npos) << t;
  EXPECT_NE(t.find("faces       8\n"), std::string::npos) << t;
  EXPECT_NE(t.find("edges       16\n"), std::string::npos) << t;
  EXPECT_NE(t.find("size        4 x 4 x 0 mm\n"), std::string::npos) << t;
  EXPECT_NE(t.find("property    stiffness in [0.1, 0.9] N/mm\n"), std::string::npos) << t;
  EXPECT_NE(t.find("manifold    yes\n"), std::string::npos) << t;
  EXPECT_NE(t.find("watertight  no\n"), std::string::npos) << t;
  EXPECT_NE(t.find("boundary    1 loops, 8 edges\n"), std::string::npos) << t;
  EXPECT_NE(t.find("components  1\n"), std::string::npos) << t;
  const nlohmann::json j = nlohmann::json::parse(mesh_info_json("g.ply", m));
  EXPECT_EQ(j["edges"], 16);
  EXPECT_EQ(j["boundary_edges"], 8);
  EXPECT_EQ(j["watertight"], false);
  EXPECT_DOUBLE_EQ(j["properties"]["stiffness"]["max"].get<double>(), 0.9);
  EXPECT_DOUBLE_EQ(j["bbox_mm"]["max"][0].get<double>(), 4.0);
}

TEST(MeshReport, ScaleAndCenter) {
  TriMesh m = test::make_grid_mesh(3, 2, 1.0);  // 2 x 1 mm
  scale_and_center(m, 10.0, true, "m");
  const Box3 b = m.bbox();
  EXPECT_NEAR(b.min.x(), -5.0, 1e-12);
  EXPECT_NEAR(b.max.x(), 5.0, 1e-12);
  EXPECT_NEAR(b.max.y(), 2.5, 1e-12);
  TriMesh point;
  point.positions = {Vec3(1, 1, 1)};
  EXPECT_THROW(scale_and_center(point, 10.0, false, "p"), Error);
}

}  // namespace
}  // namespace inhap
