// inhap demo: steps on virtual-lab recordings of the dome (thesis ch. 3 tapping, ch. 4.4 free
// exploration). Units: mm, N, s, N/mm.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <span>

#include "inhap/contact/knee.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/report/report.hpp"

namespace inhap::report {
namespace {

lab::LabRecording record_dome(const Context& c, const std::string& op, double seconds,
                              std::uint64_t seed) {
  lab::RecordSpec spec;
  spec.operator_name = op;
  spec.tap.whole_object = false;  // fig. 3.2: taps on the dome's top, seen from above
  spec.seconds = seconds;
  spec.seed = seed;
  spec.physics = c.options.physics;
  return lab::record_scene(lab::builtin_scene("dome"), spec,
                           [&](const std::string&, double f, double) {
                             c.progress(f, fmt::format("{} {:.0f} s on the dome", op, seconds));
                           });
}

// The chapter-3 contact estimator on the first tap (thesis sec. 3.2.2): threshold detection at
// 0.5 N, then the two-segment (knee) fit over the 100 ms before it. t is relative to the true
// contact instant.
void add_knee_fit(Figure& f, StepResult& r, const std::vector<double>& t,
                  const std::vector<double>& fm) {
  std::size_t d = 0;
  while (d < t.size() && (t[d] < -0.1 || fm[d] < 0.5)) ++d;
  if (d == t.size()) return;
  std::size_t b = d;
  while (b > 0 && t[b - 1] >= t[d] - 0.1) --b;
  const std::span<const double> tw(t.data() + b, d - b + 1), fw(fm.data() + b, d - b + 1);
  const KneeFit k = fit_knee(tw, fw);
  if (!k.valid) return;
  f.spec["data"].push_back(line_trace({rnd(tw.front(), 4), rnd(k.tc, 4), rnd(tw.back(), 4)},
                                      {rnd(k.g0), rnd(k.gc), rnd(k.gd)}, "two-segment fit",
                                      "#9467bd", 2.5));
  f.spec["layout"]["shapes"].push_back({{"type", "line"},
                                        {"x0", rnd(k.tc, 4)},
                                        {"x1", rnd(k.tc, 4)},
                                        {"yref", "paper"},
                                        {"y0", 0},
                                        {"y1", 1},
                                        {"line", {{"color", "#9467bd"}, {"dash", "dot"}}}});
  f.caption =
      "Force magnitude of the first tap on the dome around the true contact instant t = 0 (red "
      "dashed line, from the lab's ground truth), the two-segment fit over the 100 ms before the "
      "0.5 N threshold crossing and the contact instant it detects (purple dotted line).";
  r.rows.push_back(
      {"first tap: detected minus true contact instant (ms)", fmt_num(1000.0 * k.tc, 1), "-"});
}

}  // namespace

StepResult step_tap(const Context& c) {
  StepResult r;
  const double seconds = c.options.quick ? 8.0 : 60.0;
  const lab::LabRecording lab = record_dome(c, "tap", seconds, c.options.seed);
  lab::write_lab_recording(c.file(r, "dome_tap.csv"), lab);
  r.files.push_back("dome_tap.truth.csv");
  const auto& tr = lab.truth;
  long taps = 0;
  for (long v : tr.tap) taps = std::max(taps, v + 1);

  // The first complete tap: from 150 ms before its true contact instant to 50 ms after it ends.
  std::size_t first = tr.size(), last = tr.size();
  for (std::size_t i = 0; i < tr.size(); ++i)
    if (tr.tap[i] == 0) {
      if (first == tr.size()) first = i;
      last = i;
    }
  if (first == tr.size()) throw Error("demo tap: the operator made no contact with the dome");
  const double tc = tr.tc[first];
  const double t0 = tc - 0.15, t1 = tr.t[last] + 0.05;
  std::vector<double> t, fm, ft;
  const std::vector<std::string> units = {
      "units: t s (0 = true contact instant), forces N (magnitude; measured = "
      "compensated sensor reading, true = noise-free contact force)"};
  CsvWriter csv(c.file(r, "tap_profile.csv"), {"t", "f_measured", "f_true", "contact"}, units);
  for (std::size_t i = 0; i < tr.size(); ++i) {
    if (tr.t[i] < t0 || tr.t[i] > t1) continue;
    t.push_back(tr.t[i] - tc);
    fm.push_back(lab.rec.f[i].norm());
    ft.push_back(tr.force[i].norm());
    csv.row({t.back(), fm.back(), ft.back(), double(tr.contact[i])});
  }
  csv.commit();
  const std::size_t stride = std::max<std::size_t>(1, t.size() / 1500);
  Figure f{"fig3_2",
           "Tap force profile (fig. 3.2)",
           "Force magnitude of the first tap on the dome around the true contact instant t = 0 "
           "(dashed line, from the lab's ground truth).",
           "plotly",
           {}};
  f.spec["data"] = {
      line_trace(series(t, stride), series(fm, stride), "measured |f| (compensated)", "#1f77b4"),
      line_trace(series(t, stride), series(ft, stride), "true contact |f|", "#2ca02c", 2, "dot")};
  f.spec["layout"] = {{"xaxis", {{"title", {{"text", "time from true contact (s)"}}}}},
                      {"yaxis", {{"title", {{"text", "force (N)"}}}}},
                      {"shapes",
                       {{{"type", "line"},
                         {"x0", 0},
                         {"x1", 0},
                         {"yref", "paper"},
                         {"y0", 0},
                         {"y1", 1},
                         {"line", {{"color", "#d62728"}, {"dash", "dash"}}}}}},
                      {"annotations",
                       {{{"x", 0},
                         {"yref", "paper"},
                         {"y", 1},
                         {"text", "true contact"},
                         {"showarrow", false},
                         {"xanchor", "left"}}}}};
  add_knee_fit(f, r, t, fm);
  r.figures.push_back(f);
  r.rows.push_back({"taps recorded on the dome (count)", std::to_string(taps), "-"});
  r.rows.push_back({"peak force of the first tap (N)",
                    fmt_num(*std::max_element(ft.begin(), ft.end())), "1-4 (operator's range)"});
  return r;
}

StepResult step_explore(const Context& c) {
  StepResult r;
  const double seconds = c.options.quick ? 10.0 : 60.0;
  const lab::LabRecording lab = record_dome(c, "explore", seconds, c.options.seed + 1);
  lab::write_lab_recording(c.file(r, "dome_explore.csv"), lab);
  r.files.push_back("dome_explore.truth.csv");
  const auto& tr = lab.truth;
  const std::size_t n = tr.size();
  const std::size_t stride = std::max<std::size_t>(1, n / 2000);
  std::vector<double> t(n);
  std::array<std::vector<double>, 3> meas, truth;
  double sq = 0;
  long contact = 0;
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = tr.t[i];
    for (int a = 0; a < 3; ++a) {
      meas[a].push_back(lab.rec.f[i][a]);
      truth[a].push_back(tr.force[i][a]);
    }
    sq += (lab.rec.f[i] - tr.force[i]).squaredNorm();
    contact += tr.contact[i];
  }
  const double rms = std::sqrt(sq / double(std::max<std::size_t>(1, n)));
  const char* axes[] = {"x", "y", "z"};
  const char* colors[] = {"#1f77b4", "#ff7f0e", "#2ca02c"};
  Figure f{"explore_force",
           "Free exploration: measured vs true force per axis",
           "Free exploration of the dome: compensated sensor reading (solid) and the lab's "
           "noise-free contact force (dotted) per axis, i.e. what the force model is trained on "
           "and how noisy it is. The rendered force of the trained model is in the next step.",
           "plotly",
           {}};
  f.spec["data"] = nlohmann::json::array();
  for (int a = 0; a < 3; ++a) {
    f.spec["data"].push_back(line_trace(series(t, stride), series(meas[a], stride),
                                        fmt::format("f{} measured", axes[a]), colors[a], 1.2));
    f.spec["data"].push_back(line_trace(series(t, stride), series(truth[a], stride),
                                        fmt::format("f{} true", axes[a]), colors[a], 1.5, "dot"));
  }
  f.spec["layout"] = {{"xaxis", {{"title", {{"text", "time (s)"}}}}},
                      {"yaxis", {{"title", {{"text", "force (N)"}}}}}};
  r.figures.push_back(f);
  r.rows.push_back({"exploration recorded (s, % in contact)",
                    fmt::format("{:.0f} s, {:.0f} %", seconds, 100.0 * double(contact) / double(n)),
                    "-"});
  r.rows.push_back({"compensated vs true force, RMS (N)", fmt_num(rms, 3), "-"});
  return r;
}

}  // namespace inhap::report
