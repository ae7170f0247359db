// inhap eval tca: the virtual user study of thesis sec. 5.4 (16 participants, TCA-MESH and CBA,
// 5 trials each, shape and stiffness tasks) plus the servo-step timing on a 131,072-triangle
// height map. Units: mm, N, N/mm, s; timings in microseconds.
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/lab/participant.hpp"
#include "inhap/rendering/datasets.hpp"
#include "inhap/rendering/experiment.hpp"

namespace inhap::cli {
namespace {

using render::Algorithm;
using render::Task;

struct EvalTcaOptions {
  std::uint64_t seed = 1;
  int participants = 16, trials = 5, threads = 2;
  bool quick = false;
  std::string json, afm;
};

struct Timing {
  double p50 = 0, p99 = 0, max = 0;
  long steps = 0, contact_steps = 0;
};

// The timing surface: the AFM-like synthetic map, or a WSxM file (levelled) resampled to 257 x 257
// over 100 mm with its height range scaled to 10 mm and stiffness from height (1.0 N/mm at the
// lowest point to 0.2 N/mm at the highest) — a stand-in for timing only, the file has no
// stiffness channel.
TriMesh timing_surface(const EvalTcaOptions& o) {
  if (o.afm.empty()) return render::afm_like_surface(o.seed);
  Grid raw = read_wsxm_top(o.afm);
  level_plane(raw);
  const int n = 257;
  Grid h(n, n), k(n, n);
  const double lo = raw.min(), span = std::max(raw.max() - lo, 1e-12);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double gx = x * double(raw.width - 1) / (n - 1),
                   gy = y * double(raw.height - 1) / (n - 1);
      const int ix = std::min(raw.width - 2, int(gx)), iy = std::min(raw.height - 2, int(gy));
      const double fx = gx - ix, fy = gy - iy;
      const double v = (1 - fx) * (1 - fy) * raw.at(ix, iy) + fx * (1 - fy) * raw.at(ix + 1, iy) +
                       (1 - fx) * fy * raw.at(ix, iy + 1) + fx * fy * raw.at(ix + 1, iy + 1);
      h.at(x, y) = 10.0 * (v - lo) / span;
      k.at(x, y) = 1.0 - 0.8 * (v - lo) / span;
    }
  return grid_to_mesh(h, 100.0 / (n - 1), &k);
}

// Times render::step call by call while a force-regulated probe strokes rows across the map.
Timing time_steps(const render::Model& model, Algorithm algorithm) {
  render::State state;
  const Box3 b = model.mesh().bbox();
  std::vector<double> us;
  long contact = 0;
  const double force = 1.5, speed = 0.04;  // N, mm per tick (40 mm/s at 1 kHz)
  for (double y = b.min.y() + 5; y < b.max.y() - 4; y += 10) {
    Vec3 p(b.min.x() + 2, y, b.max.z() + 2);
    for (double x = b.min.x() + 2; x < b.max.x() - 2; x += speed) {
      p.x() = x;
      const auto t0 = std::chrono::steady_clock::now();
      const Vec3 f = render::step(model, state, p, algorithm);
      const auto t1 = std::chrono::steady_clock::now();
      us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
      contact += state.collision;
      p.z() += std::clamp(0.3 * (f.norm() - force), -0.05, 0.05);  // hand: push until 1.5 N
    }
    for (int i = 0; i < 200; ++i)
      render::step(model, state, Vec3(p.x(), p.y(), b.max.z() + 2), algorithm);  // lift
  }
  Timing t;
  t.steps = static_cast<long>(us.size());
  t.contact_steps = contact;
  std::sort(us.begin(), us.end());
  t.p50 = us[us.size() / 2];
  t.p99 = us[std::min(us.size() - 1, us.size() * 99 / 100)];
  t.max = us.back();
  return t;
}

std::vector<render::TrialResult> run_study(const EvalTcaOptions& o) {
  render::StudyConfig cfg;
  cfg.participants = o.participants;
  cfg.trials = o.trials;
  cfg.seed = o.seed;
  const long total = long(o.participants) * long(render::participant_schedule(cfg, 0).size());
  std::vector<std::vector<render::TrialResult>> per(o.participants);
  std::atomic<int> next{0};
  std::atomic<long> done{0};
  std::mutex progress_mutex;
  const auto start = std::chrono::steady_clock::now();
  auto worker = [&] {
    for (int p = next++; p < o.participants; p = next++) {
      lab::VirtualParticipant vp(lab::sample_participant(o.seed * 1000003ull + std::uint64_t(p)));
      for (const auto& spec : render::participant_schedule(cfg, p)) {
        per[p].push_back(render::run_trial(vp, vp, spec));
        const long d = ++done;
        std::lock_guard lock(progress_mutex);
        const double el =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        progress("eval tca", double(d) / double(total),
                 d < total ? el / double(d) * double(total - d) : 0.0);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, o.threads); ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  std::vector<render::TrialResult> all;
  for (auto& v : per) all.insert(all.end(), v.begin(), v.end());
  return all;
}

nlohmann::json condition_json(const render::ConditionSummary& c) {
  nlohmann::json j;
  j["trials"] = c.trials;
  j["mean"] = c.mean;
  j["sd_participants"] = c.sd_participants;
  j["sd_trials"] = c.sd_trials;
  j["per_participant"] = c.per_participant;
  j["model_correct_ratio"] = c.model_ratio;
  j["mean_time_s"] = c.mean_time_s;
  return j;
}

// Everything `eval tca` reports.
struct EvalReport {
  render::StudySummary summary;
  long incomplete = 0;
  double study_s = 0;
  std::size_t study_triangles = 0, timing_triangles = 0;
  Timing cba_t, tca_t;
};

nlohmann::json timing_json(const Timing& t) {
  return {{"p50", t.p50},
          {"p99", t.p99},
          {"max", t.max},
          {"steps", t.steps},
          {"contact_steps", t.contact_steps}};
}

void print_report(const EvalTcaOptions& o, const EvalReport& r) {
  const auto& s = r.summary;
  const auto& ts = s.get(Algorithm::kTCA, Task::kShape);
  const auto& cs = s.get(Algorithm::kCBA, Task::kShape);
  const auto& tk = s.get(Algorithm::kTCA, Task::kStiffness);
  const auto& ck = s.get(Algorithm::kCBA, Task::kStiffness);
  const auto tca_confused = s.misjudged_models(Algorithm::kTCA, Task::kShape);
  fmt::print(
      "Virtual user study (thesis 5.4): {} participants x {} trials per session, seed {}, {} "
      "triangles\n",
      o.participants, o.trials, o.seed, r.study_triangles);
  fmt::print("{:<28} {:>14} {:>14} {:>16}\n", "correct of 25 (mean +- SD)", "TCA-MESH", "CBA",
             "thesis TCA/CBA");
  fmt::print("{:<28} {:>7.2f} +- {:<4.2f} {:>7.2f} +- {:<4.2f} {:>16}\n", "shape", ts.mean,
             ts.sd_participants, cs.mean, cs.sd_participants, "24.4 / 17.0");
  fmt::print("{:<28} {:>7.2f} +- {:<4.2f} {:>7.2f} +- {:<4.2f} {:>16}\n", "stiffness", tk.mean,
             tk.sd_participants, ck.mean, ck.sd_participants, "22.7 / 22.7");
  fmt::print("{:<28} {:>14.3f} {:>14.3f}\n", "distortion RMS (mm)", ts.distortion_rms_mm,
             cs.distortion_rms_mm);
  fmt::print("{:<28} {:>6.0f} / {:<6.0f} {:>6.0f} / {:<6.0f} {:>16}\n",
             "trial time shape/stiff. (s)", ts.mean_time_s, tk.mean_time_s, cs.mean_time_s,
             ck.mean_time_s, "163/119 211/114");
  fmt::print("CBA confused models (ratio < 0.5): {}\n",
             fmt::join(s.misjudged_models(Algorithm::kCBA, Task::kShape), " "));
  fmt::print("TCA confused models:               {}\n",
             tca_confused.empty() ? "none" : fmt::format("{}", fmt::join(tca_confused, " ")));
  fmt::print("per-model shape ratio (TCA / CBA) for the 12 predicted models:\n");
  for (int m : render::thesis_cba_confusions())
    fmt::print("  M{:<2} {:.2f} / {:.2f}\n", m, ts.model_ratio[m], cs.model_ratio[m]);
  fmt::print(
      "servo step on {} triangles ({} steps, {:.0f} % in contact): CBA p50 {:.2f} us p99 {:.2f} "
      "us; TCA p50 {:.2f} us p99 {:.2f} us\n",
      r.timing_triangles, r.tca_t.steps,
      100.0 * double(r.tca_t.contact_steps) / double(std::max(1L, r.tca_t.steps)), r.cba_t.p50,
      r.cba_t.p99, r.tca_t.p50, r.tca_t.p99);
  if (r.incomplete)
    fmt::print("warning: {} trials ended before every model was labelled\n", r.incomplete);
  fmt::print("study time {:.1f} s\n", r.study_s);
}

nlohmann::json report_json(const EvalTcaOptions& o, const EvalReport& r) {
  const auto& s = r.summary;
  const auto& ts = s.get(Algorithm::kTCA, Task::kShape);
  const auto& cs = s.get(Algorithm::kCBA, Task::kShape);
  const auto& tk = s.get(Algorithm::kTCA, Task::kStiffness);
  const auto& ck = s.get(Algorithm::kCBA, Task::kStiffness);
  nlohmann::json j;
  j["seed"] = o.seed;
  j["participants"] = o.participants;
  j["trials_per_session"] = o.trials;
  j["triangles"] = r.study_triangles;
  j["shape_correct"] = {{"tca", ts.mean}, {"cba", cs.mean}};
  j["shape_correct_sd"] = {{"tca", ts.sd_participants}, {"cba", cs.sd_participants}};
  j["stiffness_correct"] = {{"tca", tk.mean}, {"cba", ck.mean}};
  j["stiffness_correct_sd"] = {{"tca", tk.sd_participants}, {"cba", ck.sd_participants}};
  j["cba_confused_models"] = s.misjudged_models(Algorithm::kCBA, Task::kShape);
  j["tca_confused_models"] = s.misjudged_models(Algorithm::kTCA, Task::kShape);
  j["thesis_cba_confusions"] = render::thesis_cba_confusions();
  j["distortion_rms_mm"] = {{"tca", ts.distortion_rms_mm}, {"cba", cs.distortion_rms_mm}};
  j["step_us"] = {{"p50", std::max(r.cba_t.p50, r.tca_t.p50)},
                  {"p99", std::max(r.cba_t.p99, r.tca_t.p99)},
                  {"triangles", r.timing_triangles},
                  {"cba", timing_json(r.cba_t)},
                  {"tca", timing_json(r.tca_t)}};
  j["conditions"] = {{"shape", {{"tca", condition_json(ts)}, {"cba", condition_json(cs)}}},
                     {"stiffness", {{"tca", condition_json(tk)}, {"cba", condition_json(ck)}}}};
  j["incomplete_trials"] = r.incomplete;
  return j;
}

void run_eval_tca(EvalTcaOptions o) {
  if (o.quick) {
    o.participants = std::min(o.participants, 4);
    o.trials = std::min(o.trials, 2);
  }
  if (o.participants < 1 || o.trials < 1)
    throw Error(fmt::format("--participants and --trials must be >= 1, got {} and {}",
                            o.participants, o.trials));
  EvalReport r;
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<render::TrialResult> results = run_study(o);
  r.summary = summarize(results);
  r.study_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (const auto& t : results) r.incomplete += !t.session.completed;
  r.study_triangles = render::StudySurface(render::DatasetParams{}, render::identity_layout())
                          .mesh()
                          .num_triangles();
  const render::Model timing_model(timing_surface(o));
  r.timing_triangles = timing_model.mesh().num_triangles();
  r.cba_t = time_steps(timing_model, Algorithm::kCBA);
  r.tca_t = time_steps(timing_model, Algorithm::kTCA);
  print_report(o, r);
  if (!o.json.empty()) write_file_atomic(o.json, report_json(o, r).dump(2) + "\n");
}

void register_eval_tca(CLI::App& app) {
  auto opt = std::make_shared<EvalTcaOptions>();
  auto* cmd = eval_group(app)->add_subcommand(
      "tca",
      "Virtual user study of TCA-MESH vs CBA (thesis 5.4, fig. 5.10-5.11): simulated participants "
      "stroke\n"
      "and tap the 25 shape-stiffness models (5x5 on 140x140 mm, 39,200 triangles, layout "
      "reshuffled per trial)\n"
      "and label shape (bump/hole/flat) and stiffness (harder/softer/same). Also times the servo "
      "step on a\n"
      "131,072-triangle height map. Units: mm, N, N/mm, s; step times in microseconds.");
  cmd->add_option("--seed", opt->seed, "Seed of participants and layouts")->capture_default_str();
  cmd->add_option("--participants", opt->participants, "Number of virtual participants")
      ->capture_default_str();
  cmd->add_option("--trials", opt->trials,
                  "Trials per session (one session per algorithm and task)")
      ->capture_default_str();
  cmd->add_option("--threads", opt->threads, "Worker threads (participants run in parallel)")
      ->capture_default_str();
  cmd->add_flag("--quick", opt->quick, "At most 4 participants x 2 trials");
  cmd->add_option("--json", opt->json, "Write the results as JSON to this file");
  cmd->add_option("--afm", opt->afm,
                  "Time the servo step on this WSxM .top topography instead of the synthetic map")
      ->check(CLI::ExistingFile);
  cmd->callback([opt] { run_eval_tca(*opt); });
}

}  // namespace

INHAP_COMMAND(60, "eval tca", register_eval_tca);

}  // namespace inhap::cli
