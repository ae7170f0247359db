// Shared helpers of the data-driven tests: small synthetic data sets and models.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <utility>

#include <gtest/gtest.h>

#include "inhap/core/random.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/datadriven/synthetic.hpp"

namespace inhap::datadriven::test {

/// In-contact samples of a synthetic recording; `truth` receives the noise-free forces.
inline TrainingSet synthetic_set(std::uint64_t seed, std::size_t samples,
                                 std::vector<Vec3>* truth = nullptr) {
  SyntheticParams sp;
  sp.samples = samples;
  sp.seed = seed;
  const Recording rec = synthetic_recording(sp);
  const ProxyTrack track = proxy_from_columns(rec, "synthetic");
  if (truth) {
    truth->clear();
    const auto *tx = rec.find_extra("tfx"), *ty = rec.find_extra("tfy"),
               *tz = rec.find_extra("tfz");
    for (std::size_t i = 0; i < rec.size(); ++i)
      if (track.contact[i]) truth->emplace_back((*tx)[i], (*ty)[i], (*tz)[i]);
  }
  return make_training_set(rec, track, FoawParams{});
}

/// Every `stride`-th sample (from `offset`).
inline TrainingSet take(const TrainingSet& s, std::size_t offset, std::size_t stride) {
  TrainingSet o;
  for (std::size_t i = offset; i < s.size(); i += stride) {
    o.p.push_back(s.p[i]);
    o.v.push_back(s.v[i]);
    o.q.push_back(s.q[i]);
    o.f.push_back(s.f[i]);
  }
  return o;
}

/// A saturating friction law in the surface frame (u = q - p, +z = depth, mm -> N):
/// f_n = kLawK d^1.5, |f_t| = kLawMu f_n tanh(|u_t| / 0.5 mm) along u_t.
inline constexpr double kLawK = 0.4, kLawMu = 0.8;
inline Vec3 friction_law(const Vec3& u) {
  const double fn = kLawK * std::pow(std::max(u.z(), 0.0), 1.5);
  const double ut = std::hypot(u.x(), u.y());
  Vec3 f(0, 0, fn);
  if (ut > 1e-12) {
    const double ft = kLawMu * fn * std::tanh(ut / 0.5);
    f.x() = ft * u.x() / ut;
    f.y() = ft * u.y() / ut;
  }
  return f;
}

/// n samples on a flat surface (normal +z, at rest): draw(rng) gives the proxy q and the elastic
/// displacement u = q - p, law(q, u) the force (N).
template <class Draw, class Law>
TrainingSet flat_set(std::uint64_t seed, std::size_t n, Draw&& draw, Law&& law) {
  Rng rng(seed);
  TrainingSet s;
  for (std::size_t i = 0; i < n; ++i) {
    const auto [q, u] = draw(rng);
    s.p.push_back(q - u);
    s.v.push_back(Vec3::Zero());
    s.q.push_back(q);
    s.f.push_back(law(q, u));
    s.n.push_back(Vec3::UnitZ());
  }
  return s;
}

/// RMS over n proxies q drawn uniformly in angle and radius on a disc (centre, radius; z of the
/// centre) of sqrt(err(rng, q)), where err draws the rest of the query and returns its squared
/// error.
template <class Err>
double rms_on_disc(std::uint64_t seed, int n, const Vec3& centre, double radius, Err&& err) {
  Rng rng(seed);
  double sq = 0;
  for (int i = 0; i < n; ++i) {
    const double a = rng.uniform(0.0, 2 * M_PI), r = rng.uniform(0.0, radius);
    sq += err(rng, Vec3(centre + Vec3(r * std::cos(a), r * std::sin(a), 0.0)));
  }
  return std::sqrt(sq / n);
}

/// Local-frame features, 2 bins, one thread (deterministic and quick).
inline TrainParams local_params(int centers, std::array<double, 3> weights, std::uint64_t seed) {
  TrainParams p;
  p.features = FeatureSet::kLocalFrame;
  p.bins = 2;
  p.centers = centers;
  p.feature_weights = {weights[0], weights[1], weights[2]};
  p.seed = seed;
  p.threads = 1;
  return p;
}

inline TrainParams small_params() {
  TrainParams p;
  p.bins = 3;
  p.centers = 60;
  p.seed = 5;
  return p;
}

/// A prior's gain on a case it was made for: prints both errors (N), expects the model with the
/// prior below `limit` and at least 3x better than the plain one.
inline void expect_prior_gain(const char* what, double plain, double prior, double limit) {
  std::printf("%s: %.3f N plain, %.3f N prior\n", what, plain, prior);
  EXPECT_LT(prior, limit);
  EXPECT_GT(plain, 3 * prior);
}

/// Saves m as JSON and reads it back: the copy renders the same force at HIP p, proxy q (normal
/// +z, hand still). Returns the copy for further checks.
inline ForceModel expect_same_force_after_save(const ForceModel& m, const Vec3& p, const Vec3& q) {
  ForceModel back = force_model_from_json(force_model_to_json(m), "mem");
  EXPECT_EQ(model_force(back, p, Vec3::Zero(), q, Vec3::UnitZ()),
            model_force(m, p, Vec3::Zero(), q, Vec3::UnitZ()));
  return back;
}

}  // namespace inhap::datadriven::test
