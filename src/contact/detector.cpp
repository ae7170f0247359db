// Tap segmentation, threshold detection and true-contact estimation; see detector.hpp.
#include "inhap/contact/detector.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "inhap/contact/knee.hpp"

namespace inhap {

std::vector<double> force_magnitudes(std::span<const Vec3> f) {
  std::vector<double> m(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) m[i] = all_finite(f[i]) ? f[i].norm() : 0.0;
  return m;
}

Vec3 position_at(std::span<const double> t, std::span<const Vec3> p, double tc) {
  if (t.empty()) return Vec3::Zero();
  if (tc <= t.front()) return p.front();
  if (tc >= t.back()) return p.back();
  const std::size_t hi =
      static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), tc) - t.begin());
  const std::size_t lo = hi - 1;
  const double w = (tc - t[lo]) / (t[hi] - t[lo]);
  return (1.0 - w) * p[lo] + w * p[hi];
}

namespace {

struct Tap {
  std::size_t start;   // first sample after the previous release (window may not go before)
  std::size_t detect;  // first sample above eps
  std::size_t end;     // first sample below the release level (or size)
};

std::vector<Tap> segment(std::span<const double> mag, const ContactOptions& o,
                         std::span<const double> t, std::vector<std::string>* notes) {
  std::vector<Tap> taps;
  const std::size_t n = mag.size();
  const double release = o.release_fraction * o.eps_f;
  std::size_t i = 0, free_since = 0;
  // A recording that starts in contact: wait for the first release.
  if (n > 0 && mag[0] > o.eps_f) {
    while (i < n && mag[i] >= release) ++i;
    if (notes)
      notes->push_back(
          fmt::format("recording starts in contact: samples before t = {:.4f} s ignored",
                      i < n ? t[i] : t.back()));
    free_since = i;
  }
  while (i < n) {
    if (!(mag[i] > o.eps_f)) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < n && j - i < o.min_contact && mag[j] > o.eps_f) ++j;
    if (j - i < o.min_contact) {  // a spike, or the recording ends
      if (j >= n && notes)
        notes->push_back(fmt::format("tap at t = {:.4f} s cut by the end of the recording", t[i]));
      i = j + 1;
      continue;
    }
    std::size_t e = j;
    while (e < n && mag[e] >= release) ++e;
    taps.push_back({free_since, i, e});
    free_since = e;
    i = e;
  }
  return taps;
}

}  // namespace

std::vector<Contact> detect_contacts(std::span<const double> t, std::span<const Vec3> p,
                                     std::span<const Vec3> f, const ContactOptions& o,
                                     std::vector<std::string>* notes) {
  std::vector<Contact> out;
  const std::size_t n = std::min({t.size(), p.size(), f.size()});
  if (n == 0) return out;
  const std::vector<double> mag = force_magnitudes(f.first(n));
  const std::vector<Tap> taps = segment(mag, o, t.first(n), notes);
  KneeOptions ko;
  ko.refine = o.refine;
  for (const Tap& tap : taps) {
    Contact c;
    c.tap = out.size();
    c.detect_index = tap.detect;
    c.t_detect = t[tap.detect];
    c.p_detect = p[tap.detect];
    c.t_contact = c.t_detect;
    c.point = c.p_detect;
    std::size_t peak = tap.detect;
    for (std::size_t k = tap.detect; k < tap.end; ++k)
      if (mag[k] > mag[peak]) peak = k;
    c.peak_force = mag[peak];
    if (mag[peak] > 0) c.direction = f[peak] / mag[peak];
    if (o.method == ContactMethod::kEstimate) {
      const std::size_t lo = std::max(tap.start, tap.detect > o.window ? tap.detect - o.window : 0);
      const std::size_t hi = std::min(n - 1, std::min(tap.end, tap.detect + o.post));
      if (tap.detect - lo < o.min_window) {
        if (notes)
          notes->push_back(fmt::format(
              "tap {} at t = {:.4f} s: only {} samples before detection, thresholding used", c.tap,
              c.t_detect, tap.detect - lo));
      } else {
        const std::size_t len = hi - lo + 1;
        const KneeFit fit =
            fit_knee(t.subspan(lo, len), std::span<const double>(mag).subspan(lo, len), ko);
        if (fit.valid) {
          c.t_contact = fit.tc;
          c.point = position_at(t.first(n), p.first(n), fit.tc);
          c.estimated = true;
        } else if (notes) {
          notes->push_back(fmt::format("tap {} at t = {:.4f} s: knee fit failed, thresholding used",
                                       c.tap, c.t_detect));
        }
      }
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace inhap
