// inhap studio palpation view (include/inhap/studio/palpation.hpp): the protocol driven as the
// servo loop's renderer gives the same cycles as `sys palpate` (eval::palpate_points) on the same
// device and seed, the ring delivers every one of them in order, and the fit matches the lab's
// friction truth; a failed point allocates nothing on the servo thread; the session refuses
// palpate / save_sys messages it cannot act on. (This file includes support/alloc_counter.hpp
// for the whole test_studio program.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "inhap/eval/sys_lab.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/lab/sim_device.hpp"
#include "inhap/studio/hand_device.hpp"
#include "inhap/studio/palpation.hpp"
#include "inhap/studio/session.hpp"
#include "support/alloc_counter.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;
using namespace inhap::studio;

namespace {

void expect_same(const friction::CycleRecord& a, const friction::CycleRecord& b) {
  EXPECT_EQ(a.point, b.point);
  EXPECT_EQ(a.direction, b.direction);
  EXPECT_EQ(a.f_normal, b.f_normal);
  EXPECT_EQ(a.f_tangential, b.f_tangential);
  EXPECT_EQ(a.t_plateau, b.t_plateau);
  EXPECT_EQ(a.pc, b.pc);
  EXPECT_EQ(a.pr, b.pr);
  EXPECT_EQ(a.f_meas, b.f_meas);
  EXPECT_EQ(a.status, b.status);
}

// The lab dome, its device (seed 5) and the shape a palpation runs on (the probe centre's height
// field over the dome, mm).
struct Dome {
  lab::Scene scene = lab::builtin_scene("dome");
  lab::DeviceParams dp = [] {
    lab::DeviceParams p;
    p.seed = 5;
    return p;
  }();
  TriMesh shape_mesh =
      eval::shape_height_field(scene, dp.probe.radius_mm, scene.region.radius + 15.0);
  friction::MeshSurface shape{shape_mesh, 0.0};
  /// The probe centre dropped onto the dome `dx` mm beside the region's centre.
  std::optional<Vec3> drop(double dx) const {
    return scene.object.shape().drop(scene.region.center.x() + dx, scene.region.center.y(),
                                     dp.probe.radius_mm);
  }
};

}  // namespace

TEST(StudioPalpation, RendererGivesTheCyclesOfSysPalpateAndTheLabsFriction) {
  const Dome d;
  const lab::Scene& scene = d.scene;
  const lab::DeviceParams& dp = d.dp;
  const friction::MeshSurface& shape = d.shape;
  const auto top = d.drop(6.0);
  ASSERT_TRUE(top);
  Vec3 c, n;
  ASSERT_TRUE(shape.closest(*top, c, n));
  const friction::PalpationConfig cfg = eval::palpation_config(true);
  const Vec3 start = c + (cfg.hover + 3.0) * n;

  // `sys palpate`'s path.
  lab::SimDevice ref_dev(scene.object, dp);
  ref_dev.detach_hand();
  ref_dev.place(start);
  const eval::DevicePalpation ref = eval::palpate_points(ref_dev, shape, {c}, {n}, cfg, {}, "");
  ASSERT_GT(ref.cycles.size(), 20u);

  // The studio's: the lab device with the hand let go, ticked as ServoLoop::tick_once does.
  LabHandDevice dev(scene.object, dp, std::make_unique<DetachedOperator>(start), 20.0);
  PalpationRenderer r(cfg, dev.device_info(), {c}, {n}, shape);
  std::vector<friction::CycleRecord> streamed;
  for (long i = 0; !r.finished() && i < 2'000'000; ++i) {
    haptics::ServoInput in;
    in.t_s = dev.time();
    in.p_mm = dev.position();
    in.sensor_force_n = dev.force_sensor();
    in.has_sensor = true;
    const haptics::ServoOutput out = r.step(in);
    dev.command_force(out.force_n);
    dev.tick();
    friction::CycleRecord rec;
    while (r.finished_cycles().pop(rec)) streamed.push_back(rec);
  }
  ASSERT_TRUE(r.finished());
  EXPECT_EQ(r.error(), "");
  EXPECT_DOUBLE_EQ(r.progress(), 1.0);
  const auto cycles = r.cycles();
  ASSERT_EQ(cycles.size(), ref.cycles.size());
  ASSERT_EQ(streamed.size(), cycles.size());
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    expect_same(cycles[i], ref.cycles[i]);
    expect_same(streamed[i], cycles[i]);
  }

  // The fitted elastic limits against the lab's truth mu * f_N (measured ones, not extrapolated).
  const friction::SysModel sys = eval::fit_palpation(cycles, shape, cfg);
  const double mu = scene.object.mu_at(sys.points[0].position);
  std::vector<double> rel;
  for (std::size_t j = 0; j < sys.f_normal_levels.size(); ++j)
    for (std::size_t k = 0; k < sys.angles.size(); ++k) {
      const friction::BorderResult& b = sys.border(0, j, k).result;
      if (b.extrapolated || b.no_sliding) continue;
      rel.push_back(std::abs(b.f_limit - mu * sys.f_normal_levels[j]) /
                    (mu * sys.f_normal_levels[j]));
    }
  ASSERT_GE(rel.size(), 4u);
  std::sort(rel.begin(), rel.end());
  EXPECT_LT(rel[rel.size() / 2], 0.1);

  // What the page gets: one row of limits per level, one entry per direction.
  const nlohmann::json y = yield_json(sys);
  ASSERT_EQ(y["points"].size(), 1u);
  EXPECT_EQ(y["points"][0]["limits"].size(), sys.f_normal_levels.size());
  EXPECT_EQ(y["points"][0]["tdirs"].size(), sys.angles.size());
  EXPECT_DOUBLE_EQ(y["points"][0]["limits"][0][0]["f"].get<double>(),
                   sys.border(0, 0, 0).result.f_limit);
}

