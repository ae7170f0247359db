// The real-time servo loop. See servo_loop.hpp.
#include "inhap/haptics/servo_loop.hpp"

#include "inhap/haptics/bridge_device.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <limits>

#include "inhap/core/error.hpp"

namespace inhap::haptics {
namespace {

double now_s() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

timespec to_timespec(double s);

void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

void sleep_until(double t_s) {
  const timespec ts = to_timespec(t_s);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

timespec to_timespec(double s) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(s);
  ts.tv_nsec = static_cast<long>((s - static_cast<double>(ts.tv_sec)) * 1e9);
  if (ts.tv_nsec >= 1000000000L) {
    ++ts.tv_sec;
    ts.tv_nsec -= 1000000000L;
  }
  return ts;
}

}  // namespace

LatencyHistogram::LatencyHistogram(double bin_us, double max_us)
    : bin_us_(bin_us), bins_(static_cast<std::size_t>(max_us / bin_us) + 1, 0) {}

void LatencyHistogram::add(double us) noexcept {
  if (!(us >= 0.0)) us = 0.0;
  const double b = us / bin_us_;
  const std::size_t i =
      b >= static_cast<double>(bins_.size() - 1) ? bins_.size() - 1 : static_cast<std::size_t>(b);
  ++bins_[i];
  ++count_;
  max_us_seen_ = std::max(max_us_seen_, us);
}

double LatencyHistogram::quantile(double q) const {
  if (count_ == 0) return std::numeric_limits<double>::quiet_NaN();
  const auto want = static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(count_)));
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < bins_.size(); ++i) {
    seen += bins_[i];
    if (seen >= std::max<std::uint64_t>(want, 1)) {
      return std::min((static_cast<double>(i) + 0.5) * bin_us_, max_us_seen_);
    }
  }
  return max_us_seen_;
}

void LatencyHistogram::clear() noexcept {
  std::fill(bins_.begin(), bins_.end(), 0u);
  count_ = 0;
  max_us_seen_ = 0;
}

ServoLoop::ServoLoop(Device& device, Renderer& renderer, LoopOptions options)
    : device_(device), renderer_(renderer), options_(options) {
  if (!(device_.info().servo_rate_hz > 0.0) || !std::isfinite(device_.info().servo_rate_hz))
    throw Error("servo loop: the device's servo rate must be a positive number of Hz");
  if (!(options_.reset_gap_s >= 0.0) || !std::isfinite(options_.reset_gap_s))
    throw Error("servo loop: the reset gap must be a finite number of seconds >= 0");
  bridge_ = dynamic_cast<BridgeDevice*>(&device_);
  observers_.reserve(4);
}

ServoLoop::~ServoLoop() {
  stop();
}

void ServoLoop::add_observer(ObserverRing& ring) {
  if (running()) throw Error("servo loop: observers are added before start()");
  if (observers_.size() >= 4) throw Error("servo loop: at most 4 observers");
  observers_.push_back(&ring);
}

void ServoLoop::start() {
  if (thread_.joinable()) return;
  stop_.store(false);
  running_.store(true, std::memory_order_release);
  thread_ = std::thread([this] {
    if (options_.realtime) setup_realtime();
    run();
  });
}

void ServoLoop::stop() {
  stop_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
}

void ServoLoop::setup_realtime() {
  sched_param sp{};
  sp.sched_priority = options_.priority;
  const int e = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
  std::string s = e == 0 ? "SCHED_FIFO " + std::to_string(options_.priority)
                         : std::string("normal priority (SCHED_FIFO refused: ") + std::strerror(e) +
                               "; run as root or grant CAP_SYS_NICE / rtprio in limits.conf)";
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
    s += ", memory locked";
  } else {
    s += std::string(", memory not locked (mlockall: ") + std::strerror(errno) + ")";
  }
  rt_status_ = s;
}

void ServoLoop::run() {
  running_.store(true, std::memory_order_release);
  if (rt_status_ == "not started") rt_status_ = "normal priority (real time not requested)";
  const double period = 1.0 / device_.info().servo_rate_hz;
  const bool paced_by_device = device_.self_paced();
  paced_by_device_ = paced_by_device;
  const double lead_s = renderer_.reads_ahead() ? std::max(0.0, options_.warm_lead_us) * 1e-6 : 0.0;
  double deadline = now_s();
  double last = deadline;
  while (!stop_.load(std::memory_order_acquire) &&
         (options_.max_ticks < 0 || ticks_.load(std::memory_order_relaxed) <
                                        static_cast<std::uint64_t>(options_.max_ticks))) {
    double late_us = 0.0;
    if (!paced_by_device) {
      deadline += period;
      const bool lead = lead_s > 0.0 && has_next_;
      sleep_until(lead ? deadline - lead_s : deadline);
      if (lead && now_s() < deadline) {
        warm_next();
        while (now_s() < deadline) cpu_relax();
      }
      const double now = now_s();
      late_us = (now - deadline) * 1e6;
      if (late_us > period * 1e6) {
        overruns_.fetch_add(1, std::memory_order_relaxed);
        ++missed_in_row_;
        deadline = now;  // resynchronise: no burst of catch-up ticks
      } else {
        missed_in_row_ = 0;
      }
    } else {
      const double now = now_s();
      late_us = std::abs(now - last - period) * 1e6;
      last = now;
    }
    jitter_.add(late_us);
    tick_once(late_us);
  }
  // The last word to the device is zero force.
  device_.command_force(Vec3::Zero());
  device_.tick();
  running_.store(false, std::memory_order_release);
}

