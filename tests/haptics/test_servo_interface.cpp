// The common servo interface: the composed data-driven step gives the forces of the pieces run
// by hand (proxy_track, then datadriven::replay) on a lab recording, allocates nothing, and the
// mesh adapters give what rendering::step gives. Units: s, mm, N. (This file includes
// support/alloc_counter.hpp for the whole test_haptics program.)
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "datadriven/dd_fixtures.hpp"
#include "friction/sys_helpers.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/friction/proxy_track.hpp"
#include "inhap/haptics/renderers.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"
#include "rendering/render_fixtures.hpp"
#include "support/alloc_counter.hpp"

namespace inhap::haptics {
namespace {

/// A 4 s free exploration of the lab's planar silicone cylinder (top at z = 25 mm), Coulomb
/// sliding yield surfaces on that plane, and a small force model trained on the recording with
/// the estimated proxy.
struct LabServo {
  lab::LabRecording lab;
  friction::SysModel sys;
  std::unique_ptr<friction::PlaneShape> plane;
  datadriven::ForceModel force;
  datadriven::ProxyTrack track;  // the pieces by hand: proxy_track -> ProxyTrack

  LabServo() {
    lab::RecordSpec spec;
    spec.seconds = 4.0;
    spec.seed = 3;
    lab = lab::record_scene(lab::builtin_scene("planar"), spec);
    double top = -std::numeric_limits<double>::infinity();  // highest probe centre in contact
    for (std::size_t i = 0; i < lab.rec.size(); ++i)
      if (lab.truth.contact[i] && lab.truth.anchor[i].allFinite())
        top = std::max(top, lab.truth.anchor[i].z());
    sys = test::coulomb_sys(
        test::grid_points(3, 3, 40.0, top), [](std::size_t i) { return 0.3 + 0.1 * (i % 3); }, 0.5,
        0.4);
    plane = std::make_unique<friction::PlaneShape>(Vec3(0, 0, top), Vec3::UnitZ());
    const friction::ProxyColumns c = friction::proxy_track({&sys, plane.get()}, lab.rec);
    track.q.resize(c.size());
    track.n.assign(c.size(), Vec3::UnitZ());
    track.contact.resize(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) {  // as eval forces builds its estimated track
      track.contact[i] = c.contact[i] && c.q[i].allFinite();
      track.q[i] = track.contact[i] ? c.q[i] : lab.rec.p[i];
      if (track.contact[i]) track.n[i] = c.n[i];
    }
    datadriven::TrainParams p = datadriven::test::small_params();
    p.features = datadriven::FeatureSet::kLocalFrame;
    force = datadriven::train_force_model(
        datadriven::make_training_set(lab.rec, track, datadriven::FoawParams{}), p);
  }
};

const LabServo& setup() {
  static const LabServo s;
  return s;
}

ServoInput input_at(const Recording& rec, std::size_t i) {
  ServoInput in;
  in.t_s = rec.t[i];
  in.p_mm = rec.p[i];
  return in;
}

TEST(DataDrivenServo, SameForcesAsThePiecesByHand) {
  const LabServo& s = setup();
  const Recording& rec = s.lab.rec;
  const std::vector<Vec3> by_hand = datadriven::replay(s.force, rec, s.track);
  const DataDrivenModel model(s.sys, *s.plane, s.force);
  DataDrivenState st;
  std::size_t contact = 0, pushing = 0;
  for (std::size_t i = 0; i < rec.size(); ++i) {
    const ServoOutput o = step(model, st, input_at(rec, i));
    ASSERT_EQ(o.force_n, by_hand[i]) << "sample " << i;
    ASSERT_EQ(o.contact, s.track.contact[i] != 0) << "sample " << i;
    ASSERT_EQ(o.ihip_mm, s.track.q[i]) << "sample " << i;
    EXPECT_EQ(o.hip_mm, rec.p[i]);
    contact += o.contact;
    pushing += o.force_n.norm() > 0.2;
  }
  // The comparison means something: the recording touches, slides and pushes.
  EXPECT_GT(contact, rec.size() / 10);
  EXPECT_GT(pushing, 100u);
}

TEST(DataDrivenServo, RendererInterfaceAndResetRepeatTheRun) {
  const LabServo& s = setup();
  const Recording& rec = s.lab.rec;
  const DataDrivenModel model(s.sys, *s.plane, s.force);
  DataDrivenRenderer r(model);
  std::unique_ptr<Renderer> again = std::make_unique<DataDrivenRenderer>(model);
  const std::vector<Vec3> by_hand = datadriven::replay(s.force, rec, s.track);
  for (std::size_t i = 0; i < rec.size(); ++i)
    ASSERT_EQ(r.step(input_at(rec, i)).force_n, by_hand[i]);
  r.reset();
  for (std::size_t i = 0; i < rec.size(); ++i) {
    ASSERT_EQ(r.step(input_at(rec, i)).force_n, by_hand[i]);
    ASSERT_EQ(again->step(input_at(rec, i)).force_n, by_hand[i]);
  }
  EXPECT_STREQ(again->name(), "data-driven");
}

TEST(DataDrivenServo, StepNeverAllocates) {
  const LabServo& s = setup();
  const Recording& rec = s.lab.rec;
  const DataDrivenModel model(s.sys, *s.plane, s.force);
  DataDrivenState st;
  DataDrivenRenderer r(model);
  long contact = 0;
  const long before = test::heap_allocations();
  for (std::size_t i = 0; i < rec.size(); ++i) {
    ServoInput in = input_at(rec, i);
    if (i == rec.size() / 2) in.p_mm.x() = std::numeric_limits<double>::quiet_NaN();  // reset path
    const ServoOutput o = step(model, st, in);
    r.step(in);
    contact += o.contact;
  }
  EXPECT_EQ(test::heap_allocations() - before, 0);
  EXPECT_GT(contact, 0);
  EXPECT_GE(st.servo.resets, 1u);  // the NaN went through the reset path
}

// A model trained on a 66 Hz recording (its filter: dt 1/66 s, a one-sample window) in a 1 kHz
// loop: the step runs the filter at the ticks' own period, so a probe moving at 12 mm/s is seen
// at 12 mm/s, not at the 0.8 mm/s of 1 ms steps taken for 15 ms ones; and replaying a 1 kHz
// recording gives the forces of the same model with its filter at 1 kHz.
TEST(DataDrivenServo, AModelTrainedAtAnotherRateSeesTheTicksVelocity) {
  const LabServo& s = setup();
  datadriven::ForceModel at66 = s.force;
  at66.foaw.dt_s = 1.0 / 66;
  at66.foaw.max_window = 1;
  const DataDrivenModel model(s.sys, *s.plane, at66);
  DataDrivenState st;
  for (int i = 0; i < 200; ++i) {
    ServoInput in;
    in.t_s = 1e-3 * i;
    in.p_mm = Vec3(12.0 * in.t_s, 0, 60);  // in the air above the object
    step(model, st, in);
  }
  EXPECT_NEAR(st.period_s, 1e-3, 1e-9);
  EXPECT_NEAR(st.servo.velocity.x(), 12.0, 1e-6);
  const Recording& rec = s.lab.rec;
  datadriven::ForceModel at1k = at66;
  at1k.foaw = at66.foaw.at_period(datadriven::median_dt(rec));
  EXPECT_EQ(at1k.foaw.max_window, 15);
  EXPECT_EQ(datadriven::replay(at66, rec, s.track), datadriven::replay(at1k, rec, s.track));
}

TEST(DataDrivenServo, NoForceModelGivesZeroForceAndTheProxy) {
  const LabServo& s = setup();
  DataDrivenModel model;
  model.proxy = {&s.sys, s.plane.get()};
  DataDrivenState st;
  std::size_t contact = 0;
  for (std::size_t i = 0; i < s.lab.rec.size(); ++i) {
    const ServoOutput o = step(model, st, input_at(s.lab.rec, i));
    ASSERT_EQ(o.force_n, Vec3::Zero());
    ASSERT_EQ(o.ihip_mm, s.track.q[i]);
    contact += o.contact;
  }
  EXPECT_GT(contact, 0u);
}

TEST(MeshServo, AdaptersGiveWhatRenderStepGives) {
  TriMesh mesh = test::grid_mesh(
      40, 40, 0.5, -10, -10,
      [](double x, double y) { return 0.5 * std::sin(0.4 * x) * std::cos(0.3 * y); },
      [](double x, double) { return x < 0 ? 1.0 : 0.3; });
  const rendering::Model m(mesh);
  for (rendering::Algorithm a : {rendering::Algorithm::kCBA, rendering::Algorithm::kTCA}) {
    rendering::State ref;
    MeshRenderer r(m, a);
    Renderer& any = r;
    long contact = 0, differs = 0;
    const long before = test::heap_allocations();
    for (int i = 0; i < 3000; ++i) {
      const double ph = i * 0.004;
      ServoInput in;
      in.t_s = i * 1e-3;
      in.p_mm = Vec3(8 * std::sin(ph), 7 * std::cos(1.3 * ph), -0.6 + 0.8 * std::sin(i * 0.03));
      const ServoOutput o = any.step(in);
      ServoInput next = in;  // the loop's read-ahead (changes nothing, allocates nothing)
      next.p_mm += Vec3(0.01, -0.02, 0.005);
      any.prefetch(next);
      const Vec3 f = rendering::step(m, ref, in.p_mm, a);
      ASSERT_EQ(o.force_n, f);
      ASSERT_EQ(o.contact, ref.collision);
      if (ref.collision) {
        ASSERT_EQ(o.ihip_mm, ref.ihip.point);
        ASSERT_EQ(o.cihip_mm, ref.cihip);
        differs += (o.cihip_mm - o.ihip_mm).norm() > 1e-9;
      } else {
        ASSERT_EQ(o.ihip_mm, in.p_mm);
      }
      contact += o.contact;
    }
    EXPECT_EQ(test::heap_allocations() - before, 0);
    EXPECT_GT(contact, 100);
    if (a == rendering::Algorithm::kTCA) {
      EXPECT_GT(differs, 0);  // TCA compensates: CIHIP != IHIP
    }
    EXPECT_STREQ(any.name(), a == rendering::Algorithm::kTCA ? "tca-mesh" : "cba");
  }
}

}  // namespace
}  // namespace inhap::haptics
