// Servo torture, short version (10^5 steps per renderer; bench/bench_torture runs 10^7): force
// always finite and within the device's limit, and no stuck state afterwards (issue 20).
#include <gtest/gtest.h>

#include "support/torture.hpp"

namespace inhap {
namespace {

constexpr std::uint64_t kSteps = 100000;

void expect_clean(const test::TortureResult& r, const char* what) {
  EXPECT_EQ(r.non_finite, 0u) << what;
  EXPECT_EQ(r.over_limit, 0u) << what << " max " << r.max_force;
  EXPECT_GT(r.nonzero, 100u) << what << ": the torture never reached the surface";
  EXPECT_TRUE(r.fresh_after) << what
                             << ": a legal trajectory afterwards differs from a fresh state";
}

TEST(Torture, Cba) {
  const rendering::Model m(test::torture_mesh());
  expect_clean(test::torture_renderer(m, rendering::Algorithm::kCBA, kSteps, 1), "CBA");
}

TEST(Torture, TcaMesh) {
  const rendering::Model m(test::torture_mesh());
  expect_clean(test::torture_renderer(m, rendering::Algorithm::kTCA, kSteps, 2), "TCA-MESH");
}

TEST(Torture, DataDriven) {
  const datadriven::ForceModel m = test::torture_dd_model();
  expect_clean(test::torture_data_driven(m, kSteps, 3), "data-driven");
}

}  // namespace
}  // namespace inhap
