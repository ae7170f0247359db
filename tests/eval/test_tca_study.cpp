// eval/tca_study reached without the program: the reduced virtual user study reproduces the
// thesis pattern (TCA-MESH near 25 of 25 shapes, CBA confusing the 12 predicted models), does not
// depend on the number of threads, and the servo timing strokes the map in contact.
// Units: mm, N, N/mm, s.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "inhap/core/error.hpp"
#include "inhap/eval/tca_study.hpp"
#include "inhap/geometry/heightmap.hpp"

namespace inhap::eval {
namespace {

using rendering::Algorithm;
using rendering::Task;

TEST(TcaStudy, ReducedStudyReproducesTheThesisPatternWithAnyThreadCount) {
  TcaStudyOptions o;
  o.seed = 3;
  o.participants = 2;
  o.trials = 1;
  o.threads = 1;
  double last_fraction = 0;
  int calls = 0;
  o.progress = [&](const std::string&, double f, double) {
    EXPECT_GE(f, last_fraction);
    last_fraction = f;
    ++calls;
  };
  const TcaStudyResult one = run_tca_study(o);
  // 2 participants x (2 tasks x 2 algorithms x 1 trial).
  ASSERT_EQ(one.trials.size(), 8u);
  EXPECT_EQ(calls, 8);
  EXPECT_DOUBLE_EQ(last_fraction, 1.0);
  EXPECT_EQ(one.incomplete, 0);
  const auto& tca = one.summary.get(Algorithm::kTCA, Task::kShape);
  const auto& cba = one.summary.get(Algorithm::kCBA, Task::kShape);
  EXPECT_GE(tca.mean, 24.0);  // thesis: 24.4 of 25
  EXPECT_LE(cba.mean, 15.0);  // thesis: 17.0; the virtual participant misses all 12
  const auto confused = one.summary.misjudged_models(Algorithm::kCBA, Task::kShape);
  for (int m : rendering::thesis_cba_confusions())
    EXPECT_NE(std::find(confused.begin(), confused.end(), m), confused.end()) << "M" << m;

  o.threads = 2;
  o.progress = {};
  const TcaStudyResult two = run_tca_study(o);
  const auto& tca2 = two.summary.get(Algorithm::kTCA, Task::kShape);
  EXPECT_EQ(tca2.per_participant, tca.per_participant);
  EXPECT_EQ(two.summary.get(Algorithm::kCBA, Task::kStiffness).per_participant,
            one.summary.get(Algorithm::kCBA, Task::kStiffness).per_participant);
  EXPECT_DOUBLE_EQ(tca2.distortion_rms_mm, tca.distortion_rms_mm);
}

TEST(TcaStudy, RejectsAnEmptyStudy) {
  TcaStudyOptions o;
  o.participants = 0;
  EXPECT_THROW(run_tca_study(o), Error);
}

TEST(TcaStudy, TimingSurfaceIsThe257GridAndTheProbeStrokesItInContact) {
  // 257 x 257 samples: 256 x 256 cells of 2 triangles.
  EXPECT_EQ(tca_timing_surface(1, "").num_triangles(), 2u * 256u * 256u);
  // A flat 40 x 40 mm plate: 4 rows (y = 5, 15, 25, 35) of (40 - 4) / 0.04 = 900 steps.
  const Grid h(41, 41), k(41, 41, 0.5);  // height 0, stiffness 0.5 N/mm
  const rendering::Model model(grid_to_mesh(h, 1.0, &k));
  for (Algorithm a : {Algorithm::kCBA, Algorithm::kTCA}) {
    const StepTiming t = time_servo_steps(model, a);
    EXPECT_NEAR(double(t.steps), 4 * 900.0, 4.0);
    EXPECT_GT(t.contact_steps, t.steps / 2);  // the hand pushes down to 1.5 N and stays in
    EXPECT_LE(t.p50, t.p99);
    EXPECT_LE(t.p99, t.max);
  }
}

}  // namespace
}  // namespace inhap::eval
