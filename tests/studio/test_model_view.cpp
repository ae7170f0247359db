// inhap studio, the Model view: malformed messages change nothing; the live coverage, the
// compare renderer and the running RMSE against answers worked out by hand
// (include/inhap/studio/model_view.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "inhap/lab/scene.hpp"
#include "inhap/lab/soft_contact.hpp"
#include "inhap/studio/model_view.hpp"
#include "inhap/studio/session.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;
using namespace inhap::studio;
using nlohmann::json;

TEST(StudioModelView, MalformedMessagesChangeNothing) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  ws.write("rec.csv", "t,px,py,pz,fx,fy,fz\n0,0,0,0,0,0,0\n");
  StudioOptions o;
  o.device = "lab:planar";
  Session s(o, ws, [](const std::string&) {});  // not started: no loop
  const std::vector<std::string> bad = {
      R"({"type":"model_record","operator":"robot","path":"r.csv"})",
      R"({"type":"model_record","operator":"explore","seconds":0,"path":"r.csv"})",
      R"({"type":"model_record","operator":"explore","seconds":601,"path":"r.csv"})",
      R"({"type":"model_record","operator":"explore","path":"../r.csv"})",
      R"({"type":"model_record","operator":"explore","path":"r.txt"})",
      R"({"type":"model_record","operator":"explore"})",
      R"({"type":"model_stop"})",  // nothing recording
      R"({"type":"model_train","recording":"missing.csv","out":"m.json"})",
      R"({"type":"model_train","recording":"rec.csv","out":"m.txt"})",
      R"({"type":"model_train","recording":"rec.csv","out":"/tmp/m.json"})",
      R"({"type":"model_train","recording":"../rec.csv","out":"m.json"})",
      R"({"type":"model_cancel"})",                   // nothing training
      R"({"type":"model_source","source":"model"})",  // no Model view
      R"({"type":"model_source","source":"c"})",
      R"({"type":"model_blind","on":true,"path":"ab.txt"})",
      R"({"type":"model_blind","on":true,"path":"ab.csv"})",  // no model trained
      R"({"type":"model_answer","model":"a"})",               // not blind
      R"({"type":"model_answer","model":"c"})",
      R"({"type":"model_stats"})",  // no loop
  };
  for (const auto& text : bad) {
    const json r = json::parse(s.handle(text));
    EXPECT_EQ(r["type"], "error") << text;
    EXPECT_FALSE(r["message"].get<std::string>().empty()) << text;
  }
  EXPECT_EQ(ws.list(), std::vector<std::string>{"rec.csv"});
}

TEST(StudioModelView, CoverageMarksCellsForcesDirectionsAndTheGap) {
  // A 3 x 3 block of 3 mm cells visited except the middle one: the middle is the one gap. One
  // slide along +x through the bottom row (sector 0), one along +y up the left column (sector 2).
  CoverageTracker c;
  double t = 0;
  const auto at = [](int i) { return (i + 0.5) * 3.0; };
  for (int i = 0; i < 3; ++i) c.add({t += 0.1, Vec3(at(i), at(0), 0), Vec3(0, 0, 1.0 + i), true});
  c.add({t += 0.1, Vec3(0, 0, 0), Vec3::Zero(), false});  // out of contact: ends the slide
  for (int j = 0; j < 3; ++j) c.add({t += 0.1, Vec3(at(0), at(j), 0), Vec3(0, 0, 0.5), true});
  c.add({t += 0.1, Vec3(0, 0, 0), Vec3::Zero(), false});
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{{2, 1}, {1, 2}, {2, 2}}) {
    c.add({t += 0.1, Vec3(at(i), at(j), 0), Vec3(0, 0, 4.0), true});
    c.add({t += 0.1, Vec3(0, 0, 0), Vec3::Zero(), false});
  }
  const json j = c.json();
  EXPECT_EQ(j["samples"], 9);
  ASSERT_EQ(j["cells"].size(), 8u);
  for (const auto& cell : j["cells"]) {
    const double x = cell[0], y = cell[1], f = cell[2];
    const unsigned mask = cell[3];
    if (x == at(2) && y == at(0)) {
      EXPECT_DOUBLE_EQ(f, 3.0);
    }
    if (x == at(0) && y == at(0)) {
      EXPECT_DOUBLE_EQ(f, 1.0);  // 1 N sliding, 0.5 N pressing
    }
    if (x == at(1) && y == at(0)) {
      EXPECT_EQ(mask, 1u << 0);  // slid along +x
    }
    if (x == at(0) && y == at(1)) {
      EXPECT_EQ(mask, 1u << 2);  // slid along +y
    }
    if (x == at(2) && y == at(2)) {
      EXPECT_EQ(mask, 0u);  // pressed only
    }
  }
  ASSERT_EQ(j["gaps"].size(), 1u);
  EXPECT_DOUBLE_EQ(j["gaps"][0][0].get<double>(), at(1));
  EXPECT_DOUBLE_EQ(j["gaps"][0][1].get<double>(), at(1));
  EXPECT_EQ(j["gaps"][0][2], 1);
}

