// Contact-point error of a lab tapping recording (see contacts_lab.hpp). Units: mm, N, s.
#include "inhap/eval/contacts_lab.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "inhap/contact/knee.hpp"

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

}  // namespace inhap::eval
