// inhap/eval/serve.hpp: the renderer, device and recorder wiring behind `inhap serve` / `inhap
// record`, reached without running the program.
#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <string>

#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/serve.hpp"
#include "inhap/lab/recorder.hpp"
#include "support/temp_dir.hpp"

namespace inhap::eval {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Serve, RendererChoiceAndItsFlags) {
  RendererOptions o;
  o.render = "none";
  const RenderSetup none = make_renderer(o);
  ASSERT_TRUE(none.renderer);
  EXPECT_STREQ(none.renderer->name(), "none");
  o.render = "tca";  // no mesh
  EXPECT_EQ(error_of([&] { make_renderer(o); }), "--render tca needs --mesh MESH.ply");
  o.render = "model";
  EXPECT_EQ(error_of([&] { make_renderer(o); }),
            "--render model needs --model MODEL.json, --sys SYS.json and --shape MESH.ply");
  o.render = "phong";
  EXPECT_NE(error_of([&] { make_renderer(o); }).find("expected tca, cba, model or none"),
            std::string::npos);
}

TEST(Serve, DeviceChecksItsFlags) {
  DeviceOptions o;
  o.max_force_n = 41;  // above kForceCeilingN
  EXPECT_NE(error_of([&] { make_device(o); }).find("--max-force"), std::string::npos);
  o.max_force_n = 6.2;
  o.device = "tcp:1";
  EXPECT_NE(error_of([&] { make_device(o); }).find("--device: expected udp"), std::string::npos);
  o.device = "udp:47999";  // the rate is checked before the socket is bound
  o.rate_hz = 50;
  EXPECT_NE(error_of([&] { make_device(o); }).find("--rate"), std::string::npos);
  EXPECT_TRUE(is_lab_device("lab:dome"));
  EXPECT_FALSE(is_lab_device("udp"));
}

TEST(Serve, KeyFromAFileWithoutItsLineEnd) {
  const test::TempDir dir;
  std::ofstream(dir.path("key")) << "s3cret\r\n";
  EXPECT_EQ(read_key("given", ""), "given");
  EXPECT_EQ(read_key("", dir.path("key")), "s3cret");
  std::ofstream(dir.path("empty")) << "\n";
  EXPECT_THROW(read_key("", dir.path("empty")), IoError);
  EXPECT_THROW(read_key("", dir.path("missing")), IoError);
}

haptics::LoopSample sample(double t, double x) {
  haptics::LoopSample s;
  s.t_s = t;
  s.p_mm = Vec3(x, 2 * x, 3);
  s.sensor_force_n = Vec3(0.5, 0, 1);
  s.commanded_n = Vec3(0, 0, 2);
  s.out.contact = true;
  s.out.ihip_mm = Vec3(x, 0, 0);
  s.out.cihip_mm = Vec3(0, x, 0);
  return s;
}

// The lab device's truth sidecar ends at the recording's last row (the loop's last tick is not
// in the recording), and a tick without a new device time is not a row.
TEST(Serve, RecordingAndTruthOfALabSession) {
  const test::TempDir dir;
  DeviceOptions o;
  o.device = "lab:planar";
  o.seconds = 0.05;
  DeviceSetup d = make_device(o);
  ASSERT_TRUE(d.lab);
  auto ring = std::make_unique<haptics::ObserverRing>();
  const std::string out = dir.path("rec.csv");
  LoopRecorder rec(out, d.device().info(), *ring);
  std::vector<double> times;
  for (int i = 0; i < 20; ++i) {
    times.push_back(d.device().time());
    d.device().tick();
  }
  for (int i = 0; i < 10; ++i) ring->push(sample(times[static_cast<std::size_t>(i)], i));
  ring->push(sample(times[9], 99));  // no new device sample: skipped
  finish_recording(rec, d, out);
  EXPECT_EQ(rec.rows(), 10u);
  EXPECT_EQ(rec.last_t(), times[9]);
  const Recording r = read_recording(out);
  ASSERT_EQ(r.size(), 10u);
  EXPECT_EQ(r.t[3], times[3]);
  EXPECT_EQ(r.p[3], Vec3(3, 6, 3));
  EXPECT_EQ(*r.find_extra("rfx"), std::vector<double>(10, 0.5));
  EXPECT_EQ((*r.find_extra("cfz"))[9], 2.0);
  EXPECT_EQ((*r.find_extra("qx"))[4], 4.0);
  EXPECT_EQ((*r.find_extra("cqy"))[5], 5.0);
  EXPECT_EQ((*r.find_extra("contact"))[0], 1.0);
  std::ifstream truth(lab::truth_path_for(out));
  int rows = 0;
  for (std::string line; std::getline(truth, line);)
    if (!line.empty() && line[0] != '#') ++rows;
  EXPECT_EQ(rows, 1 + 10);  // header + the ticks up to the last recorded one
}

TEST(Serve, TrimTruthKeepsRowsUpToTheTime) {
  lab::TruthTable t;
  for (int i = 0; i < 5; ++i) {
    t.t.push_back(i * 0.001);
    t.contact.push_back(i % 2);
    t.tap.push_back(i);
    t.tc.push_back(0);
    t.c.push_back(Vec3::Zero());
    t.anchor.push_back(Vec3::Zero());
    t.force.push_back(Vec3::Zero());
    t.k.push_back(1);
    t.mu.push_back(0.5);
  }
  trim_truth(t, 0.002);
  EXPECT_EQ(t.size(), 3u);
  EXPECT_EQ(t.mu.size(), 3u);
  EXPECT_EQ(t.tap.back(), 2);
  trim_truth(t, -1);
  EXPECT_EQ(t.size(), 0u);
}

TEST(Serve, StatsText) {
  haptics::LoopStats s;
  s.ticks = 1234;
  s.step_p50_us = 1.5;
  s.step_p99_us = 7.25;
  haptics::BridgeStats b;
  b.accepted = 1200;
  b.lost = 3;
  const std::string t = loop_stats_text(s, b);
  EXPECT_NE(t.find("ticks 1234  step p50/p99 1.50/7.25 us"), std::string::npos) << t;
  EXPECT_NE(t.find("bridge: accepted 1200  lost 3"), std::string::npos) << t;
  EXPECT_EQ(t.find("read-ahead"), std::string::npos) << t;  // a renderer that does not read ahead
  s.prefetch_p50_us = 0.25;
  s.prefetch_p99_us = 0.75;
  EXPECT_NE(loop_stats_text(s, b).find("read-ahead p50/p99 0.25/0.75 us"), std::string::npos);
}

TEST(Serve, WaitForDeviceGivesUpWhenStopped) {
  haptics::BridgeOptions bo;
  bo.port = 0;  // any free port
  haptics::BridgeDevice dev(bo);
  const std::atomic<bool> stop{true};
  EXPECT_NE(error_of([&] { wait_for_device(dev, 60, stop); }).find("no device joined"),
            std::string::npos);
}

}  // namespace
}  // namespace inhap::eval
