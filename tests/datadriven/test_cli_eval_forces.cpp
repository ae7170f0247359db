// `inhap eval forces --quick` on the virtual lab: the report has every field the issue asks for,
// says where q came from (the proxy estimator by default), the estimated proxy is close to the
// lab's true one, and the proxy model beats the (p, pdot)-only model on sliding.
#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "inhap/core/atomic_file.hpp"
#include "inhap/lab/physics.hpp"
#include "support/temp_dir.hpp"

namespace inhap::datadriven {
namespace {

TEST(CliEvalForces, QuickReportHasAllFieldsAndTheProxyHelpsOnSliding) {
  inhap::test::TempDir dir;
  const std::string out = dir.path("forces.json"), log = dir.path("log.txt");
  const std::string cmd = std::string(INHAP_CLI) +
                          " eval forces --quick --scenes planar --centers 60 --json " + out +
                          " > " + log + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << read_file(log);
  const auto j = nlohmann::json::parse(read_file(out));
  EXPECT_EQ(j["proxy_source"], "estimated:sys");
  ASSERT_EQ(j["objects"].size(), 1u);
  const auto& o = j["objects"][0];
  EXPECT_EQ(o["name"], "planar");
  EXPECT_EQ(o["train_samples"], 32500);  // 65 s / 2 at 1 kHz
  EXPECT_EQ(o["test_samples"], 18500);
  for (const char* k : {"rmse_n", "median_ae_n"})
    for (const char* a : {"x", "y", "z"}) EXPECT_TRUE(o[k][a].is_number()) << k << a;
  for (const char* k : {"re", "no_proxy_re"})
    for (const char* s : {"mean", "median"}) EXPECT_TRUE(o[k][s].is_number()) << k << s;
  EXPECT_GT(o["train_s"].get<double>(), 0.0);
  EXPECT_GT(o["step_us"]["p99"].get<double>(), 0.0);
  EXPECT_EQ(o["proxy_source"], "estimated:sys");
  EXPECT_EQ(o["contact_source"], "estimated:geometric");
  EXPECT_EQ(o["reference_points"], 4);  // quick palpation: 2 x 2 grid
  EXPECT_GT(o["palpation_s"].get<double>(), 0.0);
  EXPECT_LT(o["proxy_vs_truth"]["q_rms_mm"].get<double>(), 0.5);
  EXPECT_GT(o["proxy_vs_truth"]["contact_agreement"].get<double>(), 0.99);
  const auto& sl = o["sliding_only"];
  EXPECT_GT(sl["samples"].get<int>(), 100);
  EXPECT_LT(sl["re"]["median"].get<double>(), 0.5 * sl["no_proxy_re"]["median"].get<double>());
}

// `--proxy recording` estimates the proxy as `model train` does without proxy columns, and
// trains as it does: no tangent mirror unless --tangent-mirror asks for it.
TEST(CliEvalForces, TheRecordingsProxyTrainsAsModelTrainDoes) {
  inhap::test::TempDir dir;
  for (const bool mirror : {false, true}) {
    const std::string out = dir.path(mirror ? "m.json" : "n.json"), log = dir.path("log.txt");
    const std::string cmd = std::string(INHAP_CLI) +
                            " eval forces --quick --scenes planar --rate 66 --proxy recording "
                            "--no-baselines --json " +
                            out + (mirror ? " --tangent-mirror" : "") + " > " + log + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << read_file(log);
    const auto j = nlohmann::json::parse(read_file(out));
    EXPECT_EQ(j["proxy_source"], "estimated:recording");
    EXPECT_EQ(j["contact_source"], "estimated:surface");
    EXPECT_EQ(j["objects"][0]["model"]["tangent_mirror"], mirror);
  }
}

// The targets for the dome (RMSE <= 0.25 N per axis, RE median <= 0.15) on MuJoCo's
// contact physics, logged at 66 and 200 Hz, the proxy estimated from the training recording
// alone. Its training run palpates a grid of spots; the test run sticks 4-5 mm sideways between
// them at 3-4 mm depth, where the RBFs extrapolated their u_t dependence and rendered half the
// normal force (z 0.263 N at 200 Hz before the fallback's normal line).
TEST(CliEvalForces, TheMujocoDomeAtRigRatesMeetsItsTargets) {
  if (!lab::mujoco_available()) GTEST_SKIP() << "this build has no MuJoCo";
  inhap::test::TempDir dir;
  for (const char* rate : {"66", "200"}) {
    const std::string out = dir.path(std::string("dome") + rate + ".json"),
                      log = dir.path("log.txt");
    const std::string cmd =
        std::string(INHAP_CLI) +
        " eval forces --physics mujoco --scenes dome --proxy recording --rate " + rate +
        " --no-baselines --json " + out + " > " + log + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << read_file(log);
    const auto o = nlohmann::json::parse(read_file(out))["objects"][0];
    for (const char* a : {"x", "y", "z"})
      EXPECT_LE(o["rmse_n"][a].get<double>(), 0.25) << rate << " Hz, axis " << a;
    EXPECT_LE(o["re"]["median"].get<double>(), 0.15) << rate << " Hz";
  }
}

}  // namespace
}  // namespace inhap::datadriven
