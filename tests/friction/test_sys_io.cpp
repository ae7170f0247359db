// Cycles CSV, sys.json and the `inhap sys` commands, on palpations of the fake device.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <cstdio>

#include <fstream>

#include "friction/fake_device.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/friction/cycles_io.hpp"
#include "inhap/friction/sys_model.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace inhap::friction {
namespace test_sys_io {

// mu grows linearly with x: 0.3 at x = -20, 0.6 at x = 20.
double mu_at(const Vec3& x) {
  return 0.45 + 0.0075 * x.x();
}

const std::vector<Vec3>& points() {
  static const std::vector<Vec3> p = {Vec3(-20, -10, 0), Vec3(20, -10, 0), Vec3(0, 15, 0)};
  return p;
}

// Palpation of three reference points (2 levels x 4 directions to keep the test fast).
const std::vector<CycleRecord>& palpated() {
  static const std::vector<CycleRecord> cycles = [] {
    std::vector<CycleRecord> all;
    PalpationConfig cfg;
    cfg.normal_forces = {1.0, 3.0};
    cfg.directions = 4;
    test::FakeContactParams prm;
    prm.mu_field = mu_at;
    prm.encoder = 0.005;
    test::FakeContactDevice dev(prm);
    for (std::size_t i = 0; i < points().size(); ++i) {
      PalpationProtocol proto(cfg, dev.info(), static_cast<int>(10 + i), points()[i],
                              Vec3::UnitZ());
      run_protocol(dev, proto, 5'000'000);
      EXPECT_FALSE(proto.failed()) << proto.error();
      all.insert(all.end(), proto.cycles().begin(), proto.cycles().end());
    }
    return all;
  }();
  return cycles;
}

TEST(CyclesCsv, RoundTrip) {
  test::TempDir dir;
  const auto& c = palpated();
  write_cycles_csv(dir.path("c.csv"), c);
  const auto back = read_cycles_csv(dir.path("c.csv"));
  ASSERT_EQ(back.size(), c.size());
  for (std::size_t i = 0; i < c.size(); i += 7) {
    EXPECT_EQ(back[i].point, c[i].point);
    EXPECT_EQ(back[i].direction, c[i].direction);
    EXPECT_EQ(back[i].status, c[i].status);
    EXPECT_DOUBLE_EQ(back[i].f_tangential, c[i].f_tangential);
    EXPECT_NEAR((back[i].pr - c[i].pr).norm(), 0, 1e-9);
    EXPECT_NEAR((back[i].u_meas - c[i].u_meas).norm(), 0, 1e-9);
    EXPECT_NEAR((back[i].tdir - c[i].tdir).norm(), 0, 1e-9);
  }
}

TEST(CyclesCsv, ErrorsNameFileLineAndExpectation) {
  test::TempDir dir;
  const std::string p = dir.path("bad.csv");
  {
    std::ofstream f(p);
    f << "# "
         "units\npoint,fn,ft,t_plateau,dir,tx,ty,tz,pcx,pcy,pcz,ncx,ncy,ncz,fmx,fmy,fmz,umx,umy,"
         "umz,prx,pry,prz\n"
      << "0,1,0.1,0.1,0,1,0,0,0,0,0,0,0,1,0,0,1,0,0,0,0,0,0\n"
      << "1.5,1,0.1,0.1,0,1,0,0,0,0,0,0,0,1,0,0,1,0,0,0,0,0,0\n";
  }
  try {
    read_cycles_csv(p);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 4u);
    EXPECT_NE(std::string(e.what()).find("expected an integer point"), std::string::npos)
        << e.what();
  }
  {
    std::ofstream f(p);
    f << "point,fn,ft\n0,1,0.1\n";
  }
  EXPECT_THROW(read_cycles_csv(p), ParseError);
}

