// Loaders of the real data sets (thesis sec. 5.3) against what the thesis states and the files
// hold, and the CGAL simplification that brings the CT head to its triangle count.
// Units: mm, N/mm.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/volume.hpp"
#include "inhap/rendering/real_data.hpp"

namespace inhap::rendering {
namespace {

namespace fs = std::filesystem;

// The project's data/: found above the test executable (the build folder is in the source tree).
fs::path data_dir() {
  fs::path d = fs::canonical("/proc/self/exe").parent_path();
  for (; !d.empty() && d != d.parent_path(); d = d.parent_path())
    if (fs::exists(d / "data" / "afm-topography" / "sample_0.top")) return d / "data";
  ADD_FAILURE() << "no data/ folder above the test executable";
  return {};
}

void expect_in_cube(const TriMesh& m, double cube) {
  const Box3 b = m.bbox();
  EXPECT_NEAR((b.max - b.min).maxCoeff(), cube, 1e-6);
  EXPECT_GE(b.min.minCoeff(), -1e-9);
}

TEST(RealData, AfmIs256x256CellsWithAHaloMap) {
  const RealDataOptions o;
  const RealDataset d = load_afm((data_dir() / "afm-topography" / "sample_0.top").string(), o);
  EXPECT_EQ(d.mesh.num_triangles(), std::size_t(2 * o.afm_cells * o.afm_cells));
  const Box3 b = d.mesh.bbox();
  EXPECT_NEAR(b.max.x() - b.min.x(), o.cube_mm, 1e-9);
  EXPECT_NEAR(b.max.y() - b.min.y(), o.cube_mm, 1e-9);
  const auto& k = d.mesh.property("stiffness");
  EXPECT_DOUBLE_EQ(*std::max_element(k.begin(), k.end()), o.k_max);        // the mica
  EXPECT_NEAR(*std::min_element(k.begin(), k.end()), o.afm_k_halo, 0.02);  // the halo's rim
  // Every stroke crosses a halo: marks A and B, softer than the mica between them.
  ASSERT_FALSE(d.strokes.empty());
  for (const auto& s : d.strokes) {
    ASSERT_EQ(s.marks.size(), 2u);
    EXPECT_LT(s.marks[0].along_mm, s.marks[1].along_mm);
  }
}

TEST(RealData, BunnyStiffnessIsTheScaledConfidence) {
  const RealDataOptions o;
  const fs::path ply = data_dir() / "bunny" / "bun_zipper.ply";
  const RealDataset d = load_bunny(ply.string(), o);
  const TriMesh raw = read_mesh(ply.string());
  ASSERT_EQ(d.mesh.num_vertices(), raw.num_vertices());
  EXPECT_EQ(d.mesh.num_triangles(), 69451u);  // thesis: 69,451 triangles
  expect_in_cube(d.mesh, o.cube_mm);
  const auto& c = raw.property("confidence");
  const auto& k = d.mesh.property("stiffness");
  const double cmax = *std::max_element(c.begin(), c.end());
  for (std::size_t i = 0; i < c.size(); i += 97)
    EXPECT_NEAR(k[i], std::max(o.k_floor, o.k_max * c[i] / cmax), 1e-12) << i;
  EXPECT_DOUBLE_EQ(*std::max_element(k.begin(), k.end()), o.k_max);
  ASSERT_EQ(d.strokes.size(), 1u);
  EXPECT_EQ(d.strokes[0].marks.at(0).label, "C");
}

TEST(RealData, HeadIsSimplifiedToTheThesisCount) {
  const RealDataOptions o;
  const RealDataset d = load_head((data_dir() / "headsq" / "quarter.nhdr").string(), o);
  // A closed mesh: edges = 3 F / 2, so the edge-count stop lands on the face count.
  EXPECT_LE(d.mesh.num_triangles(), o.head_triangles);
  EXPECT_GE(d.mesh.num_triangles(), o.head_triangles - 4);
  expect_in_cube(d.mesh, o.cube_mm);
  const auto& k = d.mesh.property("stiffness");
  EXPECT_GE(*std::min_element(k.begin(), k.end()), o.head_k_min - 1e-12);
  EXPECT_LE(*std::max_element(k.begin(), k.end()), o.k_max + 1e-12);
  EXPECT_GT(*std::max_element(k.begin(), k.end()), 0.9);
  ASSERT_EQ(d.strokes.size(), 1u);
  EXPECT_EQ(d.strokes[0].marks.at(0).label, "D");
}

TEST(Simplify, ReachesTheTargetAndCarriesPropertiesOver) {
  // A ball of radius 20 mm from a synthetic volume; property = z (linear, so the interpolated
  // value at the closest input point differs from the output vertex's z by at most how far the
  // vertex moved off the input surface).
  Volume v;
  v.nx = v.ny = v.nz = 48;
  v.values.resize(std::size_t(48) * 48 * 48);
  for (int kz = 0; kz < 48; ++kz)
    for (int j = 0; j < 48; ++j)
      for (int i = 0; i < 48; ++i)
        v.values[v.index(i, j, kz)] =
            float(20.0 - (v.position(i, j, kz) - Vec3(24, 24, 24)).norm());
  TriMesh ball = extract_isosurface(v, 0.0);
  std::vector<double> z;
  for (const auto& p : ball.positions) z.push_back(p.z());
  ball.set_property("z", z);
  ASSERT_GT(ball.num_triangles(), 8000u);
  const TriMesh s = simplify_mesh(ball, 2000);
  // The stop counts edges (3 F / 2 on a closed mesh); the last collapse may remove 2 faces more.
  EXPECT_LE(s.num_triangles(), 2000u);
  EXPECT_GE(s.num_triangles(), 1996u);
  const auto& zs = s.property("z");
  for (std::size_t i = 0; i < s.num_vertices(); ++i) {
    EXPECT_NEAR(zs[i], s.positions[i].z(), 0.5) << i;
    EXPECT_NEAR((s.positions[i] - Vec3(24, 24, 24)).norm(), 20.0, 0.5) << i;
  }
  EXPECT_THROW(simplify_mesh(ball, 2), Error);
}

}  // namespace
}  // namespace inhap::rendering
