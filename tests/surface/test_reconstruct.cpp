#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/surface/alpha_shape.hpp"
#include "inhap/surface/mesh_ops.hpp"
#include "inhap/surface/points.hpp"
#include "inhap/surface/reconstruct.hpp"
#include "surface/sphere_points.hpp"

using namespace inhap;

namespace {
MeshTopology topology(const TriMesh& m) {
  return analyze_topology(m, build_adjacency(m));
}
double sphere_volume(double r) {
  return 4.0 / 3.0 * std::numbers::pi * r * r * r;
}
}  // namespace

TEST(Reconstruct, ExactlyCosphericalPointsGiveTheSphereWithinTwoTenthsOfAMillimetre) {
  // Every Delaunay tetrahedron of cospherical points has the sphere as circumsphere: the bare
  // one-component alpha leaves slivers out (holes, pinches); the closed-manifold scan fixes it.
  const double r = 40.0;
  const auto pts = test::fibonacci_sphere(2000, r, Vec3(5, -3, 12));
  ReconstructReport rep;
  const TriMesh m = reconstruct_surface(pts, {}, &rep);
  const MeshTopology topo = topology(m);
  EXPECT_TRUE(topo.watertight());
  EXPECT_TRUE(topo.oriented());
  EXPECT_EQ(topo.components, 1u);
  EXPECT_EQ(rep.outliers, 0u);
  EXPECT_EQ(rep.points_used, 2000u);
  EXPECT_LT(test::max_radial_error(m, r, Vec3(5, -3, 12)), 0.2);
  TriMesh centred = m;
  centred.transform(1.0, Vec3(5, -3, 12));
  EXPECT_NEAR(test::signed_volume(centred) / sphere_volume(r), 1.0, 0.01);  // outward, closed
  EXPECT_EQ(rep.faces, 3 * (2 * 2000 - 4));  // one sqrt(3) step of the 2000-vertex hull
}

TEST(Reconstruct, SolidModeOnCosphericalPointsToo) {
  const double r = 40.0;
  const auto pts = test::fibonacci_sphere(2000, r);
  ReconstructOptions o;
  o.mode = SurfaceMode::kSolid;
  ReconstructReport rep;
  const TriMesh m = reconstruct_surface(pts, o, &rep);
  EXPECT_TRUE(topology(m).watertight());
  EXPECT_LT(test::max_radial_error(m, r), 0.2);
  EXPECT_NEAR(rep.alpha, 1.02 * r, 0.01);  // first scan step above the degenerate alpha = R
}

TEST(Reconstruct, ShellModeKeepsAPartialSamplingOpenWithoutABase) {
  // The top of a ball (polar angle < 50 deg), as tapped from above: one open patch, every
  // vertex on the sphere; the solid mode closes it with a flat base far from the sphere.
  const double r = 35.0;
  std::vector<Vec3> cap, dirs;
  for (const Vec3& p : test::fibonacci_sphere(4000, r))
    if (p.z() > r * std::cos(50 * M_PI / 180)) cap.push_back(p), dirs.push_back(p.normalized());
  ReconstructReport rep;
  const TriMesh shell = reconstruct_surface(cap, dirs, {}, &rep);
  const MeshTopology topo = topology(shell);
  EXPECT_TRUE(topo.manifold());
  EXPECT_TRUE(topo.oriented());
  EXPECT_EQ(topo.boundary_loops, 1u);
  EXPECT_EQ(topo.components, 1u);
  EXPECT_LT(test::max_radial_error(shell, r), 0.2);
  for (std::size_t f = 0; f < shell.num_triangles(); f += 31)
    EXPECT_GT(shell.face_normal(f).dot(shell.positions[shell.triangles[f][0]].normalized()), 0.5);
  // Without directions the normals are oriented by the alpha solid: same surface.
  const TriMesh undirected = reconstruct_surface(cap);
  EXPECT_EQ(topology(undirected).boundary_loops, 1u);
  EXPECT_LT(test::max_radial_error(undirected, r), 0.2);
  ReconstructOptions solid;
  solid.mode = SurfaceMode::kSolid;
  EXPECT_GT(test::max_radial_error(reconstruct_surface(cap, solid), r), 5.0);
}

TEST(Reconstruct, ShellModeKeepsGroovesThatTheSolidFills) {
  // A plate z = 0 with a V-groove 4 mm deep and 12 mm wide along y, sampled every ~1.2 mm.
  auto height = [](double x) { return std::abs(x) < 6 ? -4.0 * (1 - std::abs(x) / 6) : 0.0; };
  std::vector<Vec3> pts, dirs;
  Rng rng(4);
  for (int i = 0; i < 1600; ++i) {
    const double x = rng.uniform(-25, 25), y = rng.uniform(-25, 25);
    pts.emplace_back(x, y, height(x));
    dirs.emplace_back(0, 0, 1);
  }
  auto worst = [&](const TriMesh& m) {
    double e = 0;
    for (const Vec3& p : m.positions)
      if (std::abs(p.x()) < 20 && std::abs(p.y()) < 20)
        e = std::max(e, std::abs(p.z() - height(p.x())));
    return e;
  };
  const TriMesh shell = reconstruct_surface(pts, dirs, {});
  EXPECT_EQ(topology(shell).boundary_loops, 1u);
  EXPECT_LT(worst(shell), 1.5);  // the sharp creases get rounded by about a millimetre
  double deepest = 0;
  for (const Vec3& p : shell.positions) deepest = std::min(deepest, p.z());
  EXPECT_LT(deepest, -3.0);  // the groove is there
  ReconstructOptions solid;
  solid.mode = SurfaceMode::kSolid;
  EXPECT_GT(worst(reconstruct_surface(pts, solid)), 2.0);
}

