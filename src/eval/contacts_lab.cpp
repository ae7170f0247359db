// Contact-point error of a lab tapping recording (see contacts_lab.hpp). Units: mm, N, s.
#include "inhap/eval/contacts_lab.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "inhap/contact/knee.hpp"
#include "inhap/eval/shape_lab.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::eval {

Vec3 position_at(const Recording& rec, double at) {
  const auto it = std::lower_bound(rec.t.begin(), rec.t.end(), at);
  const std::size_t i = std::clamp<std::size_t>(std::size_t(it - rec.t.begin()), 1, rec.size() - 1);
  const double w = std::clamp((at - rec.t[i - 1]) / (rec.t[i] - rec.t[i - 1]), 0.0, 1.0);
  return (1 - w) * rec.p[i - 1] + w * rec.p[i];
}

TapErrors tap_errors(const lab::LabRecording& lab) {
  const Recording& rec = lab.rec;
  std::vector<double> mag(rec.size());
  for (std::size_t i = 0; i < rec.size(); ++i) mag[i] = rec.f[i].norm();
  TapErrors e;
  bool armed = true;
  for (std::size_t d = 0; d < rec.size(); ++d) {
    if (!armed) {
      armed = mag[d] < 0.1;
      continue;
    }
    if (mag[d] < 0.5) continue;
    armed = false;
    const long tap = lab.truth.tap[d];
    if (tap < 0 || !std::isfinite(lab.truth.tc[d])) continue;  // not a real contact
    std::size_t b = d;
    while (b > 0 && rec.t[b - 1] >= rec.t[d] - 0.1) --b;
    const KneeFit k = fit_knee(std::span<const double>(rec.t.data() + b, d - b + 1),
                               std::span<const double>(mag.data() + b, d - b + 1));
    if (!k.valid) continue;
    const Vec3 truth = lab.truth.c[d];
    e.threshold.push_back((rec.p[d] - truth).norm());
    e.knee.push_back((position_at(rec, k.tc) - truth).norm());
  }
  return e;
}

ErrorSummary summarize_errors(std::vector<double> v) {
  ErrorSummary s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  auto at = [&](double q) {  // linear interpolation between order statistics
    const double x = q * static_cast<double>(v.size() - 1);
    const auto i = static_cast<std::size_t>(x);
    const double w = x - static_cast<double>(i);
    return i + 1 < v.size() ? (1 - w) * v[i] + w * v[i + 1] : v[i];
  };
  s.median = at(0.5);
  s.p95 = at(0.95);
  s.max = v.back();
  return s;
}

ContactObjectResult run_contact_object(const std::string& name, const ContactObjectOptions& o) {
  ContactObjectResult r;
  r.name = name;
  const lab::Scene scene = lab::builtin_scene(name);
  if (o.physics == lab::Physics::kMujoco && !lab::mujoco_represents(scene.object.shape())) {
    r.skipped = true;
    r.skipped_shape = scene.object.shape().type_name();
    return r;
  }
  lab::TapOptions top;  // fig. 3.4 is measured on the top-cap protocol (the region seen from above)
  top.whole_object = false;
  const lab::LabRecording rec = record_taps(
      scene, o.taps, o.seed,
      [&](const std::string&, double f, double) {
        if (o.progress) o.progress("taps", f, 0);
      },
      o.physics, top);
  ContactOptions est, thr;
  est.eps_f = thr.eps_f = o.eps;
  est.window = thr.window = o.window;
  thr.method = ContactMethod::kThreshold;
  const MatchedContacts me = match_contacts(rec, est, o.taps),
                        mt = match_contacts(rec, thr, o.taps);
  r.estimate = summarize_errors(me.error);
  r.threshold = summarize_errors(mt.error);
  r.stiffness_n_per_mm = summarize_errors(me.stiffness).median;
  r.taps = me.contacts.size();
  r.false_detections = me.false_detections;
  return r;
}

}  // namespace inhap::eval
