// k-means with k-means++ seeding (see include/inhap/datadriven/kmeans.hpp).
#include "inhap/datadriven/kmeans.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "inhap/core/cancel.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"

namespace inhap::datadriven {

namespace {

constexpr Eigen::Index kBlock = 1024;

// For every row of x: index of and squared distance to the nearest centroid. Also the nearest
// sample of every centroid when `nearest` is non-null.
void assign(const Eigen::MatrixXd& x, const Eigen::VectorXd& xnorm, const Eigen::MatrixXd& c,
            std::vector<int>& label, Eigen::VectorXd& dist2, std::vector<int>* nearest) {
  const Eigen::Index n = x.rows(), k = c.rows();
  const Eigen::VectorXd cnorm = c.rowwise().squaredNorm();
  std::vector<double> best_d(static_cast<std::size_t>(k), std::numeric_limits<double>::infinity());
  if (nearest) nearest->assign(static_cast<std::size_t>(k), 0);
  Eigen::MatrixXd g;
  for (Eigen::Index r0 = 0; r0 < n; r0 += kBlock) {
    const Eigen::Index nb = std::min(kBlock, n - r0);
    g.noalias() = x.middleRows(r0, nb) * c.transpose();  // nb x k
    for (Eigen::Index i = 0; i < nb; ++i) {
      double bd = std::numeric_limits<double>::infinity();
      int bj = 0;
      for (Eigen::Index j = 0; j < k; ++j) {
        const double d = std::max(0.0, xnorm[r0 + i] - 2.0 * g(i, j) + cnorm[j]);
        if (d < bd) {
          bd = d;
          bj = static_cast<int>(j);
        }
        if (nearest && d < best_d[static_cast<std::size_t>(j)]) {
          best_d[static_cast<std::size_t>(j)] = d;
          (*nearest)[static_cast<std::size_t>(j)] = static_cast<int>(r0 + i);
        }
      }
      label[static_cast<std::size_t>(r0 + i)] = bj;
      dist2[r0 + i] = bd;
    }
  }
}

void check_input(const Eigen::MatrixXd& x, int k) {
  if (x.rows() == 0 || x.cols() == 0)
    throw Error("k-means: expected at least one sample, got none");
  if (k < 1) throw Error(fmt::format("k-means: expected k >= 1, got {}", k));
  if (!x.allFinite()) throw Error("k-means: expected finite samples, got NaN or inf");
}

void check_params(const KMeansParams& p) {
  if (!(p.min_moved >= 0 && p.min_moved < 1))
    throw Error(fmt::format("k-means: expected a moved fraction in [0, 1), got {}", p.min_moved));
}

}  // namespace

std::vector<int> kmeanspp_seed(const Eigen::MatrixXd& x, int k, std::uint64_t seed) {
  check_input(x, k);
  const Eigen::Index n = x.rows();
  k = static_cast<int>(std::min<Eigen::Index>(k, n));
  Rng rng(seed);
  std::vector<int> chosen;
  chosen.reserve(static_cast<std::size_t>(k));
  chosen.push_back(static_cast<int>(rng.below(static_cast<std::uint64_t>(n))));
  Eigen::VectorXd d2 = (x.rowwise() - x.row(chosen.back())).rowwise().squaredNorm();
  while (static_cast<int>(chosen.size()) < k) {
    const double total = d2.sum();
    int pick = -1;
    if (total > 0) {
      const double target = rng.uniform() * total;
      double acc = 0;
      for (Eigen::Index i = 0; i < n; ++i) {
        acc += d2[i];
        if (acc > target && d2[i] > 0) {
          pick = static_cast<int>(i);
          break;
        }
      }
      if (pick < 0)  // rounding at the very end of the sum
        for (Eigen::Index i = n - 1; i >= 0 && pick < 0; --i)
          if (d2[i] > 0) pick = static_cast<int>(i);
    }
    if (pick < 0) break;  // fewer distinct points than k
    chosen.push_back(pick);
    d2 = d2.cwiseMin((x.rowwise() - x.row(pick)).rowwise().squaredNorm());
  }
  return chosen;
}

KMeansResult kmeans(const Eigen::MatrixXd& x, const KMeansParams& params) {
  check_input(x, params.k);
  check_params(params);
  const Eigen::Index n = x.rows();
  const std::vector<int> seeds = kmeanspp_seed(x, params.k, params.seed);
  const Eigen::Index k = static_cast<Eigen::Index>(seeds.size());
  KMeansResult res;
  res.centroids.resize(k, x.cols());
  for (Eigen::Index j = 0; j < k; ++j)
    res.centroids.row(j) = x.row(seeds[static_cast<std::size_t>(j)]);
  const Eigen::VectorXd xnorm = x.rowwise().squaredNorm();
  res.assignment.assign(static_cast<std::size_t>(n), -1);
  std::vector<int> label(static_cast<std::size_t>(n), 0);
  Eigen::VectorXd dist2(n);
  Eigen::VectorXd counts(k);
  for (int it = 0; it < params.max_iterations; ++it) {
    check_cancel();
    assign(x, xnorm, res.centroids, label, dist2, nullptr);
    res.iterations = it + 1;
    std::size_t moved = 0;
    for (std::size_t i = 0; i < label.size(); ++i) moved += label[i] != res.assignment[i];
    if (moved == 0 || static_cast<double>(moved) <= params.min_moved * static_cast<double>(n)) {
      res.converged = true;
      break;
    }
    res.assignment = label;
    res.centroids.setZero();
    counts.setZero();
    for (Eigen::Index i = 0; i < n; ++i) {
      const int j = label[static_cast<std::size_t>(i)];
      res.centroids.row(j) += x.row(i);
      counts[j] += 1;
    }
    for (Eigen::Index j = 0; j < k; ++j) {
      if (counts[j] > 0) {
        res.centroids.row(j) /= counts[j];
      } else {  // empty cluster: move it to the sample farthest from its centroid
        Eigen::Index far = 0;
        dist2.maxCoeff(&far);
        res.centroids.row(j) = x.row(far);
        dist2[far] = 0;
      }
    }
  }
  assign(x, xnorm, res.centroids, label, dist2, &res.nearest);
  res.assignment = label;
  res.inertia = dist2.sum();
  std::vector<char> used(static_cast<std::size_t>(n), 0);
  for (int s : res.nearest)
    if (!used[static_cast<std::size_t>(s)]) {
      used[static_cast<std::size_t>(s)] = 1;
      res.selected.push_back(s);
    }
  return res;
}

}  // namespace inhap::datadriven
