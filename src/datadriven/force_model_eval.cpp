// The run-time half of the force model (force_model.hpp): the bins' evaluation tables, built
// when a BinModel is constructed, and model_force(), the servo's evaluation. Training is
// force_model.cpp. Units: mm, mm/s, N.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "force_model_priors.hpp"
#include "inhap/core/device.hpp"
#include "inhap/datadriven/force_model.hpp"

namespace inhap::datadriven {

using detail::shear_force;

int ForceModel::bin_of(double key) const {
  // First edge greater than key; edges are few (bins - 1), a linear scan is fastest.
  int b = 0;
  const int ne = static_cast<int>(edges.size());
  while (b < ne && key >= edges[static_cast<std::size_t>(b)]) ++b;
  return b;
}

BinModel::BinModel(std::array<RbfExpansion, 3> axes) : axes_(std::move(axes)) {
  for (const RbfExpansion& e : axes_)  // inconsistent sizes: no table (validate_model says why)
    if (e.centres.cols() != kFeatureDim || e.weights.size() != e.centres.rows()) return;
  std::map<std::vector<double>, Eigen::Index> index;  // exact centre -> union row
  std::vector<std::vector<double>> rows;
  std::vector<std::array<double, 3>> w;
  for (int a = 0; a < 3; ++a) {
    const RbfExpansion& e = axes_[static_cast<std::size_t>(a)];
    for (Eigen::Index j = 0; j < e.centres.rows(); ++j) {
      std::vector<double> c(static_cast<std::size_t>(e.centres.cols()));
      for (Eigen::Index d = 0; d < e.centres.cols(); ++d)
        c[static_cast<std::size_t>(d)] = e.centres(j, d);
      auto [it, added] = index.emplace(c, static_cast<Eigen::Index>(rows.size()));
      if (added) {
        rows.push_back(c);
        w.push_back({0.0, 0.0, 0.0});
      }
      w[static_cast<std::size_t>(it->second)][static_cast<std::size_t>(a)] += e.weights[j];
    }
  }
  const Eigen::Index k = static_cast<Eigen::Index>(rows.size());
  union_centres_.resize(k, kFeatureDim);
  union_weights_.resize(k, 3);
  for (Eigen::Index j = 0; j < k; ++j) {
    for (int d = 0; d < kFeatureDim; ++d)
      union_centres_(j, d) = rows[static_cast<std::size_t>(j)][static_cast<std::size_t>(d)];
    for (int a = 0; a < 3; ++a)
      union_weights_(j, a) = w[static_cast<std::size_t>(j)][static_cast<std::size_t>(a)];
  }
}

namespace {

// sum_j W(j, :) psi(||z - c_j||) over the union table, plus the tails. No allocation.
Vec3 eval_union(const BinModel& bm, const double* z) {
  constexpr Eigen::Index kChunk = 64;
  const Eigen::Index k = bm.union_centres().rows();
  double r3[kChunk];
  Vec3 f = Vec3::Zero();
  for (Eigen::Index j0 = 0; j0 < k; j0 += kChunk) {
    const Eigen::Index nb = std::min(kChunk, k - j0);
    for (Eigen::Index j = 0; j < nb; ++j) r3[j] = 0;
    for (int d = 0; d < kFeatureDim; ++d) {
      const double* col = bm.union_centres().data() + d * k + j0;
      const double zd = z[d];
      for (Eigen::Index j = 0; j < nb; ++j) {
        const double t = zd - col[j];
        r3[j] += t * t;
      }
    }
    for (Eigen::Index j = 0; j < nb; ++j) r3[j] *= std::sqrt(r3[j]);
    for (int a = 0; a < 3; ++a) {
      const double* w = bm.union_weights().data() + a * k + j0;
      double acc = 0;
      for (Eigen::Index j = 0; j < nb; ++j) acc += w[j] * r3[j];
      f[a] += acc;
    }
  }
  for (int a = 0; a < 3; ++a) {
    const Eigen::VectorXd& t = bm.axes()[static_cast<std::size_t>(a)].tail;
    if (t.size() != kFeatureDim + 1) continue;
    double acc = t[0];
    for (int d = 0; d < kFeatureDim; ++d) acc += t[d + 1] * z[d];
    f[a] += acc;
  }
  return f;
}

}  // namespace

Vec3 model_force(const ForceModel& model, const Vec3& p, const Vec3& v, const Vec3& q) {
  return model_force(model, p, v, q, Vec3::UnitZ());
}

namespace {

/// Force of one bin in world axes (unclamped magnitude).
Vec3 bin_force(const ForceModel& model, const BinModel& bm, const Vec3& p, const Vec3& v,
               const Vec3& q, const SurfaceFrame& fr) {
  double z[kFeatureDim];
  make_features(model.features, p, v, q, fr, z);
  for (int d = 0; d < kFeatureDim; ++d) {
    const auto ud = static_cast<std::size_t>(d);
    z[d] = std::clamp((z[d] - bm.offset[ud]) / bm.scale[ud], bm.box_min[ud], bm.box_max[ud]);
  }
  const Vec3 f = eval_union(bm, z);
  return model.features == FeatureSet::kLocalFrame ? fr.to_world(f) : f;
}

// A sliding proxy: the tangential force is at least mu_s f_n (within the friction cone), along the
// proxy's tangential lag.
Vec3 sliding_floor(const ForceModel& m, const Vec3& f, const Vec3& p, const Vec3& q,
                   const Vec3& n) {
  const double fn = n.dot(f);
  const Vec3 ut = -detail::tangential_displacement(p, q, n);  // the proxy's lag q - p
  const double len = ut.norm();
  if (!(fn > 0) || !(len > kSlidingStepMm)) return f;
  double floor = m.sliding_mu * fn;
  if (m.friction_cone > 0) floor = std::min(floor, m.friction_cone * fn);  // never past the cone
  return fn * n + std::max((f - fn * n).norm(), floor) / len * ut;
}

// The RBF expansions' force at (p, v, q) in world axes: the bin of ||q - p||, blended with the
// neighbouring bin within bin_blend of an edge (weight of the upper bin
// smoothstep((key - e + w) / 2w)), so the force is continuous across the edge.
Vec3 rbf_force(const ForceModel& model, const Vec3& p, const Vec3& v, const Vec3& q,
               const SurfaceFrame& fr) {
  const double key = (q - p).norm();
  const auto b = static_cast<std::size_t>(model.bin_of(key));
  Vec3 f = bin_force(model, model.bins[b], p, v, q, fr);
  const double w = model.bin_blend;
  if (w > 0) {
    const std::size_t ne = model.edges.size();
    std::size_t lo = b;  // edge index e_k separates bins k and k + 1
    double t = -1;
    if (b < ne && model.edges[b] - key < w) {
      lo = b;
      t = (key - model.edges[b] + w) / (2 * w);
    } else if (b > 0 && key - model.edges[b - 1] < w) {
      lo = b - 1;
      t = (key - model.edges[b - 1] + w) / (2 * w);
    }
    if (t >= 0) {
      t = std::clamp(t, 0.0, 1.0);
      const double s = t * t * (3 - 2 * t);
      const Vec3 other = bin_force(model, model.bins[lo == b ? b + 1 : b - 1], p, v, q, fr);
      f = lo == b ? Vec3((1 - s) * f + s * other) : Vec3((1 - s) * other + s * f);
    }
  }
  return f;
}

}  // namespace

Vec3 model_force(const ForceModel& model, const Vec3& p, const Vec3& v, const Vec3& q,
                 const Vec3& normal, double slip_mm_s) {
  if (!p.allFinite() || !v.allFinite() || !q.allFinite() || model.bins.empty()) return Vec3::Zero();
  const double key = (q - p).norm();
  const SurfaceFrame fr =
      model.features == FeatureSet::kLocalFrame ? surface_frame(normal) : SurfaceFrame{};
  Vec3 f = rbf_force(model, p, v, q, fr);
  const double depth = fr.n.dot(q - p);
  const double dist = model.fallback.empty() ? 0.0 : model.fallback.support.distance(q);
  // Off the training spots: the normal force of the probe on the proxy's normal line at the same
  // depth (fallback.hpp), the tangential displacement's effect not extrapolated.
  if (const double wn = model.fallback.normal_weight_at(dist); wn > 0) {
    const double fn_line = fr.n.dot(rbf_force(model, q - depth * fr.n, v, q, fr));
    f += wn * (fn_line - fr.n.dot(f)) * fr.n;
  }
  if (!model.prior.empty()) f += model.prior.normal_force(q, depth) * fr.n;
  if (!model.shear.empty()) f += shear_force(model.shear, p, q, fr.n);
  if (!model.fallback.empty()) {  // far from the training proxies: the data's own law
    const double wl = model.fallback.weight_at(dist);
    if (wl > 0) {
      Vec3 law = model.fallback.law.force(depth) * detail::fallback_scale(model.prior, q) * fr.n;
      if (!model.shear.empty()) law += shear_force(model.shear, p, q, fr.n);
      f = (1 - wl) * f + wl * law;
    }
  }
  if (model.friction_cone > 0) {  // keep the force inside the friction cone seen in training
    const double fn = fr.n.dot(f);
    const Vec3 ft = f - fn * fr.n;
    const double lim = model.friction_cone * std::max(fn, kConeFloorN), len = ft.norm();
    if (len > lim) f = fn * fr.n + ft * (lim / len);
  }
  if (slip_mm_s > 0 && model.sliding_mu > 0) f = sliding_floor(model, f, p, q, fr.n);
  if (!f.allFinite()) return Vec3::Zero();
  // The device profile's limit caps the model's: a model struct built in code cannot raise it;
  // the training data's envelope near this state caps it further.
  const double limit =
      std::min(effective_force_limit(model.force_limit_n), model.envelope.limit(q, key));
  const double mag = f.norm();
  if (mag > limit) f *= limit / mag;
  return f;
}

}  // namespace inhap::datadriven
