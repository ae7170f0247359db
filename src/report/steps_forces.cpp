// inhap demo: the data-driven force model on the virtual lab (thesis 4.4-4.5, fig. 4.11-4.14):
// train on a free exploration, replay a held-out recording through the servo renderer and
// compare rendered with measured force, with and without the proxy. The pipeline is
// inhap/eval/forces_lab.hpp (shared with `inhap eval forces`). Units: mm, N, s.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/eval/forces_lab.hpp"
#include "inhap/report/report.hpp"

namespace inhap::report {
namespace {

struct SceneTarget {
  std::string name;
  std::string thesis_rmse, thesis_re;  ///< thesis 4.5: RMSE x / y / z (N), RE mean / median
};

const char* kAxis[] = {"x", "y", "z"};
const char* kAxisColour[] = {"#1f77b4", "#ff7f0e", "#2ca02c"};

nlohmann::json line(const nlohmann::json& x, const nlohmann::json& y, const std::string& name,
                    const std::string& colour, const std::string& yaxis, bool legend,
                    const std::string& dash = "solid") {
  nlohmann::json t = line_trace(x, y, name, colour, 1.2, dash);
  t["yaxis"] = yaxis;
  t["showlegend"] = legend;
  return t;
}

// Fig. 4.11-4.12: measured and rendered force per axis over the test recording (three stacked
// panels sharing the time axis), the sliding-only last third marked.
Figure time_figure(const eval::ForceLabResult& d, const std::string& id) {
  const Recording& rec = d.test.rec;
  const std::vector<Vec3>& fr = d.proxy.replay.forces;
  const std::size_t n = rec.size(), stride = std::max<std::size_t>(1, n / 2500);
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i) t[i] = rec.t[i] - rec.t.front();
  Figure f{id,
           fmt::format("{}: measured vs rendered force per axis (fig. 4.11-4.12)", d.name),
           fmt::format("Held-out free exploration of the {} ({:.0f} s, another seed than the "
                       "training run): measured force (grey) and the force the model renders "
                       "from the probe position and the proxy (colour), per axis. The shaded "
                       "last third is the sliding-only passage. Proxy: {}.",
                       d.name == "planar" ? "planar object" : d.name, t.back(),
                       d.test_track.proxy_source),
           "plotly",
           {}};
  f.spec["data"] = nlohmann::json::array();
  for (int a = 0; a < 3; ++a) {
    std::vector<double> m(n), r(n);
    for (std::size_t i = 0; i < n; ++i) {
      m[i] = rec.f[i][a];
      r[i] = fr[i][a];
    }
    const std::string ax = a == 0 ? "y" : fmt::format("y{}", a + 1);
    f.spec["data"].push_back(
        line(series(t, stride), series(m, stride), "measured", "#7f7f7f", ax, a == 0));
    f.spec["data"].push_back(line(series(t, stride), series(r, stride),
                                  fmt::format("rendered f{}", kAxis[a]), kAxisColour[a], ax, true));
  }
  nlohmann::json layout = {{"height", 560},
                           {"xaxis", {{"title", {{"text", "time (s)"}}}, {"anchor", "y3"}}},
                           {"shapes",
                            {{{"type", "rect"},
                              {"xref", "x"},
                              {"yref", "paper"},
                              {"x0", rnd(d.t_slide - rec.t.front(), 2)},
                              {"x1", rnd(t.back(), 2)},
                              {"y0", 0},
                              {"y1", 1},
                              {"fillcolor", "#9467bd"},
                              {"opacity", 0.08},
                              {"line", {{"width", 0}}}}}}};
  for (int a = 0; a < 3; ++a) {
    const std::string key = a == 0 ? "yaxis" : fmt::format("yaxis{}", a + 1);
    layout[key] = {{"title", {{"text", fmt::format("f{} (N)", kAxis[a])}}},
                   {"domain", {rnd(1.0 - (a + 1) / 3.0 + 0.03, 2), rnd(1.0 - a / 3.0, 2)}}};
  }
  f.spec["layout"] = layout;
  return f;
}

// Fig. 4.13: RE (eq. 4.28) against the measured force magnitude, per 0.5 N bin, with and
// without the proxy.
Figure magnitude_figure(const std::vector<eval::ForceLabResult>& all, bool baselines) {
  Figure f{"fig4_13",
           "Relative error vs measured force magnitude (fig. 4.13)",
           "Relative error RE = ||f_r - f_m|| / max(||f_r||, ||f_m||) (eq. 4.28) of the held-out "
           "test samples in contact, median per 0.5 N bin of the measured force magnitude; "
           "solid with the proxy, dotted the same model trained without it (q = p).",
           "plotly",
           {}};
  f.spec["data"] = nlohmann::json::array();
  const char* colours[] = {"#1f77b4", "#d62728"};
  for (std::size_t s = 0; s < all.size(); ++s) {
    for (int v = 0; v < (baselines ? 2 : 1); ++v) {
      const datadriven::ForceErrors& e = v == 0 ? all[s].proxy.all : all[s].no_proxy.all;
      std::vector<double> x, y;
      for (const auto& b : e.re_by_magnitude)
        if (b.n >= 20) {
          x.push_back(0.5 * (b.f_min + b.f_max));
          y.push_back(b.re_median);
        }
      f.spec["data"].push_back(
          {{"type", "scatter"},
           {"mode", "lines+markers"},
           {"x", series(x)},
           {"y", series(y)},
           {"name", fmt::format("{}, {}", all[s].name, v == 0 ? "with proxy" : "without proxy")},
           {"line", {{"color", colours[s % 2]}, {"dash", v == 0 ? "solid" : "dot"}}}});
    }
  }
  f.spec["layout"] = {
      {"xaxis", {{"title", {{"text", "measured force magnitude (N)"}}}}},
      {"yaxis", {{"title", {{"text", "RE, median per bin"}}}, {"rangemode", "tozero"}}}};
  return f;
}

nlohmann::json box(const datadriven::BoxStats& b, const std::string& x, const std::string& name,
                   const std::string& colour, bool legend) {
  return {{"type", "box"},
          {"name", name},
          {"legendgroup", name},
          {"showlegend", legend},
          {"x", {x}},
          {"q1", {rnd(b.q1)}},
          {"median", {rnd(b.median)}},
          {"q3", {rnd(b.q3)}},
          {"lowerfence", {rnd(b.whisker_low)}},
          {"upperfence", {rnd(b.whisker_high)}},
          {"mean", {rnd(b.mean)}},
          {"marker", {{"color", colour}}}};
}

// Fig. 4.14: RE box plots per axis (eq. 4.30) and 3D (eq. 4.28), with and without the proxy.
Figure box_figure(const std::vector<eval::ForceLabResult>& all, bool baselines) {
  Figure f{"fig4_14",
           "Relative error box plots (fig. 4.14)",
           "Relative error of the held-out test samples in contact per axis (eq. 4.30) and of the "
           "force vector (3D, eq. 4.28): boxes are the quartiles, whiskers the extreme samples "
           "within 1.5 IQR, dashed the mean; with the proxy and (when run) the same model "
           "trained without it.",
           "plotly",
           {}};
  f.spec["data"] = nlohmann::json::array();
  const char* colours[] = {"#1f77b4", "#aec7e8", "#d62728", "#ff9896"};
  for (std::size_t s = 0; s < all.size(); ++s)
    for (int v = 0; v < (baselines ? 2 : 1); ++v) {
      const datadriven::ForceErrors& e = v == 0 ? all[s].proxy.all : all[s].no_proxy.all;
      const std::string name =
          fmt::format("{}, {}", all[s].name, v == 0 ? "with proxy" : "without proxy");
      const std::string colour = colours[(2 * s + v) % 4];
      for (int a = 0; a < 3; ++a)
        f.spec["data"].push_back(box(e.re_axis_box[a], kAxis[a], name, colour, a == 0));
      f.spec["data"].push_back(box(e.re_box, "3D", name, colour, false));
    }
  f.spec["layout"] = {
      {"boxmode", "group"},
      {"yaxis", {{"title", {{"text", "relative error"}}}, {"rangemode", "tozero"}}}};
  return f;
}

void write_series(const std::string& path, const eval::ForceLabResult& d) {
  const std::vector<std::string> units = {
      "units: t s, p probe centre mm, q proxy mm, forces N; held-out test recording, rendered by "
      "the with-proxy model"};
  CsvWriter csv(path,
                {"t", "px", "py", "pz", "qx", "qy", "qz", "contact", "fx_measured", "fy_measured",
                 "fz_measured", "fx_rendered", "fy_rendered", "fz_rendered"},
                units);
  const Recording& rec = d.test.rec;
  for (std::size_t i = 0; i < rec.size(); ++i) {
    const Vec3 &p = rec.p[i], &q = d.test_track.q[i], &m = rec.f[i], &r = d.proxy.replay.forces[i];
    csv.row({rec.t[i], p.x(), p.y(), p.z(), q.x(), q.y(), q.z(),
             static_cast<double>(d.test_track.contact[i]), m.x(), m.y(), m.z(), r.x(), r.y(),
             r.z()});
  }
  csv.commit();
}

// Where the training recording went (issue 18): the (x, y) projection of the coverage map,
// colour = training samples per column of cells (log scale), the largest unvisited gaps marked.
Figure coverage_figure(const std::vector<eval::ForceLabResult>& all,
                       const std::vector<eval::ForceCoverage>& coverages) {
  Figure f{"coverage",
           "Training coverage: where the exploration went, and where to explore more",
           "Proxy positions of the training recording binned into cells (seen from above; "
           "colour = samples per cell column, log10). Crosses: the largest unvisited regions "
           "inside the explored area, where a model extrapolates (explore there before "
           "training). The share of the held-out test samples outside the training support "
           "is in the table.",
           "plotly",
           {}};
  f.spec["data"] = nlohmann::json::array();
  nlohmann::json layout = {{"height", 420}, {"grid", {{"rows", 1}, {"columns", all.size()}}}};
  for (std::size_t s = 0; s < all.size(); ++s) {
    const eval::ForceCoverage& cov = coverages[s];
    std::map<std::pair<int, int>, double> column;
    for (const datadriven::CoverageCell& cell : cov.map.cells())
      column[{cell.index[0], cell.index[1]}] += static_cast<double>(cell.samples);
    nlohmann::json x = nlohmann::json::array(), y = x, z = x;
    for (const auto& [ij, n] : column) {
      x.push_back((ij.first + 0.5) * cov.cell_mm);
      y.push_back((ij.second + 0.5) * cov.cell_mm);
      z.push_back(std::log10(n));
    }
    const std::string ax = s == 0 ? "" : std::to_string(s + 1);
    f.spec["data"].push_back({{"type", "scatter"},
                              {"mode", "markers"},
                              {"x", x},
                              {"y", y},
                              {"xaxis", "x" + ax},
                              {"yaxis", "y" + ax},
                              {"name", all[s].name},
                              {"marker",
                               {{"symbol", "square"},
                                {"size", 6},
                                {"color", z},
                                {"colorscale", "Viridis"},
                                {"showscale", s == 0},
                                {"colorbar", {{"title", {{"text", "log10 samples"}}}}}}}});
    nlohmann::json gx = nlohmann::json::array(), gy = gx, gt = gx;
    for (const datadriven::CoverageGap& g : cov.gaps) {
      gx.push_back(g.x_mm);
      gy.push_back(g.y_mm);
      gt.push_back(
          fmt::format("{:.0f} mm2", static_cast<double>(g.cells) * cov.cell_mm * cov.cell_mm));
    }
    f.spec["data"].push_back({{"type", "scatter"},
                              {"mode", "markers+text"},
                              {"x", gx},
                              {"y", gy},
                              {"text", gt},
                              {"textposition", "top center"},
                              {"xaxis", "x" + ax},
                              {"yaxis", "y" + ax},
                              {"name", all[s].name + ": explore here"},
                              {"marker", {{"symbol", "x"}, {"size", 12}, {"color", "#d62728"}}}});
    layout["xaxis" + ax] = {{"title", {{"text", all[s].name + ": x (mm)"}}}};
    layout["yaxis" + ax] = {{"title", {{"text", "y (mm)"}}}, {"scaleanchor", "x" + ax}};
  }
  f.spec["layout"] = layout;
  return f;
}
// The summary rows of one object: RMSE per axis, RE mean / median, and (with the baselines) the
// sliding-only RE median with and without the proxy, beside the thesis' figures.
void add_error_rows(StepResult& r, const SceneTarget& t, const eval::ForceLabResult& d,
                    bool baselines) {
  const datadriven::ForceErrors& e = d.proxy.all;
  r.rows.push_back({fmt::format("{}: force RMSE x / y / z (N)", t.name),
                    fmt::format("{:.2f} / {:.2f} / {:.2f}", e.rmse[0], e.rmse[1], e.rmse[2]),
                    t.thesis_rmse + (t.name == "dome" ? " (sec. 4.5.2)" : " (sec. 4.5.1)")});
  r.rows.push_back({fmt::format("{}: relative error RE mean / median", t.name),
                    fmt::format("{:.3f} / {:.3f} ({} samples)", e.re_mean, e.re_median, e.n),
                    t.thesis_re + (t.name == "dome" ? " (sec. 4.5.2)" : " (sec. 4.5.1)")});
  if (baselines)
    r.rows.push_back(
        {fmt::format("{}: RE median, sliding-only third: with / without proxy", t.name),
         fmt::format("{:.3f} / {:.3f}", d.proxy.sliding.re_median, d.no_proxy.sliding.re_median),
         "with < without (fig. 4.14)"});
}
}  // namespace

