// NRRD reading, marching-tetrahedra isosurfaces, surface distances and the CT-head stiffness map
// against analytic volumes (spheres) and the real headsq CT.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/volume.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;

namespace {

// Writes a NRRD header plus one little-endian int16 slice file per z (name.%d 1 nz 1).
std::string write_volume(const test::TempDir& dir, int nx, int ny, int nz, const Vec3& spacing,
                         const std::function<double(const Vec3&)>& f) {
  for (int k = 0; k < nz; ++k) {
    std::string bytes;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double v = std::round(f(Vec3(i * spacing.x(), j * spacing.y(), k * spacing.z())));
        const auto u =
            static_cast<std::uint16_t>(static_cast<std::int16_t>(std::clamp(v, -32768.0, 32767.0)));
        bytes += static_cast<char>(u & 0xff);
        bytes += static_cast<char>(u >> 8);
      }
    std::ofstream(dir.path("vol." + std::to_string(k + 1)), std::ios::binary) << bytes;
  }
  const std::string header = dir.path("vol.nhdr");
  std::ofstream(header) << "NRRD0004\n# synthetic test volume\ndimension: 3\nsizes: " << nx << " "
                        << ny << " " << nz << "\nspacings: " << spacing.x() << " " << spacing.y()
                        << " " << spacing.z()
                        << "\nendian: little\ntype: short\nencoding: raw\ndata file: vol.%d 1 "
                        << nz << " 1\n";
  return header;
}

double signed_volume(const TriMesh& m) {
  double v = 0;
  for (const Tri& t : m.triangles)
    v += m.positions[t[0]].dot(m.positions[t[1]].cross(m.positions[t[2]])) / 6.0;
  return v;
}

}  // namespace

TEST(Volume, ReadsNrrdSliceSeriesWithSpacing) {
  test::TempDir dir;
  const auto path = write_volume(dir, 5, 4, 3, Vec3(0.5, 2.0, 1.5), [](const Vec3& p) {
    return 10 * p.x() + 100 * p.y() + 1000 * p.z();
  });
  Volume v = read_nrrd(path);
  ASSERT_EQ(v.nx, 5);
  ASSERT_EQ(v.ny, 4);
  ASSERT_EQ(v.nz, 3);
  EXPECT_EQ(v.spacing, Vec3(0.5, 2.0, 1.5));
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i)
        EXPECT_EQ(v.at(i, j, k), float(std::round(5 * i + 200 * j + 1500 * k)));
  EXPECT_EQ(v.position(4, 3, 2), Vec3(2.0, 6.0, 3.0));
}

TEST(Volume, ReadsAttachedBigEndianData) {
  test::TempDir dir;
  const auto path = dir.path("a.nrrd");
  std::string data;
  for (int s = 0; s < 8; ++s) {
    data += static_cast<char>(0xff);  // big-endian int16: 0xff00 | s = -256 + s
    data += static_cast<char>(s);
  }
  std::ofstream(path, std::ios::binary)
      << "NRRD0004\ntype: int16\ndimension: 3\nsizes: 2 2 2\n"
      << "space directions: (2,0,0) (0,3,0) (0,0,4)\nendian: big\nencoding: raw\n\n"
      << data;
  Volume v = read_nrrd(path);
  EXPECT_EQ(v.spacing, Vec3(2, 3, 4));
  EXPECT_EQ(v.at(0, 0, 0), -256.0f);
  EXPECT_EQ(v.at(1, 1, 1), -249.0f);
}

TEST(Volume, BadHeadersNameFileAndLine) {
  test::TempDir dir;
  const auto bad_type = dir.path("t.nhdr");
  std::ofstream(bad_type)
      << "NRRD0004\ndimension: 3\ntype: complex\nsizes: 1 1 1\nendian: little\ndata file: x.raw\n";
  try {
    read_nrrd(bad_type);
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 3u) << e.what();
    EXPECT_NE(std::string(e.what()).find("t.nhdr"), std::string::npos);
  }
  const auto missing_slice = dir.path("m.nhdr");
  std::ofstream(missing_slice) << "NRRD0004\ndimension: 3\ntype: short\nsizes: 2 2 2\nendian: "
                                  "little\ndata file: none.%d 1 2 1\n";
  try {
    read_nrrd(missing_slice);
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 6u) << e.what();
    EXPECT_NE(std::string(e.what()).find("none.1"), std::string::npos) << e.what();
  }
  const auto short_data = dir.path("s.raw");
  std::ofstream(short_data, std::ios::binary) << "abc";
  const auto truncated = dir.path("s.nhdr");
  std::ofstream(truncated)
      << "NRRD0004\ndimension: 3\ntype: short\nsizes: 2 2 2\nendian: little\ndata file: s.raw\n";
  EXPECT_THROW(read_nrrd(truncated), ParseError);
  const auto not_nrrd = dir.path("n.nhdr");
  std::ofstream(not_nrrd) << "P5\n";
  EXPECT_THROW(read_nrrd(not_nrrd), ParseError);
  EXPECT_THROW(read_nrrd(dir.path("absent.nhdr")), IoError);
}

