// Data-driven force model: training time on 65,000 synthetic samples (thesis planar object
// size) and the servo step latency (p50/p99, us) on a held-out trajectory; variants: thesis
// design, regression design, regression design with local-frame features (normal given), and
// the settings of `inhap eval forces` (local frame, weights 1 5 0.5, bins blended over +-1 mm)
// without and with tangentially mirrored training samples, and with the local stiffness prior
// and the friction-cone guard; and preset best (`model train`'s defaults: also the sliding
// floor, the envelope and the fallback) with every query moved 3 mm along the normal, off the
// training proxies, where the fallback's normal line evaluates the RBFs a second time.
// Units: time s / us; forces N.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <vector>

#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/servo.hpp"
#include "inhap/datadriven/synthetic.hpp"

namespace {

using namespace inhap;
using namespace inhap::datadriven;

const Vec3 kNormal = Vec3(0.1, -0.2, 1.0).normalized();  // normal handed to the local variant

TrainingSet training_set() {
  SyntheticParams sp;
  sp.samples = 65000;
  sp.seed = 1;
  const Recording rec = synthetic_recording(sp);
  TrainingSet s = make_training_set(rec, proxy_from_columns(rec, "synthetic"), FoawParams{});
  s.n.assign(s.size(), kNormal);
  return s;
}

/// 0: thesis design, 1: regression design, 2: regression design with local-frame features,
/// 3: eval forces' settings without the tangent mirror, 4: with it, 5: with it, the local
/// stiffness and shear priors and the friction-cone guard (eval forces' defaults), 6: preset
/// best, queried 3 mm off the training proxies.
TrainParams params_for(int variant) {
  if (variant == 6) return preset_params("best");
  TrainParams p;
  p.design = variant == 0 ? Design::kThesis : Design::kRegression;
  if (variant >= 2) p.features = FeatureSet::kLocalFrame;
  if (variant >= 3) {
    p.feature_weights = {1.0, 5.0, 0.5};
    p.bin_blend = 1.0;
    p.tangent_mirror = variant >= 4;
    p.stiffness_prior = variant == 5;
    p.shear_prior = variant == 5;
    p.friction_cone = variant == 5;
  }
  return p;
}
const char* label(int variant) {
  static const char* names[] = {"thesis",
                                "regression",
                                "regression+local",
                                "lab",
                                "lab+mirror",
                                "lab+mirror+priors+cone",
                                "best, 3 mm off the data (normal line)"};
  return names[variant];
}

/// Trained on first use (so a --benchmark_filter on one variant trains only that one).
const ForceModel& trained(int variant) {
  static std::map<int, ForceModel> models;
  auto it = models.find(variant);
  if (it == models.end())
    it = models.emplace(variant, train_force_model(training_set(), params_for(variant))).first;
  return it->second;
}

void BM_Train(benchmark::State& state) {
  const int variant = static_cast<int>(state.range(0));
  const TrainingSet set = training_set();
  double seconds = 0;
  for (auto _ : state) {
    const TrainedForceModel m = train_with_provenance(set, params_for(variant));
    seconds = m.provenance.stats.seconds;
    benchmark::DoNotOptimize(m.model.bins.data());
  }
  state.counters["samples"] = static_cast<double>(set.size());
  state.counters["train_s"] = seconds;
  state.SetLabel(label(variant));
}
BENCHMARK(BM_Train)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Arg(3)
    ->Arg(4)
    ->Arg(5)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

void BM_ServoStep(benchmark::State& state) {
  const int variant = static_cast<int>(state.range(0));
  const ForceModel& m = trained(variant);
  SyntheticParams sp;
  sp.samples = 37000;
  sp.seed = 2;
  const Recording rec = synthetic_recording(sp);
  const ProxyTrack track = proxy_from_columns(rec, "synthetic");
  const Vec3 off = variant == 6 ? Vec3(3.0 * kNormal) : Vec3::Zero();  // q and p moved alike
  ServoState st;
  std::vector<double> us;
  us.reserve(1 << 20);
  double line = 0;  // timed ticks where the normal line is evaluated
  std::size_t i = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const Vec3 f =
        servo_step(m, st, rec.p[i] + off, track.q[i] + off, kNormal, track.contact[i] != 0);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(f);
    if (track.contact[i] && us.size() < us.capacity()) {
      us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
      line += m.fallback.normal_weight_at(m.fallback.support.distance(track.q[i] + off)) > 0;
    }
    i = (i + 1) % rec.size();
  }
  if (!us.empty()) {
    std::sort(us.begin(), us.end());
    state.counters["p50_us"] = us[us.size() / 2];
    state.counters["p99_us"] = us[us.size() * 99 / 100];
    state.counters["line_share"] = line / static_cast<double>(us.size());
  }
  state.SetLabel(label(variant));
}
BENCHMARK(BM_ServoStep)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Arg(4)->Arg(5)->Arg(6);

}  // namespace

BENCHMARK_MAIN();
