// Outlier removal, jet smoothing and jitter; see include/inhap/surface/points.hpp.
#include "inhap/surface/points.hpp"
#include "inhap/core/stats.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "inhap/core/random.hpp"

namespace inhap {

namespace {

/// Projection of q onto the quadric (jet) fitted in the local PCA frame of the neighbours, with q
/// itself among the fitted points when `with_q`; q itself when singular. The frame is centred on
/// q, so the projected height is the fit's constant term.
Vec3 jet_projection(const Vec3& q, std::span<const std::int32_t> nb, std::span<const Vec3> pts,
                    bool with_q) {
  const std::size_t m = nb.size() + (with_q ? 1 : 0);
  if (m < 6) return q;
  Vec3 centroid = with_q ? q : Vec3::Zero();
  for (auto j : nb) centroid += pts[static_cast<std::size_t>(j)];
  centroid /= static_cast<double>(m);
  Mat3 cov = with_q ? Mat3((q - centroid) * (q - centroid).transpose()) : Mat3::Zero();
  for (auto j : nb) {
    const Vec3 d = pts[static_cast<std::size_t>(j)] - centroid;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);
  const Vec3 e1 = eig.eigenvectors().col(2), e2 = eig.eigenvectors().col(1),
             nrm = eig.eigenvectors().col(0);
  const double scale = std::sqrt(std::max(eig.eigenvalues()[2], 1e-300) / static_cast<double>(m));
  Eigen::Matrix<double, 6, 6> ata = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> atb = Eigen::Matrix<double, 6, 1>::Zero();
  auto add = [&](const Vec3& p) {
    const Vec3 d = (p - q) / scale;
    const double x = d.dot(e1), y = d.dot(e2), z = d.dot(nrm);
    Eigen::Matrix<double, 6, 1> row;
    row << 1, x, y, x * x, x * y, y * y;
    ata.selfadjointView<Eigen::Lower>().rankUpdate(row);
    atb += z * row;
  };
  if (with_q) add(q);
  for (auto j : nb) add(pts[static_cast<std::size_t>(j)]);
  ata = ata.selfadjointView<Eigen::Lower>();
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(ata);
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) return q;
  const Eigen::Matrix<double, 6, 1> c = ldlt.solve(atb);
  if (!c.allFinite()) return q;
  return q + c[0] * scale * nrm;
}

/// Projection of q onto the quadric fitted to q and its neighbours; q itself when singular.
Vec3 project_on_jet(const Vec3& q, std::span<const std::int32_t> nb, std::span<const Vec3> pts) {
  return jet_projection(q, nb, pts, true);
}

/// Projection of q onto the quadric fitted to the neighbours alone; q itself when singular.
Vec3 project_on_jet_of(const Vec3& q, std::span<const std::int32_t> nb, std::span<const Vec3> pts) {
  return jet_projection(q, nb, pts, false);
}

}  // namespace

std::vector<Vec3> project_onto_jets(std::span<const Vec3> points, std::span<const Vec3> queries,
                                    std::size_t k, double max_move,
                                    std::span<const Vec3> directions, double min_cos) {
  std::vector<Vec3> out(queries.begin(), queries.end());
  const bool sided = directions.size() == points.size();
  const KnnTable t = knn_query(points, queries, sided ? 3 * k : k);
  if (t.k < 6) return out;
  std::vector<std::int32_t> nb;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    std::span<const std::int32_t> all =
        std::span<const std::int32_t>(t.index).subspan(i * t.k, t.k);
    if (sided) {
      // The side of the nearest point: only neighbours whose direction is near its direction.
      const Vec3& ref = directions[static_cast<std::size_t>(all[0])];
      nb.clear();
      for (std::size_t j = 0; j < t.k && nb.size() < k; ++j)
        if (directions[static_cast<std::size_t>(all[j])].dot(ref) > min_cos) nb.push_back(all[j]);
      all = nb;
    } else {
      all = all.subspan(0, std::min(all.size(), k));
    }
    const Vec3 p = project_on_jet_of(queries[i], all, points);
    if ((p - queries[i]).norm() <= max_move) out[i] = p;
  }
  return out;
}

