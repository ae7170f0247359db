// Readers refuse finite but absurd coordinates: vertices or heights of +-1e308 gave a mesh whose
// size was inf, reported with exit 0.
#include <gtest/gtest.h>

#include <string>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_report.hpp"
#include "inhap/geometry/obj.hpp"
#include "inhap/geometry/ply.hpp"
#include "support/temp_dir.hpp"

namespace {

template <class Fn>
std::string error_of(Fn&& fn) {
  try {
    fn();
  } catch (const inhap::Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(HugeValues, MeshVerticesOfOneE308AreRefusedNamingTheFile) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "-1e308 0 0\n1e308 0 0\n0 1 0\n3 0 1 2\n";
  // float properties: 1e308 is out of float range, so write doubles as well.
  const std::string ply_d =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "-1e308 0 0\n1e308 0 0\n0 1 0\n3 0 1 2\n";
  for (const std::string& text : {ply, ply_d})
    EXPECT_NE(error_of([&] { (void)inhap::parse_ply(text, "huge.ply"); }).find("huge.ply"),
              std::string::npos);
  const std::string obj = "v -1e308 0 0\nv 1e308 0 0\nv 0 1 0\nf 1 2 3\n";
  const std::string e = error_of([&] { (void)inhap::parse_obj(obj, "huge.obj"); });
  EXPECT_NE(e.find("huge.obj"), std::string::npos) << e;
  // Ordinary coordinates still read.
  EXPECT_EQ(inhap::parse_obj("v 0 0 0\nv 1000 0 0\nv 0 1000 0\nf 1 2 3\n", "ok.obj").num_vertices(),
            3u);
}

TEST(HugeValues, HeightsOfOneE308AreRefusedNamingTheFile) {
  inhap::test::TempDir tmp;
  const std::string csv = tmp.path("h.csv");
  inhap::write_file_atomic(csv, "0,0,0\n0,1e308,0\n0,-1e308,0\n");
  inhap::HeightmapMeshOptions o;
  o.height = csv;
  o.spacing_mm = 1.0;
  const std::string e = error_of([&] { (void)inhap::heightmap_mesh(o); });
  EXPECT_NE(e.find("h.csv"), std::string::npos) << e;
  inhap::write_file_atomic(csv, "0,0,0\n0,1,0\n0,2,0\n");
  EXPECT_EQ(inhap::heightmap_mesh(o).mesh.num_vertices(), 9u);
}
