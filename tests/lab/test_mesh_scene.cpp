// Mesh geometry in the virtual lab: a finely tessellated sphere must behave like the analytic
// sphere (up to its tessellation error), through scene files, physics and operators.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/lab/control.hpp"
#include "inhap/lab/operators.hpp"
#include "support/meshes.hpp"
#include "support/temp_dir.hpp"

namespace inhap::lab {
namespace {

constexpr double kRadius = 30.0;
const Vec3 kCentre(0, 0, 30);

/// Icosphere (5120 triangles, edges ~2 mm): the flat faces lie inside the sphere by at most
/// their circumradius^2 / (2 R) ~ (1.2 mm)^2 / 60 mm; 0.05 mm bounds the distance error.
Shape ball() {
  TriMesh m = test::make_sphere(kRadius, 4);
  for (auto& v : m.positions) v += kCentre;
  return make_mesh_shape(std::move(m));
}

TEST(MeshScene, DistanceSignAndNormalMatchTheAnalyticSphere) {
  const Shape mesh = ball();
  const Shape exact = SphereShape{kCentre, kRadius};
  EXPECT_EQ(mesh.type_name(), "mesh");
  Rng rng(2);
  for (int i = 0; i < 3000; ++i) {
    const Vec3 dir = Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
    const double r = rng.uniform(5.0, 60.0);
    const Vec3 p = kCentre + r * dir;
    const SurfaceQuery q = mesh.query(p);
    EXPECT_NEAR(q.distance, exact.distance(p), 0.05) << "r " << r;
    if (std::abs(r - kRadius) > 1.0) {
      EXPECT_EQ(q.distance > 0, r > kRadius) << "r " << r;
      EXPECT_GT(q.normal.dot(dir), std::cos(4.0 * M_PI / 180)) << "r " << r;
    }
  }
  const auto top = mesh.drop(0, 0, 8.0);
  ASSERT_TRUE(top.has_value());
  EXPECT_NEAR(top->z(), kCentre.z() + kRadius + 8.0, 0.05);
}

TEST(MeshScene, SceneFilePlacesTheMeshAndRoundTrips) {
  test::TempDir dir;
  write_mesh(dir.path("ball.ply"), test::make_sphere(1.0, 3));  // unit sphere, file units
  std::ofstream(dir.path("s.json")) << R"({
    "name": "ball",
    "geometry": {"type": "mesh", "path": "ball.ply", "scale": 25, "offset": [5, 0, 25]},
    "material": {"k": 0.35, "k_t": 0.5, "mu": 1.2}
  })";
  const Scene s = load_scene(dir.path("s.json"));
  // Coarser sphere (edges ~3.3 mm after scaling): distance error below 0.2 mm.
  EXPECT_NEAR(s.object.query(Vec3(5, 0, 80)).distance, 30.0, 0.2);  // top at z = 50
  EXPECT_NEAR(s.object.query(Vec3(5, 0, 25)).distance, -25.0, 0.2);
  // Round trip: the written scene names the same file and placement.
  const std::string j = scene_to_json(s);
  std::ofstream(dir.path("t.json")) << j;
  EXPECT_EQ(scene_to_json(load_scene(dir.path("t.json"))), j);
  // A y-up file is turned so that its +y points up: a sphere centred at (0, 2, 0) in the file
  // ends up centred at (0, 0, 50).
  TriMesh shifted = test::make_sphere(1.0, 3);
  for (auto& v : shifted.positions) v.y() += 2.0;
  write_mesh(dir.path("ball_y.ply"), shifted);
  std::ofstream(dir.path("y.json")) << R"({
    "geometry": {"type": "mesh", "path": "ball_y.ply", "scale": 25, "offset": [0, 0, 0], "up": "y"},
    "material": {"k": 0.35, "k_t": 0.5, "mu": 1.2}})";
  EXPECT_NEAR(load_scene(dir.path("y.json")).object.query(Vec3(0, 0, 90)).distance, 15.0, 0.2);
  // Errors name the scene file and the field.
  std::ofstream(dir.path("bad.json")) << R"({
    "geometry": {"type": "mesh", "path": "missing.ply"},
    "material": {"k": 0.35, "k_t": 0.5, "mu": 1.2}})";
  try {
    load_scene(dir.path("bad.json"));
    FAIL() << "no error";
  } catch (const ParseError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad.json"), std::string::npos) << msg;
    EXPECT_NE(msg.find("geometry.path"), std::string::npos) << msg;
    EXPECT_NE(msg.find("missing.ply"), std::string::npos) << msg;
  }
}

