// inhap/eval/tca_report.hpp: `eval tca`'s table and JSON say what the study and the timing found.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "inhap/eval/tca_report.hpp"

namespace inhap::eval {
namespace {

TEST(TcaReport, TextAndJsonCarryTheStudysNumbers) {
  TcaStudyOptions o;
  o.participants = 1;
  o.trials = 1;
  o.seed = 3;
  const TcaEvalReport r = run_tca_eval(o, "");
  const auto [ts, cs, tk, ck] = tca_conditions(r.study.summary);
  const nlohmann::json j = tca_eval_json(r);
  EXPECT_EQ(j["participants"], 1);
  EXPECT_EQ(j["seed"], 3);
  EXPECT_DOUBLE_EQ(j["shape_correct"]["tca"].get<double>(), ts.mean);
  EXPECT_DOUBLE_EQ(j["stiffness_correct"]["cba"].get<double>(), ck.mean);
  EXPECT_EQ(j["triangles"].get<std::size_t>(), r.study_triangles);
  EXPECT_DOUBLE_EQ(j["step_us"]["p99"].get<double>(), std::max(r.cba_t.p99, r.tca_t.p99));
  EXPECT_GT(r.timing_triangles, 100000u);  // the 257 x 257 map: 2 * 256 * 256 triangles
  const std::string t = tca_eval_text(r);
  EXPECT_EQ(
      t.rfind("Virtual user study (thesis 5.4): 1 participants x 1 trials per session, seed 3", 0),
      0u)
      << t;
  EXPECT_NE(t.find(fmt::format("{:>7.2f} +- {:<4.2f}", ts.mean, ts.sd_participants)),
            std::string::npos);
}

}  // namespace
}  // namespace inhap::eval
