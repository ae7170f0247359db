// The data-driven servo step (thesis 4.4-4.5: FOAW -> sliding-yield-surface proxy -> RBF force)
// per tick, p50/p99/max in us, three ways in the same run:
//   BM_ServoByHand      the pieces composed by hand, as `inhap eval forces` did before the
//                       haptics module: friction::proxy_step, the contact/normal gating, then
//                       datadriven::servo_step;
//   BM_ServoHaptics     haptics::step(DataDrivenModel, DataDrivenState, ServoInput) (no virtual);
//   BM_ServoRenderer    the same through the virtual haptics::Renderer (a device loop);
//   BM_ServoRendererMesh131k  the same with the shape a 131,072-triangle grid mesh.
// Input: a 12 s free exploration of the lab's planar cylinder (seed 3), replayed cyclically
// (states reset between laps, outside the timing); Coulomb sliding yield surfaces on its top
// plane (3 x 3 reference points, with creep) and a force model with `eval forces`' settings
// (local frame, weights 1 5 0.5, bin blend, mirror, priors, cone guard; 150 centres per bin)
// trained on the same recording. Units: us per tick.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "friction/sys_helpers.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/proxy_track.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/haptics/renderers.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"

namespace {

using namespace inhap;

struct Setup {
  Recording rec;
  friction::SysModel sys;
  std::unique_ptr<friction::PlaneShape> plane;
  /// The same top plane as a 257 x 257 grid mesh over the explored region: 131,072 triangles
  /// (the size of the thesis' protein-on-mica map), so the proxy queries a real mesh index.
  std::unique_ptr<friction::MeshSurface> mesh;
  datadriven::ForceModel force;

  Setup() {
    lab::RecordSpec spec;
    spec.seconds = 12.0;
    spec.seed = 3;
    const lab::LabRecording lab = lab::record_scene(lab::builtin_scene("planar"), spec);
    rec = lab.rec;
    double top = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < rec.size(); ++i)
      if (lab.truth.contact[i] && lab.truth.anchor[i].allFinite())
        top = std::max(top, lab.truth.anchor[i].z());
    sys = test::coulomb_sys(
        test::grid_points(3, 3, 40.0, top), [](std::size_t i) { return 0.3 + 0.1 * (i % 3); }, 0.5,
        0.4);
    for (auto& p : sys.points) {  // creep as palpated on the lab: c_v 0.02 N s/mm, k_t 0.5 N/mm
      p.creep_viscosity = 0.02;
      p.tangential_stiffness = 0.5;
    }
    sys.rebuild();
    plane = std::make_unique<friction::PlaneShape>(Vec3(0, 0, top), Vec3::UnitZ());
    Grid h(257, 257);
    for (int j = 0; j < 257; ++j)
      for (int i = 0; i < 257; ++i) h.at(i, j) = top;
    TriMesh m = grid_to_mesh(h, 160.0 / 256);
    for (Vec3& v : m.positions) v += Vec3(-80, -80, 0);
    mesh = std::make_unique<friction::MeshSurface>(m, 0.0);
    const friction::ProxyColumns c = friction::proxy_track({&sys, plane.get()}, rec);
    datadriven::ProxyTrack t;
    t.q.resize(c.size());
    t.n.assign(c.size(), Vec3::UnitZ());
    t.contact.resize(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) {
      t.contact[i] = c.contact[i] && c.q[i].allFinite();
      t.q[i] = t.contact[i] ? c.q[i] : rec.p[i];
      if (t.contact[i]) t.n[i] = c.n[i];
    }
    datadriven::TrainParams p = datadriven::preset_params("best");  // what `model train` runs
    p.centers = 150;
    force = datadriven::train_force_model(
        datadriven::make_training_set(rec, t, datadriven::FoawParams{}), p);
  }
};

const Setup& setup() {
  static const Setup s;
  return s;
}

void report(benchmark::State& state, std::vector<double>& ns, long contact, long ticks) {
  std::sort(ns.begin(), ns.end());
  auto pct = [&](double p) { return ns[static_cast<std::size_t>(p * (ns.size() - 1))] * 1e-3; };
  state.counters["p50_us"] = pct(0.50);
  state.counters["p99_us"] = pct(0.99);
  state.counters["max_us"] = pct(1.0);
  state.counters["contact_fraction"] = static_cast<double>(contact) / std::max(1L, ticks);
}

