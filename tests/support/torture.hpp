// Servo torture (issue 20): random ticks mixing NaN, +-1e9, 50 mm jumps and legal motion, fed to
// each renderer (CBA, TCA-MESH, data-driven). Counts non-finite and over-limit forces and checks
// that a legal trajectory afterwards renders as from a fresh state. Used by the test suite
// (short) and by bench/bench_torture.cpp (10^7 steps). Units: mm, N.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/core/device.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/datadriven/servo.hpp"
#include "inhap/datadriven/synthetic.hpp"
#include "inhap/rendering/renderer.hpp"
#include "support/meshes.hpp"

namespace inhap::test {

struct TortureResult {
  std::uint64_t steps = 0, non_finite = 0, over_limit = 0, nonzero = 0;
  double max_force = 0;
  bool fresh_after = false;  ///< a legal trajectory afterwards matched a fresh state's
};

/// The next probe position: 30% legal motion (<= 0.5 mm per tick), 20% a 50 mm jump, 10% NaN,
/// 10% +-1e9, 30% a random point in the working box (often far from the last one).
inline Vec3 torture_point(Rng& rng, const Vec3& last) {
  const double u = rng.uniform(0, 1);
  if (u < 0.3)
    return last.allFinite() && last.norm() < 1e3
               ? Vec3(last +
                      Vec3(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)))
               : Vec3(rng.uniform(0, 40), rng.uniform(0, 40), rng.uniform(-5, 5));
  if (u < 0.5) {
    const Vec3 d(rng.normal(), rng.normal(), rng.normal());
    const Vec3 base = last.allFinite() && last.norm() < 1e3 ? last : Vec3(20, 20, 0);
    return base + 50.0 * d.normalized();
  }
  if (u < 0.6) {
    Vec3 p(rng.uniform(0, 40), rng.uniform(0, 40), 0);
    p[static_cast<int>(rng.uniform(0, 2.999))] = std::numeric_limits<double>::quiet_NaN();
    return p;
  }
  if (u < 0.7) {
    Vec3 p(rng.uniform(0, 40), rng.uniform(0, 40), 0);
    p[static_cast<int>(rng.uniform(0, 2.999))] = rng.uniform(0, 1) < 0.5 ? 1e9 : -1e9;
    return p;
  }
  return Vec3(rng.uniform(0, 40), rng.uniform(0, 40), rng.uniform(-10, 5));
}

inline void count_force(TortureResult& r, const Vec3& f, double limit) {
  ++r.steps;
  const double n = f.norm();
  if (!f.allFinite() || !std::isfinite(n)) {
    ++r.non_finite;
    return;
  }
  if (n > limit * (1 + 1e-12)) ++r.over_limit;
  if (n > 0) ++r.nonzero;
  r.max_force = std::max(r.max_force, n);
}

/// A legal press-and-slide on the 40 x 40 mm grid: starts 100 mm above it (farther than a jump
/// from the torture's positions, as a real restart after a glitch), descends 3 mm into it and
/// slides.
inline std::vector<Vec3> legal_trajectory() {
  std::vector<Vec3> t;
  for (int i = 0; i <= 1030; ++i) t.emplace_back(20, 20, 100.0 - 0.1 * i);
  for (int i = 1; i <= 300; ++i) t.emplace_back(20 + 0.03 * i, 20, -3.0);
  return t;
}

/// A wavy 41 x 41 grid mesh (1 mm spacing, +-1 mm bumps) with a stiffness from 0.2 to 2 N/mm.
inline TriMesh torture_mesh() {
  TriMesh m = make_grid_mesh(
      41, 41, 1.0, [](double x, double y) { return std::sin(0.3 * x) * std::cos(0.2 * y); });
  std::vector<double> k;
  for (const Vec3& p : m.positions) k.push_back(0.2 + 1.8 * p.x() / 40.0);
  m.set_property("stiffness", k);
  return m;
}

inline TortureResult torture_renderer(const rendering::Model& model, rendering::Algorithm alg,
                                      std::uint64_t steps, std::uint64_t seed) {
  TortureResult r;
  const double limit = effective_force_limit(model.params().force_limit_n);
  Rng rng(seed);
  rendering::State st;
  Vec3 p(20, 20, 10);
  for (std::uint64_t i = 0; i < steps; ++i) {
    p = torture_point(rng, p);
    count_force(r, rendering::step(model, st, p, alg), limit);
  }
  rendering::State fresh;
  r.fresh_after = true;
  for (const Vec3& q : legal_trajectory()) {
    const Vec3 a = rendering::step(model, st, q, alg), b = rendering::step(model, fresh, q, alg);
    count_force(r, a, limit);
    if (!(a == b)) r.fresh_after = false;
  }
  return r;
}

/// A small data-driven model trained on the synthetic recording (seconds of work).
inline datadriven::ForceModel torture_dd_model() {
  datadriven::SyntheticParams sp;
  sp.samples = 8000;
  sp.seed = 2;
  const Recording rec = datadriven::synthetic_recording(sp);
  const datadriven::ProxyTrack track = datadriven::proxy_from_columns(rec, "synthetic");
  const datadriven::TrainingSet s =
      datadriven::make_training_set(rec, track, datadriven::FoawParams{});
  datadriven::TrainParams p;
  p.bins = 3;
  p.centers = 60;
  p.seed = 5;
  p.design = datadriven::Design::kRegression;
  return datadriven::train_force_model(s, p);
}

inline TortureResult torture_data_driven(const datadriven::ForceModel& model, std::uint64_t steps,
                                         std::uint64_t seed) {
  TortureResult r;
  const double limit = effective_force_limit(model.force_limit_n);
  Rng rng(seed);
  datadriven::ServoState st;
  Vec3 p(0, 0, 1);
  for (std::uint64_t i = 0; i < steps; ++i) {
    p = torture_point(rng, p);
    // The proxy: usually near p (above it), sometimes absurd; contact at random.
    const double u = rng.uniform(0, 1);
    Vec3 q = p + Vec3(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(0, 5));
    if (u < 0.05) q = Vec3(1e9, 0, 0);
    if (u > 0.95) q.x() = std::numeric_limits<double>::quiet_NaN();
    count_force(r, datadriven::servo_step(model, st, p, q, rng.uniform(0, 1) < 0.7), limit);
  }
  datadriven::ServoState fresh;
  datadriven::EntryProxyState ea, eb;
  r.fresh_after = true;
  for (const Vec3& t : legal_trajectory()) {
    const Vec3 x = t - Vec3(20, 20, 0);
    const bool contact = x.z() < 0;
    const Vec3 a =
        datadriven::servo_step(model, st, x, datadriven::entry_proxy(ea, x, contact), contact);
    const Vec3 b =
        datadriven::servo_step(model, fresh, x, datadriven::entry_proxy(eb, x, contact), contact);
    count_force(r, a, limit);
    if (!(a == b)) r.fresh_after = false;
  }
  return r;
}

}  // namespace inhap::test
