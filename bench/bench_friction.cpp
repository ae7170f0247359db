// Servo-step latency of the proxy estimator (thesis 4.3.1): p50/p99 per tick, target <= 2 us.
// Units: mm. Runs on a 3 x 3 grid of reference points with an inhomogeneous Coulomb-like g_s.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/proxy_estimator.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/heightmap.hpp"

namespace {

using namespace inhap;
using namespace inhap::friction;

// Probe-centre surface of a dome: sphere of radius 64.75 mm centred at z = -26.75 mm (cap 38 mm
// high), as a 1 mm height field over 100 x 100 mm (20,000 triangles).
constexpr double kDomeR = 64.75, kDomeZ = -26.75;
double dome_z(double x, double y) {
  return kDomeZ + std::sqrt(std::max(0.0, kDomeR * kDomeR - x * x - y * y));
}

TriMesh dome_mesh() {
  Grid g(101, 101);
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 100; ++j) g.at(j, i) = dome_z(j - 50.0, i - 50.0);
  TriMesh m = grid_to_mesh(g, 1.0);
  m.transform(1.0, Vec3(50, 50, 0));
  m.compute_normals();
  return m;
}

SysModel make_sys(bool dome = false, bool creep = false) {
  SysModel m;
  m.f_normal_levels = {1.0, 3.0, 5.0};
  for (int k = 0; k < 8; ++k) m.angles.push_back(k * std::numbers::pi / 4);
  m.plateaus = {0.1, 0.6};
  int id = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      SysPoint p;
      p.id = id++;
      p.position = Vec3(-30.0 + 30.0 * j, -30.0 + 30.0 * i, 0.0);
      if (dome) {
        p.position.z() = dome_z(p.position.x(), p.position.y());
        p.normal = (p.position - Vec3(0, 0, kDomeZ)).normalized();
      }
      const double mu = 0.3 + 0.05 * (i + j);
      for (double fn : m.f_normal_levels)
        for (int k = 0; k < 8; ++k) {
          SysBorder b;
          b.f_normal = fn;
          b.direction = k;
          b.result.f_limit = mu * fn;
          b.result.depth = fn / (0.8 + 0.1 * j);
          b.result.radius = mu * fn / (0.6 + 0.02 * k);
          p.borders.push_back(b);
        }
      if (creep) {  // as palpated on the virtual lab: c_v 0.02 N s/mm, k_t 0.5 N/mm
        p.creep_viscosity = 0.02;
        p.tangential_stiffness = 0.5;
      }
      m.points.push_back(p);
    }
  m.rebuild();
  return m;
}

// Trajectories at 1 kHz. Sliding: circles of 25 mm radius at a depth oscillating 0.5-3.5 mm.
// Elastic: a 0.3 mm wobble around a fixed point at 2-3 mm depth (inside the elastic range).
Vec3 path(long i, double speed_mm_s, bool dome) {
  if (dome) {  // circles of 20 mm radius, 2 mm deep below the dome
    const double t = i * 1e-3, w = speed_mm_s / 20.0;
    const Vec3 s(20.0 * std::cos(w * t), 20.0 * std::sin(w * t), 0.0);
    const Vec3 n = (Vec3(s.x(), s.y(), dome_z(s.x(), s.y())) - Vec3(0, 0, kDomeZ)).normalized();
    return Vec3(s.x(), s.y(), dome_z(s.x(), s.y())) - (2.0 + std::sin(2.1 * t)) * n;
  }
  const double t = i * 1e-3, w = speed_mm_s / 25.0;
  if (speed_mm_s <= 0)
    return Vec3(5.0 + 0.3 * std::sin(3.0 * t), 0.3 * std::cos(2.0 * t),
                -2.5 - 0.5 * std::sin(2.1 * t));
  return Vec3(25.0 * std::cos(w * t), 25.0 * std::sin(w * t), -2.0 - 1.5 * std::sin(2.1 * t));
}

void report(benchmark::State& state, std::vector<double>& ns) {
  std::sort(ns.begin(), ns.end());
  auto pct = [&](double p) { return ns[static_cast<std::size_t>(p * (ns.size() - 1))] * 1e-3; };
  state.counters["p50_us"] = pct(0.50);
  state.counters["p99_us"] = pct(0.99);
  state.counters["max_us"] = pct(1.0);
}

void run(benchmark::State& state, double speed, bool dome = false, bool creep = false) {
  const SysModel sys = make_sys(dome, creep);
  const PlaneShape plane(Vec3::Zero(), Vec3::UnitZ());
  const MeshSurface mesh(dome_mesh());
  const ProxyModel model{&sys, dome ? static_cast<const ShapeQuery*>(&mesh) : &plane};
  ProxyState st;
  std::vector<double> ns;
  ns.reserve(1 << 22);
  long i = 0, sliding = 0;
  for (auto _ : state) {
    const Vec3 p = path(i++, speed, dome);
    const auto t0 = std::chrono::steady_clock::now();
    const ProxyOutput o = proxy_step(model, st, p, 1e-3);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(o);
    sliding += o.sliding;
    if (ns.size() < ns.capacity())
      ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
  }
  state.counters["sliding_fraction"] = static_cast<double>(sliding) / std::max<long>(1, i);
  report(state, ns);
}

// Stick: elastic ticks (no return mapping).
void BM_ProxyStepElastic(benchmark::State& state) {
  run(state, 0.0);
}
// Fast sliding: a return mapping (with re-interpolation of g_s) on nearly every tick.
void BM_ProxyStepSliding(benchmark::State& state) {
  run(state, 60.0);
}

// Sliding on a dome given as a triangle mesh: every tick also queries the mesh (MeshIndex
// closest point) to put the proxy back on the surface.
void BM_ProxyStepSlidingDomeMesh(benchmark::State& state) {
  run(state, 60.0, true);
}
// The same with the creep-aware (Duvaut-Lions) return, one pass per tick.
void BM_ProxyStepSlidingDomeMeshCreep(benchmark::State& state) {
  run(state, 60.0, true, true);
}

BENCHMARK(BM_ProxyStepElastic);
BENCHMARK(BM_ProxyStepSliding);
BENCHMARK(BM_ProxyStepSlidingDomeMesh);
BENCHMARK(BM_ProxyStepSlidingDomeMeshCreep);

}  // namespace

BENCHMARK_MAIN();