TEST(SysFit, RecoversAnInhomogeneousFrictionField) {
  const SysModel m = fit_sys(palpated());
  ASSERT_EQ(m.points.size(), 3u);
  EXPECT_EQ(m.reference_mesh.triangles().size(), 1u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(m.points[i].id, static_cast<int>(10 + i));
    EXPECT_NEAR((m.points[i].position - points()[i]).norm(), 0, 1e-9);
    for (std::size_t j = 0; j < 2; ++j)
      for (std::size_t k = 0; k < 4; ++k) {
        const double truth = mu_at(points()[i]) * m.f_normal_levels[j];
        EXPECT_NEAR(m.border(i, j, k).result.f_limit, truth, 0.05 * truth)
            << i << " " << j << " " << k;
      }
  }
}

TEST(SysJson, RoundTripAndValidation) {
  test::TempDir dir;
  const SysModel m = fit_sys(palpated());
  write_sys_json(dir.path("sys.json"), m);
  const SysModel b = read_sys_json(dir.path("sys.json"));
  ASSERT_EQ(b.points.size(), m.points.size());
  EXPECT_EQ(b.reference_mesh.triangles(), m.reference_mesh.triangles());
  EXPECT_EQ(b.angles, m.angles);
  EXPECT_EQ(b.force_frame, m.force_frame);
  for (std::size_t i = 0; i < m.points.size(); ++i)
    for (double lv : {0.5, 1.5, 4.0})
      for (double th : {0.1, 2.0, 4.0}) {
        EXPECT_DOUBLE_EQ(b.points[i].gs.radius_at(lv, th), m.points[i].gs.radius_at(lv, th));
        EXPECT_DOUBLE_EQ(b.points[i].fs.radius_at(lv, th), m.points[i].fs.radius_at(lv, th));
      }
  const auto rows = table_4_1(b, 11, 3.0, 2);
  const auto rows0 = table_4_1(m, 11, 3.0, 2);
  ASSERT_EQ(rows.size(), rows0.size());
  EXPECT_DOUBLE_EQ(rows.back().growth, rows0.back().growth);
  EXPECT_THROW(table_4_1(b, 99, 1.0, 0), Error);

  // Validation: wrong version, a non-unit normal, a bad triangle.
  std::string text = read_file(dir.path("sys.json"));
  auto write_variant = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const auto pos = t.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    t.replace(pos, from.size(), to);
    write_file_atomic(dir.path("bad.json"), t);
  };
  write_variant("\"version\": 1", "\"version\": 7");
  EXPECT_THROW(read_sys_json(dir.path("bad.json")), ParseError);
  write_variant("\"format\": \"inhap-sys\"", "\"format\": \"other\"");
  EXPECT_THROW(read_sys_json(dir.path("bad.json")), ParseError);
  write_variant("\"force_frame\": \"probe\"", "\"force_frame\": \"sideways\"");
  EXPECT_THROW(read_sys_json(dir.path("bad.json")), ParseError);
  write_file_atomic(dir.path("bad.json"), "{ not json");
  EXPECT_THROW(read_sys_json(dir.path("bad.json")), ParseError);
}

TEST(SysCli, FitAndTable) {
  test::TempDir dir;
  write_cycles_csv(dir.path("cycles.csv"), palpated());
  auto r = test::run_cli(
      fmt::format("sys fit {} --out {}", dir.path("cycles.csv"), dir.path("sys.json")));
  ASSERT_EQ(r.status, 0) << r.out;
  std::string out = r.out;
  EXPECT_NE(out.find("3 reference points"), std::string::npos) << out;
  r = test::run_cli(fmt::format("sys table {} --point 12 --fn 3 --dir 1", dir.path("sys.json")));
  ASSERT_EQ(r.status, 0) << r.out;
  out = r.out;
  EXPECT_NE(out.find("Table 4.1: reference point 12"), std::string::npos) << out;
  EXPECT_NE(out.find("sliding"), std::string::npos) << out;
  EXPECT_NE(out.find("elastic limit: f_T = "), std::string::npos) << out;
  r = test::run_cli(fmt::format("sys table {} --point 5", dir.path("sys.json")));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.out.find("inhap: error:"), std::string::npos) << r.out;
}

}  // namespace test_sys_io
}  // namespace inhap::friction
