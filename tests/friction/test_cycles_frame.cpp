// The cycles reader for rigs that log less (issue 18, item 4): the measurement time column, the
// normal from the shape mesh and the direction from the angle when the columns are absent; and
// the samples beyond the rim of a shape mesh that `sys proxy` counts.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "friction/fake_device.hpp"
#include "friction/sys_helpers.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/friction/cycles_io.hpp"
#include "inhap/friction/mesh_rim.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/surface_frame.hpp"
#include "support/meshes.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace inhap::friction {
namespace {

// One reference point palpated on the fake device (plane z = 0, mu 0.5), 2 levels x 4
// directions, short and long plateaus.
const std::vector<CycleRecord>& palpated() {
  static const std::vector<CycleRecord> cycles = [] {
    PalpationConfig cfg;
    cfg.normal_forces = {1.0, 3.0};
    cfg.directions = 4;
    test::FakeContactParams prm;
    prm.encoder = 0.005;
    test::FakeContactDevice dev(prm);
    PalpationProtocol proto(cfg, dev.info(), 3, Vec3(1, 2, 0), Vec3::UnitZ());
    run_protocol(dev, proto, 5'000'000);
    EXPECT_FALSE(proto.failed()) << proto.error();
    return proto.cycles();
  }();
  return cycles;
}

/// Rewrites a CSV without the named columns (comment lines dropped).
void drop_columns(const std::string& in, const std::string& out,
                  const std::vector<std::string>& drop) {
  std::istringstream text(read_file(in));
  std::string line, result;
  std::vector<bool> keep;
  while (std::getline(text, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (keep.empty())
      for (const auto& c : cells)
        keep.push_back(std::find(drop.begin(), drop.end(), c) == drop.end());
    std::string row;
    for (std::size_t i = 0; i < cells.size(); ++i)
      if (keep[i]) row += (row.empty() ? "" : ",") + cells[i];
    result += row + "\n";
  }
  write_file_atomic(out, result);
}

void expect_same_fit(const SysModel& a, const SysModel& b) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i)
    for (std::size_t j = 0; j < a.points[i].borders.size(); ++j) {
      const auto& x = a.points[i].borders[j].result;
      const auto& y = b.points[i].borders[j].result;
      EXPECT_NEAR(x.f_limit, y.f_limit, 1e-9) << j;
      EXPECT_NEAR(x.radius, y.radius, 1e-9) << j;
      EXPECT_NEAR(x.depth, y.depth, 1e-9) << j;
    }
}

TEST(CyclesFrame, MeasurementTimeIsWrittenReadAndChecked) {
  test::TempDir dir;
  const auto& c = palpated();
  // The protocol measures 90 ms into the plateau, on the first servo tick at or after it.
  for (const CycleRecord& r : c)
    if (r.status == CycleStatus::kOk) {
      EXPECT_GE(r.t_measurement_s, 0.09 - 1e-9);
      EXPECT_LE(r.t_measurement_s, 0.09 + 1e-3 + 1e-9);
    }
  write_cycles_csv(dir.path("c.csv"), c);
  const auto back = read_cycles_csv(dir.path("c.csv"));
  for (std::size_t i = 0; i < c.size(); ++i)
    EXPECT_DOUBLE_EQ(back[i].t_measurement_s, c[i].t_measurement_s);
  // Without the column: the protocol's 90 ms.
  drop_columns(dir.path("c.csv"), dir.path("n.csv"), {"t_measurement"});
  EXPECT_EQ(read_cycles_csv(dir.path("n.csv")).front().t_measurement_s, 0.09);
  // A measurement after the plateau ended is an error naming the line.
  write_file_atomic(dir.path("late.csv"),
                    "point,fn,ft,t_plateau,dir,tx,ty,tz,pcx,pcy,pcz,ncx,ncy,ncz,fmx,fmy,fmz,umx,"
                    "umy,umz,prx,pry,prz,t_measurement\n"
                    "0,1,0.1,0.1,0,1,0,0,0,0,0,0,0,1,0,0,1,0,0,0,0,0,0,0.25\n");
  try {
    read_cycles_csv(dir.path("late.csv"));
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 2u);
    EXPECT_NE(std::string(e.what()).find("t_measurement <= t_plateau"), std::string::npos)
        << e.what();
  }
}

