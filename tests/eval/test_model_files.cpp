// inhap/eval/model_files.hpp: the force model on recording files (`inhap model train|eval|render`).
// Known answers: the preset rules; a model scored on a recording whose measured force is its own
// rendered force has zero error; the coverage share of an unknown model is unknown.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/datadriven/model_io.hpp"
#include "inhap/eval/model_files.hpp"
#include "support/relief_recording.hpp"
#include "support/temp_dir.hpp"

namespace inhap::eval {
namespace {

TEST(ModelFiles, WithoutNormalsTheLocalPresetFallsBackToWorld) {
  TrainRequest r;
  std::string note;
  const datadriven::TrainParams p = resolve_train_params(r, false, &note);
  EXPECT_EQ(p.features, datadriven::preset_params("world").features);
  EXPECT_NE(note.find("preset 'world'"), std::string::npos);
  std::string none;
  const datadriven::TrainParams q = resolve_train_params(r, true, &none);
  EXPECT_EQ(q.features, datadriven::FeatureSet::kLocalFrame);
  EXPECT_TRUE(none.empty());
}

TEST(ModelFiles, GivenOptionsOverrideThePreset) {
  TrainRequest r;
  r.params.bins = 7;
  r.params.centers = 11;  // not given: the preset's value stays
  r.given = {"--bins", "--features"};
  r.features = "ue_q_v";
  const datadriven::TrainParams p = resolve_train_params(r, true, nullptr);
  EXPECT_EQ(p.bins, 7);
  EXPECT_EQ(p.centers, datadriven::preset_params("best").centers);
  EXPECT_EQ(p.features, datadriven::FeatureSet::kDisplacementProxyVelocity);
  // World-frame features turn the local-only settings off unless given.
  EXPECT_FALSE(p.tangent_mirror);
  EXPECT_FALSE(p.stiffness_prior);
  EXPECT_FALSE(p.friction_cone);
}

// A probe pressing into and sliding over the plane z = 0: f = 0.5 N/mm * depth up, proxy on the
// plane above the probe.
Recording spring_recording() {
  Recording rec;
  std::vector<double> qx, qy, qz, contact;
  for (int i = 0; i < 4000; ++i) {
    const double t = i * 1e-3;
    const double depth = 2.0 + 1.5 * std::sin(2 * M_PI * 1.3 * t);
    const Vec3 p(10 * std::sin(2 * M_PI * 0.4 * t), 5 * std::cos(2 * M_PI * 0.3 * t), -depth);
    rec.t.push_back(t);
    rec.p.push_back(p);
    rec.f.push_back(Vec3(0, 0, 0.5 * depth));
    qx.push_back(p.x());
    qy.push_back(p.y());
    qz.push_back(0.0);
    contact.push_back(1.0);
  }
  rec.set_extra("qx", qx);
  rec.set_extra("qy", qy);
  rec.set_extra("qz", qz);
  rec.set_extra("contact", contact);
  return rec;
}

TEST(ModelFiles, AModelScoredOnItsOwnRenderingHasNoError) {
  test::TempDir dir;
  write_recording(dir.path("train.csv"), spring_recording());
  TrainFileOptions o;
  o.recording = dir.path("train.csv");
  o.request.preset = "world";
  o.request.params.centers = 30;
  o.request.given = {"--centers"};
  const TrainFileResult r = train_from_file(o);
  EXPECT_EQ(r.set.size(), 4000u);
  EXPECT_NE(r.notes.front().find("4000 samples, 4000 in contact"), std::string::npos);
  EXPECT_NE(r.notes.back().find("only 4.0 s of contact"), std::string::npos);
  datadriven::save_force_model(dir.path("model.json"), r.model);

  const datadriven::TrainedForceModel m =
      datadriven::load_trained_force_model(dir.path("model.json"));
  ReplayedFile rendered = replay_file(dir.path("model.json"), m, o.recording, {}, "");
  ASSERT_EQ(rendered.forces.size(), 4000u);
  Recording own = rendered.rec;
  own.f = rendered.forces;
  write_recording(dir.path("own.csv"), own);
  const ModelEvalResult e =
      evaluate_model_file(dir.path("model.json"), dir.path("own.csv"), {}, "");
  EXPECT_EQ(e.contact_samples, 4000u);
  for (int a = 0; a < 3; ++a) EXPECT_LT(e.errors.rmse[a], 1e-6);
  EXPECT_FALSE(e.support.known);  // no coverage file beside the model
  EXPECT_NE(support_note(e.support).find("training support unknown"), std::string::npos);
  EXPECT_EQ(e.json["contact_samples"], 4000);
}

// With an estimated proxy the model trains on the samples in contact with the estimated surface;
// the baselines are fitted on every sample that presses (|f| above the contact threshold, the
// rule the test recording is scored by), so a surface that misses some does not weaken them. A
// force-controlled exploration at 0.2 N over 1 mm of relief (support/relief_recording.hpp), the
// surface not raised to hold its samples: a share of them lie above it.
TEST(ModelFiles, TheBaselinesOfAnEstimatedProxyAreFittedOnEveryPressingSample) {
  const Recording rec = test::ReliefRecording{}.record();
  TrainFileOptions o;
  o.recording = "relief.csv";
  o.request.params.centers = 30;
  o.request.given = {"--centers"};
  o.estimate.hold_quantile = 0;
  const TrainFileResult r = train_from_recording(rec, o);
  ASSERT_TRUE(r.estimate);
  EXPECT_GT(r.estimate->pressing_above, 600u);
  EXPECT_LT(r.set.size(), 6000u - 600u);
  ASSERT_EQ(r.baselines().size(), 6000u);
  for (std::size_t i = 0; i < rec.size(); ++i) {
    EXPECT_EQ(r.baselines().p[i], rec.p[i]);
    EXPECT_EQ(r.baselines().f[i], rec.f[i]);
  }
}

}  // namespace
}  // namespace inhap::eval
