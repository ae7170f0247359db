// eval::training_coverage (the support report of `inhap eval forces`) reached without the
// program, on a hand-made lab result: a test run half on the training patch and half far away
// has half of its in-contact samples outside the training support; samples out of contact do
// not count. Units: mm, N.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "inhap/eval/forces_lab.hpp"

namespace inhap::eval {
namespace {

void add(lab::LabRecording& rec, datadriven::ProxyTrack& track, const Vec3& q, double f,
         bool contact) {
  rec.rec.t.push_back(static_cast<double>(rec.rec.t.size()) * 1e-3);
  rec.rec.p.push_back(q);
  rec.rec.f.push_back(Vec3(0, 0, f));
  track.q.push_back(q);
  track.contact.push_back(contact ? 1 : 0);
}

TEST(ForcesCoverage, ShareOfTestSamplesOutsideTheTrainingPatch) {
  ForceLabResult d;
  for (int x = 0; x < 30; ++x)
    for (int y = 0; y < 30; ++y) add(d.train, d.train_track, Vec3(x, y, 0), 1.0, true);
  for (int i = 0; i < 20; ++i) {
    add(d.test, d.test_track, Vec3(5 + i, 10, 0), 1.0, true);     // on the patch
    add(d.test, d.test_track, Vec3(200, 200 + i, 0), 1.0, true);  // far away
    add(d.test, d.test_track, Vec3(-300, 0, 0), 1.0, false);      // out of contact: not scored
  }
  const ForceCoverage c = training_coverage(d);
  EXPECT_DOUBLE_EQ(c.outside, 0.5);
  EXPECT_DOUBLE_EQ(c.cell_mm, datadriven::CoverageParams{}.cell_mm);
  EXPECT_LE(c.gaps.size(), 5u);

  // A force far above what the patch saw is outside too, even on the patch.
  ForceLabResult hard = d;
  for (std::size_t i = 0; i < hard.test.rec.size(); ++i) hard.test.rec.f[i] = Vec3(0, 0, 10.0);
  EXPECT_DOUBLE_EQ(training_coverage(hard).outside, 1.0);
}

// The report of `eval forces` carries the same coverage and the sample counts of the runs.
TEST(ForcesCoverage, ReportCarriesTheCoverageAndTheCounts) {
  ForceLabResult d;
  d.name = "hand-made";
  for (int x = 0; x < 30; ++x)
    for (int y = 0; y < 30; ++y) add(d.train, d.train_track, Vec3(x, y, 0), 1.0, true);
  for (int i = 0; i < 20; ++i) {
    add(d.test, d.test_track, Vec3(5 + i, 10, 0), 1.0, true);
    add(d.test, d.test_track, Vec3(200, 200 + i, 0), 1.0, true);
  }
  const auto j = nlohmann::ordered_json::parse(force_lab_json(d));
  EXPECT_EQ(j.at("name"), "hand-made");
  EXPECT_EQ(j.at("train_samples"), 900);
  EXPECT_EQ(j.at("test_samples"), 40);
  EXPECT_DOUBLE_EQ(j.at("coverage").get<double>(), 0.5);
  EXPECT_EQ(j.at("clipped_training_samples"), 0);
  EXPECT_TRUE(j.at("explore_more").is_array());
  EXPECT_TRUE(j.at("step_us").at("p50").is_null());  // no servo steps replayed: NaN -> null
  // The last fields in the order `eval forces` writes them.
  EXPECT_EQ(std::prev(j.end()).key(), "explore_more");
}

}  // namespace
}  // namespace inhap::eval
