// Simple baselines a force model must beat on the same data (DESIGN: "real data is the judge"):
// the training mean force, and k-nearest-neighbour regression on the probe position p and on
// (p, tau pdot), both fitted on the training recording's in-contact samples.
//
// Units: positions mm, velocities mm/s, forces N, tau s. The velocity enters the neighbour
// distance as the distance travelled in tau (default 0.1 s), so one mm of position weighs as
// much as 10 mm/s of velocity. k-d tree: nanoflann (Debian libnanoflann-dev, header-only).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap::datadriven {

/// k-nearest-neighbour regression of the force on a point of D = 3 or 6 dimensions: the mean
/// force of the k nearest training points (Euclidean). Immutable after construction.
class KnnForce {
 public:
  /// points: N x D row-major (D = 3 or 6); forces: N. Throws inhap::Error on bad sizes, k < 1 or
  /// no points.
  KnnForce(std::vector<double> points, int dim, std::vector<Vec3> forces, int k);
  ~KnnForce();
  KnnForce(KnnForce&&) noexcept;
  KnnForce& operator=(KnnForce&&) noexcept;
  /// Mean force of the k nearest training points to x (D numbers), N.
  Vec3 predict(const double* x) const;
  int dim() const { return dim_; }
  int k() const { return k_; }

 private:
  struct Tree;
  std::vector<double> points_;
  std::vector<Vec3> forces_;
  int dim_ = 3, k_ = 5;
  std::unique_ptr<Tree> tree_;
};

struct BaselineParams {
  int k = 5;           ///< neighbours
  double tau_s = 0.1;  ///< velocity weight in (p, tau pdot), s
};

/// The three baselines fitted on training samples (p mm, v mm/s, f N; same lengths).
struct Baselines {
  Vec3 mean = Vec3::Zero();  ///< training mean force, N
  KnnForce knn_p, knn_pv;
  BaselineParams params;
};
Baselines fit_baselines(const std::vector<Vec3>& p, const std::vector<Vec3>& v,
                        const std::vector<Vec3>& f, const BaselineParams& params = {});

/// The baselines' forces for test samples (p, v): mean, knn_p, knn_pv in that order.
std::array<std::vector<Vec3>, 3> predict_baselines(const Baselines& b, const std::vector<Vec3>& p,
                                                   const std::vector<Vec3>& v);
/// Names of the baselines in that order ("mean", "knn_p", "knn_pv").
std::array<const char*, 3> baseline_names();

}  // namespace inhap::datadriven
