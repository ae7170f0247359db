// The virtual participant on surfaces whose answers are known (a flat uniform plane, a rigid
// 3 mm bump), its device physics, and a reduced run of the thesis protocol.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "inhap/geometry/heightmap.hpp"
#include "inhap/lab/participant.hpp"
#include "inhap/rendering/experiment.hpp"

using namespace inhap;
using namespace inhap::rendering;
using inhap::lab::ParticipantProfile;
using inhap::lab::VirtualParticipant;

namespace {

// A 40 x 40 mm plane (1 mm grid) centred at (20, 20) with an optional smooth bump.
Model plane_model(double k, double bump_mm) {
  Grid h(41, 41, 0.0), s(41, 41, k);
  for (int y = 0; y <= 40; ++y)
    for (int x = 0; x <= 40; ++x) {
      const double r = std::hypot(x - 20.0, y - 20.0);
      if (r < 8) h.at(x, y) = bump_mm * 0.5 * (1 + std::cos(std::numbers::pi * r / 8));
    }
  return Model(grid_to_mesh(h, 1.0, &s));
}

SceneInfo one_cell(Task task) {
  SceneInfo sc;
  sc.task = task;
  sc.cell_centres = {Vec2(20, 20)};
  sc.cell_mm = 40;
  sc.hover_z_mm = 6 + 3;  // above the 3 mm bump too
  return sc;
}

ParticipantProfile no_lapse(std::uint64_t seed) {
  ParticipantProfile p = lab::sample_participant(seed);
  p.lapse_rate = 0;
  return p;
}

}  // namespace

TEST(Participant, ProfilesAreSeededAndInTheThesisRanges) {
  for (std::uint64_t s = 1; s <= 50; ++s) {
    const ParticipantProfile p = lab::sample_participant(s);
    EXPECT_GE(p.force_n, 0.8);
    EXPECT_LE(p.force_n, 2.0);
    EXPECT_GE(p.speed_mm_s, 20.0);
    EXPECT_LE(p.speed_mm_s, 60.0);
    double w = 0;
    for (double x : p.fluctuation_weight) w += x;
    EXPECT_NEAR(w, 1.0, 1e-12);  // fluctuation bounded by +-10 %
    EXPECT_EQ(lab::sample_participant(s).force_n, p.force_n);
  }
  EXPECT_NE(lab::sample_participant(1).force_n, lab::sample_participant(2).force_n);
}

TEST(Participant, DeviceIsAPointMassUnderHandAndRenderedForce) {
  // Hold the hand still and push with a constant rendered force: the device settles where the
  // arm spring balances it, displacement F / K_arm (0.5 N up, K = 0.5 N/mm -> 1 mm).
  ParticipantProfile p;
  VirtualParticipant vp(p);
  vp.place(Vec3(0, 0, 10));
  for (int i = 0; i < 2000; ++i) {
    vp.command_force(Vec3(0, 0, 0.5));
    vp.tick();
  }
  EXPECT_NEAR(vp.position().z(), 11.0, 1e-3);
  EXPECT_NEAR(vp.time(), 2.0, 1e-12);
  vp.command_force(Vec3(0, 0, 100));  // saturates at the device limit
  EXPECT_NEAR(vp.force_sensor().norm(), 6.2, 1e-12);
  vp.command_force(Vec3(NAN, 0, 0));
  EXPECT_EQ(vp.force_sensor(), Vec3::Zero());
}

TEST(Participant, FlatUniformPlaneIsFlatAndSame) {
  const Model plane = plane_model(0.25, 0.0);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    VirtualParticipant vp(no_lapse(seed));
    for (Algorithm alg : {Algorithm::kCBA, Algorithm::kTCA}) {
      const SessionOutcome shape = run_session(vp, vp, plane, alg, one_cell(Task::kShape));
      ASSERT_TRUE(shape.completed);
      EXPECT_EQ(shape.labels[0], int(ShapeClass::kFlat)) << "seed " << seed;
      EXPECT_EQ(vp.evidence()[0].stroke_contrast_mm.size(), 3u);
      for (double c : vp.evidence()[0].stroke_contrast_mm) EXPECT_LT(std::abs(c), 0.3);
      const SessionOutcome stiff = run_session(vp, vp, plane, alg, one_cell(Task::kStiffness));
      ASSERT_TRUE(stiff.completed);
      // Force/displacement during the taps recovers the rendered stiffness.
      for (double k : vp.evidence()[0].k_centre) EXPECT_NEAR(k, 0.25, 0.01);
      for (double k : vp.evidence()[0].k_surround) EXPECT_NEAR(k, 0.25, 0.01);
    }
  }
}

