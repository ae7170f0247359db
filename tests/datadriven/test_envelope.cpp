// The force envelope (no rendered force the training data never showed near that state) and the
// k-nearest-neighbour baselines.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "inhap/core/error.hpp"
#include "inhap/datadriven/baselines.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/envelope.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/datadriven/servo.hpp"
#include "support/palpation_rig.hpp"

namespace inhap::datadriven {
namespace {

TEST(ForceEnvelope, CapIsTheLargestForceOneDepthStepDeeperPlusTheStatedMargin) {
  // Samples at one place: |f| = 1 N at depth 0.2 mm, 3 N at 1.2 mm, 5 N at 2.7 mm.
  const std::vector<Vec3> q(3, Vec3(10, 10, 0));
  const std::vector<Vec3> p{Vec3(10, 10, -0.2), Vec3(10, 10, -1.2), Vec3(10, 10, -2.7)};
  const std::vector<Vec3> f{Vec3(0, 0, 1), Vec3(0, 0, 3), Vec3(0, 0, 5)};
  const ForceEnvelope e = make_force_envelope(q, p, f, 4.0, 0.5);
  const auto cap = [&](double max_f) { return 1.25 * max_f + 0.25; };
  EXPECT_DOUBLE_EQ(e.limit(q[0], 0.2), cap(1.0));  // bins 0 and 1 hold only the 1 N sample
  EXPECT_DOUBLE_EQ(e.limit(q[0], 0.7), cap(3.0));  // bin 1: bin 2 (1.0-1.5 mm) holds 3 N
  EXPECT_DOUBLE_EQ(e.limit(q[0], 2.6), cap(5.0));
  EXPECT_DOUBLE_EQ(e.limit(q[0], 50.0), cap(5.0));            // beyond the deepest bin: the deepest
  EXPECT_DOUBLE_EQ(e.limit(Vec3(1e4, 0, 0), 0.2), cap(1.0));  // outside the grid: global
  EXPECT_EQ(e.limit(Vec3(NAN, 0, 0), 0.2), 0.0);
  // Absurd but finite states index nothing out of range (global value, deepest bin).
  EXPECT_DOUBLE_EQ(e.limit(Vec3(1e300, -1e300, 1e300), 1e300), cap(5.0));
  EXPECT_TRUE(std::isinf(ForceEnvelope{}.limit(q[0], 0.2)));
}

// A rig that logs at 66 Hz, the probe as its own proxy (q = p: what a user without a proxy
// estimate trains on), the world-frame preset: the very first sample of a replay (no velocity
// history) and every other one must stay within what the data showed near that state.
TEST(ForceEnvelope, ALowRateReplayRendersNoForceAboveWhatTheDataShowed) {
  inhap::test::PalpationRig rig;
  rig.k_inclusion = rig.k;  // forces of 0.2-2.5 N, as on the real rig
  const Recording train = rig.record(90.0);
  rig.seed = 2;
  // The second trial: the phantom sits a little higher and the raster starts beside the first
  // one's, so the replay begins where the training data are thin.
  rig.point += 1.0 * rig.frame().n - 10.0 * rig.frame().t1;
  const Recording test_rec = rig.record(30.0);
  std::vector<char> contact(train.size(), 1), tc(test_rec.size(), 1);
  FoawParams foaw;
  foaw.dt_s = median_dt(train);
  foaw.max_window = 16;  // the 1 kHz window in samples, as before it was set in seconds
  const TrainingSet set =
      make_training_set(train, position_only_track(train, contact, "all"), foaw);
  TrainParams prm = preset_params("world");
  prm.centers = 60;
  prm.threads = 1;
  double max_train = 0;
  for (const Vec3& f : set.f) max_train = std::max(max_train, f.norm());
  prm.envelope = false;
  const ForceModel bare = train_force_model(set, prm, foaw);
  prm.envelope = true;
  const ForceModel bounded = train_force_model(set, prm, foaw);
  const ProxyTrack track = position_only_track(test_rec, tc, "all");
  const std::vector<Vec3> fb = replay(bare, test_rec, track);
  const std::vector<Vec3> fe = replay(bounded, test_rec, track);
  double over_bare = 0, over_bounded = 0;
  for (std::size_t i = 0; i < test_rec.size(); ++i) {
    const double lim = bounded.envelope.limit(track.q[i], 0.0);
    over_bare = std::max(over_bare, fb[i].norm() - lim);
    over_bounded = std::max(over_bounded, fe[i].norm() - lim);
  }
  EXPECT_GT(over_bare, 0.0) << "the unbounded model should extrapolate above the data";
  double max_bare = 0;
  for (const Vec3& f : fb) max_bare = std::max(max_bare, f.norm());
  std::printf("max %.3f N, spike above the envelope without it: %.3f N\n", max_bare, over_bare);
  EXPECT_LE(over_bounded, 1e-12);
  EXPECT_LE(bounded.envelope.limit(track.q[0], 0.0), 1.25 * max_train + 0.25 + 1e-3);
}

TEST(ForceEnvelope, SurvivesTheModelFileBitIdentical) {
  inhap::test::PalpationRig rig;
  const Recording rec = rig.record(40.0);
  std::vector<char> contact(rec.size(), 1);
  FoawParams foaw;
  foaw.dt_s = median_dt(rec);
  const TrainingSet set = make_training_set(rec, position_only_track(rec, contact, "all"), foaw);
  TrainParams prm = preset_params("world");
  prm.centers = 30;
  prm.threads = 1;
  const TrainedForceModel m = train_with_provenance(set, prm, foaw);
  ASSERT_FALSE(m.model.envelope.empty());
  const TrainedForceModel back =
      trained_force_model_from_json(force_model_to_json(m.model, m.provenance), "mem.json");
  for (std::size_t i = 0; i < set.size(); i += 97) {
    const double a = m.model.envelope.limit(set.q[i], 0.0);
    const double b = back.model.envelope.limit(set.q[i], 0.0);
    EXPECT_EQ(b, a);
  }
  EXPECT_TRUE(back.provenance.params.envelope);
}

TEST(Baselines, NearestNeighboursAndMeanHaveTheirKnownAnswers) {
  std::vector<Vec3> p, v, f;
  for (int i = 0; i < 10; ++i) {
    p.emplace_back(i, 0, 0);
    v.emplace_back(0, 0, i % 2 ? 100.0 : -100.0);
    f.emplace_back(0, 0, i);
  }
  BaselineParams prm;
  prm.k = 1;
  const Baselines b1 = fit_baselines(p, v, f, prm);
  EXPECT_DOUBLE_EQ(b1.mean.z(), 4.5);
  const double x[6] = {3.1, 0, 0, 0, 0, 0};
  EXPECT_DOUBLE_EQ(b1.knn_p.predict(x).z(), 3.0);
  prm.k = 3;
  const Baselines b3 = fit_baselines(p, v, f, prm);
  EXPECT_DOUBLE_EQ(b3.knn_p.predict(x).z(), (2.0 + 3.0 + 4.0) / 3);
  // With velocity (tau 0.1 s: 100 mm/s weighs 10 mm), the neighbours moving the same way win.
  const auto pred = predict_baselines(b3, {Vec3(3.1, 0, 0)}, {Vec3(0, 0, 100)});
  EXPECT_DOUBLE_EQ(pred[2][0].z(), (1.0 + 3.0 + 5.0) / 3);
  EXPECT_THROW(fit_baselines({}, {}, {}), Error);
}

}  // namespace
}  // namespace inhap::datadriven
