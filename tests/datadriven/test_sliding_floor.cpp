// Sliding floor (TrainParams::sliding_floor) on synthetic data with a known law: a flat surface
// (normal +z), f_n = k d^1.5; a sticking proxy pulls with a tangential spring k_t |u_t| below
// the friction limit, a sliding one with |f_t| = mu f_n (Coulomb) along u_t. The fit must
// recover mu from the samples the proxy track marks as sliding (slip speed > 0), and the servo
// step must render at least that force while (and only while) its proxy moves.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "dd_fixtures.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/datadriven/servo.hpp"

namespace inhap::datadriven {
namespace {

constexpr double kK = 0.4, kMu = 0.9, kKt = 0.3;  // N/mm^1.5, -, N/mm

double normal_force(double depth) {
  return kK * std::pow(std::max(depth, 0.0), 1.5);
}

// Samples on the plane z = 0, in three kinds: sticking (|u_t| < 1 mm, spring, at rest); sliding
// (|u_t| = the yield radius mu f_n / k_t, slipping at 1-40 mm/s, the force at the limit); and as
// many that look the same as sliding ones (same |u_t|, same velocities) but pull half as much,
// not marked sliding: what an estimated proxy's errors put beside the sliding samples. The RBFs
// average the last two; the floor restores the limit where the proxy truly moves.
TrainingSet stick_slip_set(std::uint64_t seed, std::size_t n) {
  Rng rng(seed);
  TrainingSet s;
  for (std::size_t i = 0; i < n; ++i) {
    const int kind = static_cast<int>(i % 3);  // 0 sticking, 1 sliding, 2 look-alike
    const Vec3 q(rng.uniform(-20, 20), rng.uniform(-20, 20), 0.0);
    const double depth = rng.uniform(1.5, 5.0), fn = normal_force(depth);
    const double a = rng.uniform(0.0, 2 * M_PI), speed = kind ? rng.uniform(1.0, 40.0) : 0.0;
    const Vec3 dir(std::cos(a), std::sin(a), 0.0);
    const double limit = kMu * fn;
    const double ft = kind == 0 ? kKt * rng.uniform(0.0, 1.0) : kind == 1 ? limit : 0.5 * limit;
    const double ut = kind == 0 ? ft / kKt : kMu * fn / kKt;
    s.p.push_back(q - ut * dir - Vec3(0, 0, depth));
    s.v.push_back(-speed * dir);  // the probe runs ahead of its proxy
    s.q.push_back(q);
    s.f.push_back(ft * dir + Vec3(0, 0, fn));
    s.n.push_back(Vec3::UnitZ());
    s.slip.push_back(kind == 1 ? speed : 0.0);  // slip speed, mm/s (> 0: sliding)
  }
  return s;
}

TrainParams floor_params(bool floor) {
  TrainParams p = test::local_params(40, {1.0, 0.3, 0.5}, 3);
  p.sliding_floor = floor;
  return p;
}

TEST(SlidingFloor, RecoversTheFrictionCoefficient) {
  const TrainingSet s = stick_slip_set(1, 3000);
  const ForceModel m = train_force_model(s, floor_params(true));
  // Every sample marked sliding has |f_t| / f_n = mu exactly, so any quantile is mu.
  EXPECT_NEAR(m.sliding_mu, kMu, 1e-12);
  // Sliding samples whose ratio spreads evenly over [0.8, 1.0] (the i-th of them 0.8 + 0.2 i /
  // (count - 1)): the floor is their 10 % quantile, 0.82 (to the spacing of those pressed with
  // f_n >= 1 N, a random subset).
  TrainingSet spread = s;
  std::size_t count = 0, seen = 0;
  for (double v : spread.slip) count += v > 0;
  for (std::size_t i = 0; i < spread.size(); ++i) {
    if (!(spread.slip[i] > 0)) continue;
    const double ratio = 0.8 + 0.2 * static_cast<double>(seen++) / static_cast<double>(count - 1);
    const Vec3 ft(spread.f[i].x(), spread.f[i].y(), 0.0);
    spread.f[i].head<2>() = (ratio * spread.f[i].z() / ft.norm() * ft).head<2>();
  }
  EXPECT_NEAR(train_force_model(spread, floor_params(true)).sliding_mu, 0.82, 5e-3);
  const ForceModel off = train_force_model(s, floor_params(false));
  EXPECT_EQ(off.sliding_mu, 0.0);
  // No sliding flags (or too few sliding samples): no floor.
  TrainingSet unflagged = s;
  unflagged.slip.clear();
  EXPECT_EQ(train_force_model(unflagged, floor_params(true)).sliding_mu, 0.0);
  TrainingSet few = s;
  for (std::size_t i = 50; i < few.size(); ++i) few.slip[i] = 0;  // 17 left
  EXPECT_EQ(train_force_model(few, floor_params(true)).sliding_mu, 0.0);
}

TEST(SlidingFloor, ServoRendersTheFrictionLimitWhileTheProxySlides) {
  const TrainingSet s = stick_slip_set(2, 3000);
  const ForceModel with = train_force_model(s, floor_params(true));
  const ForceModel without = train_force_model(s, floor_params(false));
  ASSERT_GT(with.sliding_mu, 0.0);
  // Drags across the plane at 20 mm/s, 1 ms ticks: the proxy trails by the yield radius and moves
  // with the probe (sliding) after the first tick in contact.
  const double depth = 3.0, fn = normal_force(depth), lag = kMu * fn / kKt, speed = 20.0;
  double sq_with = 0, sq_without = 0;
  int sliding_ticks = 0;
  for (int drag = 0; drag < 8; ++drag) {
    const double a = drag * M_PI / 4;
    const Vec3 dir(std::cos(a), std::sin(a), 0.0);
    ServoState st_with, st_without;
    for (int k = 0; k < 200; ++k) {
      const Vec3 p = Vec3(-10, 5, -depth) + speed * 1e-3 * k * dir,
                 q = p - lag * dir + Vec3(0, 0, depth);
      const Vec3 f_with = servo_step(with, st_with, p, q, Vec3::UnitZ(), true);
      const Vec3 f_without = servo_step(without, st_without, p, q, Vec3::UnitZ(), true);
      EXPECT_EQ(st_with.slip > 0, k > 0);
      if (k > 0) {
        EXPECT_NEAR(st_with.slip, speed, 1e-9);
      }
      if (k < 20) continue;  // the velocity filter settles
      ++sliding_ticks;
      const double floor = with.sliding_mu * f_with.z();
      EXPECT_GE(-f_with.head<2>().dot(dir.head<2>()), floor * (1 - 1e-9));  // along q - p
      const Vec3 truth = -kMu * fn * dir + Vec3(0, 0, fn);
      sq_with += (f_with - truth).head<2>().squaredNorm();
      sq_without += (f_without - truth).head<2>().squaredNorm();
    }
  }
  const double e_with = std::sqrt(sq_with / sliding_ticks),
               e_without = std::sqrt(sq_without / sliding_ticks);
  std::printf("sliding drags, tangential RMS error: %.3f N without the floor, %.3f N with it\n",
              e_without, e_with);
  EXPECT_LT(e_with, e_without);
  // With a friction cone narrower than mu_s the floor stops at the cone.
  ForceModel narrow = with;
  narrow.friction_cone = 0.5 * with.sliding_mu;
  ServoState sn;
  const Vec3 dir(1, 0, 0);
  Vec3 fc = Vec3::Zero();
  for (int k = 0; k < 30; ++k) {
    const Vec3 p = Vec3(-10, 5, -depth) + speed * 1e-3 * k * dir;
    fc = servo_step(narrow, sn, p, p - lag * dir + Vec3(0, 0, depth), Vec3::UnitZ(), true);
  }
  EXPECT_NEAR(fc.head<2>().norm(), narrow.friction_cone * fc.z(), 1e-9);
  // A proxy that holds still (sticking) renders exactly as without the floor's fit.
  ServoState a, b;
  const Vec3 q(3, 2, 0), p = q - Vec3(0.5, 0, depth);
  for (int k = 0; k < 30; ++k) {
    const Vec3 fa = servo_step(with, a, p, q, Vec3::UnitZ(), true);
    EXPECT_EQ(a.slip, 0.0);
    EXPECT_EQ(fa, model_force(with, p, a.velocity, q, Vec3::UnitZ(), 0.0));
    (void)servo_step(without, b, p, q, Vec3::UnitZ(), true);
  }
}

TEST(SlidingFloor, TrainingSetMarksTheSamplesWhoseProxyMoved) {
  Recording rec;
  ProxyTrack track;
  // Contact from sample 1: the proxy holds for three samples, then moves (0.5 mm in 1 ms, then
  // in 2 ms); contact lost at 7.
  const double qx[] = {0, 0, 0, 0, 0.5, 1.0, 1.0, 2.0, 2.0};
  const double t_ms[] = {0, 1, 2, 3, 4, 6, 7, 8, 9};
  const char contact[] = {0, 1, 1, 1, 1, 1, 1, 0, 1};
  for (int i = 0; i < 9; ++i) {
    rec.t.push_back(1e-3 * t_ms[i]);
    rec.p.emplace_back(qx[i], 0, -1);
    rec.f.emplace_back(0, 0, 1);
    track.q.emplace_back(qx[i], 0, 0);
    track.contact.push_back(contact[i]);
  }
  const TrainingSet s = make_training_set(rec, track, FoawParams{});
  // In-contact samples 1-6 and 8: moved since the previous in-contact tick at 4 (500 mm/s) and 5
  // (250 mm/s) only (8 follows a tick out of contact).
  const std::vector<double> expected = {0, 0, 0, 500, 250, 0, 0};
  ASSERT_EQ(s.slip.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(s.slip[i], expected[i], 1e-9);
}

TEST(SlidingFloor, FileRoundTripAndChecks) {
  const ForceModel m = train_force_model(stick_slip_set(3, 1500), floor_params(true));
  ASSERT_GT(m.sliding_mu, 0.0);
  const ForceModel back = force_model_from_json(force_model_to_json(m), "mem");
  EXPECT_EQ(back.sliding_mu, m.sliding_mu);
  auto j = nlohmann::json::parse(force_model_to_json(m));
  j["sliding_mu"] = -1.0;
  EXPECT_THROW(force_model_from_json(j.dump(), "bad.json"), ParseError);
  j["sliding_mu"] = "0.9";
  EXPECT_THROW(force_model_from_json(j.dump(), "bad.json"), ParseError);
  j.erase("sliding_mu");  // a file from before the floor: no floor
  EXPECT_EQ(force_model_from_json(j.dump(), "old.json").sliding_mu, 0.0);
  TrainParams p = floor_params(true);
  p.features = FeatureSet::kDisplacementProxyVelocity;
  EXPECT_THROW(p.validate(), Error);
}

}  // namespace
}  // namespace inhap::datadriven
