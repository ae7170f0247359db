// inhap demo: shape reconstruction from tapped contact points (thesis 3.3, fig. 3.6-3.7,
// Table 3.1) on virtual-lab objects whose exact surface is known. Units: mm, N, s.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/lab_objects.hpp"
#include "inhap/eval/shape_lab.hpp"
#include "inhap/eval/shape_study.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/report/report.hpp"
#include "inhap/report/strokes.hpp"

namespace inhap::report {
namespace {

struct ShapeTarget {
  std::string name, label;
  std::size_t taps;
  std::string thesis_hausdorff;  ///< estimate / threshold, Table 3.1 ("-": not in the thesis)
};

struct ShapeOutcome {
  ShapeTarget target;
  eval::ShapeVariant estimate, threshold;
  double coverage = 0, taps_per_minute = 0;
};

// 99th percentile of the per-vertex errors of both reconstructions: the top of the colour scale.
double colour_top(const ShapeOutcome& o) {
  std::vector<double> v = o.estimate.cmp.a_vertex_error;
  v.insert(v.end(), o.threshold.cmp.a_vertex_error.begin(), o.threshold.cmp.a_vertex_error.end());
  if (v.empty()) return 1.0;
  const auto k = static_cast<std::size_t>(0.99 * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return std::max(v[k], 0.1);
}

Figure error_figure(const ShapeOutcome& o, const std::string& id) {
  const double top = colour_top(o);
  const Box3 box = o.estimate.mesh.bbox();
  const Vec3 shift((box.max.x() - box.min.x()) + 15.0, 0.0, 0.0);
  Figure f{id,
           fmt::format("{}: reconstruction coloured by error (fig. 3.6-3.7)", o.target.label),
           fmt::format("Surfaces reconstructed from {} tapped contact points of the {}: left from "
                       "the estimated contact points (two-segment fit), right from simple "
                       "thresholding. Colour: distance of each vertex to the true surface, blue "
                       "0 mm to red {:.1f} mm and above. Drag to rotate, scroll to zoom.",
                       o.estimate.points, o.target.label, top),
           "three",
           {}};
  f.spec["meshes"] = nlohmann::json::array(
      {colored_mesh_json(o.estimate.mesh, o.estimate.cmp.a_vertex_error, 0, top),
       colored_mesh_json(o.threshold.mesh, o.threshold.cmp.a_vertex_error, 0, top, shift)});
  f.spec["lines"] = nlohmann::json::array();
  return f;
}

Figure table_figure(const std::vector<ShapeOutcome>& all) {
  std::vector<std::string> cols[10];
  for (const auto& o : all) {
    cols[0].push_back(o.target.label);
    cols[1].push_back(std::to_string(o.estimate.points));
    cols[2].push_back(fmt::format("{} / {}", o.estimate.vertices, o.estimate.faces));
    cols[3].push_back(fmt_num(o.estimate.cmp.hausdorff));
    cols[4].push_back(fmt_num(o.threshold.cmp.hausdorff));
    cols[5].push_back(fmt_num(o.estimate.cmp.mean));
    cols[6].push_back(fmt_num(o.threshold.cmp.mean));
    cols[7].push_back(o.target.thesis_hausdorff);
    cols[8].push_back(fmt::format("{} / {}", o.threshold.vertices, o.threshold.faces));
    cols[9].push_back(fmt::format("{:.2f}", o.coverage));
  }
  nlohmann::json values = nlohmann::json::array();
  for (const auto& c : cols) values.push_back(c);
  Figure f{"table3_1",
           "Table 3.1: reconstruction vs the true surface",
           "Hausdorff and mean distance between each reconstruction and the object's exact "
           "surface over the common (tapped) region, from estimated contact points (P) and from "
           "simple thresholding (S), beside the thesis' Hausdorff distances to its optical scan "
           "(P / S). mm.",
           "plotly",
           {}};
  f.spec["data"] = {
      {{"type", "table"},
       {"header",
        {{"values",
          {"object", "points", "vertices / faces (P)", "Hausdorff P", "Hausdorff S", "mean P",
           "mean S", "thesis Hausdorff P / S", "vertices / faces (S)", "coverage"}},
         {"fill", {{"color", "#e8ecf1"}}},
         {"align", "left"}}},
       {"columnwidth", {1.7, 0.9, 1.3, 1.1, 1.1, 0.9, 0.9, 1.4, 1.3, 0.9}},
       {"cells", {{"values", values}, {"align", "left"}, {"height", 26}}}}};
  f.spec["layout"] = {{"height", 90 + 30 * static_cast<int>(all.size())},
                      {"margin", {{"l", 10}, {"r", 10}, {"t", 10}, {"b", 10}}}};
  return f;
}

/// The meshes (vertex property 'error', mm), the CSV row and the summary rows of one object.
void write_outcome(const Context& c, StepResult& r, const ShapeOutcome& o, std::string& csv) {
  for (const auto* v : {&o.estimate, &o.threshold}) {
    TriMesh m = v->mesh;
    m.set_property("error", v->cmp.a_vertex_error);
    write_mesh(c.file(r, fmt::format("shape_{}_{}.ply", o.target.name,
                                     v == &o.estimate ? "estimate" : "threshold")),
               m);
  }
  csv += fmt::format("{},{},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.1f}\n",
                     o.target.name, o.estimate.points, o.estimate.cmp.hausdorff,
                     o.threshold.cmp.hausdorff, o.estimate.cmp.mean, o.threshold.cmp.mean,
                     o.estimate.cmp.rms, o.threshold.cmp.rms, o.coverage, o.taps_per_minute);
  r.rows.push_back(
      {fmt::format("{} ({} taps): Hausdorff, estimate / threshold (mm)", o.target.label,
                   o.estimate.points),
       fmt::format("{} / {}", fmt_num(o.estimate.cmp.hausdorff),
                   fmt_num(o.threshold.cmp.hausdorff)),
       o.target.thesis_hausdorff == "-" ? "-" : o.target.thesis_hausdorff + " (Table 3.1)"});
  r.rows.push_back(
      {fmt::format("{}: mean distance, estimate / threshold (mm)", o.target.label),
       fmt::format("{} / {}", fmt_num(o.estimate.cmp.mean), fmt_num(o.threshold.cmp.mean)),
       o.target.thesis_hausdorff == "-" ? "-" : "< 1 (sec. 3.3.2)"});
  r.rows.push_back(
      {fmt::format("{}: coverage (reachable surface within 5 mm of a tap), taps per minute",
                   o.target.label),
       fmt::format("{:.2f}, {:.0f}", o.coverage, o.taps_per_minute),
       "about 1,000 points in 5-15 min (ch. 3)"});
}

}  // namespace

StepResult step_shape(const Context& c) {
  StepResult r;
  const bool quick = c.options.quick;
  std::vector<ShapeTarget> targets = {{"dome", "dome", quick ? 60u : 200u, "-"}};
  std::string bunny_ply;  // the sample bunny, when the data folder is there
  if (!quick) {
    targets.push_back({"foam-ball", "foam ball", 1000, "2.16 / 2.82"});
    targets.push_back({"ridged-silicone", "ridged silicone", 950, "4.92 / 4.67"});
    targets.push_back({"silicone-hemisphere", "silicone hemisphere", 300, "3.30 / 6.69"});
    try {
      bunny_ply = find_data_dir(c.options.data) + "/bunny/bun_zipper.ply";
      targets.push_back({"bunny", "bunny (100 mm, Ecoflex 00-30)", eval::kBunnyTaps, "-"});
    } catch (const Error&) {
      // no data folder: the bunny is left out (the data steps say so)
    }
  }
  lab::TapOptions tap;  // the thesis' user tapped each object all over what the stylus reached
  tap.whole_object = true;
  std::vector<std::string> skipped;
  std::erase_if(targets, [&](const ShapeTarget& t) {
    const bool skip =
        c.options.physics == lab::Physics::kMujoco &&
        (t.name == "bunny" || !lab::mujoco_represents(lab::builtin_scene(t.name).object.shape()));
    if (skip) skipped.push_back(t.name);
    return skip;
  });
  double total_taps = 0, done_taps = 0;
  for (const auto& t : targets) total_taps += static_cast<double>(t.taps);
  std::vector<ShapeOutcome> all;
  std::string csv =
      "# units: mm; estimate = contact points of the two-segment fit, threshold = simple "
      "thresholding; whole objects tapped all over what a stylus reaches; distances between the "
      "whole reconstruction and the exact surface cropped to the tapped part; coverage = share "
      "of the reachable surface within 5 mm of a tap\n"
      "object,points,hausdorff_estimate,hausdorff_threshold,mean_estimate,mean_threshold,"
      "rms_estimate,rms_threshold,coverage,taps_per_minute\n";
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const ShapeTarget& t = targets[i];
    const lab::Scene scene =
        t.name == "bunny" ? eval::bunny_scene(bunny_ply) : lab::builtin_scene(t.name);
    eval::ShapeObjectOptions so;
    so.taps = t.taps;
    so.seed = c.options.seed + 20 + i;
    so.physics = c.options.physics;
    so.tap = tap;
    so.coverage_samples = quick ? 5000 : 20000;
    so.progress = [&](const std::string& what, double f, double) {
      c.progress((done_taps + f * static_cast<double>(t.taps)) / total_taps,
                 what == "taps" ? fmt::format("{} taps on the {}", t.taps, t.label)
                                : fmt::format("reconstruct the {}", t.label));
    };
    eval::ShapeObjectResult res = eval::run_shape_object(scene, so);
    ShapeOutcome o;
    o.target = t;
    o.estimate = std::move(res.estimate);
    o.threshold = std::move(res.threshold);
    o.coverage = res.coverage;
    o.taps_per_minute = res.taps_per_minute;
    done_taps += static_cast<double>(t.taps);
    write_outcome(c, r, o, csv);
    all.push_back(std::move(o));
  }
  write_file_atomic(c.file(r, "shape_table3_1.csv"), csv);
  for (std::size_t i = 0; i < all.size(); ++i)
    r.figures.push_back(error_figure(all[i], i == 0 ? "fig3_6" : "fig3_6_" + all[i].target.name));
  r.figures.push_back(table_figure(all));
  if (!skipped.empty())
    r.note = fmt::format("MuJoCo cannot represent (skipped): {}", fmt::join(skipped, ", "));
  return r;
}

}  // namespace inhap::report
