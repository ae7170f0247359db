// k-means++ / Lloyd against clusterings whose answer is known.
#include <gtest/gtest.h>

#include <algorithm>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/kmeans.hpp"

namespace inhap::datadriven {
namespace {

TEST(KMeans, OneDimensionalTwoClusters) {
  Eigen::MatrixXd x(4, 1);
  x << 0, 1, 10, 11;
  const KMeansResult r = kmeans(x, {.k = 2, .max_iterations = 50, .seed = 3});
  std::vector<double> c{r.centroids(0, 0), r.centroids(1, 0)};
  std::sort(c.begin(), c.end());
  EXPECT_DOUBLE_EQ(c[0], 0.5);
  EXPECT_DOUBLE_EQ(c[1], 10.5);
  EXPECT_DOUBLE_EQ(r.inertia, 1.0);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.assignment[0], r.assignment[1]);
  EXPECT_NE(r.assignment[1], r.assignment[2]);
}

TEST(KMeans, RecoversWellSeparatedBlobs) {
  const double centres[4][3] = {{5, 5, 0}, {-5, 5, 1}, {5, -5, 2}, {-5, -5, -3}};
  Rng rng(7);
  Eigen::MatrixXd x(800, 3);
  for (int i = 0; i < 800; ++i)
    for (int d = 0; d < 3; ++d) x(i, d) = centres[i % 4][d] + rng.normal(0, 0.1);
  for (std::uint64_t seed : {1u, 2u, 3u, 4u, 5u}) {
    const KMeansResult r = kmeans(x, {.k = 4, .max_iterations = 100, .seed = seed});
    ASSERT_EQ(r.centroids.rows(), 4);
    for (const auto& c : centres) {
      double best = 1e9;
      for (int j = 0; j < 4; ++j)
        best = std::min(best, (r.centroids.row(j) - Eigen::RowVector3d(c[0], c[1], c[2])).norm());
      EXPECT_LT(best, 0.05) << "seed " << seed;
    }
    for (int i = 4; i < 800; ++i)
      EXPECT_EQ(r.assignment[static_cast<std::size_t>(i)],
                r.assignment[static_cast<std::size_t>(i % 4)]);
  }
}

TEST(KMeans, SameSeedSameResultAndNearestSamplesAreNearest) {
  Rng rng(11);
  Eigen::MatrixXd x(500, 5);
  for (int i = 0; i < 500; ++i)
    for (int d = 0; d < 5; ++d) x(i, d) = rng.uniform(-1, 1);
  const KMeansParams prm{.k = 20, .max_iterations = 100, .seed = 9};
  const KMeansResult a = kmeans(x, prm), b = kmeans(x, prm);
  EXPECT_EQ(a.assignment, b.assignment);
  EXPECT_EQ(a.nearest, b.nearest);
  EXPECT_TRUE(a.centroids == b.centroids);
  for (int j = 0; j < 20; ++j) {  // brute force check of the selected rows
    Eigen::Index best = 0;
    (x.rowwise() - a.centroids.row(j)).rowwise().squaredNorm().minCoeff(&best);
    const double d_sel =
        (x.row(a.nearest[static_cast<std::size_t>(j)]) - a.centroids.row(j)).squaredNorm();
    const double d_best = (x.row(best) - a.centroids.row(j)).squaredNorm();
    EXPECT_NEAR(d_sel, d_best, 1e-12);
  }
  // Each centroid is the mean of its members (Lloyd fixed point).
  for (int j = 0; j < 20; ++j) {
    Eigen::RowVectorXd m = Eigen::RowVectorXd::Zero(5);
    int n = 0;
    for (int i = 0; i < 500; ++i)
      if (a.assignment[static_cast<std::size_t>(i)] == j) {
        m += x.row(i);
        ++n;
      }
    ASSERT_GT(n, 0);
    EXPECT_LT((m / n - a.centroids.row(j)).norm(), 1e-9);
  }
}

TEST(KMeans, MoreClustersThanSamplesSelectsEverySample) {
  Eigen::MatrixXd x(5, 2);
  x << 0, 0, 1, 0, 0, 1, 1, 1, 2, 2;
  const KMeansResult r = kmeans(x, {.k = 10, .max_iterations = 10, .seed = 1});
  std::vector<int> sel = r.selected;
  std::sort(sel.begin(), sel.end());
  EXPECT_EQ(sel, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_NEAR(r.inertia, 0.0, 1e-12);
}

TEST(KMeans, RejectsBadInput) {
  EXPECT_THROW(kmeans(Eigen::MatrixXd(0, 3), {}), Error);
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(3, 2);
  x(1, 1) = std::nan("");
  EXPECT_THROW(kmeans(x, {}), Error);
}

}  // namespace
}  // namespace inhap::datadriven