TEST(StudioModelView, CompareRendererCommandsTheObjectsLawClampedAndResetsOnNan) {
  const lab::Scene scene = lab::builtin_scene("planar");
  const Box3 b = scene.object.shape().bounds();
  CompareRenderer r(scene.object, 8.0, nullptr, nullptr, 2.0);
  r.use_model(true);  // no model: the object stays
  EXPECT_FALSE(r.using_model());
  // The probe centre 1 mm into the probe-centre surface above the region's centre, at rest: the
  // same call on a state of our own gives the force the renderer computes.
  const Vec3 p(scene.region.center.x(), scene.region.center.y(), b.max.z() + 8.0 - 1.0);
  lab::ContactState mine;
  Vec3 want = Vec3::Zero();
  for (int k = 0; k < 5; ++k) {
    want = lab::contact_step(scene.object, 8.0, mine, p, Vec3::Zero(), 1e-3 * k, 1e-3);
    const haptics::ServoOutput o = r.step({1e-3 * k, p, Vec3::Zero(), false});
    const Vec3 clamped = want.norm() > 2.0 ? Vec3(want * (2.0 / want.norm())) : want;
    EXPECT_NEAR((o.force_n - clamped).norm(), 0.0, 1e-9) << k;
    EXPECT_TRUE(o.contact);
  }
  ASSERT_GT(want.z(), 0.0);  // pushed out of the object
  ComparePoint c;
  int n = 0;
  while (r.ring().pop(c)) ++n;
  EXPECT_EQ(n, 5);
  EXPECT_TRUE(c.object_contact);
  EXPECT_FALSE(c.model_contact);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const haptics::ServoOutput o = r.step({0.01, Vec3(nan, 0, 0), Vec3::Zero(), false});
  EXPECT_EQ(o.force_n, Vec3::Zero());
  EXPECT_FALSE(o.contact);
}

