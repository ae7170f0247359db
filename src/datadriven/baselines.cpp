// Mean and k-nearest-neighbour force baselines (see baselines.hpp). Units: mm, mm/s, N, s.
#include "inhap/datadriven/baselines.hpp"

#include <fmt/format.h>

#include <nanoflann.hpp>

#include "inhap/core/error.hpp"

namespace inhap::datadriven {

namespace {
// nanoflann's dataset interface over N x D row-major points.
struct Points {
  std::vector<double> x;
  std::size_t dim = 3;
  std::size_t kdtree_get_point_count() const { return x.size() / dim; }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return x[i * dim + d]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Points>,
                                                  Points, -1, std::uint32_t>;
}  // namespace

struct KnnForce::Tree {
  Points points;
  Index index;
  Tree(std::vector<double> x, int dim)
      : points{std::move(x), static_cast<std::size_t>(dim)},
        index(dim, points, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {}
};

KnnForce::KnnForce(std::vector<double> points, int dim, std::vector<Vec3> forces, int k)
    : forces_(std::move(forces)), dim_(dim), k_(k) {
  if (dim != 3 && dim != 6)
    throw Error(fmt::format("k-nearest neighbours: expected 3 or 6 dimensions, got {}", dim));
  if (k < 1) throw Error(fmt::format("k-nearest neighbours: expected k >= 1, got {}", k));
  if (forces_.empty() || points.size() != forces_.size() * static_cast<std::size_t>(dim))
    throw Error(
        fmt::format("k-nearest neighbours: expected {} x {} coordinates for {} forces, got {}",
                    forces_.size(), dim, forces_.size(), points.size()));
  if (forces_.size() > 0xffffffffu) throw Error("k-nearest neighbours: too many training points");
  tree_ = std::make_unique<Tree>(std::move(points), dim);
}

KnnForce::~KnnForce() = default;
KnnForce::KnnForce(KnnForce&&) noexcept = default;
KnnForce& KnnForce::operator=(KnnForce&&) noexcept = default;

Vec3 KnnForce::predict(const double* x) const {
  std::vector<std::uint32_t> idx(static_cast<std::size_t>(k_));
  std::vector<double> d2(static_cast<std::size_t>(k_));
  const std::size_t n =
      tree_->index.knnSearch(x, static_cast<std::size_t>(k_), idx.data(), d2.data());
  Vec3 f = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) f += forces_[idx[i]];
  return n ? Vec3(f / static_cast<double>(n)) : f;
}

namespace {
std::vector<double> rows(const std::vector<Vec3>& p, const std::vector<Vec3>* v, double tau) {
  std::vector<double> x;
  x.reserve(p.size() * (v ? 6 : 3));
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (int a = 0; a < 3; ++a) x.push_back(p[i][a]);
    if (v)
      for (int a = 0; a < 3; ++a) x.push_back(tau * (*v)[i][a]);
  }
  return x;
}
}  // namespace

Baselines fit_baselines(const std::vector<Vec3>& p, const std::vector<Vec3>& v,
                        const std::vector<Vec3>& f, const BaselineParams& params) {
  if (p.empty() || p.size() != v.size() || p.size() != f.size())
    throw Error(
        fmt::format("baselines: expected as many positions, velocities and forces (at least "
                    "one), got {}, {} and {}",
                    p.size(), v.size(), f.size()));
  Vec3 mean = Vec3::Zero();
  for (const Vec3& x : f) mean += x;
  mean /= static_cast<double>(f.size());
  return Baselines{mean, KnnForce(rows(p, nullptr, 0), 3, f, params.k),
                   KnnForce(rows(p, &v, params.tau_s), 6, f, params.k), params};
}

std::array<std::vector<Vec3>, 3> predict_baselines(const Baselines& b, const std::vector<Vec3>& p,
                                                   const std::vector<Vec3>& v) {
  std::array<std::vector<Vec3>, 3> out;
  for (auto& o : out) o.reserve(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double x[6] = {p[i].x(),
                         p[i].y(),
                         p[i].z(),
                         b.params.tau_s * v[i].x(),
                         b.params.tau_s * v[i].y(),
                         b.params.tau_s * v[i].z()};
    out[0].push_back(b.mean);
    out[1].push_back(b.knn_p.predict(x));
    out[2].push_back(b.knn_pv.predict(x));
  }
  return out;
}

std::array<const char*, 3> baseline_names() {
  return {"mean", "knn_p", "knn_pv"};
}

}  // namespace inhap::datadriven
