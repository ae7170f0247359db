// inhap::report: the helpers every step's figures use and the mapping of an experiment's phases
// onto a step's progress, against values computed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "inhap/report/report.hpp"
#include "inhap/report/strokes.hpp"

namespace inhap::report {
namespace {

TEST(ReportHelpers, RoundsAndThinsSeries) {
  EXPECT_DOUBLE_EQ(rnd(1.23456, 2), 1.23);
  EXPECT_DOUBLE_EQ(rnd(-2.5e-4, 3), -0.0);
  EXPECT_DOUBLE_EQ(rnd(std::numeric_limits<double>::quiet_NaN()), 0.0);
  const nlohmann::json s = series({0.11111, 1.0, 2.22222, 3.0, 4.44444}, 2, 2);
  EXPECT_EQ(s, nlohmann::json({0.11, 2.22, 4.44}));
  EXPECT_EQ(fmt_num(3.14159, 3), "3.142");
}

TEST(ReportContext, FileIsRecordedUnderOut) {
  Options o;
  o.out = "/tmp/x";
  Context c{o, "tap", {}};
  StepResult r;
  EXPECT_EQ(c.file(r, "a.csv"), "/tmp/x/a.csv");
  EXPECT_EQ(r.files, std::vector<std::string>{"a.csv"});
}

TEST(ReportProgress, PhasesMapOntoTheStepsShare) {
  Options o;
  std::vector<std::pair<std::string, double>> seen;  // (label, fraction)
  Context c{o, "force-model",
            [&](const std::string& what, double f, double) { seen.emplace_back(what, f); }};
  ForwardProgress fw(c, {{"train recording", 1.0}, {"train (proxy)", 3.0}}, 0.2, 0.6);
  eval::Progress cb = fw.callback();
  cb("dome: train recording", 0.5, 0);  // 0.2 + 0.4 * (0 + 1 * 0.5) / 4
  cb("dome: train (proxy)", 1.0, 0);    // 0.2 + 0.4 * (1 + 3 * 1) / 4
  cb("something else", 0.1, 0);         // keeps the last fraction
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_NEAR(seen[0].second, 0.25, 1e-12);
  EXPECT_NEAR(seen[1].second, 0.6, 1e-12);
  EXPECT_NEAR(seen[2].second, 0.6, 1e-12);
  EXPECT_EQ(seen[0].first, "force-model: dome: train recording");
  EXPECT_EQ(seen[2].first, "force-model: something else");
}

TEST(ReportProgress, EmptyCallbackIsSilent) {
  Options o;
  Context c{o, "tap", {}};
  c.progress(0.5, "x");  // must not throw or print
  SUCCEED();
}

TEST(ReportMesh, ColoursRunFromBlueAtLowToRedAtHigh) {
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  m.triangles = {{0, 1, 2}};
  const nlohmann::json j = colored_mesh_json(m, {0.0, 10.0, 20.0}, 0.0, 10.0, Vec3(1, 0, 0));
  EXPECT_EQ(j["positions"], nlohmann::json({1, 0, 0, 2, 0, 0, 1, 1, 0}));
  EXPECT_EQ(j["indices"], nlohmann::json({0, 1, 2}));
  const std::vector<double> c = j["colors"].get<std::vector<double>>();
  ASSERT_EQ(c.size(), 9u);
  // ramp(0) = (0.2, 0.35, 0.85); ramp(1) = (1 - 0.1, 0.8 - 0.65, 1 - 0.85); above hi clamps.
  EXPECT_NEAR(c[0], 0.2, 1e-9);
  EXPECT_NEAR(c[1], 0.35, 1e-9);
  EXPECT_NEAR(c[2], 0.85, 1e-9);
  EXPECT_NEAR(c[3], 0.9, 1e-9);
  EXPECT_NEAR(c[4], 0.15, 1e-9);
  EXPECT_NEAR(c[5], 0.15, 1e-9);
  EXPECT_NEAR(c[6], c[3], 1e-12);
}

TEST(ReportStrokes, SlidingHeightsKeepTheMiddleOfTheStroke) {
  // 81 samples 0.125 mm apart along x, in contact, HIP at height x / 10, IHIP 1 mm below it.
  std::vector<rendering::StrokeSample> s(81);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double x = 0.125 * double(i);
    s[i].hip = Vec3(x, 5, 0.1 * x);
    s[i].ihip = Vec3(x, 5, 0.1 * x - 1);
    s[i].contact = i != 40;  // one sample out of contact
  }
  std::vector<double> u, z;
  sliding_heights(s, Vec2(0, 5), Vec2(1, 0), 10.0, 1, u, z);
  // Kept: 0.2 <= x <= 9.8, i.e. x = 0.25 ... 9.75 (77 samples), minus the one out of contact.
  ASSERT_EQ(u.size(), 76u);
  EXPECT_DOUBLE_EQ(u.front(), 0.25);
  EXPECT_DOUBLE_EQ(u.back(), 9.75);
  EXPECT_NEAR(z.front(), 0.025 - 1, 1e-12);
}

TEST(ReportSteps, ListsTheNineStepsInTheThesisOrder) {
  std::vector<std::string> names;
  for (const Step& s : all_steps()) names.push_back(s.name);
  EXPECT_EQ(names, (std::vector<std::string>{"tap", "contacts", "shape", "palpation", "explore",
                                             "force-model", "strokes", "study", "data"}));
}

TEST(ReportSummary, TableRowsThenTimes) {
  StepRecord rec{{"tap", "3.2", "Tap", {}}, {}};
  rec.result.rows.push_back({"taps (count)", "12", "-"});
  rec.result.seconds = 2.5;
  rec.result.cpu_seconds = 2.0;
  rec.result.note = "ok";
  const std::string s = summary_text({rec}, 3.0, 2.3);
  // Columns at least 8 wide: "taps (count)" is 12, "12" pads to 8.
  EXPECT_NE(s.find("tap          taps (count)  12        -\n"), std::string::npos) << s;
  EXPECT_NE(s.find("tap             2.5 s wall    2.0 s CPU  ok\n"), std::string::npos) << s;
  EXPECT_NE(s.find("total 3.0 s wall, 2.3 s CPU\n"), std::string::npos) << s;
}

}  // namespace
}  // namespace inhap::report
