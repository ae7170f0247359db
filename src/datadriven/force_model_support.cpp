// Where an input lies relative to a force model's training data (see force_model.hpp).
// Units: mm, mm/s; excess and distances in normalised feature units.
#include <algorithm>
#include <cmath>
#include <limits>

#include "inhap/datadriven/force_model.hpp"

namespace inhap::datadriven {

SupportCheck support_check(const ForceModel& model, double box_margin, const Vec3& p, const Vec3& v,
                           const Vec3& q, const Vec3& normal) {
  SupportCheck out;
  if (!p.allFinite() || !v.allFinite() || !q.allFinite() || model.bins.empty()) return out;
  out.bin = model.bin_of((q - p).norm());
  const BinModel& bm = model.bins[static_cast<std::size_t>(out.bin)];
  const SurfaceFrame fr =
      model.features == FeatureSet::kLocalFrame ? surface_frame(normal) : SurfaceFrame{};
  double z[kFeatureDim];
  make_features(model.features, p, v, q, fr, z);
  // The box is the training range [lo, hi] widened by margin * (hi - lo) on both sides.
  const double m = box_margin;
  for (int d = 0; d < kFeatureDim; ++d) {
    const auto ud = static_cast<std::size_t>(d);
    z[d] = (z[d] - bm.offset[ud]) / bm.scale[ud];
    const double range = (bm.box_max[ud] - bm.box_min[ud]) / (1 + 2 * m);
    const double lo = bm.box_min[ud] + m * range, hi = bm.box_max[ud] - m * range;
    const double e = std::max({lo - z[d], z[d] - hi, 0.0}) / std::max(range, 1e-12);
    out.excess[ud / 3] = std::max(out.excess[ud / 3], e);
  }
  double best = std::numeric_limits<double>::infinity();
  const Eigen::Index k = bm.union_centres().rows();
  for (Eigen::Index j = 0; j < k; ++j) {
    double r2 = 0;
    for (int d = 0; d < kFeatureDim; ++d)
      r2 += (z[d] - bm.union_centres()(j, d)) * (z[d] - bm.union_centres()(j, d));
    best = std::min(best, r2);
  }
  out.nearest = std::sqrt(best);
  return out;
}

}  // namespace inhap::datadriven
