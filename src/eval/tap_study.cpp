// Scoring a tapping recording (see tap_study.hpp). Units: mm, N, s.
#include "inhap/eval/tap_study.hpp"

#include <limits>

#include "inhap/contact/detector.hpp"
#include "inhap/lab/reach.hpp"
#include "inhap/surface/points.hpp"

namespace inhap::eval {

std::vector<Vec3> true_tap_points(const lab::LabRecording& rec) {
  std::vector<Vec3> out;
  long last = -1;
  for (std::size_t i = 0; i < rec.truth.size(); ++i)
    if (rec.truth.tap[i] > last && all_finite(rec.truth.c[i]))
      last = rec.truth.tap[i], out.push_back(rec.truth.c[i]);
  return out;
}

namespace {

/// tap_coverage for either probe: the truth's contact point of a sphere is its centre, so the
/// surface point is the closest one to it, and the reachable surface is the one the sphere
/// touches along the normal.
double probe_coverage(const lab::SoftObject& object, const std::vector<Vec3>& taps,
                      const TapScoreOptions& o) {
  const double r = o.probe_radius_mm;
  const std::vector<lab::SurfaceSample> s = lab::reachable_samples(object, r, o.samples, 99);
  if (s.empty() || taps.empty()) return 0.0;
  std::vector<Vec3> on_surface, pts;
  for (const Vec3& c : taps) on_surface.push_back(r > 0 ? object.query(c).closest : c);
  for (const auto& x : s) pts.push_back(x.point);
  const std::vector<double> d = nearest_distances(on_surface, pts);
  std::size_t near = 0;
  for (double v : d) near += v <= o.radius_mm;
  return static_cast<double>(near) / static_cast<double>(d.size());
}

}  // namespace

TapScore score_taps(const lab::LabRecording& rec, const lab::SoftObject& object,
                    const TapScoreOptions& o) {
  TapScore s;
  const std::vector<Vec3> taps = true_tap_points(rec);
  s.taps = taps.size();
  s.seconds = rec.rec.size() > 1 ? rec.rec.t.back() - rec.rec.t.front() : 0.0;
  s.taps_per_minute = taps_per_minute(rec);
  s.coverage = probe_coverage(object, taps, o);
  ContactOptions est, thr;
  est.eps_f = thr.eps_f = o.eps;
  est.window = thr.window = o.window;
  thr.method = ContactMethod::kThreshold;
  constexpr std::size_t kAll = std::numeric_limits<std::size_t>::max();
  const MatchedContacts me = match_contacts(rec, est, kAll), mt = match_contacts(rec, thr, kAll);
  s.estimate = summarize_errors(me.error);
  s.threshold = summarize_errors(mt.error);
  s.matched = me.contacts.size();
  s.false_detections = me.false_detections;
  s.sides = count_far_side_contacts(rec, object, o.probe_radius_mm);
  return s;
}

}  // namespace inhap::eval