std::vector<double> knn_mean_distances(std::span<const Vec3> points, std::size_t k) {
  const KnnTable t = knn_table(points, k);
  std::vector<double> out(points.size(), 0.0);
  if (t.k == 0) return out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    double s = 0;
    for (std::size_t j = 0; j < t.k; ++j) s += t.distance[i * t.k + j];
    out[i] = s / static_cast<double>(t.k);
  }
  return out;
}

std::vector<std::size_t> remove_knn_outliers(std::span<const Vec3> points, std::size_t k,
                                             double sigmas) {
  std::vector<std::size_t> kept;
  const std::vector<double> d = knn_mean_distances(points, k);
  const double med = median(d, 0.0);
  std::vector<double> dev(d.size());
  for (std::size_t i = 0; i < d.size(); ++i) dev[i] = std::abs(d[i] - med);
  const double mad = median(dev, 0.0);
  // A floor on the spread so that a perfectly regular sampling (MAD = 0) keeps its points.
  const double limit = med + sigmas * std::max(1.4826 * mad, 0.05 * med);
  for (std::size_t i = 0; i < d.size(); ++i)
    if (d[i] <= limit) kept.push_back(i);
  return kept;
}

std::vector<Vec3> jet_smooth(std::span<const Vec3> points, std::size_t k) {
  std::vector<Vec3> out(points.begin(), points.end());
  const KnnTable t = knn_table(points, k);
  if (t.k < 5) return out;
  for (std::size_t i = 0; i < points.size(); ++i)
    out[i] = project_on_jet(points[i], std::span<const std::int32_t>(t.index).subspan(i * t.k, t.k),
                            points);
  return out;
}

std::vector<Vec3> jet_smooth(std::span<const Vec3> points, std::size_t k,
                             std::span<const Vec3> directions, double min_cos,
                             double feature_factor) {
  if (directions.size() != points.size()) return jet_smooth(points, k);
  std::vector<Vec3> out(points.begin(), points.end());
  const KnnTable t = knn_table(points, 3 * k);
  if (t.k < 5) return out;
  std::vector<std::vector<std::int32_t>> nbs(points.size());
  std::vector<double> moves(points.size(), 0.0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::vector<std::int32_t>& nb = nbs[i];
    for (std::size_t j = 0; j < t.k && nb.size() < k; ++j) {
      const auto m = t.index[i * t.k + j];
      if (directions[static_cast<std::size_t>(m)].dot(directions[i]) > min_cos) nb.push_back(m);
    }
    out[i] = project_on_jet(points[i], nb, points);
    moves[i] = (out[i] - points[i]).norm();
  }
  if (feature_factor > 0) {
    // A sharp feature (a crest, a corner) inside the neighbourhood: the quadric misfits and
    // moves the point far more than the typical (noise) move. Refit on the nearer half of the
    // neighbours and keep the smaller move.
    const double limit = feature_factor * median(moves, 0.0);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!(moves[i] > limit)) continue;
      const std::size_t half = std::max<std::size_t>(8, k / 2);
      if (nbs[i].size() <= half) continue;
      const Vec3 p =
          project_on_jet(points[i], std::span<const std::int32_t>(nbs[i]).subspan(0, half), points);
      if ((p - points[i]).norm() < moves[i]) out[i] = p;
    }
  }
  return out;
}

std::vector<Vec3> pca_normals(std::span<const Vec3> points, std::size_t k) {
  std::vector<Vec3> out(points.size(), Vec3::UnitZ());
  const KnnTable t = knn_table(points, k);
  if (t.k < 2) return out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    Vec3 c = points[i];
    for (std::size_t j = 0; j < t.k; ++j)
      c += points[static_cast<std::size_t>(t.index[i * t.k + j])];
    c /= static_cast<double>(t.k + 1);
    Mat3 cov = (points[i] - c) * (points[i] - c).transpose();
    for (std::size_t j = 0; j < t.k; ++j) {
      const Vec3 d = points[static_cast<std::size_t>(t.index[i * t.k + j])] - c;
      cov += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);
    out[i] = eig.eigenvectors().col(0).normalized();
  }
  return out;
}

std::vector<Vec3> jitter(std::span<const Vec3> points, double amplitude, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Vec3> out(points.begin(), points.end());
  for (Vec3& p : out)
    for (int c = 0; c < 3; ++c) p[c] += amplitude * (2.0 * rng.uniform() - 1.0);
  return out;
}

}  // namespace inhap
