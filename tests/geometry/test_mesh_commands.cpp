// What `inhap mesh convert|heightmap|from-volume` compute (mesh_report.hpp, volume.hpp), on
// meshes and grids whose numbers are known by construction.
#include <gtest/gtest.h>

#include <fstream>

#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_report.hpp"
#include "inhap/geometry/volume.hpp"
#include "support/meshes.hpp"
#include "support/temp_dir.hpp"

namespace inhap {
namespace {

TEST(MeshCommands, StiffnessFromAProperty) {
  TriMesh m = test::make_grid_mesh(2, 2, 1.0);
  m.set_property("confidence", {0, 1, 2, 4});
  stiffness_from_property(m, "confidence", {0.2, 1.0});
  const std::vector<double> want{0.2, 0.4, 0.6, 1.0};  // 0..4 onto 0.2..1.0
  ASSERT_EQ(m.property("stiffness").size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(m.property("stiffness")[i], want[i], 1e-12);
  EXPECT_THROW(stiffness_from_property(m, "confidence", {}), Error);          // no range
  EXPECT_THROW(stiffness_from_property(m, "confidence", {1.0, 0.5}), Error);  // max < min
  EXPECT_THROW(stiffness_from_property(m, "", {0.1, 1.0}), Error);            // range, no prop
  TriMesh plain = test::make_grid_mesh(2, 2, 1.0);
  stiffness_from_property(plain, "", {});  // nothing asked: nothing done
  EXPECT_FALSE(plain.has_property("stiffness"));
}

TEST(MeshCommands, WrittenTextAndDroppedProperties) {
  TriMesh m = test::make_grid_mesh(3, 2, 2.0);  // 4 x 2 mm, 6 vertices, 4 triangles
  EXPECT_EQ(mesh_written_text("o.obj", m), "wrote o.obj: 6 vertices, 4 faces, size 4 x 2 x 0 mm\n");
  m.set_property("stiffness", {0.5, 0.5, 0.25, 1, 1, 1});
  EXPECT_EQ(mesh_written_text("o.ply", m),
            "wrote o.ply: 6 vertices, 4 faces, size 4 x 2 x 0 mm, stiffness in [0.25, 1] N/mm\n");
  EXPECT_EQ(dropped_properties_text("o.obj", {"k", "c"}),
            "inhap: warning: o.obj: the format cannot store vertex property 'k'; it was dropped\n"
            "inhap: warning: o.obj: the format cannot store vertex property 'c'; it was "
            "dropped\n");
  EXPECT_EQ(dropped_properties_text("o.ply", {}), "");
}

TEST(MeshCommands, HeightmapMeshWithStiffnessFromHeight) {
  const test::TempDir dir;
  std::ofstream(dir.path("h.csv")) << "0,1,2\n3,4,5\n";
  HeightmapMeshOptions o;
  o.height = dir.path("h.csv");
  o.spacing_mm = 0.5;
  o.height_scale = 2.0;
  o.k_from_height = {0.1, 1.1};
  const HeightmapMesh h = heightmap_mesh(o);
  EXPECT_EQ(h.width, 3);
  EXPECT_EQ(h.height, 2);
  EXPECT_EQ(h.mesh.num_vertices(), 6u);
  EXPECT_EQ(h.mesh.num_triangles(), 4u);  // 2 (W - 1) (H - 1)
  const Box3 b = h.mesh.bbox();
  EXPECT_DOUBLE_EQ(b.size().x(), 1.0);
  EXPECT_DOUBLE_EQ(b.size().z(), 10.0);  // heights 0..5 times 2
  const auto& k = h.mesh.property("stiffness");
  EXPECT_DOUBLE_EQ(*std::min_element(k.begin(), k.end()), 0.1);
  EXPECT_DOUBLE_EQ(*std::max_element(k.begin(), k.end()), 1.1);
  o.stiffness = dir.path("h.csv");  // both sources
  EXPECT_THROW(heightmap_mesh(o), Error);
  std::ofstream(dir.path("k.csv")) << "1,2\n3,4\n";
  o.k_from_height.clear();
  o.stiffness = dir.path("k.csv");  // another size
  EXPECT_THROW(heightmap_mesh(o), Error);
}

TEST(MeshCommands, HeadSummary) {
  HeadModel head;
  head.mesh = test::make_grid_mesh(2, 2, 10.0);  // 10 x 10 mm, 4 vertices, 2 triangles
  head.mesh.set_property("stiffness", {0.4, 0.5, 0.9, 1.0});
  head.skin_components = 3;
  head.bone_triangles = 77;
  head.distance_far_mm = 20;
  HeadModelOptions o;  // k 0.4-1.0: k_max up to 0.4 / 1.0 * 20 = 8 mm
  const std::string t = head_summary_text(head, o, 0.5);
  EXPECT_EQ(t,
            "skin        iso 500: 3 components, kept the largest: 2 triangles, 4 vertices\n"
            "bone        iso 1150: 77 triangles\n"
            "stiffness   0.400 .. 1.000 N/mm, inverse to the skin-to-bone distance (k_max up to "
            "8.0 mm, k_min from 20.0 mm)\n"
            "scaled      x0.5 into 10.0 x 10.0 x 0.0 mm\n");
}

}  // namespace
}  // namespace inhap
