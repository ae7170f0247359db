// The study protocol with scripted devices and judgement sources whose answers are known:
// label routing, scoring, schedule, summaries, and the distortion metric.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <set>

#include "inhap/core/error.hpp"
#include "inhap/rendering/experiment.hpp"

using namespace inhap;
using namespace inhap::rendering;

namespace {

// A device that follows a scripted path (one waypoint per tick) and ignores forces.
class ScriptedDevice : public Device {
 public:
  std::vector<Vec3> path;
  std::size_t i = 0;
  const DeviceInfo& info() const override { return info_; }
  double time() const override { return double(i) / info_.servo_rate_hz; }
  Vec3 position() const override {
    return path.empty() ? Vec3(0, 0, 10) : path[std::min(i, path.size() - 1)];
  }
  Vec3 force_sensor() const override { return last_; }
  void command_force(const Vec3& f) override { last_ = f; }
  void tick() override { ++i; }

  // Straight segment from a to b at `speed` mm/s (1 kHz).
  void line(Vec3 a, Vec3 b, double speed) {  // by value: a may be path.back()
    const int n = std::max(1, int(std::ceil((b - a).norm() / speed * 1000)));
    for (int k = 0; k <= n; ++k) path.push_back(a + (b - a) * (double(k) / n));
  }
  void hold(int ticks) {
    for (int k = 0; k < ticks; ++k) path.push_back(path.back());
  }

 private:
  DeviceInfo info_;
  Vec3 last_ = Vec3::Zero();
};

// A judge that labels whenever the scripted device has reached the waypoint index given.
class ScriptedJudge : public JudgementSource {
 public:
  struct Entry {
    std::size_t at_tick;
    Label label;
  };
  const ScriptedDevice* device = nullptr;
  std::vector<Entry> entries;
  std::size_t next = 0;
  int trials = 0;
  void begin_trial(const SceneInfo&) override {
    ++trials;
    next = 0;
  }
  std::optional<Label> poll() override {
    if (next < entries.size() && device->i >= entries[next].at_tick) return entries[next++].label;
    return std::nullopt;
  }
  bool quit() const override { return device->i >= device->path.size() + 5; }
};

}  // namespace

TEST(Experiment, LabelsGoToTheModelUnderTheHipAndAreScored) {
  const TrialSpec spec{.participant = 3,
                       .session = 0,
                       .trial = 0,
                       .algorithm = Algorithm::kCBA,
                       .task = Task::kShape,
                       .layout_seed = 42};
  const Layout layout = shuffled_layout(spec.layout_seed);
  const StudySurface surface(DatasetParams{}, layout);
  ScriptedDevice dev;
  ScriptedJudge judge;
  judge.device = &dev;
  // Visit every cell in the air; give the true answer except for models 0..4 (answered "bump",
  // which is right only for none of them: they are flat) and one stray label between cells.
  dev.path.push_back(Vec3(1, 1, 10));
  int expected_correct = 0;
  for (int c = 0; c < kNumModels; ++c) {
    const Vec2 o = surface.cell_centre(c);
    dev.line(dev.path.back(), Vec3(o.x(), o.y(), 10), 500);
    const int m = layout.model_at_cell[c];
    const int value = m < 5 ? int(ShapeClass::kBump) : int(true_shape_class(m));
    expected_correct += m >= 5;
    judge.entries.push_back({dev.path.size() - 1, Label{Task::kShape, value}});
    if (c == 0) {  // a label 13 mm off-centre belongs to no model
      dev.line(dev.path.back(), Vec3(o.x() + 13, o.y() + 13, 10), 500);
      judge.entries.push_back({dev.path.size() - 1, Label{Task::kShape, 0}});
    }
  }
  dev.hold(10);
  const TrialResult r = run_trial(dev, judge, spec);
  EXPECT_TRUE(r.session.completed);
  EXPECT_EQ(r.session.stray_labels, 1);
  EXPECT_EQ(r.correct, expected_correct);
  EXPECT_EQ(r.correct, 20);
  EXPECT_EQ(r.layout.model_at_cell, layout.model_at_cell);
  for (int m = 0; m < kNumModels; ++m)
    EXPECT_EQ(r.answer[m], m < 5 ? int(ShapeClass::kBump) : int(true_shape_class(m))) << m;
  EXPECT_NEAR(r.time_s, double(r.session.ticks) / 1000.0, 1e-12);
  EXPECT_EQ(r.session.strokes, 0);  // never touched the surface
}

