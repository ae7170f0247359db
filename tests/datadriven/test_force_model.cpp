// Clustered RBF force model: learns a known force law, reproduces linear laws exactly with the
// tail, equal-count bins, thread-count independence, guards.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "dd_fixtures.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/metrics.hpp"
#include "inhap/datadriven/model_io.hpp"

namespace inhap::datadriven {
namespace {

struct HeldOut {
  TrainingSet train, test;
  std::vector<Vec3> truth;  // noise-free force of the test samples
  std::array<double, 3> sd{};
};

const HeldOut& held_out() {
  static const HeldOut h = [] {
    HeldOut o;
    std::vector<Vec3> truth;
    const TrainingSet all = test::synthetic_set(1, 12000, &truth);
    o.train = test::take(all, 0, 2);
    o.test = test::take(all, 1, 2);
    for (std::size_t i = 1; i < truth.size(); i += 2) o.truth.push_back(truth[i]);
    Vec3 mean = Vec3::Zero();
    for (const auto& f : o.truth) mean += f;
    mean /= static_cast<double>(o.truth.size());
    for (const auto& f : o.truth)
      for (int a = 0; a < 3; ++a)
        o.sd[static_cast<std::size_t>(a)] += (f[a] - mean[a]) * (f[a] - mean[a]);
    for (auto& s : o.sd) s = std::sqrt(s / static_cast<double>(o.truth.size()));
    return o;
  }();
  return h;
}

ForceErrors test_errors(const ForceModel& m) {
  const HeldOut& h = held_out();
  std::vector<Vec3> r;
  for (std::size_t i = 0; i < h.test.size(); ++i)
    r.push_back(model_force(m, h.test.p[i], h.test.v[i], h.test.q[i]));
  return force_errors(r, h.truth);
}

TEST(ForceModel, RegressionDesignLearnsTheSyntheticLaw) {
  TrainParams p = test::small_params();
  p.design = Design::kRegression;
  for (bool tail : {false, true}) {
    p.linear_tail = tail;
    const ForceModel m = train_force_model(held_out().train, p);
    const ForceErrors e = test_errors(m);
    SCOPED_TRACE(tail);
    for (std::size_t a = 0; a < 3; ++a) {
      EXPECT_GT(held_out().sd[a], 0.9);  // forces of about 1 N spread
      EXPECT_LT(e.rmse[a], 0.05) << "axis " << a;
    }
    EXPECT_LT(e.re_median, 0.03);
  }
}

TEST(ForceModel, ThesisDesignLearnsTheSyntheticLaw) {
  TrainParams p = test::small_params();
  p.design = Design::kThesis;
  p.linear_tail = true;
  const TrainedForceModel tm = train_with_provenance(held_out().train, p);
  const ForceErrors e = test_errors(tm.model);
  for (std::size_t a = 0; a < 3; ++a) EXPECT_LT(e.rmse[a], 0.25 * held_out().sd[a]) << "axis " << a;
  EXPECT_LT(e.re_median, 0.1);
  for (const auto& s : tm.provenance.stats.support)
    for (int k : s) EXPECT_LE(k, p.centers);  // at most M non-zeros
}

TEST(ForceModel, LinearTailReproducesALinearLawExactly) {
  // f = B x + c in the raw features: the tail alone represents it, so the model is exact
  // everywhere inside the clamping box, whatever the bins and centres.
  Rng rng(3);
  Eigen::Matrix<double, 3, kFeatureDim> b;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < kFeatureDim; ++j) b(i, j) = rng.uniform(-0.05, 0.05);
  const Vec3 c(0.2, -0.1, 1.0);
  auto law = [&](const Vec3& p, const Vec3& v, const Vec3& q) {
    Eigen::Matrix<double, kFeatureDim, 1> x;
    make_features(FeatureSet::kDisplacementProxyVelocity, p, v, q, x.data());
    return Vec3(b * x + c);
  };
  TrainingSet s;
  for (int i = 0; i < 3000; ++i) {
    s.p.emplace_back(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-4, 0));
    s.q.emplace_back(s.p.back().x() + rng.uniform(-2, 2), s.p.back().y() + rng.uniform(-2, 2), 0.0);
    s.v.emplace_back(rng.normal(0, 20), rng.normal(0, 20), rng.normal(0, 10));
    s.f.push_back(law(s.p.back(), s.v.back(), s.q.back()));
  }
  for (Design d : {Design::kThesis, Design::kRegression}) {
    TrainParams p = test::small_params();
    p.linear_tail = true;
    p.design = d;
    const ForceModel m = train_force_model(s, p);
    for (int i = 0; i < 200; ++i) {  // fresh inputs inside the training range
      const Vec3 pp(rng.uniform(-15, 15), rng.uniform(-15, 15), rng.uniform(-3.5, -0.5));
      const Vec3 q(pp.x() + rng.uniform(-1, 1), pp.y() + rng.uniform(-1, 1), 0.0);
      const Vec3 v(rng.normal(0, 10), rng.normal(0, 10), rng.normal(0, 5));
      EXPECT_LT((model_force(m, pp, v, q) - law(pp, v, q)).norm(), 1e-6) << to_string(d);
    }
  }
}

TEST(ForceModel, BinsHaveEqualCountsAndIncreasingEdges) {
  TrainParams p = test::small_params();
  p.bins = 4;
  const ForceModel m = train_force_model(held_out().train, p);
  ASSERT_EQ(m.bins.size(), 4u);
  ASSERT_EQ(m.edges.size(), 3u);
  const std::size_t n = held_out().train.size();
  for (const BinModel& b : m.bins) {
    EXPECT_GE(b.samples, n / 4);
    EXPECT_LE(b.samples, n / 4 + 1);
    EXPECT_LE(b.key_min, b.key_max);
  }
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_GE(m.edges[i], m.bins[i].key_max);
    EXPECT_LE(m.edges[i], m.bins[i + 1].key_min);
    EXPECT_EQ(m.bin_of(m.bins[i].key_max), static_cast<int>(i));
    EXPECT_EQ(m.bin_of(m.bins[i + 1].key_min), static_cast<int>(i) + 1);
  }
  EXPECT_EQ(m.bin_of(-1.0), 0);
  EXPECT_EQ(m.bin_of(1e9), 3);
}