TEST(MeshScene, IndentationAndTapsOnAMeshObject) {
  Scene scene;
  scene.name = "mesh-ball";
  ContactLaw law;
  law.k = 0.35, law.k_t = 0.5, law.mu = 1.2;
  scene.object = SoftObject(ball(), law);
  scene.region = {Vec2::Zero(), 15.0};
  // 3 N pressed on the top: depth (3 / k)^(1 / 1.5), up to the tessellation error.
  SimDevice dev(scene.object);
  const Vec3 top = kCentre + Vec3(0, 0, kRadius + 8.0);
  dev.place(top + Vec3(0, 0, 0.3));
  ForceProfileControl ctl(
      dev.info(), [](double t) { return Vec3(0, 0, -3.0 * std::min(1.0, t / 0.5)); }, 2.0, 20.0);
  const LabRecording lab = run_palpation(dev, ctl, 2.0);
  const double depth = top.z() - lab.rec.p.back().z();
  EXPECT_NEAR(depth, std::pow(3.0 / 0.35, 1 / 1.5), 0.05);
  // Taps: every first-contact point lies on the offset surface of the mesh.
  RecordSpec spec;
  spec.operator_name = "tap";
  spec.seconds = 8;
  const LabRecording taps = record_scene(scene, spec);
  int n = 0;
  for (std::size_t k = 1; k < taps.truth.size(); ++k)
    if (taps.truth.contact[k] && !taps.truth.contact[k - 1]) {
      EXPECT_NEAR(scene.object.query(taps.truth.c[k]).distance, 8.0, 2e-3);
      ++n;
    }
  EXPECT_GE(n, 4);
}

TEST(MeshScene, StanfordBunnyFromTheSharedData) {
  const std::string path = test::shared_data("bunny/bun_zipper.ply");
  if (!std::ifstream(path)) GTEST_SKIP() << "no " << path;
  test::TempDir dir;
  std::ofstream(dir.path("bunny.json")) << R"({"geometry": {"type": "mesh", "path": ")" << path
                                        << R"(", "scale": 1000, "offset": [0, 0, -33], "up": "y"},
    "material": {"k": 0.35, "k_t": 0.5, "mu": 1.0}})";
  const Scene s = load_scene(dir.path("bunny.json"));
  const Box3 b = s.object.shape().bounds();
  EXPECT_NEAR(b.min.z(), 0.0, 1.0);  // sits on the table, ~155 mm tall
  EXPECT_NEAR(b.size().z(), 154.0, 3.0);
  const auto spot = s.object.shape().drop(s.region.center.x(), s.region.center.y(), 8.0);
  ASSERT_TRUE(spot.has_value());
  EXPECT_NEAR(s.object.query(*spot).distance, 8.0, 1e-6);
}

}  // namespace
}  // namespace inhap::lab

namespace inhap::lab {
namespace {

TEST(MeshScene, OperatorsOnTheBunnyNeverPushThroughItsParts) {
  const std::string path = test::shared_data("bunny/bun_zipper.ply");
  if (!std::ifstream(path)) GTEST_SKIP() << "no " << path;
  test::TempDir dir;
  std::ofstream(dir.path("bunny.json")) << R"({"geometry": {"type": "mesh", "path": ")" << path
                                        << R"(", "scale": 1000, "offset": [0, 0, -33], "up": "y"},
    "material": {"k": 0.35, "k_t": 0.5, "mu": 1.0}, "region": {"center": [-20, -5], "radius": 25}})";
  const Scene s = load_scene(dir.path("bunny.json"));
  for (const char* op : {"tap", "explore"}) {
    RecordSpec spec;
    spec.operator_name = op;
    spec.seconds = 20;
    const LabRecording lab = record_scene(s, spec);
    double peak = 0;
    for (const Vec3& f : lab.truth.force) peak = std::max(peak, f.norm());
    // Moving through an ear instead of over it would show up as a huge contact force.
    EXPECT_LT(peak, 6.2) << op;
    EXPECT_GT(peak, 1.0) << op;
  }
}

}  // namespace
}  // namespace inhap::lab
