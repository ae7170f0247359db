// Servo-step latency of the renderer (CBA and TCA-MESH) while a force-tracking hand strokes a
// bumpy heightmap with a stiffness map: 257 x 257 grid at 0.39 mm (131,072 triangles, the
// protein-on-mica size of thesis sec. 5.3) and a 708 x 708 grid (1.0 M triangles).
// Each step() is timed on its own; counters report p50/p99/max in microseconds (target: p99 <= 1
// through the common interface on the 131k map).
// BM_ServoStep calls rendering::step directly; BM_RendererInterface runs the same strokes through
// the common servo interface (haptics::Renderer, a virtual call per tick, as the servo loop does).
// Units: mm, N, N/mm, s.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include "bumpy_map.hpp"
#include "inhap/haptics/renderers.hpp"
#include "inhap/rendering/renderer.hpp"

using namespace inhap;

namespace {

const rendering::Model& model(int n) {
  static std::unique_ptr<rendering::Model> m257, m708;
  auto& m = n == 257 ? m257 : m708;
  if (!m) m = std::make_unique<rendering::Model>(bench::bumpy_map(n, 42));
  return *m;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const auto i = static_cast<std::size_t>(q * double(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(i), v.end());
  return v[i];
}

// args: grid size, algorithm (0 CBA, 1 TCA), mean stroke speed (mm/s)
void BM_ServoStep(benchmark::State& bs) {
  const int n = static_cast<int>(bs.range(0));
  const auto alg = bs.range(1) ? rendering::Algorithm::kTCA : rendering::Algorithm::kCBA;
  const double speed = static_cast<double>(bs.range(2));
  const rendering::Model& m = model(n);
  bench::StrokeHand hand{speed};
  rendering::State st;
  Vec3 p = hand.p;
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(bs.max_iterations));
  long contact = 0, touches = 0, walk = 0, max_walk = 0;
  bool was = false;
  for (auto _ : bs) {
    const auto t0 = std::chrono::steady_clock::now();
    const Vec3 f = rendering::step(m, st, p, alg);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(f);
    const double sec = std::chrono::duration<double>(t1 - t0).count();
    bs.SetIterationTime(sec);
    us.push_back(sec * 1e6);
    contact += st.collision;
    touches += st.collision && !was;
    was = st.collision;
    walk += st.walk_steps;
    max_walk = std::max<long>(max_walk, st.walk_steps);
    p = hand.next(st.collision, f, st.k);
  }
  const double ticks = static_cast<double>(us.size());
  bs.counters["p50_us"] = percentile(us, 0.50);
  bs.counters["p99_us"] = percentile(us, 0.99);
  bs.counters["max_us"] = *std::max_element(us.begin(), us.end());
  bs.counters["contact_frac"] = double(contact) / ticks;
  bs.counters["touches"] = double(touches);
  bs.counters["walk_mean"] = double(walk) / ticks;
  bs.counters["walk_max"] = double(max_walk);
  bs.counters["fallbacks"] = st.fallbacks;
  bs.counters["triangles"] = double(m.mesh().num_triangles());
}

// The same strokes through the common servo interface (haptics::Renderer, one virtual call per
// tick, as the servo loop runs every renderer). args: grid size, algorithm (0 CBA, 1 TCA), mm/s,
// prefetch (1: after each step, untimed in p50/p99 and timed on its own in prefetch_p99_us,
// Renderer::prefetch with the loop's constant-velocity prediction p + (p - p_prev), as
// ServoLoop does once the force has gone out).
void BM_RendererInterface(benchmark::State& bs) {
  const int n = static_cast<int>(bs.range(0));
  const auto alg = bs.range(1) ? rendering::Algorithm::kTCA : rendering::Algorithm::kCBA;
  const double speed = static_cast<double>(bs.range(2));
  const bool warm = bs.range(3) != 0;
  const rendering::Model& m = model(n);
  std::unique_ptr<haptics::Renderer> r = std::make_unique<haptics::MeshRenderer>(m, alg);
  const auto& st = static_cast<const haptics::MeshRenderer&>(*r).state();
  bench::StrokeHand hand{speed};
  haptics::ServoInput in;
  in.p_mm = hand.p;
  Vec3 p_prev = in.p_mm;
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(bs.max_iterations));
  long contact = 0;
  for (auto _ : bs) {
    const auto t0 = std::chrono::steady_clock::now();
    const haptics::ServoOutput o = r->step(in);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(o);
    const double sec = std::chrono::duration<double>(t1 - t0).count();
    bs.SetIterationTime(sec);
    us.push_back(sec * 1e6);
    if (warm) {
      haptics::ServoInput next = in;
      next.t_s += 1e-3;
      next.p_mm = in.p_mm + (in.p_mm - p_prev);
      r->prefetch(next);
    }
    p_prev = in.p_mm;
    contact += o.contact;
    in.t_s += 1e-3;
    in.p_mm = hand.next(o.contact, o.force_n, st.k);
  }
  bs.counters["p50_us"] = percentile(us, 0.50);
  bs.counters["p99_us"] = percentile(us, 0.99);
  bs.counters["max_us"] = *std::max_element(us.begin(), us.end());
  bs.counters["contact_frac"] = double(contact) / static_cast<double>(us.size());
  bs.counters["triangles"] = double(m.mesh().num_triangles());
}

}  // namespace

BENCHMARK(BM_RendererInterface)
    ->ArgNames({"grid", "tca", "mm_s", "prefetch"})
    ->ArgsProduct({{257}, {0, 1}, {50, 500}, {0, 1}})
    ->Iterations(200000)
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

BENCHMARK(BM_ServoStep)
    ->ArgNames({"grid", "tca", "mm_s"})
    ->Args({257, 0, 50})
    ->Args({257, 1, 50})
    ->Args({257, 0, 500})
    ->Args({257, 1, 500})
    ->Args({708, 0, 50})
    ->Args({708, 1, 50})
    ->Iterations(200000)
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
