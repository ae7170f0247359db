// `inhap sys palpate`, `sys proxy` and `eval sys` on the virtual lab, scored with its ground
// truth (the lab's mu at each reference point and its true tangential anchor).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/lab/recorder.hpp"
#include "inhap/lab/scene.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace inhap::friction {
namespace {

TEST(SysLab, PalpateThenProxyAgainstGroundTruth) {
  test::TempDir dir;
  const std::string sys = dir.path("sys.json");
  auto r = test::run_cli("sys palpate --scene planar --points grid:2x2:20 --quick --out " + sys);
  ASSERT_EQ(r.status, 0) << r.out;
  ASSERT_TRUE(std::filesystem::exists(dir.path("sys.cycles.csv")));
  ASSERT_TRUE(std::filesystem::exists(dir.path("sys.shape.ply")));
  const SysModel m = read_sys_json(sys);
  ASSERT_EQ(m.points.size(), 4u);
  EXPECT_EQ(m.reference_mesh.triangles().size(), 2u);
  const lab::Scene scene = lab::builtin_scene("planar");
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const double mu = scene.object.mu_at(m.points[i].position);
    for (std::size_t j = 0; j < m.f_normal_levels.size(); ++j)
      for (std::size_t k = 0; k < m.angles.size(); ++k) {
        const double truth = mu * m.f_normal_levels[j];
        EXPECT_NEAR(m.border(i, j, k).result.f_limit, truth, 0.08 * truth)
            << i << " " << j << " " << k;
      }
    EXPECT_NEAR(m.points[i].creep_viscosity, 0.02, 0.004);  // the lab's slip viscosity
  }
  // Fit again offline from the cycles (the real-device path) -> same limits.
  r = test::run_cli("sys fit " + dir.path("sys.cycles.csv") + " --mesh " +
                    dir.path("sys.shape.ply") + " --out " + dir.path("refit.json"));
  ASSERT_EQ(r.status, 0) << r.out;
  const SysModel refit = read_sys_json(dir.path("refit.json"));
  for (std::size_t i = 0; i < m.points.size(); ++i)
    EXPECT_NEAR(refit.border(i, 1, 2).result.f_limit, m.border(i, 1, 2).result.f_limit, 1e-6);

  // Proxy of an exploration recording against the lab's true anchor.
  r = test::run_cli("lab record --scene planar --operator explore --seconds 6 --seed 2 --out " +
                    dir.path("rec.csv"));
  ASSERT_EQ(r.status, 0) << r.out;
  r = test::run_cli("sys proxy --sys " + sys + " --mesh " + dir.path("sys.shape.ply") + " " +
                    dir.path("rec.csv") + " --out " + dir.path("rec_q.csv"));
  ASSERT_EQ(r.status, 0) << r.out;
  const Recording q = read_recording(dir.path("rec_q.csv"));
  const lab::TruthTable truth = lab::read_truth(dir.path("rec.truth.csv"));
  ASSERT_EQ(q.size(), truth.size());
  const auto *qx = q.find_extra("qx"), *qy = q.find_extra("qy"), *qz = q.find_extra("qz");
  ASSERT_TRUE(qx && qy && qz);
  // The estimator's contact flag and normal at q come along (model train needs no flags then):
  // on the planar top the normal is +z wherever the estimator is in contact.
  const auto *cf = q.find_extra("contact"), *nz = q.find_extra("nz");
  ASSERT_TRUE(cf && nz && q.find_extra("nx") && q.find_extra("ny"));
  std::size_t in_contact = 0;
  for (std::size_t i = 0; i < q.size(); ++i)
    if ((*cf)[i] != 0) {
      ++in_contact;
      EXPECT_NEAR((*nz)[i], 1.0, 1e-3) << i;
    }
  EXPECT_GT(in_contact, 1000u);
  std::vector<double> err;
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (!truth.contact[i]) {
      EXPECT_EQ(Vec3((*qx)[i], (*qy)[i], (*qz)[i]), q.p[i]);  // out of contact q = p
      continue;
    }
    err.push_back((Vec3((*qx)[i], (*qy)[i], (*qz)[i]) - truth.anchor[i]).norm());
  }
  ASSERT_GT(err.size(), 1000u);
  std::sort(err.begin(), err.end());
  EXPECT_LT(err[err.size() / 2], 0.3);
  EXPECT_LT(err[err.size() * 95 / 100], 1.0);
}

TEST(SysLab, EvalSysWritesTheReport) {
  test::TempDir dir;
  const auto r =
      test::run_cli("eval sys --quick --scenes planar --seconds 5 --json " + dir.path("o.json"));
  ASSERT_EQ(r.status, 0) << r.out;
  const auto j = nlohmann::json::parse(read_file(dir.path("o.json")));
  ASSERT_EQ(j["objects"].size(), 1u);
  const auto& o = j["objects"][0];
  EXPECT_EQ(o["name"], "planar");
  EXPECT_EQ(o["reference_points"], 4);
  for (const char* k : {"palpation_sim_hours", "palpation_wall_s"})
    EXPECT_GT(o[k].get<double>(), 0.0);
  EXPECT_LT(o["limit_rel_error"]["median"].get<double>(), 0.1);
  EXPECT_GE(o["limit_rel_error"]["max"].get<double>(),
            o["limit_rel_error"]["median"].get<double>());
  EXPECT_LT(o["proxy_error_mm"]["median"].get<double>(), 0.3);
  EXPECT_LT(o["proxy_error_mm"]["p95"].get<double>(), 1.0);
}

TEST(SysLab, BadArgumentsFailWithOneLine) {
  auto r = test::run_cli("sys palpate --scene nowhere --out /tmp/x.json");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.out.find("unknown scene"), std::string::npos) << r.out;
  r = test::run_cli("sys palpate --scene planar --points grid:0x3 --out /tmp/x.json");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.out.find("--points: expected"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace inhap::friction
