// The per-object report of `inhap eval forces` as JSON (see forces_lab.hpp). Units: mm, N, s;
// step times in microseconds.
#include <nlohmann/json.hpp>

#include "inhap/core/stats.hpp"
#include "inhap/eval/forces_lab.hpp"

namespace inhap::eval {
namespace {

using namespace inhap::datadriven;
using ojson = nlohmann::ordered_json;

ojson xyz(const std::array<double, 3>& v) {
  return {{"x", v[0]}, {"y", v[1]}, {"z", v[2]}};
}
ojson mean_median(double mean, double median) {
  return {{"mean", mean}, {"median", median}};
}

/// Exponent, fitted samples and grid size of a prior's map (null when the prior is off).
ojson map_summary(const datadriven::StiffnessPrior& m) {
  if (m.empty()) return nullptr;
  return {{"exponent", m.exponent}, {"fitted_samples", m.fitted_samples}, {"dims", m.dims}};
}

/// Training vs test ranges (ForceSupport).
ojson support_json(const ForceSupport& su) {
  return {
      {"definition",
       "scored test samples with a normalised feature outside its bin's training range [min, "
       "max] (any group; per group q - p, q, pdot), their share of the squared error per axis; "
       "||q - p|| (mm) and ||pdot|| (mm/s) of training vs test contact samples"},
      {"samples", su.samples},
      {"outside_any", su.outside_any},
      {"outside", {{"q_minus_p", su.outside[0]}, {"q", su.outside[1]}, {"pdot", su.outside[2]}}},
      {"sse_share_outside", xyz(su.sse_share_outside)},
      {"depth_mm",
       {{"train_p99", su.train_depth_p99},
        {"train_max", su.train_depth_max},
        {"test_p99", su.test_depth_p99},
        {"test_max", su.test_depth_max},
        {"test_beyond_train_max", su.beyond_depth}}},
      {"speed_mm_s",
       {{"train_p99", su.train_speed_p99},
        {"train_max", su.train_speed_max},
        {"test_p99", su.test_speed_p99},
        {"test_max", su.test_speed_max},
        {"test_beyond_train_max", su.beyond_speed}}}};
}

/// The settings and priors of a trained model.
ojson model_json(const ForceModel& m, const ForceModelProvenance& pv) {
  const TrainParams& p = pv.params;
  return {{"design", to_string(p.design)},
          {"features", to_string(p.features)},
          {"bins", p.bins},
          {"centers", p.centers},
          {"nonzeros", p.nonzeros},
          {"lambda_ratio", p.lambda_ratio},
          {"linear_tail", p.linear_tail},
          {"feature_weights", p.feature_weights},
          {"ridge", p.ridge},
          {"box_margin", p.box_margin},
          {"tangent_mirror", p.tangent_mirror},
          {"stiffness_prior", map_summary(m.prior)},
          {"shear_prior", map_summary(m.shear)},
          {"friction_cone", m.friction_cone},
          {"sliding_mu", m.sliding_mu},
          {"bin_blend_mm", m.bin_blend},
          {"seed", p.seed},
          {"edges_mm", m.edges},
          {"support", pv.stats.support}};
}

ojson object_json(const ForceLabResult& d) {
  const ForceVariant& v = d.proxy;
  const ForceVariant& v0 = d.no_proxy;
  const ForceVariant& v1 = d.onset;
  const ForceErrors& cov = d.covered;
  const std::vector<double>& us = v.replay.step_us;
  ojson j;
  j["name"] = d.name;
  j["train_samples"] = d.train.rec.size();
  j["test_samples"] = d.test.rec.size();
  j["rmse_n"] = xyz(v.all.rmse);
  j["median_ae_n"] = xyz(v.all.ae_axis_median);
  j["re"] = mean_median(v.all.re_mean, v.all.re_median);
  j["no_proxy_re"] = mean_median(v0.all.re_mean, v0.all.re_median);
  j["train_s"] = v.provenance.stats.seconds;
  j["step_us"] = {
      {"p50", quantile(us, 0.5)}, {"p99", quantile(us, 0.99)}, {"max", quantile(us, 1.0)}};
  j["proxy_source"] = d.train_track.proxy_source;
  j["contact_source"] = d.train_track.contact_source;
  j["train_recording"] = d.train.comments.empty() ? "" : d.train.comments.front();
  j["scored_on"] = "test samples the lab says are in contact (true contact flag)";
  j["palpation_s"] = d.palpation_s;
  j["reference_points"] = d.reference_points;
  j["proxy_vs_truth"] = {{"q_rms_mm", d.proxy_rms_mm}, {"contact_agreement", d.contact_agreement}};
  j["train_contact_samples"] = v.train_contact;
  j["test_contact_samples"] = v.all.n;
  j["sliding_only"] = {{"t_from_s", d.t_slide},
                       {"samples", v.sliding.n},
                       {"re", mean_median(v.sliding.re_mean, v.sliding.re_median)},
                       {"no_proxy_re", mean_median(v0.sliding.re_mean, v0.sliding.re_median)},
                       {"onset_proxy_re", mean_median(v1.sliding.re_mean, v1.sliding.re_median)},
                       {"rmse_n", xyz(v.sliding.rmse)},
                       {"no_proxy_rmse_n", xyz(v0.sliding.rmse)}};
  j["covered"] = {{"definition", "a training contact sample within 3 mm in (q, ||q - p||)"},
                  {"samples", cov.n},
                  {"rmse_n", xyz(cov.rmse)},
                  {"re", mean_median(cov.re_mean, cov.re_median)}};
  j["support"] = support_json(d.support);
  j["no_proxy_rmse_n"] = xyz(v0.all.rmse);
  j["onset_proxy_re"] = mean_median(v1.all.re_mean, v1.all.re_median);
  j["onset_proxy_rmse_n"] = xyz(v1.all.rmse);
  j["no_proxy_train_s"] = v0.provenance.stats.seconds;
  j["model"] = model_json(v.model, v.provenance);
  j["errors"] = ojson::parse(force_errors_json(v.all));
  if (v0.all.n > 0) j["no_proxy_errors"] = ojson::parse(force_errors_json(v0.all));
  return j;
}

}  // namespace

std::string force_lab_json(const ForceLabResult& d) {
  ojson j = object_json(d);
  // Training never clips a target (forces above the modeling range are kept and counted).
  j["clipped_training_samples"] = 0;
  j["training_samples_above_range"] = d.proxy.provenance.stats.above_range;
  const ForceCoverage cov = training_coverage(d);
  j["coverage"] = cov.outside;
  // Where the training run left the largest unvisited areas (x, y projection): explore there.
  ojson gaps = ojson::array();
  for (const CoverageGap& g : cov.gaps)
    gaps.push_back({{"x_mm", g.x_mm},
                    {"y_mm", g.y_mm},
                    {"area_mm2", static_cast<double>(g.cells) * cov.cell_mm * cov.cell_mm}});
  j["explore_more"] = std::move(gaps);
  return j.dump();
}

}  // namespace inhap::eval
