// One absurd sample in a tapping recording is rejected and counted before the compensation:
// before, a single 1e308 raw-force sample moved the fitted tool mass (0.278 -> 0.315 kg in the
// report) and added a tap, without a word.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/contact/tapping.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"

using namespace inhap;

TEST(TapOutliers, AOneE308SampleIsRejectedWithACountBeforeCompensation) {
  lab::RecordSpec spec;
  spec.operator_name = "tap";
  spec.probe = lab::ProbeSpec::tip();
  spec.seconds = 12.0;
  spec.seed = 4;
  const lab::LabRecording lab = lab::record_scene(lab::builtin_scene("sponge"), spec);
  const TappingResult clean = contacts_from_recording(lab.rec, {}, ForceSource::kRaw);
  ASSERT_GE(clean.contacts.size(), 3u);
  EXPECT_EQ(clean.rejected, 0u);
  Recording bad = lab.rec;
  auto* rz = const_cast<std::vector<double>*>(bad.find_extra("rfz"));
  ASSERT_NE(rz, nullptr);
  const std::size_t at = bad.size() / 3;
  (*rz)[at] = 1e308;
  bad.p[at + 100].x() = -1e308;
  const TappingResult r = contacts_from_recording(bad, {}, ForceSource::kRaw);
  EXPECT_EQ(r.rejected, 2u);
  ASSERT_FALSE(r.notes.empty());
  EXPECT_NE(r.notes.front().find("2 samples rejected as outliers"), std::string::npos);
  EXPECT_EQ(r.contacts.size(), clean.contacts.size());
  EXPECT_NEAR(r.compensation.mass_kg, clean.compensation.mass_kg,
              1e-2 * std::abs(clean.compensation.mass_kg) + 1e-6);
}
