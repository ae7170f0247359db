#include <gtest/gtest.h>

#include <filesystem>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/obj.hpp"
#include "mesh_test_util.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;

TEST(ObjRead, AllFaceFormsNegativeIndicesAndIgnoredStatements) {
  const std::string text =
      "# a comment\nmtllib scene.mtl\no thing\ng group\ns 1\nusemtl red\n"
      "v 0 0 0 1 0 0\n"         // r g b ignored
      "v 1 0 0\nv 1 1 0 1.0\n"  // w ignored
      "v 0 1 0   # trailing comment\n"
      "vt 0 0\nvt 1 0\nvn 0 0 1\nvp 0.5\n"
      "f 1 2 3 4\n"  // quad -> (0,1,2), (0,2,3)
      "v 2 0.5 0\n"
      "f 2/1 -1/2 3/2\n"         // v/vt with a relative index: vertex 5 is -1
      "f 1//1 2//1 -2//1\n"      // v//vn
      "f 1/1/1 3/2/1 4/1/1\r\n"  // v/vt/vn, CRLF
      "l 1 2\np 3\n";
  const TriMesh m = parse_obj(text, "mem.obj");
  const std::vector<Vec3> pos = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                                 Vec3(2, 0.5, 0)};
  EXPECT_EQ(m.positions, pos);
  const std::vector<Tri> tris = {{0, 1, 2}, {0, 2, 3}, {1, 4, 2}, {0, 1, 3}, {0, 2, 3}};
  EXPECT_EQ(m.triangles, tris);
  EXPECT_TRUE(m.properties.empty());
  ASSERT_EQ(m.normals.size(), 5u);
  EXPECT_LT((m.normals[4] - Vec3(0, 0, 1)).norm(), 1e-12);
}

TEST(ObjRead, FacesMayReferenceVerticesDefinedLater) {
  const TriMesh m = parse_obj("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "mem.obj");
  EXPECT_EQ(m.triangles, (std::vector<Tri>{{0, 1, 2}}));
}

TEST(ObjWrite, RoundTripIsExactAndPropertiesAreReportedDropped) {
  test::TempDir dir;
  TriMesh m = test::awkward_mesh();
  const auto dropped = write_obj(dir.path("m.obj"), m);
  EXPECT_EQ(dropped, (std::vector<std::string>{"confidence", "stiffness", "z_last"}));
  const std::string text = read_file(dir.path("m.obj"));
  EXPECT_NE(text.find("f 1 3 4\n"), std::string::npos);  // 1-based
  const TriMesh back = read_obj(dir.path("m.obj"));
  EXPECT_EQ(back.triangles, m.triangles);
  ASSERT_EQ(back.positions.size(), m.positions.size());
  EXPECT_EQ(
      std::memcmp(back.positions.data(), m.positions.data(), m.positions.size() * sizeof(Vec3)), 0);
  EXPECT_TRUE(back.properties.empty());
}

TEST(MeshIo, DispatchesOnCaseInsensitiveExtension) {
  test::TempDir dir;
  const TriMesh m = test::awkward_mesh();
  EXPECT_TRUE(write_mesh(dir.path("a.PLY"), m).empty());
  EXPECT_EQ(read_file(dir.path("a.PLY")).find("ply\nformat binary_little_endian 1.0\n"), 0u);
  EXPECT_TRUE(test::bit_identical(read_mesh(dir.path("a.PLY")), m));
  EXPECT_TRUE(write_mesh(dir.path("b.ply"), m, {.ascii = true}).empty());
  EXPECT_EQ(read_file(dir.path("b.ply")).find("ply\nformat ascii 1.0\n"), 0u);
  EXPECT_TRUE(test::bit_identical(read_mesh(dir.path("b.ply")), m));
  EXPECT_EQ(write_mesh(dir.path("c.Obj"), m).size(), 3u);
  EXPECT_EQ(read_mesh(dir.path("c.Obj")).triangles, m.triangles);
}

TEST(MeshIo, UnknownExtensionIsAClearError) {
  test::TempDir dir;
  for (const std::string name : {"mesh.stl", "mesh"}) {
    const std::string path = dir.path(name);
    try {
      read_mesh(path);
      FAIL() << "expected an error for " << path;
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find(path + ": expected a mesh file ending in .ply or .obj"), 0u) << msg;
    }
    EXPECT_THROW(write_mesh(path, test::awkward_mesh()), Error);
    EXPECT_FALSE(std::filesystem::exists(path));
  }
}

TEST(MeshIo, MissingFileIsAnIoError) {
  test::TempDir dir;
  EXPECT_THROW(read_mesh(dir.path("nope.ply")), IoError);
  EXPECT_THROW(read_mesh(dir.path("nope.obj")), IoError);
}
