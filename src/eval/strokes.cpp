// Strokes on the real data sets, TCA-MESH vs CBA, distortion against the original surface
// (see strokes.hpp). Units: mm, N, N/mm, s; step times in microseconds.
#include "inhap/eval/strokes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "inhap/core/error.hpp"

namespace inhap::eval {

SurfaceTrace surface_trace(const rendering::Model& model,
                           const std::vector<rendering::StrokeSample>& samples, const Vec2& from,
                           const Vec2& to, const MetricOptions& o) {
  SurfaceTrace tr;
  const double len = (to - from).norm();
  if (!(len > 0)) throw Error("surface_trace: expected a stroke of non-zero length");
  const Vec2 dir = (to - from) / len;
  std::int32_t hint = -1;
  for (const auto& s : samples) {
    if (!s.contact) continue;
    const double u = (Vec2(s.hip.x(), s.hip.y()) - from).dot(dir);
    if (u < o.margin_mm || u > len - o.margin_mm) continue;
    const ClosestPoint cp =
        model.index().closest_point(s.hip, std::numeric_limits<double>::infinity(), hint);
    if (!cp.valid()) continue;
    hint = cp.triangle;
    tr.along_mm.push_back(u);
    tr.offset_mm.push_back((s.hip - cp.point).dot(model.normal(cp)));
    tr.k.push_back(model.stiffness(cp));
  }
  return tr;
}

StrokeMetrics stroke_metrics(const SurfaceTrace& tr, const MetricOptions& o) {
  StrokeMetrics m;
  const std::size_t n = tr.offset_mm.size();
  m.samples = long(n);
  if (n == 0) return m;
  double mean = 0, sq = 0;
  for (double v : tr.offset_mm) mean += v / double(n);
  for (double v : tr.offset_mm) sq += (v - mean) * (v - mean);
  m.mean_offset_mm = mean;
  m.distortion_rms_mm = std::sqrt(sq / double(n));
  // Windows [j, i] spanning jump_window_mm of travel (two pointers; the stroke moves forward).
  std::size_t j = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (j < i && tr.along_mm[i] - tr.along_mm[j + 1] >= o.jump_window_mm) ++j;
    if (tr.along_mm[i] - tr.along_mm[j] < o.jump_window_mm) continue;
    // A boundary: the stiffness somewhere in the window differs from its start by boundary_dk.
    double kmin = tr.k[j], kmax = tr.k[j];
    for (std::size_t q = j; q <= i; q += 5) {
      kmin = std::min(kmin, tr.k[q]);
      kmax = std::max(kmax, tr.k[q]);
    }
    kmin = std::min(kmin, tr.k[i]);
    kmax = std::max(kmax, tr.k[i]);
    if (kmax - kmin < o.boundary_dk) continue;
    ++m.boundary_windows;
    m.max_jump_mm = std::max(m.max_jump_mm, std::abs(tr.offset_mm[i] - tr.offset_mm[j]));
  }
  return m;
}