TEST(StudioPalpation, SessionRefusesWhatItCannotDo) {
  test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  StudioOptions o;
  Session s(o, ws, [](const std::string&) {});  // not started
  const auto type_of = [&](const std::string& text) {
    return nlohmann::json::parse(s.handle(text))["type"].get<std::string>();
  };
  // Before the palpation view has a shape, and with malformed points.
  EXPECT_EQ(type_of(R"({"type":"palpate","points":[[0,0,20]]})"), "error");
  EXPECT_EQ(type_of(R"({"type":"palpate","points":[]})"), "error");
  EXPECT_EQ(type_of(R"({"type":"palpate","points":"top"})"), "error");
  EXPECT_EQ(type_of(R"({"type":"palpate","points":[[0,0,20]],"speed":99})"), "error");
  // Nothing fitted yet; a path outside the workspace; not .json.
  EXPECT_EQ(type_of(R"({"type":"save_sys","path":"sys.json"})"), "error");
  EXPECT_EQ(type_of(R"({"type":"save_sys","path":"../sys.json"})"), "error");
  EXPECT_EQ(type_of(R"({"type":"save_sys","path":"sys.txt"})"), "error");
  EXPECT_FALSE(std::filesystem::exists(ws.root() / "sys.json"));
  // With the shape: a point 40 mm above it is not on it.
  EXPECT_EQ(type_of(R"({"type":"mode","mode":"palpation"})"), "ok");
  EXPECT_EQ(type_of(R"({"type":"palpate","points":[[0,0,80]]})"), "error");
  EXPECT_EQ(s.mode(), "palpation");
}

// The servo thread's side of a failed point allocates nothing: the protocol's reason stays a
// pointer to its static text until error() formats it on the reader's side. Two ways to fail: a
// reference point in the air (the approach finds no surface) and a non-finite device reading.
TEST(StudioPalpation, AFailedPointAllocatesNothingOnTheServoThread) {
  const Dome d;
  const lab::Scene& scene = d.scene;
  const lab::DeviceParams& dp = d.dp;
  const friction::MeshSurface& shape = d.shape;
  const auto top = d.drop(0.0);
  ASSERT_TRUE(top);
  const Vec3 n = Vec3::UnitZ(), air = *top + 20.0 * n;
  const friction::PalpationConfig cfg = eval::palpation_config(true);
  for (const bool nan_reading : {false, true}) {
    LabHandDevice dev(scene.object, dp,
                      std::make_unique<DetachedOperator>(air + (cfg.hover + 3.0) * n), 20.0);
    PalpationRenderer r(cfg, dev.device_info(), {air, *top}, {n, n}, shape);
    long ticks = 0, allocations = 0;
    for (; !r.finished() && ticks < 200'000; ++ticks) {
      haptics::ServoInput in;
      in.t_s = dev.time();
      in.p_mm = dev.position();
      in.sensor_force_n = dev.force_sensor();
      in.has_sensor = true;
      if (nan_reading && ticks == 500) in.sensor_force_n.x() = std::nan("");
      const long before = test::heap_allocations();
      const haptics::ServoOutput out = r.step(in);
      allocations += test::heap_allocations() - before;
      dev.command_force(out.force_n);
      dev.tick();
    }
    ASSERT_TRUE(r.finished()) << "nan " << nan_reading;
    EXPECT_EQ(allocations, 0) << "nan " << nan_reading;
    const std::string why =
        nan_reading ? "non-finite device reading" : "no contact found below the reference point";
    EXPECT_EQ(r.error(), "palpation of reference point 0 failed: " + why);
    if (nan_reading) {
      EXPECT_EQ(ticks, 501);  // failed at the tick that carried the NaN
    }
  }
}
