// Period jitter of the servo loop (haptics::ServoLoop) at 1 kHz: a clock-paced device with a
// fixed probe and the null renderer, so what is measured is the loop's wake-up lateness against
// its absolute deadlines (clock_nanosleep), not a renderer. Real-time scheduling is requested
// (SCHED_FIFO 80 + mlockall); the label says what was granted. Run it on an otherwise idle
// machine for the figure the docs quote. Units: us.
#include <benchmark/benchmark.h>

#include <chrono>
#include <thread>

#include "inhap/haptics/renderers.hpp"
#include "inhap/haptics/servo_loop.hpp"

namespace {

using namespace inhap;

class StillDevice final : public Device {
 public:
  const DeviceInfo& info() const override { return info_; }
  double time() const override { return static_cast<double>(ticks_) * 1e-3; }
  Vec3 position() const override { return Vec3(0, 0, 10); }
  Vec3 force_sensor() const override { return Vec3::Zero(); }
  void command_force(const Vec3&) override {}
  void tick() override { ++ticks_; }

 private:
  DeviceInfo info_;
  long ticks_ = 0;
};

// arg: seconds of loop per run.
void BM_LoopJitter(benchmark::State& state) {
  for (auto _ : state) {
    StillDevice dev;
    haptics::NullRenderer none;
    haptics::LoopOptions o;
    o.realtime = true;
    o.max_ticks = state.range(0) * 1000;
    haptics::ServoLoop loop(dev, none, o);
    loop.start();
    while (loop.running()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    loop.stop();
    const haptics::LoopStats s = loop.stats();
    state.counters["jitter_p50_us"] = s.jitter_p50_us;
    state.counters["jitter_p99_us"] = s.jitter_p99_us;
    state.counters["jitter_max_us"] = s.jitter_max_us;
    state.counters["overruns"] = static_cast<double>(s.overruns);
    state.counters["ticks"] = static_cast<double>(s.ticks);
    state.SetLabel(loop.rt_status());
  }
}

}  // namespace

BENCHMARK(BM_LoopJitter)->Arg(10)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK_MAIN();
