// Tapping whole objects (issue 22): the lab contact never lets the tip through a thin part, the
// whole-object operator covers what a stylus reaches at a person's pace. Units: mm, N, s.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/eval/shape_lab.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/reach.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/surface/points.hpp"

namespace inhap::eval {
namespace {

// A 2 mm plate of the softest tapping silicone (Ecoflex 00-10), floating 29-31 mm above the
// table, tapped at 1-4 N with the sharp tip: the static depth at 4 N is
// (4 / k)^(1 / 1.5) = 5.9 mm, almost three times the plate, so a contact that pushed toward the
// nearest surface would carry the tip out underneath and touch the plate from below on the way
// back.
TEST(WholeObject, ThinPlateTappedAtFullForceIsNeverTouchedFromItsFarSide) {
  lab::Scene scene = lab::builtin_scene("silicone-hemisphere");
  const lab::ContactLaw law = scene.object.material();
  ASSERT_GT(law.depth_at(4.0), 2.5 * 2.0);
  scene.object = lab::SoftObject(lab::BoxShape{Vec3(0, 0, 30), Vec3(40, 40, 1)}, law);
  scene.region = {Vec2(0, 0), 25.0};
  lab::RecordSpec spec;
  spec.operator_name = "tap";
  spec.tap.whole_object = false;  // straight down onto the plate (the top-cap protocol)
  spec.probe = lab::ProbeSpec::tip();
  spec.seconds = 40;
  spec.seed = 3;
  const lab::LabRecording rec = lab::record_scene(scene, spec);
  const EntrySideCounts c = count_far_side_contacts(rec, scene.object);
  EXPECT_GE(c.episodes, 20u);
  EXPECT_EQ(c.far_side_first_contacts, 0u);
  EXPECT_EQ(c.force_reversals, 0u);
  // The tip did go deeper than the plate is thick (so the test can fail).
  double deepest = 0;
  for (std::size_t i = 0; i < rec.truth.size(); ++i)
    if (rec.truth.contact[i]) deepest = std::max(deepest, 31.0 - rec.rec.p[i].z());
  EXPECT_GT(deepest, 2.5);
}

// The counter itself on a prescribed path through a 2 mm plate (z 29..31): down from 40 mm,
// in through the top, out underneath, and back up into the bottom face without getting 5 mm
// away: the second episode touches the bottom (normal -z) right after the top (+z) within the
// same tap: a far-side first contact. The same two episodes with a retreat to 40 mm between
// them are two taps (one from above, one from below), and a contact left through the top
// followed by one on the bottom is the stylus going round: neither counts.
TEST(WholeObject, FarSideCounterComparesTheNormalWithWhereTheStylusCameFrom) {
  const lab::SoftObject plate(lab::BoxShape{Vec3(0, 0, 30), Vec3(40, 40, 1)}, lab::ContactLaw{});
  lab::LabRecording rec;
  auto add = [&](double z, bool in, const Vec3& c, const Vec3& f) {
    rec.rec.t.push_back(0.001 * static_cast<double>(rec.rec.t.size()));
    rec.rec.p.push_back(Vec3(0, 0, z));
    rec.rec.f.push_back(Vec3::Zero());
    rec.truth.t.push_back(rec.rec.t.back());
    rec.truth.contact.push_back(in);
    rec.truth.c.push_back(c);
    rec.truth.force.push_back(f);
  };
  const Vec3 none = Vec3::Constant(NAN);
  for (double z = 40; z > 31; z -= 0.5) add(z, false, none, Vec3::Zero());
  for (double z = 31; z > 28.9; z -= 0.5) add(z, true, Vec3(0, 0, 31), Vec3(0, 0, 1));
  for (double z = 28.5; z > 27; z -= 0.5) add(z, false, none, Vec3::Zero());
  for (double z = 27; z < 28.9; z += 0.5) add(z, false, none, Vec3::Zero());
  for (double z = 29; z < 30; z += 0.5) add(z, true, Vec3(0, 0, 29), Vec3(0, 0, -1));
  const EntrySideCounts c = count_far_side_contacts(rec, plate);
  EXPECT_EQ(c.episodes, 2u);
  EXPECT_EQ(c.far_side_first_contacts, 1u);
  EXPECT_EQ(c.force_reversals, 0u);
  rec = {};
  for (double z = 40; z > 31; z -= 0.5) add(z, false, none, Vec3::Zero());
  for (double z = 31; z > 28.9; z -= 0.5) add(z, true, Vec3(0, 0, 31), Vec3(0, 0, 1));
  for (double z = 31.5; z < 40; z += 0.5) add(z, false, none, Vec3::Zero());
  for (double z = 20; z < 28.9; z += 0.5) add(z, false, none, Vec3::Zero());
  for (double z = 29; z < 30; z += 0.5) add(z, true, Vec3(0, 0, 29), Vec3(0, 0, -1));
  EXPECT_EQ(count_far_side_contacts(rec, plate).far_side_first_contacts, 0u);
  // Out through the top (the side it entered) and, staying within 5 mm, onto the bottom face
  // (as when the back of an ear is tapped right after its front): not a far-side contact.
  rec = {};
  for (double z = 40; z > 31; z -= 0.5) add(z, false, none, Vec3::Zero());
  for (double z = 31; z > 29.4; z -= 0.5) add(z, true, Vec3(0, 0, 31), Vec3(0, 0, 1));
  add(31.5, false, none, Vec3::Zero());
  for (double z = 28.0; z < 28.9; z += 0.5) add(z, false, none, Vec3::Zero());
  for (double z = 29; z < 30; z += 0.5) add(z, true, Vec3(0, 0, 29), Vec3(0, 0, -1));
  EXPECT_EQ(count_far_side_contacts(rec, plate).far_side_first_contacts, 0u);
}

// Whole-object mode on the hemisphere (radius 40 on the table): 300 taps reach the sides as
// well as the top (the share of the reachable dome whose normal is more than 60 deg from +z is
// the band 2 < z < 20: 18 / 38 = 0.47 of it), at >= 1 tap per second, spread so that no two taps
// land within 2 mm of each other and >= 90 % of the reachable surface is within 5 mm of a tap.
TEST(WholeObject, HemisphereIsTappedAllOverAtAPersonsPace) {
  const lab::Scene scene = lab::builtin_scene("silicone-hemisphere");
  lab::TapOptions tap;
  tap.whole_object = true;
  const lab::LabRecording rec = record_taps(scene, 300, 7, {}, lab::Physics::kBuiltin, tap);
  EXPECT_GE(taps_per_minute(rec), 60.0);
  std::vector<Vec3> taps;
  long last = -1;
  for (std::size_t i = 0; i < rec.truth.size(); ++i)
    if (rec.truth.tap[i] >= 0 && rec.truth.tap[i] != last)
      last = rec.truth.tap[i], taps.push_back(rec.truth.c[i]);
  ASSERT_GE(taps.size(), 300u);
  std::size_t side = 0;
  for (const Vec3& p : taps) side += p.z() < 20.0;
  EXPECT_NEAR(double(side) / double(taps.size()), 18.0 / 38.0, 0.1);
  const KnnTable nn = knn_table(taps, 1);
  double closest = 1e9;
  for (double d : nn.distance) closest = std::min(closest, d);
  EXPECT_GT(closest, 2.0);
  EXPECT_GE(tap_coverage(scene.object, taps, 5.0, 5000), 0.9);
  EXPECT_EQ(count_far_side_contacts(rec, scene.object).far_side_first_contacts, 0u);
}

}  // namespace
}  // namespace inhap::eval
