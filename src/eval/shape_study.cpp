// One object of the shape study (see shape_study.hpp). Units: mm, N, s.
#include "inhap/eval/shape_study.hpp"

namespace inhap::eval {

ShapeObjectResult run_shape_object(const lab::Scene& scene, const ShapeObjectOptions& o) {
  auto report = [&](const char* what, double f) {
    if (o.progress) o.progress(what, f, 0);
  };
  const lab::LabRecording rec = record_taps(
      scene, o.taps, o.seed, [&](const std::string&, double f, double) { report("taps", 0.8 * f); },
      o.physics, o.tap);
  report("reconstruct", 0.8);
  ShapeObjectResult r;
  r.reference = reference_mesh(scene.object.shape());
  const TriMesh reachable = reachable_part(r.reference, scene.object, o.tap.reach);
  ShapeCompareOptions co = o.compare;
  co.reachable_reference = o.score_reachable_part ? &reachable : nullptr;
  if (o.tap.whole_object && !(co.reconstruct.local_alpha > 0))
    co.reconstruct.local_alpha = o.whole_object_local_alpha;
  r.estimate = reconstruct_and_compare(rec, ContactMethod::kEstimate, o.taps, r.reference, co);
  r.threshold = reconstruct_and_compare(rec, ContactMethod::kThreshold, o.taps, r.reference, co);
  r.coverage = tap_coverage(scene.object, r.estimate.matched.truth, o.coverage_radius_mm,
                            o.coverage_samples, o.tap.reach);
  r.taps_per_minute = taps_per_minute(rec);
  r.recording_s = rec.rec.size() ? rec.rec.t.back() : 0.0;
  if (o.count_entry_sides) r.sides = count_far_side_contacts(rec, scene.object);
  report("done", 1.0);
  return r;
}

}  // namespace inhap::eval