TEST(Volume, SphereIsosurfaceIsWithinVoxelToleranceWatertightAndOutward) {
  test::TempDir dir;
  const Vec3 c(20.3, 19.6, 21.1), spacing(1.0, 1.2, 1.5);
  const double R = 12.0;
  const auto path = write_volume(dir, 41, 34, 29, spacing,
                                 [&](const Vec3& p) { return 500 + 100 * (R - (p - c).norm()); });
  TriMesh m = extract_isosurface(read_nrrd(path), 500);
  ASSERT_GT(m.num_triangles(), 1000u);
  double worst = 0;
  for (const auto& p : m.positions) worst = std::max(worst, std::abs((p - c).norm() - R));
  EXPECT_LT(worst, 0.25) << "mm from the true sphere";
  const MeshTopology topo = analyze_topology(m, build_adjacency(m));
  EXPECT_TRUE(topo.watertight());
  EXPECT_TRUE(topo.oriented());
  EXPECT_EQ(topo.components, 1u);
  EXPECT_NEAR(signed_volume(m), 4.0 / 3.0 * M_PI * R * R * R,
              0.02 * 4.0 / 3.0 * M_PI * R * R * R);  // > 0: outward
  // Face normals point away from the centre (slivers may tilt, so area-weighted).
  double radial = 0, area = 0;
  std::size_t inward = 0;
  for (std::size_t f = 0; f < m.num_triangles(); ++f) {
    const Tri& t = m.triangles[f];
    const Vec3 centroid = (m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) / 3;
    const double dot = m.face_normal(f).dot((centroid - c).normalized());
    ASSERT_GT(m.face_area(f), 0) << "face " << f;
    radial += m.face_area(f) * dot;
    area += m.face_area(f);
    inward += dot < 0;
  }
  EXPECT_GT(radial / area, 0.97);
  EXPECT_LT(inward, m.num_triangles() / 200);
  for (std::size_t v = 0; v < m.num_vertices(); ++v)
    EXPECT_GT(m.normals[v].dot((m.positions[v] - c).normalized()), 0.95);
}

TEST(Volume, SurfaceClosesAtTheVolumeBorder) {
  Volume v;
  v.nx = v.ny = v.nz = 4;
  v.values.assign(64, 1000.0f);  // all inside: the surface is the padded box
  TriMesh m = extract_isosurface(v, 500);
  const MeshTopology topo = analyze_topology(m, build_adjacency(m));
  EXPECT_TRUE(topo.watertight());
  EXPECT_EQ(topo.components, 1u);
  EXPECT_GT(signed_volume(m), 0);
  // Without closing, no surface at all.
  EXPECT_EQ(extract_isosurface(v, 500, IsosurfaceOptions{.close_at_border = false}).num_triangles(),
            0u);
}

TEST(Volume, LargestComponentAndDistanceBetweenSpheres) {
  test::TempDir dir;
  // Skin: sphere R = 15 around c (CT numbers 500 at the surface, capped below the bone level);
  // bone: sphere r = 7 around c + (3, 0, 0) (1150 at its surface); plus a small separate blob.
  const Vec3 c(20, 20, 20), cb(23, 20, 20), blob(4, 4, 4);
  const auto path = write_volume(dir, 41, 41, 41, Vec3::Ones(), [&](const Vec3& p) {
    const double skin = std::min(500 + 40 * (15 - (p - c).norm()), 1100.0);
    const double bone = 1150 + 300 * (7 - (p - cb).norm());
    const double b = 500 + 100 * (1.5 - (p - blob).norm());
    return std::max({skin, bone, b});
  });
  const Volume vol = read_nrrd(path);
  TriMesh all = extract_isosurface(vol, 500);
  TriMesh skin = keep_largest_component(all);
  EXPECT_EQ(analyze_topology(all, build_adjacency(all)).components, 2u);
  EXPECT_EQ(analyze_topology(skin, build_adjacency(skin)).components, 1u);
  EXPECT_LT(skin.num_triangles(), all.num_triangles());
  for (const auto& p : skin.positions) ASSERT_NEAR((p - c).norm(), 15, 0.3);
  const TriMesh bone = extract_isosurface(vol, 1150);
  const std::vector<double> d = distance_to_surface(skin, bone);
  double worst = 0;
  for (std::size_t v = 0; v < d.size(); ++v)
    worst = std::max(worst, std::abs(d[v] - ((skin.positions[v] - cb).norm() - 7)));
  EXPECT_LT(worst, 0.3) << "mm against the analytic distance between the spheres";

  HeadModel h = head_from_volume(vol, HeadModelOptions{});
  EXPECT_EQ(h.skin_components, 2u);
  const auto& k = h.mesh.property("stiffness");
  const auto& dist = h.mesh.property("bone_distance");
  for (std::size_t v = 0; v < k.size(); ++v) {
    EXPECT_GE(k[v], 0.4 - 1e-12);
    EXPECT_LE(k[v], 1.0 + 1e-12);
    // Thinner tissue -> stiffer: k * d is constant where not clamped.
    if (k[v] > 0.4 + 1e-9 && k[v] < 1.0 - 1e-9) {
      EXPECT_NEAR(k[v] * dist[v], 0.4 * h.distance_far_mm, 1e-9);
    }
  }
}

