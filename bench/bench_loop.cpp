// The servo loop (haptics::ServoLoop) at 1 kHz. BM_LoopJitter: a clock-paced device with a fixed
// probe and the null renderer, so what is measured is the loop's wake-up lateness against its
// absolute deadlines (clock_nanosleep), not a renderer. BM_LoopRender: the renderer's step time
// as the loop measures it (LoopStats), CBA / TCA-MESH on the 131,072-triangle benchmark map
// stroked by bench_render's force-tracking hand, with and without the loop's read-ahead
// (Renderer::prefetch after the force went out). Real-time scheduling is requested
// (SCHED_FIFO 80 + mlockall); the label says what was granted. Run it on an otherwise idle
// machine for the figures the docs quote. Units: us.
#include <benchmark/benchmark.h>

#include <chrono>
#include <thread>

#include "bumpy_map.hpp"
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

// Runs a real-time loop for `seconds` on its own thread; the label says what was granted.
haptics::LoopStats run_loop(benchmark::State& state, Device& dev, haptics::Renderer& r,
                            long seconds) {
  haptics::LoopOptions o;
  o.realtime = true;
  o.max_ticks = seconds * 1000;
  o.watchdog_misses = 1000000;  // a late wake-up is measured, not acted on
  haptics::ServoLoop loop(dev, r, o);
  loop.start();
  while (loop.running()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  loop.stop();
  state.SetLabel(loop.rt_status());
  return loop.stats();
}

// arg: seconds of loop per run.
void BM_LoopJitter(benchmark::State& state) {
  for (auto _ : state) {
    StillDevice dev;
    haptics::NullRenderer none;
    const haptics::LoopStats s = run_loop(state, dev, none, state.range(0));
    state.counters["jitter_p50_us"] = s.jitter_p50_us;
    state.counters["jitter_p99_us"] = s.jitter_p99_us;
    state.counters["jitter_max_us"] = s.jitter_max_us;
    state.counters["overruns"] = static_cast<double>(s.overruns);
    state.counters["ticks"] = static_cast<double>(s.ticks);
  }
}

// The stroking hand as a device: it moves 1 ms of the Lissajous stroke per tick, pressing on the
// force it was commanded.
class HandDevice final : public Device {
 public:
  HandDevice(double speed, const double& k) : hand_{speed}, k_(k) {}
  const DeviceInfo& info() const override { return info_; }
  double time() const override { return hand_.t; }
  Vec3 position() const override { return hand_.p; }
  Vec3 force_sensor() const override { return Vec3::Zero(); }
  void command_force(const Vec3& f) override { force_ = f; }
  void tick() override { hand_.next(force_.squaredNorm() > 0, force_, k_ > 0 ? k_ : 1.0); }

 private:
  DeviceInfo info_;
  bench::StrokeHand hand_;
  const double& k_;  // the renderer's k(n), N/mm (the hand's force tracking uses it)
  Vec3 force_ = Vec3::Zero();
};

// The mesh renderer without the read-ahead (Renderer::prefetch and reads_ahead at their
// defaults: nothing, false).
class NoPrefetch final : public haptics::Renderer {
 public:
  explicit NoPrefetch(haptics::MeshRenderer& r) : r_(r) {}
  haptics::ServoOutput step(const haptics::ServoInput& in) noexcept override { return r_.step(in); }
  void reset() noexcept override { r_.reset(); }
  const char* name() const noexcept override { return r_.name(); }

 private:
  haptics::MeshRenderer& r_;
};

// args: algorithm (0 CBA, 1 TCA), stroke speed mm/s, prefetch (0/1), seconds.
void BM_LoopRender(benchmark::State& state) {
  static const rendering::Model model(bench::bumpy_map(257, 42));
  const auto alg = state.range(0) ? rendering::Algorithm::kTCA : rendering::Algorithm::kCBA;
  for (auto _ : state) {
    haptics::MeshRenderer mesh(model, alg);
    NoPrefetch plain(mesh);
    HandDevice dev(static_cast<double>(state.range(1)), mesh.state().k);
    haptics::Renderer& r = state.range(2) ? static_cast<haptics::Renderer&>(mesh) : plain;
    const haptics::LoopStats s = run_loop(state, dev, r, state.range(3));
    state.counters["step_p50_us"] = s.step_p50_us;
    state.counters["step_p99_us"] = s.step_p99_us;
    state.counters["step_max_us"] = s.step_max_us;
    state.counters["prefetch_p50_us"] = s.prefetch_p50_us;
    state.counters["prefetch_p99_us"] = s.prefetch_p99_us;
    state.counters["triangles"] = static_cast<double>(model.mesh().num_triangles());
  }
}

}  // namespace

BENCHMARK(BM_LoopRender)
    ->ArgNames({"tca", "mm_s", "prefetch", "s"})
    ->ArgsProduct({{0, 1}, {50, 500}, {0, 1}, {5}})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();
BENCHMARK(BM_LoopJitter)->Arg(10)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK_MAIN();
