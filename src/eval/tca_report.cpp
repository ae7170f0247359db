// `inhap eval tca` as one report: the study, the servo-step timing, the table and the JSON.
// Units: mm, N, N/mm, s; step times in microseconds.
#include "inhap/eval/tca_report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "inhap/rendering/datasets.hpp"

namespace inhap::eval {

using rendering::Algorithm;
using rendering::Task;

TcaEvalReport run_tca_eval(const TcaStudyOptions& options, const std::string& afm) {
  TcaEvalReport r;
  r.options = options;
  r.study = run_tca_study(options);
  r.study_triangles =
      rendering::StudySurface(rendering::DatasetParams{}, rendering::identity_layout())
          .mesh()
          .num_triangles();
  const rendering::Model timing_model(tca_timing_surface(options.seed, afm));
  r.timing_triangles = timing_model.mesh().num_triangles();
  r.cba_t = time_servo_steps(timing_model, Algorithm::kCBA);
  r.tca_t = time_servo_steps(timing_model, Algorithm::kTCA);
  return r;
}

namespace {

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

nlohmann::json timing_json(const StepTiming& t) {
  return {{"p50", t.p50},
          {"p99", t.p99},
          {"max", t.max},
          {"steps", t.steps},
          {"contact_steps", t.contact_steps}};
}

}  // namespace

std::string tca_eval_text(const TcaEvalReport& r) {
  const TcaStudyOptions& o = r.options;
  std::string out;
  const auto& s = r.study.summary;
  const auto [ts, cs, tk, ck] = tca_conditions(s);
  const auto tca_confused = s.misjudged_models(Algorithm::kTCA, Task::kShape);
  out += fmt::format(
      "Virtual user study (thesis 5.4): {} participants x {} trials per session, seed {}, {} "
      "triangles\n",
      o.participants, o.trials, o.seed, r.study_triangles);
  out += fmt::format("{:<28} {:>14} {:>14} {:>16}\n", "correct of 25 (mean +- SD)", "TCA-MESH",
                     "CBA", "thesis TCA/CBA");
  out += fmt::format("{:<28} {:>7.2f} +- {:<4.2f} {:>7.2f} +- {:<4.2f} {:>16}\n", "shape", ts.mean,
                     ts.sd_participants, cs.mean, cs.sd_participants, "24.4 / 17.0");
  out += fmt::format("{:<28} {:>7.2f} +- {:<4.2f} {:>7.2f} +- {:<4.2f} {:>16}\n", "stiffness",
                     tk.mean, tk.sd_participants, ck.mean, ck.sd_participants, "22.7 / 22.7");
  out += fmt::format("{:<28} {:>14.3f} {:>14.3f}\n", "distortion RMS (mm)", ts.distortion_rms_mm,
                     cs.distortion_rms_mm);
  out += fmt::format("{:<28} {:>6.0f} / {:<6.0f} {:>6.0f} / {:<6.0f} {:>16}\n",
                     "trial time shape/stiff. (s)", ts.mean_time_s, tk.mean_time_s, cs.mean_time_s,
                     ck.mean_time_s, "163/119 211/114");
  out += fmt::format("CBA confused models (ratio < 0.5): {}\n",
                     fmt::join(s.misjudged_models(Algorithm::kCBA, Task::kShape), " "));
  out +=
      fmt::format("TCA confused models:               {}\n",
                  tca_confused.empty() ? "none" : fmt::format("{}", fmt::join(tca_confused, " ")));
  out += fmt::format("per-model shape ratio (TCA / CBA) for the 12 predicted models:\n");
  for (int m : rendering::thesis_cba_confusions())
    out += fmt::format("  M{:<2} {:.2f} / {:.2f}\n", m, ts.model_ratio[m], cs.model_ratio[m]);
  out += fmt::format(
      "servo step on {} triangles ({} steps, {:.0f} % in contact): CBA p50 {:.2f} us p99 {:.2f} "
      "us; TCA p50 {:.2f} us p99 {:.2f} us\n",
      r.timing_triangles, r.tca_t.steps,
      100.0 * double(r.tca_t.contact_steps) / double(std::max(1L, r.tca_t.steps)), r.cba_t.p50,
      r.cba_t.p99, r.tca_t.p50, r.tca_t.p99);
  if (r.study.incomplete)
    out += fmt::format("warning: {} trials ended before every model was labelled\n",
                       r.study.incomplete);
  out += fmt::format("study time {:.1f} s\n", r.study.study_s);
  return out;
}

nlohmann::json tca_eval_json(const TcaEvalReport& r) {
  const TcaStudyOptions& o = r.options;
  const auto& s = r.study.summary;
  const auto [ts, cs, tk, ck] = tca_conditions(s);
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

}  // namespace inhap::eval
