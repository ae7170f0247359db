// The studio's streaming tap detector (session.hpp: StreamTapDetector) against taps with a known
// contact instant: it must report each tap once, when the tap ends, at the point the batch
// detector (detect_contacts, thesis 3.2) finds, and that point must be p(t_c).
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/studio/session.hpp"

using inhap::Vec3;

namespace {

// Tap k starts at 0.6 k s: the probe at (10 k, 0, 10) moves down at 50 mm/s; contact at
// t_c = start + 0.1003 s (between samples); the force rises at 40 N/s for 80 ms, falls back at
// the same rate, then the probe rests in free air (zero force).
struct Synthetic {
  static constexpr double kSpeed = 50.0, kRate = 40.0, kApproach = 0.1003;
  double tc(int k) const { return 0.6 * k + kApproach; }
  Vec3 p(double t) const {
    const int k = int(std::floor(t / 0.6));
    const double z = 10.0 - kSpeed * std::min(t - 0.6 * k, 0.26);
    return Vec3(10.0 * k, 0, z);
  }
  double f(double t) const {
    const int k = int(std::floor(t / 0.6));
    const double u = t - tc(k);
    if (u <= 0) return 0;
    if (u <= 0.08) return kRate * u;
    return std::max(0.0, kRate * (0.16 - u));
  }
};

}  // namespace

TEST(StudioStreamTaps, EachTapOnceAtItsTrueContactPoint) {
  const Synthetic s;
  inhap::studio::StreamTapDetector det;
  std::vector<inhap::Contact> found;
  std::vector<double> t_reported;
  for (int i = 0; i < 6 * 600; ++i) {  // six taps
    const double t = i * 1e-3;
    if (auto c = det.add(t, s.p(t), Vec3(0, 0, s.f(t)))) {
      found.push_back(*c);
      t_reported.push_back(t);
    }
  }
  ASSERT_EQ(found.size(), 6u);
  for (int k = 0; k < 6; ++k) {
    const inhap::Contact& c = found[static_cast<std::size_t>(k)];
    const double tc = s.tc(k);
    const Vec3 truth = s.p(tc);
    EXPECT_TRUE(c.estimated) << k;
    EXPECT_NEAR(c.t_contact, tc, 1e-3) << k;          // within a sample
    EXPECT_LT((c.point - truth).norm(), 0.05) << k;   // 50 mm/s x 1 ms
    EXPECT_GT(c.p_detect.z(), truth.z() - 1.0) << k;  // threshold point lies deeper...
    EXPECT_LT(c.p_detect.z(), truth.z()) << k;        // ...than the true contact
    EXPECT_GT(t_reported[static_cast<std::size_t>(k)], tc + 0.16) << k;  // after the tap ended
  }
}

TEST(StudioStreamTaps, NoTapInFreeAirOrOnANoiseSpike) {
  inhap::studio::StreamTapDetector det;
  int taps = 0;
  for (int i = 0; i < 5000; ++i) {
    const double t = i * 1e-3;
    const double f = (i % 997 == 0) ? 1.0 : 0.0;  // one-sample spikes: shorter than min_contact
    taps += det.add(t, Vec3(0, 0, 10), Vec3(0, 0, f)).has_value();
  }
  EXPECT_EQ(taps, 0);
}
