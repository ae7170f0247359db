// Seeded l1 test problems (see include/inhap/datadriven/l1_problems.hpp).
#include "inhap/datadriven/l1_problems.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "inhap/core/random.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/kmeans.hpp"
#include "inhap/datadriven/rbf.hpp"
#include "inhap/datadriven/synthetic.hpp"

namespace inhap::datadriven {

namespace {

double lambda_of(const Eigen::MatrixXd& a, const Eigen::VectorXd& f, double ratio) {
  return ratio * (a.transpose() * f).lpNorm<Eigen::Infinity>();
}

}  // namespace

L1Problem r3_cube_problem(int n, int m, std::uint64_t seed, double noise) {
  Rng rng(seed);
  Eigen::MatrixXd x(n, 3), c(m, 3);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) x(i, d) = rng.uniform();
  for (int i = 0; i < m; ++i)
    for (int d = 0; d < 3; ++d) c(i, d) = rng.uniform();
  L1Problem p;
  p.name = "r3_cube";
  p.a = rbf_matrix(x, c);
  p.f.resize(n);
  constexpr double kPi = 3.14159265358979323846;
  for (int i = 0; i < n; ++i)
    p.f[i] = std::sin(2 * kPi * x(i, 0)) * std::cos(kPi * x(i, 1)) + x(i, 2) * x(i, 2) +
             noise * rng.normal();
  p.lambda = lambda_of(p.a, p.f, 0.001);
  return p;
}

void normalise_columns(L1Problem& p, double ratio) {
  for (Eigen::Index j = 0; j < p.a.cols(); ++j) {
    const double s = p.a.col(j).norm();
    if (s > 0) p.a.col(j) /= s;
  }
  p.lambda = lambda_of(p.a, p.f, ratio);
  p.name += "_normalised";
}

L1Problem force_model_problem(int samples, int m, std::uint64_t seed) {
  SyntheticParams sp;
  sp.samples = static_cast<std::size_t>(samples);
  sp.seed = seed;
  const Recording rec = synthetic_recording(sp);
  const TrainingSet t = make_training_set(rec, proxy_from_columns(rec, "synthetic"), FoawParams{});
  // The bin of the larger half of ||q - p|| (the default model has two bins of equal count).
  std::vector<std::size_t> order(t.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
    return (t.q[i] - t.p[i]).norm() < (t.q[j] - t.p[j]).norm();
  });
  const std::size_t first = order.size() / 2;
  const auto n = static_cast<Eigen::Index>(order.size() - first);
  Eigen::MatrixXd x(n, kFeatureDim);
  Eigen::VectorXd fz(n);
  double row[kFeatureDim];
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::size_t k = order[first + static_cast<std::size_t>(i)];
    make_features(FeatureSet::kDisplacementProxyVelocity, t.p[k], t.v[k], t.q[k], row);
    for (int d = 0; d < kFeatureDim; ++d) x(i, d) = row[d];
    fz[i] = t.f[k].z();
  }
  const double weights[3] = {1.0, 3.0, 0.5};
  for (int d = 0; d < kFeatureDim; ++d) {
    const double mean = x.col(d).mean();
    const double sd = std::sqrt((x.col(d).array() - mean).square().mean());
    x.col(d) = (x.col(d).array() - mean) * (weights[d / 3] / (sd > 1e-12 ? sd : 1.0));
  }
  const KMeansResult km = kmeans(x, {.k = m, .max_iterations = 100, .seed = seed});
  Eigen::MatrixXd sel(static_cast<Eigen::Index>(km.selected.size()), kFeatureDim);
  for (Eigen::Index i = 0; i < sel.rows(); ++i)
    sel.row(i) = x.row(km.selected[static_cast<std::size_t>(i)]);
  L1Problem p;
  p.name = "force_model";
  p.a = rbf_matrix(x, sel);
  const Eigen::MatrixXd tail = tail_matrix(x);
  p.f = fz - tail * tail.colPivHouseholderQr().solve(fz);
  normalise_columns(p, 0.001);
  p.name = "force_model";
  return p;
}

}  // namespace inhap::datadriven