namespace {

// Replays the HIP sequence through a fresh State, timing each step (microseconds).
void time_replay(const rendering::Model& model, const std::vector<rendering::StrokeSample>& s,
                 rendering::Algorithm a, std::vector<double>& us) {
  rendering::State st;
  using clock = std::chrono::steady_clock;
  for (const auto& x : s) {
    const auto t0 = clock::now();
    static_cast<void>(rendering::step(model, st, x.hip, a));
    const auto t1 = clock::now();
    us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
}

double pct(std::vector<double>& v, double q) {
  if (v.empty()) return 0;
  const auto i = static_cast<std::size_t>(std::floor(q * double(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(i), v.end());
  return v[i];
}

}  // namespace

DatasetResult run_dataset(const rendering::Model& model, const rendering::RealDataset& ds,
                          const StrokesConfig& c) {
  if (c.speeds_mm_s.empty()) throw Error("eval strokes: expected at least one speed");
  DatasetResult r;
  r.name = ds.name;
  r.triangles = model.mesh().num_triangles();
  std::vector<double> us;
  double sq_t = 0, sq_c = 0;
  long n_t = 0, n_c = 0;
  for (const auto& line : ds.strokes)
    for (double v : c.speeds_mm_s) {
      rendering::StrokeOptions so;
      so.from = line.from;
      so.to = line.to;
      so.force_n = c.force_n;
      so.speed_mm_s = v;
      so.seed = c.seed;
      StrokeRun run;
      run.stroke = line.name;
      run.speed_mm_s = v;
      run.line = line;
      std::vector<rendering::StrokeSample> tca =
          rendering::simulate_stroke(model, rendering::Algorithm::kTCA, so);
      std::vector<rendering::StrokeSample> cba =
          rendering::simulate_stroke(model, rendering::Algorithm::kCBA, so);
      run.trace_tca = surface_trace(model, tca, line.from, line.to, c.metric);
      run.trace_cba = surface_trace(model, cba, line.from, line.to, c.metric);
      run.tca = stroke_metrics(run.trace_tca, c.metric);
      run.cba = stroke_metrics(run.trace_cba, c.metric);
      time_replay(model, tca, rendering::Algorithm::kTCA, us);
      time_replay(model, cba, rendering::Algorithm::kCBA, us);
      sq_t += double(run.tca.samples) * run.tca.distortion_rms_mm * run.tca.distortion_rms_mm;
      sq_c += double(run.cba.samples) * run.cba.distortion_rms_mm * run.cba.distortion_rms_mm;
      n_t += run.tca.samples;
      n_c += run.cba.samples;
      r.jump_tca = std::max(r.jump_tca, run.tca.max_jump_mm);
      r.jump_cba = std::max(r.jump_cba, run.cba.max_jump_mm);
      if (c.keep_samples) {
        run.samples_tca = std::move(tca);
        run.samples_cba = std::move(cba);
      }
      r.runs.push_back(std::move(run));
    }
  r.strokes = int(r.runs.size());
  r.distortion_tca = n_t ? std::sqrt(sq_t / double(n_t)) : 0;
  r.distortion_cba = n_c ? std::sqrt(sq_c / double(n_c)) : 0;
  r.timed_steps = long(us.size());
  r.step_p50_us = pct(us, 0.5);
  r.step_p99_us = pct(us, 0.99);
  r.step_max_us = us.empty() ? 0 : *std::max_element(us.begin(), us.end());
  return r;
}

nlohmann::json to_json(const std::vector<DatasetResult>& results) {
  nlohmann::json arr = nlohmann::json::array();
  for (const auto& r : results) {
    nlohmann::json runs = nlohmann::json::array();
    for (const auto& s : r.runs)
      runs.push_back(
          {{"stroke", s.stroke},
           {"speed_mm_s", s.speed_mm_s},
           {"from", {s.line.from.x(), s.line.from.y()}},
           {"to", {s.line.to.x(), s.line.to.y()}},
           {"distortion_rms_mm",
            {{"tca", s.tca.distortion_rms_mm}, {"cba", s.cba.distortion_rms_mm}}},
           {"mean_offset_mm", {{"tca", s.tca.mean_offset_mm}, {"cba", s.cba.mean_offset_mm}}},
           {"max_jump_mm", {{"tca", s.tca.max_jump_mm}, {"cba", s.cba.max_jump_mm}}},
           {"boundary_windows",
            {{"tca", s.tca.boundary_windows}, {"cba", s.cba.boundary_windows}}}});
    arr.push_back({{"name", r.name},
                   {"triangles", r.triangles},
                   {"strokes", r.strokes},
                   {"distortion_rms_mm", {{"tca", r.distortion_tca}, {"cba", r.distortion_cba}}},
                   {"max_jump_mm", {{"tca", r.jump_tca}, {"cba", r.jump_cba}}},
                   {"step_us",
                    {{"p50", r.step_p50_us},
                     {"p99", r.step_p99_us},
                     {"max", r.step_max_us},
                     {"steps", r.timed_steps}}},
                   {"runs", runs}});
  }
  return {{"units", "mm, N, N/mm, s; step times in microseconds"}, {"datasets", arr}};
}

std::string strokes_table_header() {
  return fmt::format("{:<8} {:>9} {:>7}  {:>19}  {:>19}  {:>15}\n", "data set", "triangles",
                     "strokes", "distortion TCA/CBA", "max jump TCA/CBA", "step p50/p99");
}

std::string strokes_table_row(const DatasetResult& r) {
  return fmt::format(
      "{:<8} {:>9} {:>7}  {:>8.3f} / {:<8.3f}  {:>8.3f} / {:<8.3f}  {:>6.1f} / {:<6.1f}\n", r.name,
      r.triangles, r.strokes, r.distortion_tca, r.distortion_cba, r.jump_tca, r.jump_cba,
      r.step_p50_us, r.step_p99_us);
}

StrokesConfig strokes_config(const std::vector<double>& speeds_mm_s, double force_n,
                             std::uint64_t seed, bool quick) {
  StrokesConfig cfg;
  cfg.speeds_mm_s = quick ? std::vector<double>{20.0} : speeds_mm_s;
  cfg.force_n = force_n;
  cfg.seed = seed;
  for (double v : cfg.speeds_mm_s)
    if (!(v > 0)) throw Error(fmt::format("--speeds: expected speeds > 0 mm/s, got {}", v));
  return cfg;
}

}  // namespace inhap::eval