TEST(ForceModel, SameModelWithOneOrTwoThreads) {
  TrainParams p = test::small_params();
  p.threads = 1;
  TrainedForceModel a = train_with_provenance(held_out().train, p);
  p.threads = 2;
  TrainedForceModel b = train_with_provenance(held_out().train, p);
  a.provenance.stats.seconds = b.provenance.stats.seconds = 0;
  a.provenance.params.threads = b.provenance.params.threads = 0;
  EXPECT_EQ(force_model_to_json(a), force_model_to_json(b));
}

// The force as the three expansions give it one by one (world features, no blend or priors): bin
// by ||q - p||, normalise, clamp to the box, evaluate, clamp the magnitude to the limit.
Vec3 per_axis_force(const ForceModel& m, const Vec3& p, const Vec3& v, const Vec3& q) {
  const BinModel& bm = m.bins[static_cast<std::size_t>(m.bin_of((q - p).norm()))];
  double z[kFeatureDim];
  make_features(m.features, p, v, q, z);
  for (std::size_t d = 0; d < kFeatureDim; ++d)
    z[d] = std::clamp((z[d] - bm.offset[d]) / bm.scale[d], bm.box_min[d], bm.box_max[d]);
  Vec3 f(bm.axes()[0].eval(z), bm.axes()[1].eval(z), bm.axes()[2].eval(z));
  if (f.norm() > m.force_limit_n) f *= m.force_limit_n / f.norm();
  return f;
}

TEST(ForceModel, UnionEvaluationMatchesPerAxisExpansions) {
  for (Design d : {Design::kThesis, Design::kRegression}) {
    TrainParams p = test::small_params();
    p.design = d;
    const ForceModel m = train_force_model(held_out().train, p);
    std::size_t sum = 0, uni = 0;
    for (const BinModel& b : m.bins) {
      for (const auto& e : b.axes()) sum += static_cast<std::size_t>(e.size());
      uni += static_cast<std::size_t>(b.union_centres().rows());
    }
    EXPECT_LE(uni, sum);
    if (d == Design::kRegression) {
      EXPECT_EQ(uni * 3, sum);  // the axes share their centres
    }
    const HeldOut& h = held_out();
    for (std::size_t i = 0; i < h.test.size(); i += 7) {
      const Vec3 a = model_force(m, h.test.p[i], h.test.v[i], h.test.q[i]);
      const Vec3 b = per_axis_force(m, h.test.p[i], h.test.v[i], h.test.q[i]);
      ASSERT_LT((a - b).norm(), 1e-9 * (1 + b.norm())) << to_string(d) << " " << i;
    }
  }
}

TEST(ForceModel, GuardsNonFiniteAndLargeInputs) {
  const ForceModel m = train_force_model(held_out().train, test::small_params());
  const double nan = std::nan("");
  EXPECT_EQ(model_force(m, Vec3(nan, 0, 0), Vec3::Zero(), Vec3::Zero()), Vec3::Zero());
  EXPECT_EQ(model_force(m, Vec3::Zero(), Vec3::Zero(), Vec3(0, 0, INFINITY)), Vec3::Zero());
  // Far outside the training range (r^3 would explode): bounded by the device limit.
  for (double s : {50.0, 1e3, 1e6}) {
    const Vec3 f = model_force(m, Vec3(s, -s, -s), Vec3(s, s, s), Vec3(-s, s, 0));
    EXPECT_TRUE(f.allFinite());
    EXPECT_LE(f.norm(), m.force_limit_n + 1e-12);
  }
}

TEST(ForceModel, RejectsBadParametersAndData) {
  TrainParams p = test::small_params();
  p.nonzeros = p.centers + 1;
  EXPECT_THROW(train_force_model(held_out().train, p), Error);
  p = test::small_params();
  p.lambda_ratio = 0;
  EXPECT_THROW(train_force_model(held_out().train, p), Error);
  TrainingSet tiny = test::take(held_out().train, 0, 2000);
  EXPECT_THROW(train_force_model(tiny, test::small_params()), Error);
  TrainingSet bad = test::take(held_out().train, 0, 10);
  bad.f[3].x() = std::nan("");
  EXPECT_THROW(train_force_model(bad, test::small_params()), Error);
}

TEST(ForceModel, ProgressReportsEachBinOnceAndEndsAtOne) {
  TrainParams p = test::small_params();
  p.bins = 4;
  p.threads = 2;
  std::vector<double> fractions;
  std::vector<std::string> whats;
  const ForceModel m = train_force_model(
      held_out().train, p, {}, [&](const std::string& what, double fraction, double eta_s) {
        fractions.push_back(fraction);  // serialised by the trainer
        whats.push_back(what);
        EXPECT_GE(eta_s, 0.0);
      });
  EXPECT_EQ(m.bins.size(), 4u);
  ASSERT_EQ(fractions.size(), 4u);  // one call per bin: 1/4, 2/4, 3/4, 4/4
  for (std::size_t i = 0; i < fractions.size(); ++i)
    EXPECT_DOUBLE_EQ(fractions[i], double(i + 1) / 4.0);
  for (const std::string& w : whats) EXPECT_NE(w.find("bin "), std::string::npos) << w;
}

}  // namespace
}  // namespace inhap::datadriven