TEST(Reconstruct, BareAlphaShapeOfCosphericalPointsIsTheHull) {
  const auto pts = test::fibonacci_sphere(500, 10.0);
  const AlphaShapeResult as = alpha_shape(pts, {});
  EXPECT_TRUE(as.closed_manifold);
  EXPECT_EQ(as.mesh.num_triangles(), 2 * 500 - 4u);  // Euler: closed genus 0, all points used
  EXPECT_EQ(as.points_on_surface, 500u);
  EXPECT_GE(as.alpha, as.alpha_one_component);
  EXPECT_NEAR(as.alpha_one_component, 10.0, 1e-6);
  AlphaShapeOptions bare;
  bare.require_closed_manifold = false;
  EXPECT_NEAR(alpha_shape(pts, bare).alpha, 10.0, 1e-6);
}

TEST(Reconstruct, NoisySphereIsRecoveredAndNormalsPointOut) {
  const double r = 30.0;
  const auto pts = test::random_sphere(3000, r, 0.05, 9);
  const TriMesh m = reconstruct_surface(pts);
  EXPECT_TRUE(topology(m).watertight());
  double mean = 0;
  for (const Vec3& p : m.positions) mean += std::abs(p.norm() - r);
  mean /= static_cast<double>(m.num_vertices());
  EXPECT_LT(mean, 0.05);
  EXPECT_NEAR(test::signed_volume(m) / sphere_volume(r), 1.0, 0.01);
  for (std::size_t f = 0; f < m.num_triangles(); f += 97)
    EXPECT_GT(m.face_normal(f).dot(m.positions[m.triangles[f][0]].normalized()), 0.5);
}

TEST(Reconstruct, FixedAlphaSmallerThanTheGapSeparatesTwoBalls) {
  auto a = test::fibonacci_sphere(400, 5.0, Vec3(0, 0, 0));
  const auto b = test::fibonacci_sphere(400, 5.0, Vec3(30, 0, 0));
  a.insert(a.end(), b.begin(), b.end());
  AlphaShapeOptions o;
  o.alpha = 6.0;  // > sphere radius, < the gap of 20 mm
  const AlphaShapeResult two = alpha_shape(a, o);
  EXPECT_EQ(two.solid_components, 2u);
  EXPECT_EQ(topology(two.mesh).components, 2u);
  // Automatic alpha: one component needs a circumsphere bridging the 20 mm gap.
  const AlphaShapeResult one = alpha_shape(a, {});
  EXPECT_EQ(one.solid_components, 1u);
  EXPECT_GT(one.alpha, 10.0);
}

TEST(Reconstruct, TooFewPointsIsAnError) {
  std::vector<Vec3> pts{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_THROW(reconstruct_surface(pts), Error);
  std::vector<Vec3> flat;
  for (int i = 0; i < 50; ++i) flat.emplace_back(i % 7, i / 7, 0.0);
  EXPECT_THROW(reconstruct_surface(flat), Error);
}

TEST(Points, OutliersFarFromTheSurfaceAreRemovedAndOnlyThem) {
  auto pts = test::fibonacci_sphere(1500, 20.0);
  Rng rng(2);
  for (int i = 0; i < 12; ++i)
    pts.push_back(Vec3(rng.normal(), rng.normal(), rng.normal()).normalized() *
                  rng.uniform(26, 40));
  const auto kept = remove_knn_outliers(pts, 8, 4.0);
  ASSERT_EQ(kept.size(), 1500u);
  for (std::size_t i = 0; i < kept.size(); ++i) EXPECT_EQ(kept[i], i);
}

TEST(Points, KnnDistancesOfAGridAreTheSpacing) {
  std::vector<Vec3> pts;
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 10; ++y)
      for (int z = 0; z < 10; ++z) pts.emplace_back(2.0 * x, 2.0 * y, 2.0 * z);
  const auto d = knn_mean_distances(pts, 6);
  EXPECT_NEAR(d[5 * 100 + 5 * 10 + 5], 2.0, 1e-12);  // interior point: six neighbours at 2 mm
  const KnnTable t = knn_table(pts, 3);
  ASSERT_EQ(t.k, 3u);
  EXPECT_DOUBLE_EQ(t.distance[0], 2.0);  // corner (0,0,0): three neighbours at 2 mm
  EXPECT_DOUBLE_EQ(t.distance[2], 2.0);
}

