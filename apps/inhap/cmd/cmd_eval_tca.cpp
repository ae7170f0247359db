// inhap eval tca: the virtual user study of thesis sec. 5.4 (16 participants, TCA-MESH and CBA,
// 5 trials each, shape and stiffness tasks) plus the servo-step timing on a 131,072-triangle
// height map (the experiment: eval/tca_study.hpp). Units: mm, N, N/mm, s; timings in
// microseconds.
#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/eval/tca_study.hpp"
#include "inhap/rendering/datasets.hpp"

namespace inhap::cli {
namespace {

using rendering::Algorithm;
using rendering::Task;

struct EvalTcaOptions {
  std::uint64_t seed = 1;
  int participants = 16, trials = 5, threads = 2;
  bool quick = false;
  std::string json, afm;
};

nlohmann::json condition_json(const rendering::ConditionSummary& c) {
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
  eval::TcaStudyResult study;
  std::size_t study_triangles = 0, timing_triangles = 0;
  eval::StepTiming cba_t, tca_t;
};

nlohmann::json timing_json(const eval::StepTiming& t) {
  return {{"p50", t.p50},
          {"p99", t.p99},
          {"max", t.max},
          {"steps", t.steps},
          {"contact_steps", t.contact_steps}};
}

void print_report(const EvalTcaOptions& o, const EvalReport& r) {
  const auto& s = r.study.summary;
  const auto [ts, cs, tk, ck] = eval::tca_conditions(s);
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
  for (int m : rendering::thesis_cba_confusions())
    fmt::print("  M{:<2} {:.2f} / {:.2f}\n", m, ts.model_ratio[m], cs.model_ratio[m]);
  fmt::print(
      "servo step on {} triangles ({} steps, {:.0f} % in contact): CBA p50 {:.2f} us p99 {:.2f} "
      "us; TCA p50 {:.2f} us p99 {:.2f} us\n",
      r.timing_triangles, r.tca_t.steps,
      100.0 * double(r.tca_t.contact_steps) / double(std::max(1L, r.tca_t.steps)), r.cba_t.p50,
      r.cba_t.p99, r.tca_t.p50, r.tca_t.p99);
  if (r.study.incomplete)
    fmt::print("warning: {} trials ended before every model was labelled\n", r.study.incomplete);
  fmt::print("study time {:.1f} s\n", r.study.study_s);
}

nlohmann::json report_json(const EvalTcaOptions& o, const EvalReport& r) {
  const auto& s = r.study.summary;
  const auto [ts, cs, tk, ck] = eval::tca_conditions(s);
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
  j["thesis_cba_confusions"] = rendering::thesis_cba_confusions();
  j["distortion_rms_mm"] = {{"tca", ts.distortion_rms_mm}, {"cba", cs.distortion_rms_mm}};
  j["step_us"] = {{"p50", std::max(r.cba_t.p50, r.tca_t.p50)},
                  {"p99", std::max(r.cba_t.p99, r.tca_t.p99)},
                  {"triangles", r.timing_triangles},
                  {"cba", timing_json(r.cba_t)},
                  {"tca", timing_json(r.tca_t)}};
  j["conditions"] = {{"shape", {{"tca", condition_json(ts)}, {"cba", condition_json(cs)}}},
                     {"stiffness", {{"tca", condition_json(tk)}, {"cba", condition_json(ck)}}}};
  j["incomplete_trials"] = r.study.incomplete;
  return j;
}

void run_eval_tca(EvalTcaOptions o) {
  if (o.quick) {
    o.participants = std::min(o.participants, 4);
    o.trials = std::min(o.trials, 2);
  }
  EvalReport r;
  eval::TcaStudyOptions so;
  so.seed = o.seed;
  so.participants = o.participants;
  so.trials = o.trials;
  so.threads = o.threads;
  so.progress = [](const std::string&, double f, double eta) { progress("eval tca", f, eta); };
  r.study = eval::run_tca_study(so);
  r.study_triangles = rendering::StudySurface(rendering::DatasetParams{}, rendering::identity_layout())
                          .mesh()
                          .num_triangles();
  const rendering::Model timing_model(eval::tca_timing_surface(o.seed, o.afm));
  r.timing_triangles = timing_model.mesh().num_triangles();
  r.cba_t = eval::time_servo_steps(timing_model, Algorithm::kCBA);
  r.tca_t = eval::time_servo_steps(timing_model, Algorithm::kTCA);
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
