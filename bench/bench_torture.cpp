// Servo torture, full length (issue 20): 10^7 random ticks per renderer mixing NaN, +-1e9,
// 50 mm jumps and legal motion. Reports, as counters, the non-finite forces, the forces over the
// device's limit (both must be 0), the largest force (N) and whether a legal trajectory
// afterwards rendered as from a fresh state (fresh_after = 1). Time per tick is the mean servo
// step under this abuse. Run: build/bench/bench_torture [--benchmark_filter=Cba]
#include <benchmark/benchmark.h>

#include "support/torture.hpp"

namespace {

using namespace inhap;

constexpr std::uint64_t kSteps = 10'000'000;

void report(benchmark::State& state, const test::TortureResult& r) {
  state.counters["steps"] = static_cast<double>(r.steps);
  state.counters["non_finite"] = static_cast<double>(r.non_finite);
  state.counters["over_limit"] = static_cast<double>(r.over_limit);
  state.counters["nonzero"] = static_cast<double>(r.nonzero);
  state.counters["max_force_N"] = r.max_force;
  state.counters["fresh_after"] = r.fresh_after ? 1 : 0;
  state.counters["ns_per_step"] = benchmark::Counter(
      static_cast<double>(r.steps), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  if (r.non_finite || r.over_limit || !r.fresh_after) state.SkipWithError("torture failed");
}

void BM_TortureCba(benchmark::State& state) {
  const rendering::Model m(test::torture_mesh());
  for (auto _ : state)
    report(state, test::torture_renderer(m, rendering::Algorithm::kCBA, kSteps, 1));
}
void BM_TortureTcaMesh(benchmark::State& state) {
  const rendering::Model m(test::torture_mesh());
  for (auto _ : state)
    report(state, test::torture_renderer(m, rendering::Algorithm::kTCA, kSteps, 2));
}
void BM_TortureDataDriven(benchmark::State& state) {
  const datadriven::ForceModel m = test::torture_dd_model();
  for (auto _ : state) report(state, test::torture_data_driven(m, kSteps, 3));
}

BENCHMARK(BM_TortureCba)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(BM_TortureTcaMesh)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(BM_TortureDataDriven)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
