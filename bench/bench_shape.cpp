// Shape modeling benchmarks (thesis ch. 3). Targets: knee estimation <= 20 us per tap (N = 100
// samples), whole reconstruction of 30,000 points <= 5 s.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "inhap/contact/knee.hpp"
#include "inhap/core/random.hpp"
#include "inhap/surface/reconstruct.hpp"

using namespace inhap;

namespace {

struct Window {
  std::vector<double> t, f;
};

std::vector<Window> windows(int count, int n) {
  std::vector<Window> out;
  Rng rng(1);
  for (int w = 0; w < count; ++w) {
    Window win;
    const double tk = 1e-3 * rng.uniform(20, 80), slope = rng.uniform(2, 40);
    for (int i = 0; i <= n; ++i) {
      const double t = 1e-3 * i;
      win.t.push_back(t);
      win.f.push_back((t > tk ? slope * (t - tk) : 0.0) + 0.005 * rng.normal());
    }
    out.push_back(std::move(win));
  }
  return out;
}

/// Per-call latency percentiles as counters (us).
void report_percentiles(benchmark::State& state, std::vector<double>& us) {
  if (us.empty()) return;
  std::sort(us.begin(), us.end());
  state.counters["p50_us"] = us[us.size() / 2];
  state.counters["p99_us"] = us[us.size() * 99 / 100];
  state.counters["max_us"] = us.back();
}

void BM_KneeFit(benchmark::State& state) {
  const bool refine = state.range(1) != 0;
  const auto ws = windows(256, static_cast<int>(state.range(0)));
  KneeOptions o;
  o.refine = refine;
  std::vector<double> us;
  us.reserve(1 << 16);
  std::size_t k = 0;
  for (auto _ : state) {
    const Window& w = ws[k++ % ws.size()];
    const auto t0 = std::chrono::steady_clock::now();
    KneeFit fit = fit_knee(w.t, w.f, o);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(fit);
    if (us.size() < (1u << 16))
      us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  report_percentiles(state, us);
}
BENCHMARK(BM_KneeFit)->Args({100, 1})->Args({100, 0})->Args({500, 1});

std::vector<Vec3> noisy_sphere(int n, double r, double sigma) {
  Rng rng(3);
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i) {
    const Vec3 d = Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
    pts.push_back(r * d + sigma * Vec3(rng.normal(), rng.normal(), rng.normal()));
  }
  return pts;
}

void BM_Reconstruct(benchmark::State& state) {
  const auto pts = noisy_sphere(static_cast<int>(state.range(0)), 40.0, 0.05);
  ReconstructOptions o;
  o.mode = state.range(1) ? SurfaceMode::kShell : SurfaceMode::kSolid;
  std::size_t faces = 0;
  for (auto _ : state) {
    ReconstructReport rep;
    TriMesh m = reconstruct_surface(pts, o, &rep);
    faces = rep.faces;
    benchmark::DoNotOptimize(m);
  }
  state.counters["faces"] = static_cast<double>(faces);
}
BENCHMARK(BM_Reconstruct)
    ->Args({30000, 1})
    ->Args({30000, 0})
    ->Args({1000, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
