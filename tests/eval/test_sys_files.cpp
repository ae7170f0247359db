// inhap/eval/sys_files.hpp: the sliding yield surfaces on files (`inhap sys ...`), on models and
// recordings with known answers.
#include <gtest/gtest.h>

#include <cmath>

#include "friction/sys_helpers.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/sys_files.hpp"
#include "support/meshes.hpp"
#include "support/temp_dir.hpp"

namespace inhap::eval {
namespace {

TEST(SysFiles, SummaryListsTheCoulombLimits) {
  // mu = 0.5: the limit is 0.5 f_N in every direction (0.5, 1.5, 2.5 N at 1, 3, 5 N).
  const friction::SysModel m = test::coulomb_sys(
      {Vec3(0, 0, 0)}, [](std::size_t) { return 0.5; }, 1.0, 2.0);
  const std::string s = sys_summary(m);
  EXPECT_EQ(s.rfind("1 reference points, f_N levels 1 3 5 N, 8 directions", 0), 0u) << s;
  EXPECT_NE(s.find("    0         1   0.500   0.500"), std::string::npos) << s;
  EXPECT_NE(s.find("    0         5   2.500 "), std::string::npos) << s;
}

TEST(SysFiles, TableGivesTheLimitAtTheNearestLevel) {
  const friction::SysModel m = test::coulomb_sys(
      {Vec3(0, 0, 0)}, [](std::size_t) { return 0.4; }, 2.0, 4.0);
  const std::string s = table_4_1_text(m, 0, 2.6, 0);  // nearest level 3 N
  EXPECT_NE(s.find("f_N = 3 N"), std::string::npos) << s;
  EXPECT_NE(s.find("elastic limit: f_T = 1.200 N"), std::string::npos) << s;
  // u_elastic_limit: depth f_N / k_n = 1.5 mm, tangential mu f_N / k_t = 0.3 mm.
  EXPECT_NE(s.find("depth 1.500 mm, tangential 0.300 mm"), std::string::npos) << s;
}

TEST(SysFiles, ReferencePointsRoundTripAndNormalsMustBeUnit) {
  test::TempDir dir;
  const friction::MeshSurface shape(test::make_grid_mesh(4, 4, 10.0), 0.0);
  const std::vector<Vec3> pts = {Vec3(1, 2, 3), Vec3(-4, 5, 0.5)};
  const std::vector<Vec3> ns = {Vec3::UnitZ(), Vec3(0, 0.6, 0.8)};
  write_reference_points(dir.path("refs.csv"), pts, ns);
  std::vector<Vec3> p2, n2;
  read_reference_points(dir.path("refs.csv"), shape, p2, n2);
  ASSERT_EQ(p2.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_LT((p2[i] - pts[i]).norm(), 1e-9);
    EXPECT_LT((n2[i] - ns[i]).norm(), 1e-9);
  }
  write_reference_points(dir.path("bad.csv"), pts, {Vec3::UnitZ(), Vec3(0, 0, 2)});
  std::vector<Vec3> p3, n3;
  EXPECT_THROW(read_reference_points(dir.path("bad.csv"), shape, p3, n3), IoError);
}

TEST(SysFiles, ProxyOutOfContactIsTheProbe) {
  const friction::SysModel m = test::coulomb_sys(
      {Vec3(0, 0, 0)}, [](std::size_t) { return 0.5; }, 1.0, 2.0);
  const TriMesh plane = test::make_grid_mesh(5, 5, 10.0);  // z = 0
  Recording rec;
  for (int i = 0; i < 50; ++i) {  // 5 mm above the plane: never in contact
    rec.t.push_back(i * 1e-3);
    rec.p.push_back(Vec3(10 + 0.1 * i, 10, 5));
    rec.f.push_back(Vec3::Zero());
  }
  const ProxyFileResult r = add_proxy_columns(rec, m, plane, 0.0, true);
  EXPECT_EQ(r.contact, 0u);
  EXPECT_EQ(r.beyond, 0u);
  const auto* qx = rec.find_extra("qx");
  const auto* nz = rec.find_extra("nz");
  const auto* c = rec.find_extra("contact");
  ASSERT_TRUE(qx && nz && c && rec.find_extra("beyond_mesh"));
  for (std::size_t i = 0; i < rec.size(); ++i) {
    EXPECT_DOUBLE_EQ((*qx)[i], rec.p[i].x());
    EXPECT_DOUBLE_EQ((*nz)[i], 1.0);
    EXPECT_DOUBLE_EQ((*c)[i], 0.0);
  }
}

TEST(SysFiles, LabJsonHasTheQuantilesAndTheTableShowsThem) {
  SysLabResult res;
  res.palpation.sys = test::coulomb_sys(
      {Vec3(0, 0, 0), Vec3(10, 0, 0)}, [](std::size_t) { return 0.5; }, 1, 2);
  res.palpation.ticks = 3600000;  // one simulated hour
  res.palpation.wall_s = 4.0;
  res.limit_rel = {0.1, 0.3, 0.2};
  res.limit_rel_measured = {0.1};
  res.proxy.err = {0.0, 1.0, 2.0, 3.0, 4.0};
  const nlohmann::json j = sys_lab_json("dome", res);
  EXPECT_DOUBLE_EQ(j["limit_rel_error"]["median"].get<double>(), 0.2);
  EXPECT_DOUBLE_EQ(j["limit_rel_error"]["max"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(j["proxy_error_mm"]["median"].get<double>(), 2.0);
  EXPECT_NEAR(j["proxy_error_mm"]["p95"].get<double>(), 3.8, 1e-12);  // 3 + 0.8 (4 - 3)
  EXPECT_DOUBLE_EQ(j["palpation_sim_hours"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["palpation_wall_s_per_point"].get<double>(), 2.0);
  EXPECT_EQ(j["reference_points"].get<int>(), 2);
  const std::string t = sys_lab_table(nlohmann::json::array({j}));
  EXPECT_NE(t.find("dome          2          0.200          0.300            2.000            "
                   "3.800       1.00       2.00"),
            std::string::npos)
      << t;
}

}  // namespace
}  // namespace inhap::eval