TEST(Participant, SameAnswerRateOnUniformPlaneFollowsTheWeberFraction) {
  // With per-tap noise sigma = ln(1.22) / (0.6745 sqrt 2) = 0.209 and 3 + 3 taps the centre-minus-
  // surround log ratio has SD 0.209 sqrt(2/3) = 0.171, so "same" is answered with probability
  // P(|z| < ln(1.22) / 0.171) = P(|z| < 1.164) = 0.756.
  const Model plane = plane_model(0.5, 0.0);
  VirtualParticipant vp(no_lapse(5));
  int same = 0, n = 100;
  for (int i = 0; i < n; ++i)
    same += run_session(vp, vp, plane, Algorithm::kCBA, one_cell(Task::kStiffness)).labels[0] == 0;
  EXPECT_NEAR(double(same) / n, 0.756, 0.12);
}

TEST(Participant, RigidThreeMillimetreBumpIsABump) {
  const Model bump = plane_model(1.0, 3.0);
  for (std::uint64_t seed : {1u, 4u}) {
    VirtualParticipant vp(no_lapse(seed));
    const SessionOutcome o = run_session(vp, vp, bump, Algorithm::kCBA, one_cell(Task::kShape));
    ASSERT_TRUE(o.completed);
    EXPECT_EQ(o.labels[0], int(ShapeClass::kBump));
    // The HIP rides F/k below the surface and lags a little on the slopes: most of the 3 mm
    // (less the centre window's averaging over |u| <= 2 mm) comes through.
    for (double c : vp.evidence()[0].stroke_contrast_mm) {
      EXPECT_GT(c, 2.0);
      EXPECT_LT(c, 3.1);
    }
  }
}

TEST(Participant, ReducedProtocolReproducesTheThesisPattern) {
  // 2 participants x 1 trial per condition (the full 16 x 5 runs in `inhap eval tca`).
  std::vector<TrialResult> results;
  StudyConfig cfg;
  cfg.participants = 2;
  cfg.trials = 1;
  for (int p = 0; p < cfg.participants; ++p) {
    VirtualParticipant vp(lab::sample_participant(100 + p));
    for (const TrialSpec& spec : participant_schedule(cfg, p))
      results.push_back(run_trial(vp, vp, spec));
  }
  for (const auto& r : results) EXPECT_TRUE(r.session.completed);
  const StudySummary s = summarize(results);
  const auto& tca = s.get(Algorithm::kTCA, Task::kShape);
  const auto& cba = s.get(Algorithm::kCBA, Task::kShape);
  std::printf(
      "shape: TCA %.1f, CBA %.1f; stiffness: TCA %.1f, CBA %.1f; distortion TCA %.3f CBA %.3f mm\n",
      tca.mean, cba.mean, s.get(Algorithm::kTCA, Task::kStiffness).mean,
      s.get(Algorithm::kCBA, Task::kStiffness).mean, tca.distortion_rms_mm, cba.distortion_rms_mm);
  EXPECT_GE(tca.mean, 24.0);
  EXPECT_LE(cba.mean, 15.0);
  // Every model the thesis predicts is misjudged under CBA, and (almost) nothing else.
  const auto confused = s.misjudged_models(Algorithm::kCBA, Task::kShape);
  for (int m : thesis_cba_confusions())
    EXPECT_NE(std::find(confused.begin(), confused.end(), m), confused.end()) << "M" << m;
  EXPECT_LE(confused.size(), 13u);
  EXPECT_GE(s.get(Algorithm::kTCA, Task::kStiffness).mean, 21.0);
  EXPECT_GE(s.get(Algorithm::kCBA, Task::kStiffness).mean, 21.0);
  EXPECT_LT(tca.distortion_rms_mm, cba.distortion_rms_mm / 3);
}
