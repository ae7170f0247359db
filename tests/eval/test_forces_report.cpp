// inhap/eval/forces_report.hpp: the line `eval forces` prints and its report's head.
#include <gtest/gtest.h>

#include "inhap/eval/forces_report.hpp"

namespace inhap::eval {
namespace {

TEST(ForcesReport, SummaryLineCarriesTheErrors) {
  ForceLabResult d;
  d.name = "dome";
  d.proxy.all.rmse = {0.1, 0.2, 0.3};
  d.proxy.all.re_mean = 0.25;
  d.proxy.all.re_median = 0.125;
  d.proxy.replay.step_us = {1.0, 2.0, 3.0};  // p50 2 us
  d.train_track.proxy_source = "estimated:sys";
  const std::string s = force_lab_summary(d);
  EXPECT_EQ(s.rfind("dome: RMSE x/y/z 0.100 0.200 0.300 N", 0), 0u) << s;
  EXPECT_NE(s.find("RE mean 0.250 median 0.125"), std::string::npos) << s;
  EXPECT_NE(s.find("step p50 2.00 us p99 2.98 us; proxy estimated:sys"), std::string::npos) << s;
}

TEST(ForcesReport, HeadSaysWhereTheProxyCameFrom) {
  const auto est = forces_report_head("builtin", "estimated");
  EXPECT_EQ(est["proxy_source"], "estimated:sys");
  EXPECT_EQ(est["contact_source"], "estimated:geometric");
  const auto rec = forces_report_head("builtin", "recording");
  EXPECT_EQ(rec["proxy_source"], "estimated:recording");
  EXPECT_EQ(rec["contact_source"], "estimated:surface");
  const auto truth = forces_report_head("mujoco", "truth");
  EXPECT_EQ(truth["proxy_source"], "truth");
  EXPECT_EQ(truth["physics"], "mujoco");
  EXPECT_EQ(truth["units"]["force"], "N");
}

}  // namespace
}  // namespace inhap::eval