TEST(Volume, StiffnessIsInverseToDistanceWithinRange) {
  // d_far = 10 (quantile 1): d_ref = 0.4 * 10 = 4 -> k = 1 up to 4 mm, then 4 / d, 0.4 at 10 mm.
  const auto k = stiffness_from_distance({0.0, 2.0, 4.0, 5.0, 8.0, 10.0}, 0.4, 1.0, 1.0);
  const std::vector<double> want{1.0, 1.0, 1.0, 0.8, 0.5, 0.4};
  // Quantile 0.5 of {1, 3, 10, 30, 100}: d_far = 10, so 30 and 100 mm get k_min.
  const auto kq = stiffness_from_distance({1.0, 3.0, 10.0, 30.0, 100.0}, 0.4, 1.0, 0.5);
  EXPECT_NEAR(kq[2], 0.4, 1e-12);
  EXPECT_NEAR(kq[4], 0.4, 1e-12);
  EXPECT_NEAR(kq[1], 1.0, 1e-12);
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(k[i], want[i], 1e-12) << i;
  EXPECT_THROW(stiffness_from_distance({1.0}, 0.0, 1.0), Error);
}

TEST(Volume, CtHeadGivesOneBigSkinComponentWithStiffnessInRange) {
  const std::string path = test::shared_data("headsq/quarter.nhdr");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " absent";
  const Volume vol = read_nrrd(path);
  EXPECT_EQ(vol.nx, 64);
  EXPECT_EQ(vol.ny, 64);
  EXPECT_EQ(vol.nz, 93);
  EXPECT_EQ(vol.spacing, Vec3(3.2, 3.2, 1.5));
  const HeadModel h = head_from_volume(vol);
  const TriMesh& m = h.mesh;
  const MeshTopology topo = analyze_topology(m, build_adjacency(m));
  std::printf(
      "CT head skin: %zu triangles, %zu vertices (raw isosurface: %zu components), bone %zu "
      "triangles, d_far %.1f mm\n",
      m.num_triangles(), m.num_vertices(), h.skin_components, h.bone_triangles, h.distance_far_mm);
  EXPECT_GT(m.num_triangles(), 20000u);
  EXPECT_TRUE(topo.watertight());
  EXPECT_TRUE(topo.oriented());
  EXPECT_GT(signed_volume(m), 0);  // outward
  // A head: roughly 200 x 200 x 140 mm.
  const Vec3 size = m.bbox().size();
  EXPECT_GT(size.minCoeff(), 100.0);
  const auto& k = m.property("stiffness");
  const auto [lo, hi] = std::minmax_element(k.begin(), k.end());
  EXPECT_NEAR(*lo, 0.4, 1e-12);
  EXPECT_NEAR(*hi, 1.0, 1e-12);
}

TEST(Volume, CommandWritesAScaledHeadMesh) {
  test::TempDir dir;
  const Vec3 c(20, 20, 20), cb(23, 20, 20);
  const auto header = write_volume(dir, 41, 41, 41, Vec3(1.0, 1.0, 1.0), [&](const Vec3& p) {
    return std::max(std::min(500 + 40 * (15 - (p - c).norm()), 1100.0),
                    1150 + 300 * (7 - (p - cb).norm()));
  });
  const std::string out = dir.path("head.ply");
  const std::string cmd = std::string(INHAP_CLI) + " mesh from-volume " + header +
                          " --iso 500 --bone-iso 1150 --k-range 0.4 1.0 --fit-mm 100 --out " + out +
                          " > " + dir.path("log.txt");
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const TriMesh m = read_mesh(out);
  EXPECT_NEAR(m.bbox().size().maxCoeff(), 100.0, 1e-6);
  EXPECT_NEAR(m.bbox().min.minCoeff(), 0.0, 1e-6);
  const auto& k = m.property("stiffness");
  EXPECT_NEAR(*std::min_element(k.begin(), k.end()), 0.4, 1e-6);
  // Skin-to-bone distances run from 5 to 11 mm: the nearest skin is 0.4 * d_far / 5 ~ 0.87 N/mm.
  EXPECT_GT(*std::max_element(k.begin(), k.end()), 0.8);
  EXPECT_LE(*std::max_element(k.begin(), k.end()), 1.0);
  EXPECT_TRUE(m.has_property("bone_distance"));
  EXPECT_GT(signed_volume(m), 0);
  // Bad flags: one line naming what was expected, status 1.
  const std::string bad = std::string(INHAP_CLI) + " mesh from-volume " + header +
                          " --k-range 1.0 0.4 --out " + out + " 2> " + dir.path("err.txt");
  EXPECT_NE(std::system(bad.c_str()), 0);
}
