#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "inhap/contact/detector.hpp"
#include "inhap/core/random.hpp"

using namespace inhap;

namespace {

/// 1 kHz recording of a probe tapping a linear spring surface z = 0 (stiffness k N/mm) from
/// above: each tap approaches at `speed` mm/s, presses to `depth` mm, retracts. Records the true
/// contact instants (z crossing 0 downwards).
struct Synthetic {
  std::vector<double> t;
  std::vector<Vec3> p, f;
  std::vector<double> truth_t;
  std::vector<Vec3> truth_p;
};

Synthetic tapping(int taps, double k, double speed, double noise, std::uint64_t seed) {
  Synthetic s;
  Rng rng(seed);
  double time = 0;
  for (int tap = 0; tap < taps; ++tap) {
    const double x = 3.0 * tap, h = 5.0, depth = 4.0;
    const double phase = rng.uniform();  // contact between samples
    // Down from h to -depth, up to h; then rest 50 ms.
    const double down = (h + depth) / speed;
    const int n = static_cast<int>(2 * down * 1000);
    for (int i = 0; i < n; ++i) {
      const double tau = (i + phase) * 1e-3;
      const double z = tau < down ? h - speed * tau : -depth + speed * (tau - down);
      s.t.push_back(time + i * 1e-3);
      s.p.emplace_back(x, 0.0, z);
      const double fz = z < 0 ? -k * z : 0.0;
      s.f.emplace_back(noise * rng.normal(), noise * rng.normal(), fz + noise * rng.normal());
    }
    s.truth_t.push_back(time + h / speed - phase * 1e-3);
    s.truth_p.emplace_back(x, 0.0, 0.0);
    time += n * 1e-3;
    for (int i = 0; i < 50; ++i) {
      s.t.push_back(time + i * 1e-3);
      s.p.emplace_back(x, 0.0, h);
      s.f.emplace_back(noise * rng.normal(), noise * rng.normal(), noise * rng.normal());
    }
    time += 0.05;
  }
  return s;
}

}  // namespace

TEST(Detector, ThresholdErrorIsEpsOverStiffnessAndEstimationRemovesIt) {
  // Soft surface 0.1 N/mm: thresholding at 0.2 N detects 2 mm deep.
  const Synthetic s = tapping(10, 0.1, 40.0, 0.003, 3);
  ContactOptions est, thr;
  thr.method = ContactMethod::kThreshold;
  const auto a = detect_contacts(s.t, s.p, s.f, est);
  const auto b = detect_contacts(s.t, s.p, s.f, thr);
  ASSERT_EQ(a.size(), 10u);
  ASSERT_EQ(b.size(), 10u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(a[i].estimated);
    EXPECT_FALSE(b[i].estimated);
    EXPECT_NEAR((b[i].point - s.truth_p[i]).norm(), 2.0, 0.1);
    EXPECT_LT((a[i].point - s.truth_p[i]).norm(), 0.15) << "tap " << i;
    EXPECT_NEAR(a[i].t_contact, s.truth_t[i], 4e-3);
    EXPECT_NEAR(a[i].direction.z(), 1.0, 1e-3);
    EXPECT_EQ(a[i].tap, i);
  }
}

TEST(Detector, NoContactGivesNothing) {
  Synthetic s = tapping(3, 0.1, 40.0, 0.02, 4);
  for (auto& f : s.f) f *= 0.0;
  std::vector<std::string> notes;
  EXPECT_TRUE(detect_contacts(s.t, s.p, s.f, {}, &notes).empty());
  EXPECT_TRUE(detect_contacts({}, {}, {}, {}).empty());
}

TEST(Detector, NoiseSpikesAreNotTaps) {
  Synthetic s = tapping(2, 0.5, 40.0, 0.003, 5);
  s.f[20] = Vec3(0, 0, 1.0);  // one-sample spike far from any tap
  s.f[21] = Vec3(0, 0, 1.0);
  EXPECT_EQ(detect_contacts(s.t, s.p, s.f, {}).size(), 2u);
}

TEST(Detector, TapTooCloseToTheStartFallsBackToThresholding) {
  // The recording starts 4 samples before the first detection: no window for the knee fit.
  const Synthetic s = tapping(2, 0.1, 40.0, 0.003, 6);
  ContactOptions thr;
  thr.method = ContactMethod::kThreshold;
  const std::size_t cut = detect_contacts(s.t, s.p, s.f, thr).front().detect_index - 4;
  const auto from = static_cast<std::ptrdiff_t>(cut);
  const std::vector<double> t(s.t.begin() + from, s.t.end());
  const std::vector<Vec3> p(s.p.begin() + from, s.p.end()), f(s.f.begin() + from, s.f.end());
  std::vector<std::string> notes;
  const auto c = detect_contacts(t, p, f, {}, &notes);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_FALSE(c[0].estimated);
  EXPECT_EQ(c[0].detect_index, 4u);
  EXPECT_TRUE(c[1].estimated);
  EXPECT_LT((c[1].point - s.truth_p[1]).norm(), 0.15);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes.front().find("thresholding"), std::string::npos) << notes.front();
}

TEST(Detector, RecordingStartingInContactSkipsThatTap) {
  Synthetic s = tapping(2, 0.1, 40.0, 0.003, 7);
  const std::size_t cut = static_cast<std::size_t>((s.truth_t[0] + 0.05) * 1000);  // mid-press
  Synthetic r;
  r.t.assign(s.t.begin() + static_cast<std::ptrdiff_t>(cut), s.t.end());
  r.p.assign(s.p.begin() + static_cast<std::ptrdiff_t>(cut), s.p.end());
  r.f.assign(s.f.begin() + static_cast<std::ptrdiff_t>(cut), s.f.end());
  std::vector<std::string> notes;
  const auto c = detect_contacts(r.t, r.p, r.f, {}, &notes);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_LT((c[0].point - s.truth_p[1]).norm(), 0.15);
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes.front().find("starts in contact"), std::string::npos);
}

TEST(Detector, PositionIsInterpolatedBetweenSamples) {
  std::vector<double> t{0.0, 1.0, 2.0};
  std::vector<Vec3> p{Vec3(0, 0, 0), Vec3(1, 2, 3), Vec3(3, 2, 1)};
  EXPECT_TRUE(position_at(t, p, 0.25).isApprox(Vec3(0.25, 0.5, 0.75)));
  EXPECT_TRUE(position_at(t, p, 1.5).isApprox(Vec3(2, 2, 2)));
  EXPECT_EQ(position_at(t, p, -1.0), p.front());
  EXPECT_EQ(position_at(t, p, 5.0), p.back());
}