void ServoLoop::tick_once(double /*wake_late_us*/) {
  ServoInput in;
  in.t_s = device_.time();
  in.p_mm = device_.position();
  in.sensor_force_n = device_.force_sensor();
  in.has_sensor = true;
  const double t0 = now_s();
  const ServoOutput out = renderer_.step(in);
  const double step_us = (now_s() - t0) * 1e6;
  step_.add(step_us);

  // A device fault zeroes the force at once. A short one (under reset_gap_s: late datagrams, a
  // short pause) releases as soon as the device is back; a long one, or missed deadlines, holds
  // zero for recover_ticks good ticks and resets the renderer (no kick from a stale proxy).
  const bool device_fault = device_.faulted();
  fault_in_row_ = device_fault ? fault_in_row_ + 1 : 0;
  if (fault_in_row_ == 1) fault_since_s_ = t0;
  if (missed_in_row_ >= options_.watchdog_misses ||
      (device_fault && t0 - fault_since_s_ >= options_.reset_gap_s))
    long_fault_ = true;
  if (device_fault || missed_in_row_ >= options_.watchdog_misses) {
    if (!holding_) trips_.fetch_add(1, std::memory_order_relaxed);
    holding_ = true;
    good_in_row_ = 0;
  } else if (holding_ && (!long_fault_ || ++good_in_row_ >= options_.recover_ticks)) {
    holding_ = false;
    if (long_fault_) renderer_.reset();
    long_fault_ = false;
  }
  if (holding_) watchdog_ticks_.fetch_add(1, std::memory_order_relaxed);
  const bool zeroed = holding_ || !out.force_n.allFinite();
  const Vec3 cmd = zeroed ? Vec3::Zero() : out.force_n;
  if (bridge_) bridge_->set_zeroed(zeroed);  // status bit kStatusZeroed with this force
  device_.command_force(cmd);

  if (!observers_.empty()) {
    LoopSample s;
    s.tick = ticks_.load(std::memory_order_relaxed);
    s.t_s = in.t_s;
    s.p_mm = in.p_mm;
    s.sensor_force_n = in.sensor_force_n;
    s.out = out;
    s.commanded_n = cmd;
    s.watchdog = holding_;
    s.step_us = static_cast<float>(step_us);
    s.wall_s = t0;
    for (ObserverRing* r : observers_) r->push(s);
  }
  device_.tick();  // the force is out: the rest of the period is idle

  // The next input, predicted at constant velocity, for the read-ahead.
  has_next_ = has_last_p_ && in.p_mm.allFinite();
  if (has_next_) {
    next_in_ = in;
    next_in_.t_s = in.t_s + 1.0 / device_.info().servo_rate_hz;
    next_in_.p_mm = in.p_mm + (in.p_mm - last_p_);
  }
  last_p_ = in.p_mm;
  has_last_p_ = in.p_mm.allFinite();
  if (has_next_ && renderer_.reads_ahead() && (paced_by_device_ || !(options_.warm_lead_us > 0.0)))
    warm_next();
  ticks_.fetch_add(1, std::memory_order_relaxed);
}

void ServoLoop::warm_next() {
  const double t0 = now_s();
  renderer_.prefetch(next_in_);
  prefetch_.add((now_s() - t0) * 1e6);
  has_next_ = false;
}

LoopStats ServoLoop::stats() const {
  LoopStats s;
  s.ticks = ticks_.load(std::memory_order_relaxed);
  s.period_us = 1e6 / device_.info().servo_rate_hz;
  s.overruns = overruns_.load(std::memory_order_relaxed);
  s.watchdog_trips = trips_.load(std::memory_order_relaxed);
  s.watchdog_ticks = watchdog_ticks_.load(std::memory_order_relaxed);
  if (running()) return s;  // the histograms belong to the loop thread while it runs
  for (const ObserverRing* r : observers_) s.dropped_samples += r->dropped();
  s.jitter_p50_us = jitter_.quantile(0.5);
  s.jitter_p99_us = jitter_.quantile(0.99);
  s.jitter_max_us = jitter_.max();
  s.step_p50_us = step_.quantile(0.5);
  s.step_p99_us = step_.quantile(0.99);
  s.step_max_us = step_.max();
  s.prefetch_p50_us = prefetch_.quantile(0.5);
  s.prefetch_p99_us = prefetch_.quantile(0.99);
  return s;
}

}  // namespace inhap::haptics