// The fit compares every step at the protocol's 90 ms: the cycle of a step measured nearer to
// it is the one used. Corrupting the measurement of the other cycle changes nothing.
TEST(CyclesFrame, FitUsesTheMeasurementNearestTheProtocolTime) {
  const auto& c = palpated();
  const SysModel truth = fit_sys(c);
  const double short_tp = 0.1;
  std::vector<CycleRecord> late_long = c, late_short = c;
  for (CycleRecord& r : late_long)
    if (r.t_plateau > short_tp + 1e-9) {  // measured at the end of the 600 ms plateau
      r.t_measurement_s = r.t_plateau;
      r.u_meas += Vec3(0.7, -0.4, 0.3);
      r.f_meas += Vec3(0.2, 0.1, 0.0);
    }
  {
    SCOPED_TRACE("long cycles measured late");
    expect_same_fit(fit_sys(late_long), truth);
  }
  // The other way round (steps whose two cycles ended normally): the short cycle measured late
  // and corrupted, the long one at 90 ms with the short one's true measurement (u, f and n_c; its
  // own p_c and release point stay, they give u^p).
  int swapped = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c[i].t_plateau > short_tp + 1e-9 || c[i].status != CycleStatus::kOk) continue;
    for (CycleRecord& l : late_short)
      if (l.t_plateau > short_tp + 1e-9 && l.status == CycleStatus::kOk && l.point == c[i].point &&
          l.direction == c[i].direction && l.f_normal == c[i].f_normal &&
          l.f_tangential == c[i].f_tangential) {
        l.u_meas = c[i].u_meas, l.f_meas = c[i].f_meas, l.nc = c[i].nc;
        l.t_measurement_s = 0.09;
        late_short[i].t_measurement_s = 0.1;
        late_short[i].u_meas += Vec3(0.7, -0.4, 0.3);
        late_short[i].f_meas += Vec3(0.2, 0.1, 0.0);
        ++swapped;
      }
  }
  EXPECT_GT(swapped, 20);
  SCOPED_TRACE("short cycles measured late");
  expect_same_fit(fit_sys(late_short), truth);
}

// On a plane the protocol's frame is known exactly: n = +z, t_k = cos a t_0 + sin a t_1.
TEST(CyclesFrame, NormalAndDirectionFromTheShapeAndTheAngle) {
  test::TempDir dir;
  const auto& c = palpated();
  write_cycles_csv(dir.path("c.csv"), c);
  drop_columns(dir.path("c.csv"), dir.path("bare.csv"), {"tx", "ty", "tz", "ncx", "ncy", "ncz"});
  const PlaneShape plane(Vec3::Zero(), Vec3::UnitZ());
  const auto back = read_cycles_csv(dir.path("bare.csv"), CycleGeometry{&plane, Vec3::UnitX()});
  ASSERT_EQ(back.size(), c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_NEAR((back[i].nc - Vec3::UnitZ()).norm(), 0, 1e-12) << i;
    EXPECT_NEAR((back[i].tdir - c[i].tdir).norm(), 0, 1e-9) << i;
  }
  expect_same_fit(fit_sys(back), fit_sys(c));
  // Without a shape the normal columns are required; without the angle, the direction ones.
  try {
    read_cycles_csv(dir.path("bare.csv"));
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("ncx,ncy,ncz"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--mesh"), std::string::npos) << e.what();
  }
  drop_columns(dir.path("c.csv"), dir.path("noangle.csv"), {"tx", "ty", "tz", "angle"});
  EXPECT_THROW(read_cycles_csv(dir.path("noangle.csv")), ParseError);
  drop_columns(dir.path("c.csv"), dir.path("partial.csv"), {"ty"});
  EXPECT_THROW(read_cycles_csv(dir.path("partial.csv")), ParseError);
}

// On a sphere mesh the normal at p_c is the radial direction (to the mesh's resolution) and the
// direction is built in its tangent plane.
TEST(CyclesFrame, NormalFromACurvedMesh) {
  test::TempDir dir;
  const double radius = 30.0;
  const MeshSurface sphere(test::make_sphere(radius, 5), 0.0);
  std::string csv =
      "point,fn,ft,t_plateau,dir,angle,pcx,pcy,pcz,fmx,fmy,fmz,umx,umy,umz,prx,pry,prz\n";
  std::vector<Vec3> pcs;
  for (int i = 0; i < 12; ++i) {
    const double th = 0.2 + 0.1 * i, ph = 0.5 * i;
    const Vec3 pc =
        radius * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    pcs.push_back(pc);
    csv +=
        fmt::format("{},1,0.2,0.1,{},{},{},{},{},0,0,1,0,0,0,{},{},{}\n", i, i % 4,
                    (i % 4) * std::numbers::pi / 2, pc.x(), pc.y(), pc.z(), pc.x(), pc.y(), pc.z());
  }
  write_file_atomic(dir.path("s.csv"), csv);
  const auto cycles = read_cycles_csv(dir.path("s.csv"), CycleGeometry{&sphere, Vec3::UnitX()});
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    const Vec3 n = pcs[i].normalized();
    EXPECT_NEAR((cycles[i].nc - n).norm(), 0, 2e-3) << i;
    Vec3 t0, t1;
    tangent_basis(n, Vec3::UnitX(), t0, t1);
    const double a = cycles[i].angle;
    EXPECT_NEAR((cycles[i].tdir - (std::cos(a) * t0 + std::sin(a) * t1)).norm(), 0, 5e-3) << i;
    EXPECT_NEAR(cycles[i].tdir.dot(cycles[i].nc), 0, 1e-12) << i;
  }
  // p_c far from the shape: an error naming the line.
  write_file_atomic(dir.path("far.csv"),
                    "point,fn,ft,t_plateau,dir,angle,pcx,pcy,pcz,fmx,fmy,fmz,umx,umy,umz,prx,pry,"
                    "prz\n0,1,0.2,0.1,0,0,0,0,90,0,0,1,0,0,0,0,0,90\n");
  EXPECT_THROW(read_cycles_csv(dir.path("far.csv"), CycleGeometry{&sphere, Vec3::UnitX()}),
               ParseError);
}