TEST(Experiment, DistortionIsHipMinusTrueHeightWithTheStrokeMeanRemoved) {
  // Stroke at a fixed height 0.5 mm below the base surface straight through the centre of a
  // flat K1 model (M1), of a K3 bump (M8) and of a K0 bump (M5, not counted).
  const TrialSpec spec{.algorithm = Algorithm::kCBA, .task = Task::kShape, .layout_seed = 9};
  const Layout layout = shuffled_layout(spec.layout_seed);
  const DatasetParams params;
  const StudySurface surface(params, layout);
  ScriptedDevice dev;
  ScriptedJudge judge;
  judge.device = &dev;
  dev.path.push_back(Vec3(0.5, 0.5, 8));
  double expect_sq = 0;
  long expect_n = 0;
  for (int m : {1, 8, 5}) {
    const Vec2 o = surface.cell_centre(layout.cell_of(m));
    const Vec3 a(o.x() - 12, o.y(), -0.5), b(o.x() + 12, o.y(), -0.5);
    dev.line(dev.path.back(), Vec3(a.x(), a.y(), 8), 500);
    dev.line(Vec3(a.x(), a.y(), 8), a, 100);
    const std::size_t begin = dev.path.size() + 1;  // sliding from the second sample of a -> b
    dev.line(a, b, 40);
    const std::size_t end = dev.path.size();
    dev.line(b, Vec3(b.x(), b.y(), 8), 100);  // pressing and lifting do not count
    if (stiffness_index(m) == 0) continue;
    // Ground truth of the same samples (in contact: below the mesh surface).
    std::vector<double> e;
    for (std::size_t k = begin; k < end; ++k) {
      const Vec3& p = dev.path[k];
      const double h = surface.mesh_height(p.x(), p.y());
      if (p.z() < h) e.push_back(p.z() - h);
    }
    const double mean = std::accumulate(e.begin(), e.end(), 0.0) / double(e.size());
    for (double v : e) expect_sq += (v - mean) * (v - mean);
    expect_n += long(e.size());
  }
  dev.hold(10);
  const TrialResult r = run_trial(dev, judge, spec);
  EXPECT_FALSE(r.session.completed);
  EXPECT_EQ(r.session.strokes, 2);
  EXPECT_EQ(r.session.distortion_samples, expect_n);
  const double rms = std::sqrt(r.session.distortion_sq_sum / double(r.session.distortion_samples));
  EXPECT_NEAR(rms, std::sqrt(expect_sq / double(expect_n)), 0.01);
  EXPECT_GT(rms, 0.3);  // the bump's profile (1.2 mm high) shows up in M8's stroke
}

TEST(Experiment, ScheduleBalancesOrderAndReshufflesEveryTrial) {
  StudyConfig cfg;
  cfg.trials = 5;
  std::set<std::uint64_t> seeds;
  for (int p = 0; p < 4; ++p) {
    const auto s = participant_schedule(cfg, p);
    ASSERT_EQ(s.size(), 20u);                 // 2 tasks x 2 sessions x 5 trials
    EXPECT_EQ(s.front().task, Task::kShape);  // shape experiment first
    EXPECT_EQ(s.back().task, Task::kStiffness);
    EXPECT_EQ(s.front().algorithm, p % 2 == 0 ? Algorithm::kTCA : Algorithm::kCBA);
    EXPECT_EQ(s[5].algorithm, p % 2 == 0 ? Algorithm::kCBA : Algorithm::kTCA);
    for (const auto& t : s) seeds.insert(t.layout_seed);
  }
  EXPECT_EQ(seeds.size(), 80u);
  StudyConfig other = cfg;
  other.seed = 2;
  EXPECT_NE(participant_schedule(other, 0).front().layout_seed,
            participant_schedule(cfg, 0).front().layout_seed);
}

TEST(Experiment, SummaryMeansSdsAndModelRatios) {
  std::vector<TrialResult> rs;
  // Participant 0: 25 and 23 correct (misses M1 in trial 2 and M2 twice); participant 1: 20, 22.
  auto make = [](int p, int correct, std::vector<int> wrong) {
    TrialResult r;
    r.spec.participant = p;
    r.spec.algorithm = Algorithm::kCBA;
    r.spec.task = Task::kShape;
    for (int m = 0; m < kNumModels; ++m) r.answer[m] = int(true_shape_class(m));
    for (int m : wrong) r.answer[m] = (int(true_shape_class(m)) + 1) % 3;
    r.correct = correct;
    r.session.distortion_sq_sum = 4.0;
    r.session.distortion_samples = 100;
    r.time_s = 100.0 + correct;
    return r;
  };
  rs.push_back(make(0, 25, {}));
  rs.push_back(make(0, 23, {1, 2}));
  rs.push_back(make(1, 20, {1, 2, 3, 4, 6}));
  rs.push_back(make(1, 22, {2, 3, 4}));
  const StudySummary s = summarize(rs);
  const ConditionSummary& c = s.get(Algorithm::kCBA, Task::kShape);
  EXPECT_EQ(c.trials, 4);
  EXPECT_DOUBLE_EQ(c.mean, 22.5);                         // (24 + 21) / 2
  EXPECT_NEAR(c.sd_participants, std::sqrt(4.5), 1e-12);  // SD of {24, 21}
  EXPECT_NEAR(c.sd_trials, std::sqrt((6.25 + 0.25 + 6.25 + 0.25) / 3), 1e-12);
  EXPECT_DOUBLE_EQ(c.model_ratio[0], 1.0);
  EXPECT_DOUBLE_EQ(c.model_ratio[1], 0.5);
  EXPECT_DOUBLE_EQ(c.model_ratio[2], 0.25);
  EXPECT_DOUBLE_EQ(c.model_ratio[6], 0.75);
  EXPECT_EQ(s.misjudged_models(Algorithm::kCBA, Task::kShape), (std::vector<int>{2}));
  EXPECT_EQ(s.misjudged_models(Algorithm::kCBA, Task::kShape, 0.6), (std::vector<int>{1, 2, 3, 4}));
  EXPECT_NEAR(c.distortion_rms_mm, 0.2, 1e-12);
  EXPECT_DOUBLE_EQ(c.mean_time_s, 122.5);
  EXPECT_THROW(s.get(Algorithm::kTCA, Task::kShape), Error);
}