/// Runs `tick(i)` (returns the contact flag) once per benchmark iteration over the recording's
/// samples, cyclically; `reset()` between laps, untimed.
template <class Tick, class Reset>
void run(benchmark::State& state, Tick&& tick, Reset&& reset) {
  const std::size_t n = setup().rec.size();
  std::vector<double> ns;
  ns.reserve(1 << 22);
  std::size_t i = 0;
  long contact = 0, ticks = 0;
  for (auto _ : state) {
    if (i == n) {
      state.PauseTiming();
      reset();
      i = 0;
      state.ResumeTiming();
    }
    const auto t0 = std::chrono::steady_clock::now();
    const bool c = tick(i++);
    const auto t1 = std::chrono::steady_clock::now();
    contact += c;
    ++ticks;
    if (ns.size() < ns.capacity())
      ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
  }
  report(state, ns, contact, ticks);
}

void BM_ServoByHand(benchmark::State& state) {
  const Setup& s = setup();
  const friction::ProxyModel pm{&s.sys, s.plane.get()};
  friction::ProxyState ps;
  datadriven::ServoState ss;
  run(
      state,
      [&](std::size_t i) {
        const Vec3& p = s.rec.p[i];
        const double dt = i ? s.rec.t[i] - s.rec.t[i - 1] : 0.0;
        const friction::ProxyOutput o = friction::proxy_step(pm, ps, p, dt);
        const bool contact = o.contact && o.q.allFinite();
        const Vec3 f = datadriven::servo_step(s.force, ss, p, contact ? o.q : p,
                                              contact ? o.n : Vec3::UnitZ(), contact);
        benchmark::DoNotOptimize(f);
        return contact;
      },
      [&] {
        ps = friction::ProxyState{};
        ss = datadriven::ServoState{};
      });
}

haptics::ServoInput input_at(std::size_t i) {
  haptics::ServoInput in;
  in.t_s = setup().rec.t[i];
  in.p_mm = setup().rec.p[i];
  return in;
}

void BM_ServoHaptics(benchmark::State& state) {
  const Setup& s = setup();
  const haptics::DataDrivenModel model(s.sys, *s.plane, s.force);
  haptics::DataDrivenState st;
  run(
      state,
      [&](std::size_t i) {
        const haptics::ServoOutput o = haptics::step(model, st, input_at(i));
        benchmark::DoNotOptimize(o);
        return o.contact;
      },
      [&] { st.reset(); });
}

// The data-driven renderer through the virtual interface on a shape.
void run_renderer(benchmark::State& state, const friction::ShapeQuery& shape) {
  const Setup& s = setup();
  const haptics::DataDrivenModel model(s.sys, shape, s.force);
  std::unique_ptr<haptics::Renderer> r = std::make_unique<haptics::DataDrivenRenderer>(model);
  run(
      state,
      [&](std::size_t i) {
        const haptics::ServoOutput o = r->step(input_at(i));
        benchmark::DoNotOptimize(o);
        return o.contact;
      },
      [&] { r->reset(); });
}

void BM_ServoRenderer(benchmark::State& state) {
  run_renderer(state, *setup().plane);
}

// The same with the shape a 131,072-triangle mesh.
void BM_ServoRendererMesh131k(benchmark::State& state) {
  run_renderer(state, *setup().mesh);
  state.counters["triangles"] = 131072;
}

}  // namespace

BENCHMARK(BM_ServoRendererMesh131k);
// Interleaved three times (old, new, virtual, old, new, ...): on a shared machine the load drifts
// within a run, so compare the rounds, not one pair.
BENCHMARK(BM_ServoByHand);
BENCHMARK(BM_ServoHaptics);
BENCHMARK(BM_ServoRenderer);
BENCHMARK(BM_ServoByHand);
BENCHMARK(BM_ServoHaptics);
BENCHMARK(BM_ServoRenderer);
BENCHMARK(BM_ServoByHand);
BENCHMARK(BM_ServoHaptics);
BENCHMARK(BM_ServoRenderer);
BENCHMARK_MAIN();
