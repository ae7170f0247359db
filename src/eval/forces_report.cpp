// `inhap eval forces`: the line per object and the report's head. Units: N, s, us.
#include "inhap/eval/forces_report.hpp"

#include <fmt/format.h>

#include "inhap/core/stats.hpp"

namespace inhap::eval {

std::string force_lab_summary(const ForceLabResult& d) {
  const ForceVariant& v = d.proxy;
  return fmt::format(
      "{}: RMSE x/y/z {:.3f} {:.3f} {:.3f} N, median AE {:.3f} {:.3f} {:.3f} N, RE mean {:.3f} "
      "median {:.3f}; sliding-only RE median {:.3f} (no proxy {:.3f}, onset proxy {:.3f}); "
      "train {:.1f} s; step p50 {:.2f} us p99 {:.2f} us; proxy {} (palpation {:.1f} s); outside "
      "training range {:.3f} (SSE share {:.2f} {:.2f} {:.2f})",
      d.name, v.all.rmse[0], v.all.rmse[1], v.all.rmse[2], v.all.ae_axis_median[0],
      v.all.ae_axis_median[1], v.all.ae_axis_median[2], v.all.re_mean, v.all.re_median,
      v.sliding.re_median, d.no_proxy.sliding.re_median, d.onset.sliding.re_median,
      v.provenance.stats.seconds, quantile(v.replay.step_us, 0.5), quantile(v.replay.step_us, 0.99),
      d.train_track.proxy_source, d.palpation_s, d.support.outside_any,
      d.support.sse_share_outside[0], d.support.sse_share_outside[1],
      d.support.sse_share_outside[2]);
}

nlohmann::ordered_json forces_report_head(const std::string& physics, const std::string& proxy) {
  using json = nlohmann::ordered_json;
  json out;
  out["units"] = {{"force", "N"}, {"time", "s"}, {"step", "us"}};
  out["physics"] = physics;
  out["proxy_source"] = proxy == "estimated"   ? "estimated:sys"
                        : proxy == "recording" ? "estimated:recording"
                                               : "truth";
  out["contact_source"] = proxy == "estimated"   ? "estimated:geometric"
                          : proxy == "recording" ? "estimated:surface"
                                                 : "truth";
  out["note"] =
      "estimated: q, the normal at q and contact from the friction module's proxy estimator "
      "(sliding yield surfaces of a palpation of the scene, geometric contact with the palpated "
      "shape mesh); recording: the same estimator with the surface, normals and friction "
      "estimated from the training recording alone (no palpation, no mesh); truth: the virtual "
      "lab's true proxy (anchor ax,ay,az) and contact flag; "
      "errors against the measured force on the truly-in-contact test samples; no_proxy = the "
      "same model trained on (p, pdot) only (q = p); onset_proxy = q held at the contact-onset "
      "position (u = p - p_c "
      "of earlier methods); sliding_only = last third of the test run (the explore operator's "
      "sliding-only passage); step_us = servo steps of the with-proxy model in contact";
  return out;
}

}  // namespace inhap::eval