TEST(StudioModelView, RunningRmseCountsTicksWhereEitherTouches) {
  RunningRmse e;
  e.add({0, Vec3(1, 0, 0), Vec3(0, 0, 0), true, false});   // error (-1, 0, 0)
  e.add({0, Vec3(0, 0, 0), Vec3(0, 3, 0), false, true});   // error (0, 3, 0)
  e.add({0, Vec3(5, 5, 5), Vec3(0, 0, 0), false, false});  // neither touches: not counted
  EXPECT_EQ(e.n, 2u);
  EXPECT_DOUBLE_EQ(e.rmse().x(), std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(e.rmse().y(), std::sqrt(4.5));
  EXPECT_DOUBLE_EQ(e.rmse().z(), 0.0);
}

// A bridged device (sensed mode): the object is the sensor's reading, compensated (no tool mass
// here, so compensation leaves it as it is); nothing is commanded while the object is selected.
TEST(StudioModelView, SensedCompareRendererCommandsNothingAndReportsTheSensedForce) {
  CompensatorConfig cc;
  cc.tool_mass_kg = 0;
  CompareRenderer r(cc, nullptr, 2.0);
  r.use_model(true);  // no model: the object stays
  EXPECT_FALSE(r.using_model());
  const Vec3 p(1, 2, 3);
  const haptics::ServoOutput a = r.step({0.000, p, Vec3(0.5, 0, 2), true});
  EXPECT_EQ(a.force_n, Vec3::Zero());
  EXPECT_TRUE(a.contact);
  const haptics::ServoOutput b = r.step({0.001, p, Vec3(0, 0.05, 0), true});  // below 0.1 N
  EXPECT_EQ(b.force_n, Vec3::Zero());
  EXPECT_FALSE(b.contact);
  ComparePoint c1, c2;
  ASSERT_TRUE(r.ring().pop(c1));
  ASSERT_TRUE(r.ring().pop(c2));
  EXPECT_NEAR((c1.object - Vec3(0.5, 0, 2)).norm(), 0.0, 1e-12);
  EXPECT_TRUE(c1.object_contact);
  EXPECT_NEAR((c2.object - Vec3(0, 0.05, 0)).norm(), 0.0, 1e-12);
  EXPECT_FALSE(c2.object_contact);
  EXPECT_EQ(c1.model, Vec3::Zero());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const haptics::ServoOutput o = r.step({0.002, Vec3(nan, 0, 0), Vec3(0, 0, 2), true});
  EXPECT_EQ(o.force_n, Vec3::Zero());
  EXPECT_FALSE(o.contact);
}

// The recording of a bridged device from the loop's samples: one row per new device time (a
// repeat is dropped silently, a time running backwards is counted), up to `seconds`.
TEST(StudioModelView, ObservedRecordingKeepsNewSamplesUpToItsLength) {
  CompensatorConfig cc;
  cc.tool_mass_kg = 0;
  ObservedRecording rec;
  rec.start(cc, 0.003);
  const auto sample = [](double t, double fz) {
    haptics::LoopSample s;
    s.t_s = t;
    s.p_mm = Vec3(t * 1000, 0, 5);
    s.sensor_force_n = Vec3(0, 0, fz);
    return s;
  };
  TickPoint tp;
  EXPECT_TRUE(rec.add(sample(0.000, 1.0), tp));
  EXPECT_TRUE(tp.contact);
  EXPECT_EQ(tp.q, Vec3(0, 0, 5));
  EXPECT_FALSE(rec.add(sample(0.000, 1.0), tp));  // the same device sample again
  EXPECT_TRUE(rec.add(sample(0.001, 0.05), tp));
  EXPECT_FALSE(tp.contact);
  EXPECT_FALSE(rec.add(sample(0.0005, 1.0), tp));  // backwards
  EXPECT_TRUE(rec.add(sample(0.002, 2.0), tp));
  EXPECT_FALSE(rec.full());
  EXPECT_TRUE(rec.add(sample(0.003, 3.0), tp));
  EXPECT_TRUE(rec.full());
  EXPECT_FALSE(rec.add(sample(0.004, 3.0), tp));  // full
  EXPECT_EQ(rec.skipped(), 1u);
  EXPECT_EQ(rec.contact_rows(), 3u);
  EXPECT_DOUBLE_EQ(rec.seconds(), 0.003);
  const Recording r = rec.take();
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r.t, (std::vector<double>{0.000, 0.001, 0.002, 0.003}));
  EXPECT_NEAR(r.f[2].z(), 2.0, 1e-12);
  EXPECT_NEAR(r.p[3].x(), 3.0, 1e-12);
  EXPECT_EQ(rec.seconds(), 0.0);
}