StepResult step_force_model(const Context& c) {
  StepResult r;
  const bool quick = c.options.quick;
  std::vector<SceneTarget> targets;
  if (!quick) targets.push_back({"planar", "0.26 / 0.15 / 0.25", "0.138 / 0.115"});
  targets.push_back({"dome", "0.51 / 0.33 / 0.50", "0.260 / 0.211"});
  const bool baselines = true;
  std::vector<eval::ForceLabResult> all;
  std::vector<eval::ForceCoverage> coverages;  // per scene, for its table row and the map
  nlohmann::json summary = nlohmann::json::array();
  for (std::size_t s = 0; s < targets.size(); ++s) {
    const SceneTarget& t = targets[s];
    eval::ForceLabOptions fo;
    fo.scene = t.name;
    fo.train_seed = c.options.seed;
    fo.test_seed = c.options.seed + 1;
    fo.quick = quick;
    fo.physics = c.options.physics;
    fo.baselines = baselines;
    fo.params.seed = c.options.seed;
    // Quick: M = 100 centres per bin instead of 300 (training ~15x faster, the errors about the
    // same on the lab: RE median 0.129 vs 0.131 on the dome).
    if (quick) fo.params.centers = 100;
    fo.progress_label = t.name;
    const double share = 1.0 / static_cast<double>(targets.size());
    {
      ForwardProgress fw(c,
                         {{"train recording", 0.12},
                          {"test recording", 0.06},
                          {"train (proxy)", baselines ? 0.28 : 0.82},
                          {"train (no proxy)", 0.27},
                          {"train (onset proxy)", 0.27}},
                         share * static_cast<double>(s), share * static_cast<double>(s + 1));
      fo.progress = fw.callback();
      all.push_back(eval::evaluate_forces_on_lab(fo));
    }
    const eval::ForceLabResult& d = all.back();
    write_series(c.file(r, fmt::format("forces_{}_test.csv", t.name)), d);
    add_error_rows(r, t, d, baselines);
    const datadriven::ForceErrors& e = d.proxy.all;
    const eval::ForceCoverage& cov = coverages.emplace_back(eval::training_coverage(d));
    std::string where;
    for (std::size_t g = 0; g < std::min<std::size_t>(2, cov.gaps.size()); ++g)
      where += fmt::format("{}({:.0f}, {:.0f})", g ? ", " : "; explore more at x, y mm ",
                           cov.gaps[g].x_mm, cov.gaps[g].y_mm);
    r.rows.push_back({fmt::format("{}: test samples outside the training support", t.name),
                      fmt::format("{:.1f} %{}", 100.0 * cov.outside, where), "-"});
    summary.push_back(
        {{"name", t.name},
         {"coverage", cov.outside},
         {"proxy_source", d.test_track.proxy_source},
         {"contact_source", d.test_track.contact_source},
         {"train_samples", d.train.rec.size()},
         {"test_samples", d.test.rec.size()},
         {"rmse_n", e.rmse},
         {"re_mean", e.re_mean},
         {"re_median", e.re_median},
         {"no_proxy_re_median", baselines ? d.no_proxy.all.re_median : NAN},
         {"sliding_re_median", d.proxy.sliding.re_median},
         {"no_proxy_sliding_re_median", baselines ? d.no_proxy.sliding.re_median : NAN},
         {"train_s", d.proxy.provenance.stats.seconds}});
  }
  write_file_atomic(c.file(r, "forces.json"), summary.dump(2) + "\n");
  for (const auto& d : all)
    r.figures.push_back(time_figure(d, d.name == "dome" ? "fig4_12" : "fig4_11"));
  r.figures.push_back(magnitude_figure(all, baselines));
  r.figures.push_back(box_figure(all, baselines));
  r.figures.push_back(coverage_figure(all, coverages));
  r.note = fmt::format("proxy: {}", all.back().test_track.proxy_source);
  return r;
}

}  // namespace inhap::report
