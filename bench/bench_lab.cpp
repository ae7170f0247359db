// Virtual lab speed: simulating 60 s of 1 kHz explore recording (target <= 2 s wall time), the
// same with the CSV files written, and the per-tick latency (p50/p99) of the simulated device.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "inhap/lab/operators.hpp"

namespace {

using namespace inhap::lab;

void BM_Explore60s(benchmark::State& state) {
  const Scene scene = builtin_scene("planar");
  RecordSpec spec;
  spec.operator_name = "explore";
  spec.seconds = 60;
  for (auto _ : state) {
    LabRecording lab = record_scene(scene, spec);
    benchmark::DoNotOptimize(lab.rec.f.data());
  }
  state.counters["sim_s_per_wall_s"] =
      benchmark::Counter(60.0 * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Explore60s)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

void BM_Explore60sWithCsv(benchmark::State& state) {
  const Scene scene = builtin_scene("planar");
  RecordSpec spec;
  spec.operator_name = "explore";
  spec.seconds = 60;
  const auto path = std::filesystem::temp_directory_path() / "inhap-bench-lab.csv";
  for (auto _ : state) write_lab_recording(path.string(), record_scene(scene, spec));
  std::filesystem::remove(path);
  std::filesystem::remove(truth_path_for(path.string()));
}
BENCHMARK(BM_Explore60sWithCsv)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

/// Per-tick latency of SimDevice::tick() (20 physics substeps with contact) and of a whole
/// recording step (operator + logger + tick), during 60 s of exploration.
void BM_TickLatency(benchmark::State& state) {
  const Scene scene = builtin_scene("planar");
  std::vector<double> tick_ns, step_ns;
  tick_ns.reserve(60000), step_ns.reserve(60000);
  for (auto _ : state) {
    SimDevice dev(scene.object);
    auto op = make_operator("explore", scene, 7, 60.0);
    op->begin(dev);
    TickLogger log(dev, 60000);
    for (int i = 0; i < 60000; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      log.sample();
      op->step(dev);
      const auto t1 = std::chrono::steady_clock::now();
      dev.tick();
      const auto t2 = std::chrono::steady_clock::now();
      tick_ns.push_back(std::chrono::duration<double, std::nano>(t2 - t1).count());
      step_ns.push_back(std::chrono::duration<double, std::nano>(t2 - t0).count());
    }
  }
  auto pct = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(q * (v.size() - 1))];
  };
  state.counters["tick_p50_us"] = pct(tick_ns, 0.50) * 1e-3;
  state.counters["tick_p99_us"] = pct(tick_ns, 0.99) * 1e-3;
  state.counters["step_p50_us"] = pct(step_ns, 0.50) * 1e-3;
  state.counters["step_p99_us"] = pct(step_ns, 0.99) * 1e-3;
}
BENCHMARK(BM_TickLatency)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
