// inhap demo: chapter-5 steps: the TCA-MESH vs CBA virtual user study (fig. 5.10-5.11) and
// strokes on the 25-model surface (fig. 5.7). Units: mm, N, N/mm, s.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "demo.hpp"
#include "demo_strokes.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/eval/tca_study.hpp"
#include "inhap/rendering/datasets.hpp"
#include "inhap/rendering/experiment.hpp"

namespace inhap::demo {
namespace {

using rendering::Algorithm;
using rendering::Task;

nlohmann::json bar(const std::vector<std::string>& x, const std::vector<double>& y,
                   const std::vector<double>& err, const std::string& name,
                   const std::string& color) {
  nlohmann::json j = {
      {"type", "bar"}, {"x", x}, {"y", y}, {"name", name}, {"marker", {{"color", color}}}};
  if (!err.empty()) j["error_y"] = {{"type", "data"}, {"array", err}, {"visible", true}};
  return j;
}

nlohmann::json study_json(const rendering::StudyConfig& cfg, const rendering::StudySummary& s) {
  const auto [ts, cs, tk, ck] = eval::tca_conditions(s);
  nlohmann::json j;
  j["participants"] = cfg.participants;
  j["trials_per_session"] = cfg.trials;
  j["seed"] = cfg.seed;
  auto cond = [](const rendering::ConditionSummary& x) {
    return nlohmann::json{{"mean", x.mean},
                          {"sd_participants", x.sd_participants},
                          {"per_participant", x.per_participant},
                          {"model_ratio", x.model_ratio},
                          {"mean_time_s", x.mean_time_s},
                          {"distortion_rms_mm", x.distortion_rms_mm}};
  };
  j["shape"] = {{"tca", cond(ts)}, {"cba", cond(cs)}};
  j["stiffness"] = {{"tca", cond(tk)}, {"cba", cond(ck)}};
  j["thesis"] = {{"shape", {{"tca", 24.4}, {"cba", 17.0}}},
                 {"stiffness", {{"tca", 22.7}, {"cba", 22.7}}},
                 {"cba_confusions", rendering::thesis_cba_confusions()}};
  return j;
}

Figure fig_5_10(const rendering::StudyConfig& cfg, const rendering::StudySummary& s) {
  const auto [ts, cs, tk, ck] = eval::tca_conditions(s);
  const std::vector<std::string> tasks = {"shape", "stiffness"};
  Figure f10{"fig5_10",
             "Correct classifications of 25 models (fig. 5.10)",
             fmt::format("Virtual user study, {} participants x {} trials per session (thesis: 16 "
                         "x 5). Bars: mean over participants, error bars: SD over participants. "
                         "Diamonds: the thesis' means.",
                         cfg.participants, cfg.trials),
             "plotly",
             {}};
  f10.spec["data"] = {
      bar(tasks, {ts.mean, tk.mean}, {ts.sd_participants, tk.sd_participants}, "TCA-MESH",
          "#1f77b4"),
      bar(tasks, {cs.mean, ck.mean}, {cs.sd_participants, ck.sd_participants}, "CBA", "#ff7f0e"),
      {{"type", "scatter"},
       {"mode", "markers"},
       {"x", tasks},
       {"y", {24.4, 22.7}},
       {"name", "thesis TCA-MESH"},
       {"marker", {{"symbol", "diamond"}, {"size", 12}, {"color", "#0b3c68"}}},
       {"offsetgroup", "a"}},
      {{"type", "scatter"},
       {"mode", "markers"},
       {"x", tasks},
       {"y", {17.0, 22.7}},
       {"name", "thesis CBA"},
       {"marker", {{"symbol", "diamond-open"}, {"size", 12}, {"color", "#a04000"}}}}};
  f10.spec["layout"] = {{"barmode", "group"},
                        {"yaxis", {{"title", {{"text", "correct of 25"}}}, {"range", {0, 25.5}}}}};
  return f10;
}

Figure fig_5_11(const rendering::StudySummary& s) {
  const auto& ts = s.get(Algorithm::kTCA, Task::kShape);
  const auto& cs = s.get(Algorithm::kCBA, Task::kShape);
  std::vector<std::string> models;
  std::vector<double> rt, rc;
  for (int m = 0; m < rendering::kNumModels; ++m) {
    models.push_back(fmt::format("M{}", m));
    rt.push_back(ts.model_ratio[m]);
    rc.push_back(cs.model_ratio[m]);
  }
  nlohmann::json confusions = nlohmann::json::array();
  for (int m : rendering::thesis_cba_confusions()) confusions.push_back(fmt::format("M{}", m));
  Figure f11{"fig5_11",
             "Per-model correct ratio, shape task (fig. 5.11)",
             "Fraction of trials in which each model's shape was classified correctly. Triangles "
             "mark the 12 models the thesis reports CBA to confuse.",
             "plotly",
             {}};
  f11.spec["data"] = {
      bar(models, rt, {}, "TCA-MESH", "#1f77b4"),
      bar(models, rc, {}, "CBA", "#ff7f0e"),
      {{"type", "scatter"},
       {"mode", "markers"},
       {"x", confusions},
       {"y", std::vector<double>(confusions.size(), 1.05)},
       {"name", "thesis: CBA confused"},
       {"marker", {{"symbol", "triangle-down"}, {"size", 10}, {"color", "#d62728"}}}}};
  f11.spec["layout"] = {{"barmode", "group"},
                        {"yaxis", {{"title", {{"text", "correct ratio"}}}, {"range", {0, 1.12}}}}};
  return f11;
}

}  // namespace

StepResult step_study(const Context& c) {
  StepResult r;
  eval::TcaStudyOptions so;
  so.participants = c.options.quick ? 4 : 16;  // the thesis' protocol in the full run
  so.trials = c.options.quick ? 2 : 5;
  so.seed = c.options.seed;
  so.progress = [&c](const std::string& what, double f, double) { c.progress(f, what); };
  const eval::TcaStudyResult study = eval::run_tca_study(so);
  const rendering::StudyConfig& cfg = study.config;
  const rendering::StudySummary& s = study.summary;
  const auto [ts, cs, tk, ck] = eval::tca_conditions(s);

  write_file_atomic(c.file(r, "study.json"), study_json(cfg, s).dump(2) + "\n");
  r.figures.push_back(fig_5_10(cfg, s));
  r.figures.push_back(fig_5_11(s));

  auto pm = [](const rendering::ConditionSummary& x) {
    return fmt::format("{:.1f} +- {:.1f}", x.mean, x.sd_participants);
  };
  r.rows.push_back({"shape correct of 25, TCA-MESH", pm(ts), "24.4 +- 1.1"});
  r.rows.push_back({"shape correct of 25, CBA", pm(cs), "17.0 +- 2.2"});
  r.rows.push_back({"stiffness correct of 25, TCA-MESH", pm(tk), "22.7"});
  r.rows.push_back({"stiffness correct of 25, CBA", pm(ck), "22.7"});
  const auto conf = s.misjudged_models(Algorithm::kCBA, Task::kShape);
  r.rows.push_back({"models CBA confuses (count)", std::to_string(conf.size()), "12"});
  r.note = c.options.quick
               ? fmt::format("reduced protocol: {} participants x {} trials (thesis 16 x 5)",
                             cfg.participants, cfg.trials)
               : std::string("the thesis' protocol: 16 participants x 5 trials per session");
  return r;
}

StepResult step_strokes(const Context& c) {
  StepResult r;
  const rendering::StudySurface surface(rendering::DatasetParams{}, rendering::identity_layout());
  const rendering::Model model(surface.mesh());
  // Models the thesis reports CBA to confuse (M1, M3 flat with a softer / harder centre; M6
  // bump, M18 hole with inhomogeneous stiffness) and M5, a bump of constant stiffness.
  std::vector<int> ids =
      c.options.quick ? std::vector<int>{1, 6} : std::vector<int>{1, 3, 6, 18, 5};
  std::vector<StrokeLine> lines;
  std::vector<double> dist_t, dist_c;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const int m = ids[i];
    const Vec2 centre = surface.cell_centre(surface.layout().cell_of(m));
    StrokeCase sc;
    sc.name = fmt::format("M{}", m);
    sc.from = centre - Vec2(12, 0);
    sc.to = centre + Vec2(12, 0);
    sc.truth = [&surface](double x, double y) { return surface.mesh_height(x, y); };
    const StrokePair p = run_stroke_pair(model, sc, c.options.seed + i);
    dist_t.push_back(p.distortion_tca);
    dist_c.push_back(p.distortion_cba);
    r.figures.push_back(stroke_figure(sc, p, fmt::format("fig5_7_m{}", m),
                                      fmt::format("Stroke across model M{} (fig. 5.7)", m)));
    write_stroke_csv(c.file(r, fmt::format("stroke_m{}.csv", m)), p);
    lines.push_back({p.tca, "#1f77b4"});
    lines.push_back({p.cba, "#ff7f0e"});
    c.progress(double(i + 1) / double(ids.size()), sc.name);
  }
  r.figures.push_back(
      mesh_figure(surface.mesh(), "stiffness", lines, "fig5_7_3d",
                  "The 25-model surface, coloured by stiffness, with the strokes",
                  "Rotate with the mouse. Colour: stiffness (blue 0.12 N/mm soft "
                  "to red 1.0 N/mm hard). Lines: IHIP paths of the TCA-MESH (blue) and "
                  "CBA (orange) strokes."));
  double mt = 0, mc = 0;
  for (std::size_t i = 0; i < ids.size(); ++i) mt += dist_t[i] / double(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) mc += dist_c[i] / double(ids.size());
  r.rows.push_back(
      {"stroke shape distortion RMS, TCA-MESH (mm)", fmt_num(mt, 3), "TCA-MESH follows the shape"});
  r.rows.push_back(
      {"stroke shape distortion RMS, CBA (mm)", fmt_num(mc, 3), "CBA distorts it (fig. 5.7)"});
  return r;
}

}  // namespace inhap::demo
