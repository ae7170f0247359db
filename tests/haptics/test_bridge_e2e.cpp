// The bridge end to end across process boundaries (issue: a haptic runtime, item 5): the virtual
// lab behind the C client (`inhap lab device`, its own process) drives inhap over loopback.
//   - taps recorded through the bridge (`inhap record`) give the contact points of a direct
//     `inhap lab record` of the same seed, while a flood of malformed datagrams hits the port;
//   - a palpation over the bridge (`inhap sys palpate --device udp`) gives the elastic limits
//     of the direct lab palpation;
//   - killing the device process makes the loop command zero force within one period after the
//     next state was due.
#include <arpa/inet.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/core/random.hpp"
#include "inhap/friction/palpation.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/haptics/bridge_device.hpp"
#include "inhap/haptics/servo_loop.hpp"
#include "support/run_cli.hpp"
#include "support/spawn.hpp"
#include "support/temp_dir.hpp"

namespace inhap {
namespace {

int test_port(int offset) {
  return 21000 + static_cast<int>(getpid() % 9000) * 4 + offset;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Random datagrams (some with the right magic) at the port until stopped.
class Flood {
 public:
  explicit Flood(int port) {
    thread_ = std::thread([this, port] {
      const int fd = socket(AF_INET, SOCK_DGRAM, 0);
      sockaddr_in a{};
      a.sin_family = AF_INET;
      a.sin_port = htons(static_cast<std::uint16_t>(port));
      inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
      Rng rng(7);
      std::uint8_t buf[160];
      while (!stop_) {
        const auto n = static_cast<std::size_t>(rng.uniform(0, 150));
        for (std::size_t i = 0; i < n; ++i) buf[i] = static_cast<std::uint8_t>(rng.next_u64());
        if (n >= 4 && rng.uniform(0, 1) < 0.5) {
          const std::uint32_t magic = haptics::kBridgeMagic;
          std::memcpy(buf, &magic, 4);
        }
        sendto(fd, buf, n, 0, reinterpret_cast<const sockaddr*>(&a), sizeof a);
        ++sent_;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
      close(fd);
    });
  }
  ~Flood() {
    stop_ = true;
    thread_.join();
  }
  long sent() const { return sent_; }

 private:
  std::atomic<bool> stop_{false};
  std::atomic<long> sent_{0};
  std::thread thread_;
};

TEST(BridgeEndToEnd, TapsThroughTheBridgeGiveTheContactPointsOfTheDirectRecording) {
  test::TempDir dir;
  const std::string lab_args = "--scene foam-ball --operator tap --probe tip --seconds 15 --seed 3";
  auto r = test::run_cli("lab record " + lab_args + " --out " + dir.path("direct.csv"));
  ASSERT_EQ(r.status, 0) << r.out;

  const int port = test_port(0);
  // --idle-stop 6: under a loaded ctest -j2 the flooded device stalled for more than 1.5 s and
  // the recording stopped early (12,477 of 15,000 rows).
  test::Child rec("record --device udp:" + std::to_string(port) + " --out " +
                      dir.path("bridge.csv") +
                      " --tool-mass 0.01 --no-realtime --idle-stop 6 --connect-timeout 60",
                  dir.path("record.log"));
  long flooded = 0;
  {
    Flood flood(port);
    test::Child device("lab device " + lab_args + " --port " + std::to_string(port) +
                           " --lockstep --connect-timeout 60",
                       dir.path("device.log"));
    EXPECT_EQ(device.wait(), 0) << slurp(dir.path("device.log"));
    flooded = flood.sent();
  }
  EXPECT_EQ(rec.wait(), 0) << slurp(dir.path("record.log"));
  const std::string log = slurp(dir.path("record.log"));
  EXPECT_GT(flooded, 100);
  EXPECT_NE(log.find("malformed"), std::string::npos) << log;

  const Recording direct = read_recording(dir.path("direct.csv"));
  const Recording bridge = read_recording(dir.path("bridge.csv"));
  ASSERT_EQ(bridge.size(), direct.size()) << log;
  for (std::size_t i = 0; i < direct.size(); ++i) {
    ASSERT_EQ(bridge.t[i], direct.t[i]) << "row " << i;
    ASSERT_LE((bridge.p[i] - direct.p[i]).norm(), 1e-9) << "row " << i;
    ASSERT_LE((bridge.f[i] - direct.f[i]).norm(), 1e-9) << "row " << i;
  }
  for (const char* which : {"direct", "bridge"}) {
    r = test::run_cli("shape contacts " + dir.path(std::string(which) + ".csv") + " --out " +
                      dir.path(std::string(which) + ".ply"));
    ASSERT_EQ(r.status, 0) << r.out;
  }
  const TriMesh a = read_mesh(dir.path("direct.ply")), b = read_mesh(dir.path("bridge.ply"));
  ASSERT_GE(a.num_vertices(), 8u) << "a 15 s tapping session has taps";
  ASSERT_EQ(b.num_vertices(), a.num_vertices());
  for (std::size_t i = 0; i < a.num_vertices(); ++i)
    EXPECT_LE((a.positions[i] - b.positions[i]).norm(), 1e-9) << "contact point " << i;
}

TEST(BridgeEndToEnd, APalpationOverTheBridgeGivesTheElasticLimitsOfTheDirectOne) {
  test::TempDir dir;
  auto r = test::run_cli("sys palpate --scene planar --quick --points grid:1x1 --seed 3 --out " +
                         dir.path("direct.json"));
  ASSERT_EQ(r.status, 0) << r.out;
  // Where the lab palpation placed its probe: above the first reference point.
  const CsvTable refs = read_csv(dir.path("direct.refs.csv"));
  ASSERT_EQ(refs.rows(), 1u);
  const Vec3 p(refs.column("x")[0], refs.column("y")[0], refs.column("z")[0]);
  const Vec3 n(refs.column("nx")[0], refs.column("ny")[0], refs.column("nz")[0]);
  const Vec3 place = p + (friction::PalpationConfig{}.hover + 3.0) * n;

  const int port = test_port(1);
  test::Child palpate("sys palpate --device udp:" + std::to_string(port) + " --shape " +
                          dir.path("direct.shape.ply") + " --refs " + dir.path("direct.refs.csv") +
                          " --quick --tool-mass 0.01 --connect-timeout 60 --out " +
                          dir.path("bridge.json"),
                      dir.path("palpate.log"));
  test::Child device(fmt::format("lab device --scene planar --operator none --seed 3 --seconds "
                                 "36000 --lockstep --connect-timeout 60 --port {} --place {},{},{}",
                                 port, place.x(), place.y(), place.z()),
                     dir.path("device.log"));
  ASSERT_EQ(palpate.wait(), 0) << slurp(dir.path("palpate.log"));
  EXPECT_EQ(device.wait(), 0) << slurp(dir.path("device.log"));
  EXPECT_NE(slurp(dir.path("device.log")).find("inhap stopped the session"), std::string::npos);

  const friction::SysModel d = friction::read_sys_json(dir.path("direct.json"));
  const friction::SysModel b = friction::read_sys_json(dir.path("bridge.json"));
  ASSERT_EQ(b.points.size(), d.points.size());
  std::size_t limits = 0;
  for (std::size_t i = 0; i < d.points.size(); ++i) {
    ASSERT_EQ(b.points[i].borders.size(), d.points[i].borders.size());
    for (std::size_t k = 0; k < d.points[i].borders.size(); ++k, ++limits) {
      const auto& x = d.points[i].borders[k].result;
      const auto& y = b.points[i].borders[k].result;
      EXPECT_NEAR(y.f_limit, x.f_limit, 1e-9 * std::max(1.0, std::abs(x.f_limit)))
          << "point " << i << " border " << k;
      EXPECT_NEAR(y.radius, x.radius, 1e-9) << "point " << i << " border " << k;
    }
  }
  EXPECT_GE(limits, 8u) << "2 levels x 4 directions";
}

// Constant small force: the watchdog's zero is what the test looks for.
class Push final : public haptics::Renderer {
 public:
  haptics::ServoOutput step(const haptics::ServoInput& in) noexcept override {
    haptics::ServoOutput o;
    o.force_n = Vec3(0, 0, 0.01);
    o.hip_mm = o.ihip_mm = o.cihip_mm = in.p_mm;
    return o;
  }
  void reset() noexcept override {}
  const char* name() const noexcept override { return "push"; }
};

TEST(BridgeEndToEnd, KillingTheDeviceProcessZeroesTheForceWithinOnePeriod) {
  test::TempDir dir;
  haptics::BridgeOptions o;
  o.port = static_cast<std::uint16_t>(test_port(2));
  haptics::BridgeDevice dev(o);
  test::Child device(
      "lab device --scene planar --operator none --seconds 60 --place 0,0,120 "
      "--connect-timeout 60 --port " +
          std::to_string(o.port),
      dir.path("device.log"));
  ASSERT_TRUE(dev.connect(60.0)) << slurp(dir.path("device.log"));
  Push push;
  haptics::LoopOptions lo;
  lo.realtime = false;
  haptics::ServoLoop loop(dev, push, lo);
  auto ring = std::make_unique<haptics::ObserverRing>();
  loop.add_observer(*ring);
  loop.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  device.kill();
  device.wait();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  loop.stop();

  std::vector<haptics::LoopSample> samples;
  for (haptics::LoopSample s; ring->pop(s);) samples.push_back(s);
  // The last tick with force (late datagrams before the kill may have zeroed single ticks).
  std::size_t last = samples.size();
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (samples[i].commanded_n.norm() > 0) last = i;
  ASSERT_LT(last + 10, samples.size()) << "ticks after the device died";
  const double delay_s = samples[last + 1].wall_s - samples[last].wall_s;
  for (std::size_t i = last + 1; i < samples.size(); ++i)
    EXPECT_EQ(samples[i].commanded_n.norm(), 0.0) << "force after the device died";
  const double period = 1.0 / dev.info().servo_rate_hz;
  // The next state was due one period after the last; zero force one period after that. The
  // margin is scheduling on a loaded test machine (the loop runs without real-time priority
  // here: with two CPU hogs beside it, 6.1-7.6 ms were seen, with and without the bridge's
  // busy-wait window; idle it is 2.1 ms); the figure is printed for the record.
  std::printf("zero force %.0f us after the last state (period %.0f us)\n", delay_s * 1e6,
              period * 1e6);
  EXPECT_LE(delay_s, 2 * period + 0.010);
}

}  // namespace
}  // namespace inhap
