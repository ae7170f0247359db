// The tapping operator's default protocol (thesis ch. 3: every surface a stylus reaches on the
// object as it rests, spread evenly, at a person's pace) on a mesh scene no built-in object
// resembles. Units: mm, N, s.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/eval/tap_study.hpp"
#include "inhap/geometry/trimesh.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::eval {
namespace {

// A four-lobed ring with three grooves along its tube, lying on the table: centre line
// R(u) = R0 (1 + 0.12 cos 4u) (concave between the lobes), tube radius r0 (1 + 0.12 cos 3v)
// (three concave grooves), a hole in the middle. Closed and outward; 2.24 (R0 + r0) across.
TriMesh lobed_ring(double r0_centre, double r0_tube, int nu = 160, int nv = 48) {
  TriMesh m;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
      const double rc = r0_centre * (1 + 0.12 * std::cos(4 * u));
      const double rt = r0_tube * (1 + 0.12 * std::cos(3 * v));
      const Vec3 er(std::cos(u), std::sin(u), 0);
      m.positions.push_back(rc * er + rt * (std::cos(v) * er + std::sin(v) * Vec3::UnitZ()));
    }
  auto id = [&](int i, int j) { return ((i + nu) % nu) * nv + (j + nv) % nv; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  double volume = 0;  // orientation: outward when the signed volume is positive
  for (const Tri& t : m.triangles)
    volume += m.positions[t[0]].dot(m.positions[t[1]].cross(m.positions[t[2]])) / 6.0;
  if (volume < 0)
    for (Tri& t : m.triangles) std::swap(t[1], t[2]);
  double zmin = 1e9;
  for (const Vec3& p : m.positions) zmin = std::min(zmin, p.z());
  for (Vec3& p : m.positions) p.z() -= zmin;
  return m;
}

lab::Scene ring_scene(double r0_centre, double r0_tube) {
  lab::Scene scene = lab::builtin_scene("planar");  // Ecoflex 00-30
  scene.name = "lobed-ring";
  scene.object = lab::SoftObject(lab::make_mesh_shape(lobed_ring(r0_centre, r0_tube)),
                                 scene.object.material());
  scene.region = lab::default_region(scene.object.shape());
  return scene;
}

TEST(TapDefault, GeneratedRingIsClosedAndHasConcavities) {
  const TriMesh m = lobed_ring(18, 7);
  double volume = 0;
  for (const Tri& t : m.triangles)
    volume += m.positions[t[0]].dot(m.positions[t[1]].cross(m.positions[t[2]])) / 6.0;
  // A torus of these mean radii: 2 pi^2 R r^2 = 17,400 mm^3 (the modulations change it by a
  // few per cent).
  EXPECT_NEAR(volume, 2 * M_PI * M_PI * 18 * 7 * 7, 0.1 * 2 * M_PI * M_PI * 18 * 7 * 7);
}

// The full check is 10 simulated minutes on the ring at R0 = 36, r0 = 14 (`inhap eval taps`,
// docs/virtual-lab.md); here the ring at half size (a quarter of the area) for a quarter of the
// time: the same taps per unit area. Defaults: the reachable surface (no option set), the sharp
// tip of the shape-modeling protocol.
TEST(TapDefault, LobedRingIsCoveredAtAPersonsPaceByDefault) {
  const lab::Scene scene = ring_scene(18, 7);
  lab::RecordSpec spec;
  spec.operator_name = "tap";
  spec.probe = lab::ProbeSpec::tip();
  spec.seconds = 150;
  spec.seed = 5;
  const lab::LabRecording rec = lab::record_scene(scene, spec);
  const TapScore s = score_taps(rec, scene.object);
  EXPECT_GE(s.taps_per_minute, 60.0);
  EXPECT_GE(s.coverage, 0.85);
  EXPECT_LE(s.estimate.median, 0.3);
  EXPECT_GE(s.matched, s.taps * 9 / 10);
  EXPECT_EQ(s.sides.far_side_first_contacts, 0u);
  // The same operator with the top-cap protocol leaves the sides and the lobes' flanks untapped.
  lab::RecordSpec top = spec;
  top.tap.whole_object = false;
  const TapScore t = score_taps(lab::record_scene(scene, top), scene.object);
  EXPECT_LT(t.coverage, 0.85);
}

}  // namespace
}  // namespace inhap::eval
