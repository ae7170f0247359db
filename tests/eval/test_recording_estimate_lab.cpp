// The surface, normals and friction estimated from a lab recording logged at a rig's rate (no
// palpation cycles, no mesh), against the lab's ground truth: the true proxy (anchor), the
// object's normal there and its friction coefficient.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "inhap/datadriven/estimate.hpp"
#include "inhap/eval/lab_files.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::eval {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

struct Scores {
  double surface_mm, normal_deg, mu_rel;
  std::size_t samples;
};

Scores score(const std::string& scene_name, double rate_hz, double seconds) {
  const lab::Scene scene = lab::builtin_scene(scene_name);
  LabRecordRequest req;
  req.op = "explore";
  req.coverage = true;
  req.seconds = seconds;
  const lab::LabRecording lr =
      downsample_recording(lab::record_scene(scene, lab_record_spec(req)), rate_hz, 1);
  const datadriven::RecordingEstimate e =
      datadriven::estimate_recording(lr.rec, {}, scene_name + ".csv");
  const friction::MeshSurface est(e.mesh, 0.0);
  std::vector<double> dist, ang, mu;
  for (std::size_t i = 0; i < lr.truth.size(); ++i) {
    const Vec3& a = lr.truth.anchor[i];
    if (!lr.truth.contact[i] || !a.allFinite()) continue;
    Vec3 c, n;
    if (!est.closest(a, c, n)) continue;
    const lab::SurfaceQuery truth = scene.object.query(a);
    if (!truth.normal.allFinite()) continue;
    dist.push_back(std::abs((a - c).dot(n)));
    ang.push_back(std::acos(std::clamp(n.dot(truth.normal.normalized()), -1.0, 1.0)) * 180 /
                  std::numbers::pi);
    mu.push_back(lr.truth.mu[i]);
  }
  const double mu_true = median(mu);
  return {median(dist), median(ang), std::abs(e.friction.mu - mu_true) / mu_true, dist.size()};
}

// Bounds: what the estimators reach now (printed), with room for other seeds. The dome's
// curvature is the harder case: a height field of 2 mm cells under a 100 mm dome, and a friction
// fit that sees its slopes' normal force through that surface.
TEST(RecordingEstimateLab, PlanarAndDomeAt66HzAgainstTheLabsTruth) {
  struct Case {
    const char* name;
    double seconds, surface_mm, normal_deg, mu_rel;
  };
  // The training runs of `eval forces` (65 s planar, 52 s dome). On the 65 s planar run a
  // depth-force law fitted on the lighter forces alone took gamma 1/2 for the silicone's 2/3 and
  // put the surface 0.8 mm high; cells fitted each on their own (no shrinking of the slope
  // towards the recording's law) tilted the normals by 1.1 degrees and the friction by 21 %.
  for (const Case& c :
       {Case{"planar", 65.0, 0.15, 1.0, 0.10}, Case{"dome", 52.0, 0.25, 4.0, 0.25}}) {
    const Scores s = score(c.name, 66.0, c.seconds);
    std::printf("%s at 66 Hz: surface %.3f mm, normal %.2f deg, mu %.3f relative (%zu samples)\n",
                c.name, s.surface_mm, s.normal_deg, s.mu_rel, s.samples);
    SCOPED_TRACE(c.name);
    ASSERT_GT(s.samples, 1000u);
    EXPECT_LT(s.surface_mm, c.surface_mm);
    EXPECT_LT(s.normal_deg, c.normal_deg);
    EXPECT_LT(s.mu_rel, c.mu_rel);
  }
}

TEST(RecordingEstimateLab, DownsamplingKeepsTheRateAndTheTruthAligned) {
  const lab::Scene scene = lab::builtin_scene("planar");
  LabRecordRequest req;
  req.seconds = 3.0;
  const lab::LabRecording full = lab::record_scene(scene, lab_record_spec(req));
  const lab::LabRecording low = downsample_recording(full, 66.0, 1);
  ASSERT_EQ(low.rec.size(), low.truth.size());
  EXPECT_NEAR(static_cast<double>(low.rec.size()), 3.0 * 66.0, 3.0);
  for (std::size_t i = 0; i < low.rec.size(); ++i) EXPECT_EQ(low.rec.t[i], low.truth.t[i]);
  std::vector<double> dt;
  for (std::size_t i = 1; i < low.rec.size(); ++i) dt.push_back(low.rec.t[i] - low.rec.t[i - 1]);
  EXPECT_NEAR(median(dt), 1.0 / 66.0, 2e-3);
  EXPECT_GT(*std::max_element(dt.begin(), dt.end()) - *std::min_element(dt.begin(), dt.end()),
            2e-3);  // jittered
  EXPECT_EQ(downsample_recording(full, 1000.0, 1).rec.size(), full.rec.size());
}

// A recording with the tool's weight left in (as a bridged device's without --tool-mass): the
// estimate says so; the compensated one does not.
TEST(RecordingEstimateLab, WarnsOfAForceInTheAir) {
  const lab::Scene scene = lab::builtin_scene("planar");
  LabRecordRequest req;
  req.op = "explore";
  req.seconds = 15.0;
  const lab::LabRecording lr = lab::record_scene(scene, lab_record_spec(req));
  const datadriven::RecordingEstimate clean = datadriven::estimate_recording(lr.rec, {}, "c.csv");
  ASSERT_GT(clean.air_samples, 50u);  // the operator starts above the object
  EXPECT_LT(clean.air_force.norm(), 0.01);
  EXPECT_EQ(datadriven::estimate_warning(clean), "");
  Recording heavy = lr.rec;
  const Vec3 weight(0, 0, -0.0981);  // a 10 g tool
  for (Vec3& f : heavy.f) f += weight;
  const datadriven::RecordingEstimate e = datadriven::estimate_recording(heavy, {}, "h.csv");
  EXPECT_LT((e.air_force - weight).norm(), 0.01) << e.air_samples << " samples in the air";
  const std::string w = datadriven::estimate_warning(e);
  EXPECT_NE(w.find("-0.098) N"), std::string::npos) << w;
  EXPECT_NE(w.find("--tool-mass"), std::string::npos) << w;
  // The samples in the air, pulling along -z, are left out of the surface: it stays within
  // about half a millimetre of the clean one (with them it was 4.8 mm above the truth).
  std::vector<double> shift;
  for (std::size_t i = 0; i < lr.truth.size(); ++i)
    if (lr.truth.contact[i])
      shift.push_back(e.surface.depth(lr.rec.p[i]) - clean.surface.depth(lr.rec.p[i]));
  ASSERT_GT(shift.size(), 1000u);
  EXPECT_LT(std::abs(median(shift)), 0.6);
}

}  // namespace
}  // namespace inhap::eval