// A flat 20 x 20 mm patch (x, y in [0, 20]): beside an edge the distance beyond the rim is the
// in-plane distance to the patch (beside a corner, the larger of the two); over the patch, or
// straight above/below the rim, zero.
TEST(MeshRimTest, DistanceBeyondTheRimOfAFlatPatch) {
  const MeshRim rim(test::make_grid_mesh(11, 11, 2.0));
  ASSERT_TRUE(rim.has_rim());
  EXPECT_EQ(rim.beyond_mm(Vec3(10, 10, -1)), 0.0);
  EXPECT_EQ(rim.beyond_mm(Vec3(19.5, 7, -2)), 0.0);
  EXPECT_NEAR(rim.beyond_mm(Vec3(20, 7, -2)), 0.0, 1e-12);
  for (double d : {0.05, 0.5, 3.0}) {
    EXPECT_NEAR(rim.beyond_mm(Vec3(20 + d, 7, -1)), d, 1e-9);  // on an edge, +x side
    EXPECT_NEAR(rim.beyond_mm(Vec3(9, -d, 0.5)), d, 1e-9);     // -y side, above the plane
    EXPECT_NEAR(rim.beyond_mm(Vec3(20 + d, 8, -1)), d, 1e-9);  // at a rim vertex (y = 8)
  }
  EXPECT_NEAR(rim.beyond_mm(Vec3(21, 22, -1)), 2.0, 1e-9);  // beside the corner: the larger side
  // A closed mesh has no rim.
  const MeshRim sphere(test::make_sphere(10, 2));
  EXPECT_FALSE(sphere.has_rim());
  EXPECT_EQ(sphere.beyond_mm(Vec3(20, 0, 0)), 0.0);
}

// `sys proxy` on a probe pressing 1 mm into a flat patch and sliding 8 mm past its +x rim: the
// samples past the rim are counted, flagged in column beyond_mesh, and warned about.
TEST(MeshRimTest, SysProxyCountsSamplesBeyondTheRim) {
  test::TempDir dir;
  write_mesh(dir.path("patch.ply"), test::make_grid_mesh(11, 11, 2.0));
  write_sys_json(dir.path("sys.json"),
                 test::coulomb_sys(
                     test::grid_points(2, 2, 10.0), [](std::size_t) { return 0.5; }, 1.0, 0.8));
  Recording rec;
  std::size_t expected = 0;
  for (int i = 0; i <= 2000; ++i) {  // x from 12 to 28 mm at 1 mm depth, 8 mm/s
    const double x = 12.0 + 0.008 * i;
    rec.t.push_back(1e-3 * i);
    rec.p.emplace_back(x, 10.0, -1.0);
    rec.f.emplace_back(0.0, 0.0, 1.0);
    if (x > 20.0 + 0.01) ++expected;
  }
  write_recording(dir.path("rec.csv"), rec);
  const auto r =
      test::run_cli("sys proxy " + dir.path("rec.csv") + " --sys " + dir.path("sys.json") +
                    " --mesh " + dir.path("patch.ply") + " --out " + dir.path("out.csv"));
  ASSERT_EQ(r.status, 0) << r.out;
  const CsvTable t = read_csv(dir.path("out.csv"));
  const auto& flag = t.column("beyond_mesh");
  const auto& contact = t.column("contact");
  std::size_t flagged = 0, in_contact_past_rim = 0;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    flagged += flag[i] > 0.5;
    in_contact_past_rim += contact[i] > 0.5 && rec.p[i].x() > 20.01;
    if (flag[i] > 0.5) {
      EXPECT_GT(rec.p[i].x(), 20.01) << i;
    }
  }
  EXPECT_EQ(flagged, in_contact_past_rim);
  EXPECT_GT(flagged, expected / 2) << r.out;  // the probe stays in contact past the rim
  EXPECT_NE(r.out.find(fmt::format("{} beyond the mesh rim", flagged)), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("inhap: warning: " + std::to_string(flagged)), std::string::npos) << r.out;
  // Inside the patch: nothing counted, no warning.
  Recording inside = rec;
  for (Vec3& p : inside.p) p.x() -= 10.0;  // x from 2 to 18 mm
  write_recording(dir.path("in.csv"), inside);
  const auto r2 =
      test::run_cli("sys proxy " + dir.path("in.csv") + " --sys " + dir.path("sys.json") +
                    " --mesh " + dir.path("patch.ply") + " --out " + dir.path("out2.csv"));
  ASSERT_EQ(r2.status, 0) << r2.out;
  EXPECT_NE(r2.out.find(" 0 beyond the mesh rim"), std::string::npos) << r2.out;
  EXPECT_EQ(r2.out.find("warning"), std::string::npos) << r2.out;
}

}  // namespace
}  // namespace inhap::friction
