// `model train | eval` and `eval recordings` on recordings as a rig writes them: 66 Hz with
// jittered stamps, no proxy, no mesh, no palpation cycles (tests/support/palpation_rig.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "support/palpation_rig.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace inhap::datadriven {
namespace {

using inhap::test::run_cli;

struct Trials {
  inhap::test::TempDir dir;
  std::string train = dir.path("t1.csv"), test = dir.path("t2.csv");
  Trials() {
    inhap::test::PalpationRig rig;
    write_recording(train, rig.record(120.0));
    rig.seed = 2;
    rig.point += 0.2 * rig.frame().n;  // the second trial: the phantom a little higher
    write_recording(test, rig.record(60.0));
  }
};

TEST(CliRecordings, ModelTrainEstimatesWhatARigRecordingLacksAndEvalScoresBaselines) {
  Trials t;
  const std::string m = t.dir.path("m.json");
  const auto r = run_cli("model train --recording " + t.train + " --out " + m);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("estimated from the recording"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(t.dir.path("m.surface.ply")));
  EXPECT_TRUE(std::filesystem::exists(t.dir.path("m.sys.json")));
  const auto model = nlohmann::json::parse(read_file(m));
  EXPECT_EQ(model["proxy_source"], "estimated");
  EXPECT_EQ(model["estimated"], nlohmann::json::array({"surface", "normals", "proxy", "friction"}));
  EXPECT_EQ(model["references"]["recording"]["path"], t.train);
  // The velocity window in seconds: 16 ms at 66 Hz is one sample.
  EXPECT_EQ(model["foaw"]["max_window"], 1);
  EXPECT_NEAR(model["foaw"]["dt_s"].get<double>(), 1.0 / 66, 1e-3);

  const auto e = run_cli("model eval --model " + m + " --recording " + t.test + " --json " +
                         t.dir.path("e.json"));
  ASSERT_EQ(e.status, 0) << e.out;
  const auto ev = nlohmann::json::parse(read_file(t.dir.path("e.json")));
  for (const char* b : {"mean", "knn_p", "knn_pv"})
    ASSERT_TRUE(ev["baselines"].contains(b)) << ev.dump(1);
  EXPECT_NE(e.out.find("knn_pv"), std::string::npos) << e.out;
  // A rig with a known law: the model is closer than the mean force on the normal axis.
  EXPECT_LT(ev["errors"]["rmse_n"]["z"].get<double>(),
            ev["baselines"]["mean"]["rmse_n"][2].get<double>());
}

TEST(CliRecordings, EvalRecordingsWritesTheComparisonAndTheCurves) {
  Trials t;
  const auto r = run_cli("eval recordings --train " + t.train + " --test " + t.test + " --json " +
                         t.dir.path("r.json") + " --csv " + t.dir.path("r.csv"));
  ASSERT_EQ(r.status, 0) << r.out;
  const auto j = nlohmann::json::parse(read_file(t.dir.path("r.json")));
  ASSERT_EQ(j["model"]["rmse_n"].size(), 3u);
  EXPECT_GT(j["model"]["re_median"].get<double>(), 0.0);
  for (const char* b : {"mean", "knn_p", "knn_pv"})
    EXPECT_EQ(j["baselines"][b]["rmse_n"].size(), 3u);
  EXPECT_NEAR(j["rate_hz"].get<double>(), 66.0, 3.0);
  EXPECT_EQ(j["estimated"].size(), 4u);
  // t, measured, model and best-baseline forces: one row per scored sample after the header.
  std::size_t rows = 0;
  const std::string csv = read_file(t.dir.path("r.csv"));
  std::size_t at = 0;
  while (at < csv.size()) {
    const std::size_t nl = csv.find('\n', at);
    if (csv[at] != '#') ++rows;
    at = nl == std::string::npos ? csv.size() : nl + 1;
  }
  EXPECT_EQ(rows, j["samples"].get<std::size_t>() + 1);
}

TEST(CliRecordings, ProxyPrefixErrorsSayWhatIsWrongAndPMeansTheProbe) {
  Trials t;
  const auto bad = run_cli("model train --recording " + t.train + " --proxy-prefix zz --out " +
                           t.dir.path("b.json"));
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.out.find(t.train), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("zzx,zzy,zzz"), std::string::npos) << bad.out;
  const auto p = run_cli("model train --recording " + t.train + " --proxy-prefix p --out " +
                         t.dir.path("p.json"));
  ASSERT_EQ(p.status, 0) << p.out;
  EXPECT_EQ(nlohmann::json::parse(read_file(t.dir.path("p.json")))["proxy_source"],
            "probe (--proxy-prefix p)");
}

TEST(CliRecordings, MillisecondsAndMetresByFlagGiveTheSameModel) {
  Trials t;
  Recording r = read_recording(t.train);
  for (double& x : r.t) x *= 1e3;
  for (Vec3& p : r.p) p *= 1e-3;
  const std::string raw = t.dir.path("raw.csv");
  write_recording(raw, r);
  ASSERT_EQ(run_cli("model train --recording " + t.train + " --out " + t.dir.path("a.json")).status,
            0);
  const auto b = run_cli("model train --recording " + raw +
                         " --time-unit ms --length-unit m --out " + t.dir.path("b.json"));
  ASSERT_EQ(b.status, 0) << b.out;
  std::string ea, eb;
  for (const char* m : {"a", "b"}) {
    const auto e =
        run_cli("model eval --model " + t.dir.path(std::string(m) + ".json") + " --recording " +
                t.test + " --json " + t.dir.path(std::string(m) + "-e.json"));
    ASSERT_EQ(e.status, 0) << e.out;
  }
  const auto ja = nlohmann::json::parse(read_file(t.dir.path("a-e.json")));
  const auto jb = nlohmann::json::parse(read_file(t.dir.path("b-e.json")));
  for (const char* a : {"x", "y", "z"})
    EXPECT_NEAR(ja["errors"]["rmse_n"][a].get<double>(), jb["errors"]["rmse_n"][a].get<double>(),
                0.01 * ja["errors"]["rmse_n"][a].get<double>() + 1e-3);
}

}  // namespace
}  // namespace inhap::datadriven
