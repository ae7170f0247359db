// eval::run_contact_object (`inhap eval contacts`, thesis fig. 3.4) reached without the program:
// on a lab tapping object the true-contact estimate lands within a tenth of a millimetre or so
// of the true contact points, several times closer than plain thresholding; and the summary's
// order statistics on a known sample. Units: mm, N, s.
#include <gtest/gtest.h>

#include "inhap/core/error.hpp"
#include "inhap/eval/contacts_lab.hpp"

namespace inhap::eval {
namespace {

TEST(ContactObject, SummaryOfAKnownSample) {
  const ErrorSummary s = summarize_errors({5, 1, 4, 2, 3});
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  EXPECT_DOUBLE_EQ(s.p95, 4.8);  // 0.95 * 4 = 3.8: between the 4th and 5th values
  EXPECT_DOUBLE_EQ(s.max, 5.0);
  const ErrorSummary e = summarize_errors({});
  EXPECT_EQ(e.max, 0.0);
}

TEST(ContactObject, EstimateBeatsThresholdingOnTheSiliconeBlock) {
  ContactObjectOptions o;
  o.taps = 30;
  o.seed = 4;
  int calls = 0;
  o.progress = [&](const std::string& what, double f, double) {
    EXPECT_EQ(what, "taps");
    EXPECT_GE(f, 0.0);
    EXPECT_LE(f, 1.0);
    ++calls;
  };
  const ContactObjectResult r = run_contact_object("silicone-block", o);
  EXPECT_FALSE(r.skipped);
  EXPECT_GT(calls, 0);
  EXPECT_EQ(r.taps, 30u);
  EXPECT_EQ(r.false_detections, 0u);
  EXPECT_NEAR(r.stiffness_n_per_mm, 3.0, 0.3);  // the block's material: 3 N/mm
  EXPECT_LT(r.estimate.median, 0.15);
  EXPECT_LT(2 * r.estimate.median, r.threshold.median);
  EXPECT_LE(r.estimate.median, r.estimate.p95);
  EXPECT_LE(r.estimate.p95, r.estimate.max);
  EXPECT_THROW(run_contact_object("no-such-scene", o), Error);
}

}  // namespace
}  // namespace inhap::eval
