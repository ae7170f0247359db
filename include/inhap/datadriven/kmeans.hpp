// k-means clustering with k-means++ seeding (Arthur and Vassilvitskii 2007), used for the
// "random selection" of RBF rows in thesis sec. 4.4.2: the recorded sample nearest each
// centroid becomes a selected row.
//
// Units: whatever the rows are in (the force model passes normalised, dimensionless features).
// Deterministic: same data, k and seed give the same result (inhap::Rng, fixed block order).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace inhap::datadriven {

struct KMeansParams {
  int k = 300;               ///< number of clusters (clamped to the number of samples)
  int max_iterations = 100;  ///< Lloyd iterations at most
  std::uint64_t seed = 1;    ///< seed of the k-means++ draws
  /// Stop when an iteration moves at most this fraction of the samples to another cluster
  /// (0: only when none moves). The selected rows (samples nearest the centroids) hardly change
  /// in the long tail of Lloyd iterations that move a handful of samples each.
  double min_moved = 0;
};

struct KMeansResult {
  Eigen::MatrixXd centroids;    ///< k x D
  std::vector<int> assignment;  ///< cluster of each sample (N)
  std::vector<int> nearest;     ///< for each centroid, the index of the nearest sample
  std::vector<int> selected;    ///< `nearest` with duplicates removed, in centroid order
  double inertia = 0;           ///< sum of squared distances to the assigned centroids
  int iterations = 0;           ///< Lloyd iterations run
  bool converged = false;       ///< at most min_moved of the samples moved before max_iterations
};

/// Clusters the rows of `x` (N x D). Throws inhap::Error when x is empty, k < 1 or x has a
/// non-finite entry.
KMeansResult kmeans(const Eigen::MatrixXd& x, const KMeansParams& params);

/// k-means++ seeding alone: indices of the k rows chosen as initial centres.
std::vector<int> kmeanspp_seed(const Eigen::MatrixXd& x, int k, std::uint64_t seed);

}  // namespace inhap::datadriven
