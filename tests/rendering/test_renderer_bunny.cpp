// Real data (thesis sec. 5.3): the Stanford bunny (69,451 triangles) scaled into a 100 mm cube,
// confidence mapped to stiffness (max 1 N/mm), stroked with both algorithms. Invariants with
// known answers: the IHIP lies on the (translated) mesh, the rendered spring is non-negative
// (x + s >= 0 in contact), forces are finite and within the limit. Skips without the data.
// Units: mm, N, N/mm.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "inhap/geometry/mesh_io.hpp"
#include "inhap/rendering/stroke.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;
using rendering::Algorithm;

TEST(RendererBunny, StrokesKeepTheProxyOnTheSurfaceWithBoundedForce) {
  const std::string path = test::shared_data("bunny/bun_zipper.ply");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
  TriMesh mesh = read_mesh(path);
  const Box3 b = mesh.bbox();
  mesh.transform(100.0 / b.size().maxCoeff(), b.center());  // mm, centred at 0
  std::vector<double> k = mesh.property("confidence");
  const double kmax = *std::max_element(k.begin(), k.end());
  for (auto& v : k) v = std::max(0.05, v / kmax);  // N/mm
  mesh.set_property("stiffness", k);
  rendering::Model m(std::move(mesh));
  ASSERT_EQ(m.mesh().num_triangles(), 69451u);

  // Strokes across the body seen from +z.
  const Vec2 ends[][2] = {{{-25, -10}, {25, 10}}, {{-5, -30}, {5, 30}}, {{-30, 15}, {20, -15}}};
  for (Algorithm a : {Algorithm::kCBA, Algorithm::kTCA})
    for (const auto& e : ends) {
      rendering::StrokeOptions o;
      o.from = e[0];
      o.to = e[1];
      o.force_n = 1.5;
      o.speed_mm_s = 40;
      o.tremor_n = 0.05;
      const auto run = rendering::simulate_stroke(m, a, o);
      std::size_t contact = 0;
      for (const auto& s : run) {
        ASSERT_TRUE(s.force.allFinite());
        ASSERT_LE(s.force.norm(), 6.2 + 1e-9);
        if (!s.contact) {
          ASSERT_EQ(s.force, Vec3::Zero());
          continue;
        }
        ++contact;
        const ClosestPoint cp = m.index().closest_point(s.ihip - s.t, 1.0);
        ASSERT_TRUE(cp.valid()) << s.time;
        ASSERT_LT(std::sqrt(cp.distance2), 1e-6) << s.time;
        // The force is a push toward the CIHIP, never a pull (k (x + s) >= 0).
        ASSERT_GE(s.force.dot(s.cihip - s.hip), -1e-9) << s.time;
      }
      EXPECT_GT(contact, run.size() / 2) << (a == Algorithm::kTCA ? "TCA" : "CBA");
    }
}