TEST(Points, JetSmoothingPullsNoisyPointsOntoTheSphere) {
  const double r = 25.0;
  const auto noisy = test::random_sphere(4000, r, 0.2, 4);
  const auto smooth = jet_smooth(noisy, 24);
  auto rms = [&](const std::vector<Vec3>& p) {
    double s = 0;
    for (const Vec3& q : p) s += (q.norm() - r) * (q.norm() - r);
    return std::sqrt(s / static_cast<double>(p.size()));
  };
  EXPECT_NEAR(rms(noisy), 0.2, 0.02);
  EXPECT_LT(rms(smooth), 0.5 * rms(noisy));
  // Exact points stay (a sphere is locally a quadric up to 4th-order terms).
  const auto exact = test::fibonacci_sphere(2000, r);
  EXPECT_LT(rms(jet_smooth(exact, 18)), 1e-3);
}

TEST(MeshOps, TaubinRemovesNoiseWithoutShrinking) {
  const double r = 20.0;
  TriMesh m = test::icosphere(4, r);
  Rng rng(8);
  for (Vec3& p : m.positions) p *= 1.0 + 0.01 * rng.normal();  // 0.2 mm radial noise
  auto stats = [&](const TriMesh& mm, double& mean, double& rms) {
    mean = 0, rms = 0;
    for (const Vec3& p : mm.positions) mean += p.norm();
    mean /= static_cast<double>(mm.num_vertices());
    for (const Vec3& p : mm.positions) rms += (p.norm() - mean) * (p.norm() - mean);
    rms = std::sqrt(rms / static_cast<double>(mm.num_vertices()));
  };
  double mean0, rms0, mean1, rms1;
  stats(m, mean0, rms0);
  TriMesh laplace = m;
  taubin_smooth(m, 10);
  stats(m, mean1, rms1);
  EXPECT_LT(rms1, 0.5 * rms0);
  EXPECT_NEAR(mean1, r, 0.01 * r);
  // Plain Laplacian smoothing (mu = 0 means two lambda steps) shrinks visibly more.
  taubin_smooth(laplace, 10, 0.5, 0.5);
  double mean2, rms2;
  stats(laplace, mean2, rms2);
  EXPECT_LT(mean2, mean1 - 0.1);
}

TEST(MeshOps, TaubinKeepsTheRimOfACorrugatedPatch) {
  // Open grid patch z = 3 mm triangle wave in x (period 8 mm, crests at x = 4, 12, ...), 1 mm
  // cells: the rims y = 0 and y = 12 cross the crests. Smoothing a rim along itself would flatten
  // its zigzag (two neighbours per vertex); the rim must stay exactly where it is, while the
  // interior crests are rounded.
  auto wave = [](int x) { return 3.0 * (1.0 - std::abs((x % 8) - 4) / 4.0); };
  TriMesh m;
  const int nx = 24, ny = 12;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.positions.emplace_back(i, j, wave(i));
  auto v = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      m.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      m.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  const TriMesh before = m;
  taubin_smooth(m, 10);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const auto k = static_cast<std::size_t>(v(i, j));
      if (i == 0 || j == 0 || i == nx || j == ny) {
        EXPECT_EQ(m.positions[k], before.positions[k]) << i << "," << j;
      }
    }
  EXPECT_LT(m.positions[static_cast<std::size_t>(v(12, 6))].z(), 3.0 - 0.1);  // rounded crest
}

TEST(MeshOps, Sqrt3TriplesTheFacesOfAClosedMesh) {
  const TriMesh m = test::icosphere(1, 10.0);
  const TriMesh s = sqrt3_subdivide(m, 2);
  EXPECT_EQ(s.num_triangles(), 9 * m.num_triangles());
  EXPECT_EQ(s.num_vertices(), m.num_vertices() + m.num_triangles() + 3 * m.num_triangles());
  EXPECT_TRUE(topology(s).watertight());
  EXPECT_GT(test::signed_volume(s), 0.0);
  // Approximating scheme: vertices move inside the convex input, never outside.
  for (const Vec3& p : s.positions) EXPECT_LE(p.norm(), 10.0 + 1e-9);
}

TEST(MeshOps, MakeManifoldSplitsAPinchedVertexAndOrientsOutward) {
  // Two closed tetrahedra sharing one vertex (non-manifold vertex 0); the second one inside out.
  TriMesh soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  soup.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3},
                    {0, 4, 5}, {0, 6, 4}, {0, 5, 6}, {4, 6, 5}};
  ManifoldReport rep;
  const TriMesh both = make_manifold(soup, false, &rep);
  EXPECT_EQ(rep.duplicated_vertices, 1u);
  EXPECT_EQ(rep.components, 2u);
  const MeshTopology topo = topology(both);
  EXPECT_TRUE(topo.manifold());
  EXPECT_TRUE(topo.oriented());
  EXPECT_EQ(both.num_vertices(), 8u);
  const TriMesh one = make_manifold(soup, true, &rep);
  EXPECT_EQ(one.num_triangles(), 4u);
  EXPECT_GT(test::signed_volume(one), 0.0);
}
