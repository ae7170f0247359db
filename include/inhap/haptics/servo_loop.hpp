// The real-time servo loop: runs any Renderer (servo.hpp) against any Device on a dedicated
// thread at the device's rate.
//
// Units: time s, positions mm, forces N; statistics in microseconds.
//
// - Pacing: absolute deadlines with clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME), unless the
//   device paces itself (Device::self_paced(), e.g. the UDP bridge: tick() waits for the
//   device's next state).
// - Real time: SCHED_FIFO and mlockall when permitted (LoopOptions::realtime); rt_status() says
//   what was granted, and why not.
// - Watchdog: zero force while the device reports a fault (from the first faulted tick) and after
//   `watchdog_misses` deadlines missed in a row. A device fault shorter than `reset_gap_s` (late
//   or lost datagrams, a short pause) releases when the device is back, renderer state kept; a
//   longer one holds zero for `recover_ticks` and resets the renderer (no kick from a stale
//   proxy). A device that takes a zero flag (the bridge) is told every tick that the force was
//   zeroed by the watchdog or a non-finite renderer output.
// - Observers read the loop through lock-free SPSC rings (spsc_ring.hpp); the loop never
//   blocks on them: a full ring drops the sample and counts it.
// - Read-ahead: between ticks the loop calls Renderer::prefetch with the next position predicted
//   at constant velocity (LoopOptions::warm_lead_us), so a renderer bound by memory latency finds
//   its data in cache; never on the path from reading the device to commanding the force.
// - The loop's steady state allocates nothing and takes no lock; on stop it commands zero force
//   for one last tick.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "inhap/core/device.hpp"
#include "inhap/haptics/servo.hpp"
#include "inhap/haptics/spsc_ring.hpp"

namespace inhap::haptics {

/// One tick as observers see it.
class BridgeDevice;

struct LoopSample {
  std::uint64_t tick = 0;
  double t_s = 0;                      ///< device time, s
  Vec3 p_mm = Vec3::Zero();            ///< probe position, mm
  Vec3 sensor_force_n = Vec3::Zero();  ///< raw sensor reading, N
  ServoOutput out;                     ///< what the renderer returned
  Vec3 commanded_n = Vec3::Zero();     ///< force actually commanded (zero when the watchdog holds)
  bool watchdog = false;               ///< the watchdog held the force at zero
  float step_us = 0;                   ///< renderer step time, us
  double wall_s = 0;                   ///< monotonic clock when the step began, s
};

using ObserverRing = SpscRing<LoopSample, 8192>;

struct LoopOptions {
  bool realtime = true;      ///< try SCHED_FIFO + mlockall
  int priority = 80;         ///< SCHED_FIFO priority when granted
  int watchdog_misses = 10;  ///< deadlines missed in a row before zero force
  int recover_ticks = 100;   ///< good ticks before force comes back after a trip
  /// A device fault shorter than this (wall-clock time from its first faulted tick, s) releases
  /// as soon as the device is back, without recover_ticks and without a renderer reset.
  double reset_gap_s = 0.05;
  long max_ticks = -1;  ///< stop by itself after this many ticks (-1: until stop())
  /// Read-ahead (Renderer::prefetch, with the next position predicted at constant velocity), for
  /// renderers that read ahead (Renderer::reads_ahead()).
  /// A clock-paced loop wakes this long before each deadline, runs it, then spins to the
  /// deadline: the next step finds its data in cache (a sleeping core's caches are taken by
  /// whatever ran meanwhile) and the device is read on time; it costs up to this share of each
  /// period in CPU. If the wake-up comes later than the deadline the read-ahead is skipped, so it
  /// never delays a tick. 0, or a device that paces itself: the read-ahead runs right after the
  /// force has gone out instead. us.
  double warm_lead_us = 150.0;
};

/// Latency histogram with fixed bins (allocated once, before the loop starts).
class LatencyHistogram {
 public:
  explicit LatencyHistogram(double bin_us = 0.05, double max_us = 20000.0);
  void add(double us) noexcept;
  double quantile(double q) const;  ///< us; NaN when empty
  double max() const { return max_us_seen_; }
  std::uint64_t count() const { return count_; }
  void clear() noexcept;

 private:
  double bin_us_;
  std::vector<std::uint32_t> bins_;
  std::uint64_t count_ = 0;
  double max_us_seen_ = 0;
};

struct LoopStats {
  std::uint64_t ticks = 0;
  std::uint64_t overruns = 0;         ///< deadlines missed (woke more than one period late)
  std::uint64_t watchdog_trips = 0;   ///< times the watchdog zeroed the force
  std::uint64_t watchdog_ticks = 0;   ///< ticks with force held at zero
  std::uint64_t dropped_samples = 0;  ///< samples no observer had room for
  double jitter_p50_us = 0, jitter_p99_us = 0, jitter_max_us = 0;  ///< wake-up lateness
  double step_p50_us = 0, step_p99_us = 0, step_max_us = 0;        ///< renderer step
  /// Renderer::prefetch after the force went out (off the force's critical path).
  double prefetch_p50_us = 0, prefetch_p99_us = 0;
  double period_us = 0;
};

class ServoLoop {
 public:
  ServoLoop(Device& device, Renderer& renderer, LoopOptions options = {});
  ~ServoLoop();
  ServoLoop(const ServoLoop&) = delete;
  ServoLoop& operator=(const ServoLoop&) = delete;

  /// Before start(): an observer ring the loop pushes every tick into (at most 4).
  void add_observer(ObserverRing& ring);
  void start();
  /// Asks the loop to stop, waits for it; the last tick commands zero force.
  void stop();
  /// Runs the loop on the calling thread until stop() or max_ticks (what start() runs).
  void run();
  bool running() const { return running_.load(std::memory_order_acquire); }
  std::uint64_t ticks() const { return ticks_.load(std::memory_order_relaxed); }
  /// Statistics; complete after stop() (or run() returned). While running: ticks, overruns and
  /// the watchdog's counts only (the histograms belong to the loop thread).
  LoopStats stats() const;
  /// What real-time scheduling was granted ("SCHED_FIFO 80, memory locked", or why not).
  std::string rt_status() const { return rt_status_; }

 private:
  void setup_realtime();
  void tick_once(double wake_late_us);
  void warm_next();

  Device& device_;
  Renderer& renderer_;
  LoopOptions options_;
  std::vector<ObserverRing*> observers_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> running_{false};
  std::atomic<std::uint64_t> ticks_{0};
  LatencyHistogram jitter_{1.0, 100000.0};
  LatencyHistogram step_{0.02, 2000.0};
  LatencyHistogram prefetch_{0.02, 2000.0};
  Vec3 last_p_ = Vec3::Zero();  ///< the previous tick's probe position, for the prediction
  bool has_last_p_ = false;
  ServoInput next_in_;  ///< the predicted next input (valid when has_next_)
  bool has_next_ = false;
  bool paced_by_device_ = false;
  // Written by the loop thread only; atomic so stats() can read them while the loop runs.
  std::atomic<std::uint64_t> overruns_{0}, trips_{0}, watchdog_ticks_{0};
  int missed_in_row_ = 0, good_in_row_ = 0, fault_in_row_ = 0;
  bool holding_ = false;
  bool long_fault_ = false;         ///< the current hold needs recover_ticks and a renderer reset
  double fault_since_s_ = 0;        ///< wall-clock time of the current fault's first tick
  BridgeDevice* bridge_ = nullptr;  ///< the device, when it is the bridge (zero flag)
  std::string rt_status_ = "not started";
};

}  // namespace inhap::haptics
