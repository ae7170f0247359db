// Small pieces of the commands that live in inhap::eval: `sys` (sys_bridge.hpp), `lab record`
// (lab_files.hpp), `eval forces --design thesis` (forces_lab.hpp), `model eval|render`
// (model_files.hpp).
#include <gtest/gtest.h>

#include <set>

#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/forces_lab.hpp"
#include "inhap/eval/lab_files.hpp"
#include "inhap/eval/model_files.hpp"
#include "inhap/eval/sys_bridge.hpp"
#include "support/temp_dir.hpp"

namespace inhap::eval {
namespace {

TEST(CommandHelpers, Vec3AndStem) {
  EXPECT_EQ(parse_vec3("1,0.5,-2", "--x"), Vec3(1, 0.5, -2));
  try {
    parse_vec3("1,2", "--tangent-reference");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "--tangent-reference: expected x,y,z, got '1,2'");
  }
  EXPECT_EQ(sys_output_stem("out/sys.json"), "out/sys");
  EXPECT_EQ(sys_output_stem("sys"), "sys");
  EXPECT_EQ(sys_output_stem(".json"), ".json");  // nothing before the extension: kept
}

TEST(CommandHelpers, BeyondRimWarning) {
  ProxyFileResult r;
  r.contact = 200;
  EXPECT_EQ(beyond_rim_warning(r, "m.ply"), "");
  r.beyond = 5;
  r.beyond_max_mm = 1.234;
  const std::string w = beyond_rim_warning(r, "m.ply");
  EXPECT_NE(w.find("5 of 200 in-contact samples (2.5 %)"), std::string::npos) << w;
  EXPECT_NE(w.find("shape mesh m.ply (up to 1.23 mm"), std::string::npos) << w;
}

TEST(CommandHelpers, BridgePalpationChecksItsOptions) {
  BridgePalpationOptions o;
  o.device = "udp";
  EXPECT_THROW(palpate_bridge(o), Error);  // no --shape / --refs
}

TEST(CommandHelpers, LabRecordSpec) {
  LabRecordRequest r;
  r.op = "tap";
  r.probe = "tip";
  r.seconds = 12;
  r.seed = 9;
  r.no_gravity = true;
  r.whole_object = true;
  const lab::RecordSpec s = lab_record_spec(r);
  EXPECT_EQ(s.operator_name, "tap");
  EXPECT_EQ(s.seconds, 12.0);
  EXPECT_EQ(s.seed, 9u);
  EXPECT_EQ(s.probe.radius_mm, lab::ProbeSpec::tip().radius_mm);
  EXPECT_TRUE(s.noise);
  EXPECT_FALSE(s.gravity);
  EXPECT_TRUE(s.tap.whole_object);
  r.probe = "cube";
  EXPECT_THROW(lab_record_spec(r), Error);
  r.probe = "sphere";
  r.coverage = true;  // only the explore operator covers
  EXPECT_THROW(lab_record_spec(r), Error);
  r.op = "explore";
  EXPECT_TRUE(lab_record_spec(r).explore.coverage);
}

// The tap operator's default is the reachable surface (the thesis' protocol); --region top is the
// top cap; --whole-object is accepted (the default) but contradicts --region top.
TEST(CommandHelpers, LabRecordTapRegion) {
  LabRecordRequest r;
  r.op = "tap";
  EXPECT_TRUE(lab_record_spec(r).tap.whole_object);
  EXPECT_TRUE(lab::TapOptions{}.whole_object);
  r.region = "top";
  EXPECT_FALSE(lab_record_spec(r).tap.whole_object);
  r.whole_object = true;
  EXPECT_THROW(lab_record_spec(r), Error);
  r.region = "reachable";
  EXPECT_TRUE(lab_record_spec(r).tap.whole_object);
  r.region = "side";
  EXPECT_THROW(lab_record_spec(r), Error);
}

TEST(CommandHelpers, LongRecordingNote) {
  EXPECT_EQ(long_recording_note(600), "");
  // 1000 s: 1e6 rows of 400 bytes = 0.4 GB
  EXPECT_EQ(long_recording_note(1000),
            "note: 1000 s at 1 kHz is 1000000 rows, about 0.4 GB of CSV (recording and truth)\n");
}

TEST(CommandHelpers, ThesisSettingsUnlessGiven) {
  datadriven::TrainParams p = lab_train_params();
  p.bins = 3;
  p.ridge = 0.5;
  const std::set<std::string> given{"--bins"};
  apply_thesis_settings(p, [&](const std::string& f) { return given.count(f) > 0; });
  EXPECT_EQ(p.bins, 3);  // given: kept
  EXPECT_EQ(p.ridge, 0.0);
  EXPECT_FALSE(p.linear_tail);
  EXPECT_EQ(p.feature_weights, (std::array<double, 3>{1, 1, 1}));
  EXPECT_EQ(p.box_margin, 0.1);
  EXPECT_FALSE(p.stiffness_prior || p.shear_prior || p.friction_cone || p.tangent_mirror);
  datadriven::TrainParams q = lab_train_params();
  apply_thesis_settings(q, [](const std::string&) { return false; });
  EXPECT_EQ(q.bins, 5);
}

TEST(CommandHelpers, ModelEvalTextAndRenderedCsv) {
  ModelEvalResult r;
  r.errors.n = 10;
  r.errors.rmse = {0.1, 0.2, 0.3};
  r.errors.re_median = 0.05;
  EXPECT_EQ(model_eval_text(r).rfind("10 contact samples: RMSE x/y/z 0.100 0.200 0.300 N", 0), 0u);
  EXPECT_EQ(model_eval_text(r).find("render clamp"), std::string::npos);
  r.above_force_limit = 2;
  r.force_limit_n = 6.2;
  EXPECT_NE(model_eval_text(r).find("2 contact samples measured above the 6.20 N render clamp"),
            std::string::npos);

  const test::TempDir dir;
  ReplayedFile f;
  for (int i = 0; i < 3; ++i) {
    f.rec.t.push_back(i * 0.001);
    f.rec.p.push_back(Vec3(i, 0, 0));
    f.rec.f.push_back(Vec3(0, 0, i));
    f.forces.push_back(Vec3(0, 0, 2 * i));
    f.track.contact.push_back(i > 0);
  }
  write_rendered_csv(dir.path("r.csv"), f, "rec.csv", "model.json");
  const Recording back = read_recording(dir.path("r.csv"));
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back.f[2], Vec3(0, 0, 4));  // the rendered force is f
  EXPECT_EQ((*back.find_extra("mfz"))[2], 2.0);
  EXPECT_EQ(*back.find_extra("contact"), (std::vector<double>{0, 1, 1}));
}

}  // namespace
}  // namespace inhap::eval
