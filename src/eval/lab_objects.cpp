#include "inhap/eval/lab_objects.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "inhap/eval/shape_lab.hpp"

namespace inhap::eval {

using json = nlohmann::json;

std::vector<ShapeTarget> shape_targets(bool top_only, const std::vector<std::string>& only,
                                       std::size_t taps, bool quick) {
  std::vector<ShapeTarget> targets = {{"foam-ball", 1000},
                                      {"ridged-silicone", 950},
                                      {"silicone-hemisphere", 300},
                                      {"bunny", kBunnyTaps}};
  if (top_only) targets.pop_back();  // the top-cap protocol has no bunny
  std::vector<ShapeTarget> out;
  for (ShapeTarget t : targets) {
    if (!only.empty() && std::find(only.begin(), only.end(), t.name) == only.end()) continue;
    if (taps > 0)
      t.taps = taps;
    else if (quick)
      t.taps = std::max<std::size_t>(60, t.taps / 5);
    out.push_back(t);
  }
  return out;
}

lab::Scene shape_target_scene(const std::string& name, const std::string& bunny_ply) {
  return name == "bunny" ? bunny_scene(bunny_ply) : lab::builtin_scene(name);
}

ShapeObjectOptions shape_object_options(std::size_t taps, const ShapeEvalSettings& s) {
  ShapeObjectOptions o;
  o.taps = taps;
  o.seed = s.seed;
  o.physics = s.physics;
  o.tap.whole_object = !s.top_only;
  o.compare.icp = s.icp;
  o.compare.region_mm = s.region_mm;
  o.compare.rim_margin_mm = s.rim_margin_mm;
  o.compare.normal_overlap = !s.no_normal_overlap;
  o.compare.uncropped_reconstruction = !s.top_only;
  o.score_reachable_part = !s.top_only;
  o.coverage_samples = s.quick ? 5000 : 20000;
  o.count_entry_sides = true;
  return o;
}

json error_summary_json(const ErrorSummary& s) {
  return {{"median", s.median}, {"p95", s.p95}, {"max", s.max}};
}

json contact_object_json(const ContactObjectResult& r) {
  return {{"name", r.name},
          {"stiffness_n_per_mm", r.stiffness_n_per_mm},
          {"taps", r.taps},
          {"false_detections", r.false_detections},
          {"estimate_mm", error_summary_json(r.estimate)},
          {"threshold_mm", error_summary_json(r.threshold)}};
}

json shape_object_json(const std::string& name, const ShapeObjectResult& r) {
  const ShapeVariant &e = r.estimate, &s = r.threshold;
  auto side = [](const OneSided& d) { return json{{"max", d.max}, {"mean", d.mean}}; };
  return {
      {"name", name},
      {"points", e.points},
      {"vertices", e.vertices},
      {"faces", e.faces},
      {"hausdorff_mm", {{"estimate", e.cmp.hausdorff}, {"threshold", s.cmp.hausdorff}}},
      {"mean_mm", {{"estimate", e.cmp.mean}, {"threshold", s.cmp.mean}}},
      {"rms_mm", {{"estimate", e.cmp.rms}, {"threshold", s.cmp.rms}}},
      {"threshold_variant", {{"points", s.points}, {"vertices", s.vertices}, {"faces", s.faces}}},
      {"coverage", r.coverage},
      {"taps_per_minute", r.taps_per_minute},
      {"recording_s", r.recording_s},
      {"reconstruction_to_reference_mm",
       {{"estimate", side(e.cmp.a_to_b)}, {"threshold", side(s.cmp.a_to_b)}}},
      {"reference_to_reconstruction_mm",
       {{"estimate", side(e.cmp.b_to_a)}, {"threshold", side(s.cmp.b_to_a)}}},
      {"episodes", r.sides.episodes},
      {"far_side_first_contacts", r.sides.far_side_first_contacts},
      {"force_reversals", r.sides.force_reversals}};
}

json contacts_run_json(json objects, double eps_n, std::size_t window, std::uint64_t seed) {
  return {{"objects", std::move(objects)},
          {"units", "mm; stiffness N/mm (effective, at 5 N)"},
          {"eps_f_n", eps_n},
          {"window_samples", window},
          {"seed", seed}};
}

json shape_run_json(json objects, const ShapeEvalSettings& s) {
  return {{"objects", std::move(objects)},
          {"units", "mm; coverage: share of the reachable surface within 5 mm of a tap"},
          {"protocol", s.top_only ? "top caps (region seen from above)" : "whole objects"},
          {"common_region",
           fmt::format("reference within {} mm of the true contact points, overlap only; the "
                       "reconstruction {}",
                       s.region_mm, s.top_only ? "cropped likewise" : "uncropped")},
          {"icp", s.icp},
          {"normal_overlap", !s.no_normal_overlap},
          {"seed", s.seed}};
}

}  // namespace inhap::eval
