// Contact points on virtual-lab recordings against the lab's ground truth (thesis fig. 3.4).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "inhap/contact/tapping.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"

using namespace inhap;

namespace test_lab_contacts {

lab::LabRecording tapping(const std::string& scene, double seconds, std::uint64_t seed) {
  lab::RecordSpec spec;
  spec.operator_name = "tap";
  spec.tap.whole_object = false;  // the top-cap protocol of fig. 3.4 (eval contacts)
  spec.probe = lab::ProbeSpec::tip();
  spec.seconds = seconds;
  spec.seed = seed;
  return lab::record_scene(lab::builtin_scene(scene), spec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 1e9 : v[v.size() / 2];
}

/// Errors (mm) of the detected contacts that fall in a true contact episode; counts the true
/// episodes and the detections outside any.
std::vector<double> errors(const lab::LabRecording& rec, const ContactOptions& o, ForceSource src,
                           long& true_taps, long& false_detections) {
  const TappingResult r = contacts_from_recording(rec.rec, o, src);
  true_taps = 0;
  for (long t : rec.truth.tap) true_taps = std::max(true_taps, t + 1);
  false_detections = 0;
  std::vector<double> e;
  for (const Contact& c : r.contacts) {
    if (rec.truth.tap[c.detect_index] < 0) {
      ++false_detections;
      continue;
    }
    e.push_back((c.point - rec.truth.c[c.detect_index]).norm());
  }
  return e;
}

TEST(LabContacts, EstimationBeatsThresholdingOnSoftObjects) {
  for (const std::string scene : {"sponge", "silicone-hemisphere"}) {
    const lab::LabRecording rec = tapping(scene, 40.0, 11);
    ContactOptions est, thr;
    thr.method = ContactMethod::kThreshold;
    for (ForceSource src : {ForceSource::kRaw, ForceSource::kRecorded}) {
      long taps = 0, false_est = 0, false_thr = 0;
      const auto e = errors(rec, est, src, taps, false_est);
      const auto t = errors(rec, thr, src, taps, false_thr);
      ASSERT_GE(taps, 15) << scene;
      EXPECT_EQ(static_cast<long>(e.size()), taps) << scene;  // every tap found once
      EXPECT_EQ(false_est, 0) << scene;
      EXPECT_LT(median(e), 0.3) << scene;
      EXPECT_GT(median(t), 3.0 * median(e)) << scene;
    }
  }
}

TEST(LabContacts, OfflineCompensationFindsTheToolMass) {
  const lab::LabRecording rec = tapping("foam-ball", 20.0, 5);
  const TappingResult r = contacts_from_recording(rec.rec, {}, ForceSource::kAuto);
  EXPECT_EQ(r.source, ForceSource::kRaw);
  // The lab's tool: 10 g beyond the sensor (DeviceParams::tool_mass_kg).
  EXPECT_NEAR(r.compensation.mass_kg, 0.01, 0.001);
  EXPECT_NEAR(r.compensation.offset.z(), -0.01 * 9.81, 0.005);
}

TEST(LabContacts, FreeMotionGivesNoContact) {
  lab::RecordSpec spec;
  spec.operator_name = "air";
  spec.probe = lab::ProbeSpec::tip();
  spec.seconds = 10.0;
  const lab::LabRecording rec = lab::record_scene(lab::builtin_scene("foam-ball"), spec);
  const TappingResult r = contacts_from_recording(rec.rec, {}, ForceSource::kAuto);
  EXPECT_TRUE(r.contacts.empty());
  ASSERT_FALSE(r.notes.empty());
  EXPECT_NE(r.notes.back().find("no contact found"), std::string::npos);
}
}  // namespace test_lab_contacts
