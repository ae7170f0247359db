// The real-time servo loop: pacing, watchdog, observers, allocation-free steady state.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <thread>
#include <vector>

#include "inhap/haptics/servo_loop.hpp"
#include "inhap/haptics/spsc_ring.hpp"
// test_servo_interface.cpp replaces operator new for this program; count only here.
#define INHAP_ALLOC_COUNTER_COUNT_ONLY
#include "support/alloc_counter.hpp"

namespace inhap::haptics {
namespace {

// A scripted device: z goes down 0.01 mm per tick from 2 mm; faults in [fault_from, fault_to).
class ScriptDevice final : public Device {
 public:
  ScriptDevice() { info_.servo_rate_hz = 2000.0; }
  const DeviceInfo& info() const override { return info_; }
  double time() const override { return 1e-3 * static_cast<double>(ticks); }
  Vec3 position() const override { return {0.0, 0.0, 2.0 - 0.01 * static_cast<double>(ticks)}; }
  Vec3 force_sensor() const override { return Vec3::Zero(); }
  void command_force(const Vec3& f) override { last = f; }
  void tick() override {
    commanded.push_back(last);  // reserved in the tests
    ++ticks;
  }
  bool faulted() const override { return ticks >= fault_from && ticks < fault_to; }

  DeviceInfo info_;
  long ticks = 0;
  long fault_from = -1, fault_to = -1;
  Vec3 last = Vec3::Zero();
  std::vector<Vec3> commanded;
};

// A wall at z = 0 (0.5 N/mm); counts resets; samples the allocation counter at two ticks.
class Wall final : public Renderer {
 public:
  ServoOutput step(const ServoInput& in) noexcept override {
    ServoOutput o;
    o.hip_mm = o.ihip_mm = o.cihip_mm = in.p_mm;
    o.contact = in.p_mm.z() < 0;
    o.force_n = {0, 0, o.contact ? -0.5 * in.p_mm.z() : 0.0};
    if (steps == 100) alloc_at_100 = test::heap_allocations();
    if (steps == 1000) alloc_at_1000 = test::heap_allocations();
    ++steps;
    return o;
  }
  void reset() noexcept override { ++resets; }
  const char* name() const noexcept override { return "wall"; }
  long steps = 0, resets = 0, alloc_at_100 = -1, alloc_at_1000 = -1;
};

Vec3 dev_position(long tick) {
  return {0.0, 0.0, 2.0 - 0.01 * static_cast<double>(tick)};
}

Vec3 wall_force(double z) {
  return {0, 0, z < 0 ? -0.5 * z : 0.0};
}

LoopOptions quiet(long ticks) {
  LoopOptions o;
  o.realtime = false;  // never change the scheduling of the test machine
  o.max_ticks = ticks;
  o.watchdog_misses = 1000000;  // a loaded test machine misses deadlines; not what is tested
  return o;
}

TEST(ServoLoop, CommandsTheRenderersForceEveryTickAndZeroAtTheEnd) {
  ScriptDevice dev;
  dev.commanded.reserve(2000);
  Wall wall;
  ServoLoop loop(dev, wall, quiet(600));
  loop.start();  // on its own thread
  while (loop.running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  loop.stop();
  ASSERT_EQ(dev.commanded.size(), 601u) << "600 ticks and the final zero-force tick";
  for (long i = 0; i < 600; ++i)
    EXPECT_EQ(dev.commanded[i], wall_force(2.0 - 0.01 * static_cast<double>(i))) << "tick " << i;
  EXPECT_EQ(dev.commanded.back(), Vec3::Zero());
  const LoopStats s = loop.stats();
  EXPECT_EQ(s.ticks, 600u);
  EXPECT_EQ(s.period_us, 500.0);
  EXPECT_GE(s.step_p99_us, s.step_p50_us);
  EXPECT_GE(s.jitter_max_us, s.jitter_p99_us);
}

TEST(ServoLoop, AWallClockSecondOfTicksTakesASecond) {
  ScriptDevice dev;
  dev.commanded.reserve(3000);
  Wall wall;
  ServoLoop loop(dev, wall, quiet(1000));  // 1000 ticks at 2 kHz = 0.5 s
  const auto t0 = std::chrono::steady_clock::now();
  loop.run();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_GE(s, 0.499);  // absolute deadlines: never faster than the rate
}

TEST(ServoLoop, TheWatchdogHoldsZeroForceWhileTheDeviceFaultsAndResetsTheRenderer) {
  ScriptDevice dev;
  dev.commanded.reserve(2000);
  dev.fault_from = 300;
  dev.fault_to = 330;
  Wall wall;
  LoopOptions o = quiet(800);
  o.recover_ticks = 50;
  o.reset_gap_s = 0.005;  // 30 ticks at 2 kHz: 15 ms, a long fault here
  ServoLoop loop(dev, wall, o);
  loop.run();
  // Faulted at ticks 300-329; the 50th good tick after it (379) has force again.
  for (long i = 300; i < 379; ++i) EXPECT_EQ(dev.commanded[i], Vec3::Zero()) << "tick " << i;
  EXPECT_EQ(dev.commanded[379], wall_force(2.0 - 0.01 * 379));
  EXPECT_EQ(dev.commanded[299], wall_force(2.0 - 0.01 * 299));
  EXPECT_EQ(wall.resets, 1);
  EXPECT_EQ(loop.stats().watchdog_trips, 1u);
  EXPECT_EQ(loop.stats().watchdog_ticks, 79u);
}

TEST(ServoLoop, AShortDeviceFaultZeroesOnlyItsTicksAndKeepsTheRendererState) {
  ScriptDevice dev;
  dev.commanded.reserve(2000);
  dev.fault_from = 300;
  dev.fault_to = 302;  // two late datagrams
  Wall wall;
  LoopOptions o = quiet(600);
  ServoLoop loop(dev, wall, o);
  loop.run();
  EXPECT_EQ(dev.commanded[299], wall_force(2.0 - 0.01 * 299));
  EXPECT_EQ(dev.commanded[300], Vec3::Zero());
  EXPECT_EQ(dev.commanded[301], Vec3::Zero());
  EXPECT_EQ(dev.commanded[302], wall_force(2.0 - 0.01 * 302)) << "force back with the device";
  EXPECT_EQ(wall.resets, 0);
  EXPECT_EQ(loop.stats().watchdog_trips, 1u);
  EXPECT_EQ(loop.stats().watchdog_ticks, 2u);
}

// Before, a pause of 5 ticks or more (20 ms here) held zero for recover_ticks and reset the
// renderer: the probe inside an object got 0 N for about 300 ticks.
TEST(ServoLoop, ADeviceGapShorterThanTheResetGapKeepsTheRenderer) {
  ScriptDevice dev;
  dev.commanded.reserve(2000);
  dev.fault_from = 300;
  dev.fault_to = 340;  // 40 ticks at 2 kHz: 20 ms
  Wall wall;
  LoopOptions o = quiet(600);
  ASSERT_EQ(o.reset_gap_s, 0.05);
  ServoLoop loop(dev, wall, o);
  loop.run();
  for (long i = 300; i < 340; ++i) EXPECT_EQ(dev.commanded[i], Vec3::Zero()) << "tick " << i;
  EXPECT_EQ(dev.commanded[340], wall_force(2.0 - 0.01 * 340)) << "force back with the device";
  EXPECT_EQ(wall.resets, 0);
  EXPECT_EQ(loop.stats().watchdog_ticks, 40u);
}

TEST(ServoLoop, ObserversGetEveryTickInOrderAndAFullRingNeverBlocksTheLoop) {
  ScriptDevice dev;
  dev.info_.servo_rate_hz = 20000.0;  // 8,692 ticks in 0.43 s
  dev.commanded.reserve(3000);
  Wall wall;
  auto ring = std::make_unique<ObserverRing>();
  auto full = std::make_unique<ObserverRing>();  // nobody reads it
  ServoLoop loop(dev, wall, quiet(static_cast<long>(ObserverRing::capacity()) + 500));
  loop.add_observer(*ring);
  loop.add_observer(*full);
  std::vector<std::uint64_t> seen;
  seen.reserve(20000);
  loop.start();
  LoopSample s;
  while (loop.running() || ring->size() > 0) {
    while (ring->pop(s)) seen.push_back(s.tick);
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  loop.stop();
  ASSERT_EQ(seen.size(), ObserverRing::capacity() + 500);
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], i);
  EXPECT_EQ(full->dropped(), 500u);
  EXPECT_EQ(loop.stats().dropped_samples, 500u);
}

TEST(ServoLoop, TheSteadyStateAllocatesNothing) {
  ScriptDevice dev;
  dev.commanded.reserve(3000);
  Wall wall;
  auto ring = std::make_unique<ObserverRing>();
  ServoLoop loop(dev, wall, quiet(1200));
  loop.add_observer(*ring);
  loop.run();
  ASSERT_GE(wall.alloc_at_100, 0);
  EXPECT_EQ(wall.alloc_at_1000 - wall.alloc_at_100, 0);
}

// Records when and with what the loop calls Renderer::prefetch.
class Predicted final : public Renderer {
 public:
  explicit Predicted(const ScriptDevice& dev) : dev_(dev) {}
  ServoOutput step(const ServoInput& in) noexcept override {
    ++steps;
    ServoOutput o;
    o.hip_mm = o.ihip_mm = o.cihip_mm = in.p_mm;
    return o;
  }
  void prefetch(const ServoInput& next) noexcept override {
    if (calls < static_cast<long>(next_p.size())) {
      next_p[static_cast<std::size_t>(calls)] = next.p_mm;
      sent_before[static_cast<std::size_t>(calls)] = static_cast<long>(dev_.commanded.size());
      steps_at[static_cast<std::size_t>(calls)] = steps;
    }
    ++calls;
  }
  bool reads_ahead() const noexcept override { return ahead; }
  void reset() noexcept override {}
  const char* name() const noexcept override { return "predicted"; }
  bool ahead = true;
  const ScriptDevice& dev_;
  long steps = 0, calls = 0;
  std::vector<Vec3> next_p = std::vector<Vec3>(400, Vec3::Constant(-1.0));
  std::vector<long> sent_before = std::vector<long>(400, -1), steps_at = std::vector<long>(400, -1);
};

TEST(ServoLoop, PrefetchGetsTheNextPositionPredictedAfterTheForceWentOut) {
  // warm_lead_us 0: right after the force went out; 300: before the next deadline.
  for (double lead : {0.0, 300.0}) {
    ScriptDevice dev;
    dev.commanded.reserve(2000);
    Predicted r(dev);
    LoopOptions o = quiet(300);
    o.warm_lead_us = lead;
    ServoLoop loop(dev, r, o);
    loop.run();
    // No prediction at the first tick (no velocity yet), then at most one per tick: the lead
    // mode skips it when the wake-up came too late (a loaded test machine), never more.
    EXPECT_LE(r.calls, 299) << "lead " << lead;
    EXPECT_GE(r.calls, lead > 0 ? 150 : 299) << "lead " << lead;
    for (long k = 0; k < std::min(r.calls, 299L); ++k) {
      const auto i = static_cast<std::size_t>(k);
      const long tick = r.steps_at[i] - 1;  // the tick after which this call came
      ASSERT_GE(tick, 1);
      // The device moves 0.01 mm per tick: constant velocity, so the prediction is the next
      // tick's true position.
      EXPECT_NEAR((r.next_p[i] - dev_position(tick + 1)).norm(), 0.0, 1e-12) << "tick " << tick;
      EXPECT_EQ(r.sent_before[i], tick + 1) << "after the tick's force went to the device";
    }
    EXPECT_GE(loop.stats().prefetch_p99_us, loop.stats().prefetch_p50_us);
  }
}

TEST(ServoLoop, ARendererThatDoesNotReadAheadIsNeverAskedTo) {
  for (double lead : {0.0, 300.0}) {
    ScriptDevice dev;
    dev.commanded.reserve(2000);
    Predicted r(dev);
    r.ahead = false;
    LoopOptions o = quiet(100);
    o.warm_lead_us = lead;
    ServoLoop loop(dev, r, o);
    loop.run();
    EXPECT_EQ(r.steps, 100);
    EXPECT_EQ(r.calls, 0) << "lead " << lead;
  }
}

TEST(SpscRing, TwoThreadsPassTwoHundredThousandItemsInOrder) {
  auto ring = std::make_unique<SpscRing<std::uint64_t, 1024>>();
  constexpr std::uint64_t kN = 200000;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kN;) {
      if (ring->push(i))
        ++i;
      else
        std::this_thread::yield();
    }
  });
  std::uint64_t expect = 0, v = 0;
  while (expect < kN) {
    if (ring->pop(v)) {
      ASSERT_EQ(v, expect);
      ++expect;
    } else {
      std::this_thread::yield();
    }
  }
  producer.join();
  EXPECT_FALSE(ring->pop(v));
}

TEST(LatencyHistogram, QuantilesOfAKnownSample) {
  LatencyHistogram h(0.5, 1000.0);
  for (int i = 1; i <= 100; ++i) h.add(i);
  EXPECT_NEAR(h.quantile(0.5), 50.0, 0.5);
  EXPECT_NEAR(h.quantile(0.99), 99.0, 0.5);
  EXPECT_EQ(h.max(), 100.0);
  h.add(1e9);  // beyond the last bin: counted there, max kept
  EXPECT_EQ(h.max(), 1e9);
  EXPECT_EQ(h.count(), 101u);
}

}  // namespace
}  // namespace inhap::haptics
