// Depth-force law and distance to the training support (see fallback.hpp). Units: mm, N.
#include "inhap/datadriven/fallback.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_set>

#include "inhap/core/error.hpp"

namespace inhap::datadriven {

double DepthLaw::force(double d) const {
  if (empty() || !(d > 0) || !std::isfinite(d)) return 0.0;
  const std::size_t n = depth_mm.size();
  if (d >= depth_mm[n - 1]) return force_n[n - 1] + slope_n_per_mm * (d - depth_mm[n - 1]);
  if (d <= depth_mm[0]) return force_n[0] * d / depth_mm[0];  // through (0, 0)
  const auto it = std::upper_bound(depth_mm.begin(), depth_mm.end(), d);
  const auto i = static_cast<std::size_t>(it - depth_mm.begin());
  const double t = (d - depth_mm[i - 1]) / (depth_mm[i] - depth_mm[i - 1]);
  return force_n[i - 1] + t * (force_n[i] - force_n[i - 1]);
}

DepthLaw fit_depth_law(const std::vector<double>& depth_mm, const std::vector<double>& normal_n,
                       int knots) {
  if (depth_mm.size() != normal_n.size())
    throw Error("depth law: expected as many normal forces as depths");
  if (knots < 2) throw Error(fmt::format("depth law: expected at least 2 knots, got {}", knots));
  double dmax = 0;
  std::size_t used = 0;
  for (std::size_t i = 0; i < depth_mm.size(); ++i)
    if (depth_mm[i] > 0 && std::isfinite(depth_mm[i]) && std::isfinite(normal_n[i])) {
      dmax = std::max(dmax, depth_mm[i]);
      ++used;
    }
  DepthLaw law;
  if (used < 20 || !(dmax > 0)) return law;
  // Depth bins of equal width: mean depth, mean force and count of each.
  const auto nb = static_cast<std::size_t>(knots);
  std::vector<double> sd(nb, 0.0), sf(nb, 0.0), w(nb, 0.0);
  for (std::size_t i = 0; i < depth_mm.size(); ++i) {
    if (!(depth_mm[i] > 0) || !std::isfinite(depth_mm[i]) || !std::isfinite(normal_n[i])) continue;
    const auto b = std::min(nb - 1, static_cast<std::size_t>(depth_mm[i] / dmax * knots));
    sd[b] += depth_mm[i], sf[b] += normal_n[i], w[b] += 1;
  }
  // Pool adjacent violators on the non-empty bins (weights = counts): blocks of mean depth,
  // mean force and weight, forces non-decreasing.
  std::vector<double> bd, bf, bw;
  for (std::size_t b = 0; b < nb; ++b) {
    if (w[b] == 0) continue;
    bd.push_back(sd[b]), bf.push_back(sf[b]), bw.push_back(w[b]);
    while (bf.size() > 1 && bf[bf.size() - 2] / bw[bw.size() - 2] > bf.back() / bw.back()) {
      bd[bd.size() - 2] += bd.back(), bf[bf.size() - 2] += bf.back(),
          bw[bw.size() - 2] += bw.back();
      bd.pop_back(), bf.pop_back(), bw.pop_back();
    }
  }
  for (std::size_t k = 0; k < bd.size(); ++k) {
    law.depth_mm.push_back(bd[k] / bw[k]);
    law.force_n.push_back(std::max(0.0, bf[k] / bw[k]));
  }
  if (law.depth_mm.size() < 2) {  // one block: a line through (0, 0)
    const double d = law.depth_mm.empty() ? 1.0 : law.depth_mm[0];
    const double f = law.force_n.empty() ? 0.0 : law.force_n[0];
    law.depth_mm = {0.5 * d, d};
    law.force_n = {0.5 * f, f};
  }
  // Beyond the last knot: the least-squares slope of the deepest quarter of the knots (>= 0).
  const std::size_t n = law.depth_mm.size(),
                    k0 = std::min(n - 2, n - std::max<std::size_t>(2, n / 4));
  double md = 0, mf = 0;
  for (std::size_t k = k0; k < n; ++k) md += law.depth_mm[k], mf += law.force_n[k];
  md /= static_cast<double>(n - k0), mf /= static_cast<double>(n - k0);
  double sxy = 0, sxx = 0;
  for (std::size_t k = k0; k < n; ++k)
    sxy += (law.depth_mm[k] - md) * (law.force_n[k] - mf),
        sxx += (law.depth_mm[k] - md) * (law.depth_mm[k] - md);
  law.slope_n_per_mm = sxx > 0 ? std::max(0.0, sxy / sxx) : 0.0;
  return law;
}

namespace {

std::array<int, 3> voxel(const Vec3& q, double cell) {
  return {static_cast<int>(std::floor(q.x() / cell)), static_cast<int>(std::floor(q.y() / cell)),
          static_cast<int>(std::floor(q.z() / cell))};
}

}  // namespace

SupportDistance make_support_distance(const std::vector<Vec3>& q, double cell_mm) {
  if (!(cell_mm > 0) || !std::isfinite(cell_mm))
    throw Error(fmt::format("support distance: expected a cell > 0 mm, got {}", cell_mm));
  SupportDistance s;
  s.cell_mm = cell_mm;
  std::unordered_set<std::uint64_t> seen;
  for (const Vec3& x : q) {
    if (!x.allFinite() || x.cwiseAbs().maxCoeff() > 1e6) continue;
    const auto v = voxel(x, cell_mm);
    const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(v[0])) << 42) ^
                              (static_cast<std::uint64_t>(static_cast<std::uint32_t>(v[1])) << 21) ^
                              static_cast<std::uint64_t>(static_cast<std::uint32_t>(v[2]));
    if (seen.insert(key).second)  // 0.001 mm: short in a file, the same when read back
      s.points.push_back((x * 1000.0).array().round().matrix() / 1000.0);
  }
  return s;
}

void SupportDistance::build(double reach) {
  reach_mm = reach;
  distance_mm.clear();
  dims = {0, 0, 0};
  if (points.empty()) return;
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& x : points) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double pad = reach + cell_mm;
  origin = lo.array() - pad;
  std::size_t nodes = 1;
  for (int a = 0; a < 3; ++a) {
    dims[static_cast<std::size_t>(a)] =
        static_cast<int>(std::ceil((hi[a] + pad - origin[a]) / cell_mm)) + 1;
    nodes *= static_cast<std::size_t>(dims[static_cast<std::size_t>(a)]);
  }
  if (nodes > 20'000'000)
    throw Error("support distance: the training proxies span too large a grid");
  distance_mm.assign(nodes, static_cast<float>(reach));
  const auto nx = static_cast<std::size_t>(dims[0]);
  const std::size_t nxy = nx * static_cast<std::size_t>(dims[1]);
  auto at = [&](int i, int j, int k) -> float& {
    return distance_mm[static_cast<std::size_t>(i) + nx * static_cast<std::size_t>(j) +
                       nxy * static_cast<std::size_t>(k)];
  };
  // Seeds: the exact distance at the 27 nodes around each point.
  for (const Vec3& x : points) {
    const Vec3 g = (x - origin) / cell_mm;
    const int i0 = static_cast<int>(std::round(g.x())), j0 = static_cast<int>(std::round(g.y())),
              k0 = static_cast<int>(std::round(g.z()));
    for (int i = i0 - 1; i <= i0 + 1; ++i)
      for (int j = j0 - 1; j <= j0 + 1; ++j)
        for (int k = k0 - 1; k <= k0 + 1; ++k) {
          if (i < 0 || j < 0 || k < 0 || i >= dims[0] || j >= dims[1] || k >= dims[2]) continue;
          const Vec3 node = origin + cell_mm * Vec3(i, j, k);
          float& d = at(i, j, k);
          d = std::min(d, static_cast<float>((node - x).norm()));
        }
  }
  // Two-pass 3x3x3 chamfer (weights 1, sqrt 2, sqrt 3 cells): overestimates the Euclidean
  // distance by at most ~8 %, enough for a blend weight.
  const double c1 = cell_mm, c2 = std::sqrt(2.0) * cell_mm, c3 = std::sqrt(3.0) * cell_mm;
  auto relax = [&](int i, int j, int k, int sgn) {
    float& d = at(i, j, k);
    for (int dk = -1; dk <= 0; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          // half of the neighbourhood visited before (i, j, k) in this pass's order
          if (dk == 0 && (dj > 0 || (dj == 0 && di >= 0))) continue;
          const int a = i + sgn * di, b = j + sgn * dj, c = k + sgn * dk;
          if (a < 0 || b < 0 || c < 0 || a >= dims[0] || b >= dims[1] || c >= dims[2]) continue;
          const int m = (di != 0) + (dj != 0) + (dk != 0);
          const double step = m == 1 ? c1 : m == 2 ? c2 : c3;
          d = std::min(d, static_cast<float>(at(a, b, c) + step));
        }
  };
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) relax(i, j, k, 1);
  for (int k = dims[2] - 1; k >= 0; --k)
    for (int j = dims[1] - 1; j >= 0; --j)
      for (int i = dims[0] - 1; i >= 0; --i) relax(i, j, k, -1);
}

double SupportDistance::distance(const Vec3& q) const {
  if (distance_mm.empty() || !q.allFinite()) return reach_mm;
  double t[3];
  std::size_t i0[3];
  for (int a = 0; a < 3; ++a) {
    const int n = dims[static_cast<std::size_t>(a)];
    const double g = (q[a] - origin[a]) / cell_mm;
    if (!(g >= 0) || g > n - 1) return reach_mm;
    const int i = std::min(static_cast<int>(g), std::max(n - 2, 0));
    i0[a] = static_cast<std::size_t>(i);
    t[a] = n > 1 ? g - i : 0.0;
  }
  const auto nx = static_cast<std::size_t>(dims[0]);
  const std::size_t nxy = nx * static_cast<std::size_t>(dims[1]);
  const std::size_t b = i0[0] + nx * i0[1] + nxy * i0[2];
  const std::size_t sx = dims[0] > 1 ? 1 : 0, sy = dims[1] > 1 ? nx : 0, sz = dims[2] > 1 ? nxy : 0;
  auto v = [&](std::size_t o) { return static_cast<double>(distance_mm[b + o]); };
  auto lerp = [](double u, double w, double s) { return u + s * (w - u); };
  const double c00 = lerp(v(0), v(sx), t[0]), c10 = lerp(v(sy), v(sy + sx), t[0]);
  const double c01 = lerp(v(sz), v(sz + sx), t[0]), c11 = lerp(v(sz + sy), v(sz + sy + sx), t[0]);
  return lerp(lerp(c00, c10, t[1]), lerp(c01, c11, t[1]), t[2]);
}

namespace {

// 0 up to lo, 1 from hi on, smoothstep between (0 for a NaN distance).
double smooth_ramp(double d, double lo, double hi) {
  if (!(d > lo)) return 0.0;
  if (d >= hi) return 1.0;
  const double t = (d - lo) / (hi - lo);
  return t * t * (3 - 2 * t);
}

}  // namespace

double Fallback::weight_at(double dist_mm) const {
  return empty() ? 0.0 : smooth_ramp(dist_mm, near_mm, far_mm);
}

double Fallback::normal_weight_at(double dist_mm) const {
  if (empty() || !(normal_far_mm > 0)) return 0.0;
  return smooth_ramp(dist_mm, normal_near_mm, normal_far_mm);
}

bool valid_normal_blend(double near_mm, double far_mm) {
  return (near_mm == 0 && far_mm == 0) ||  // off
         (near_mm >= 0 && far_mm > near_mm && std::isfinite(far_mm));
}

void validate_normal_blend(double near_mm, double far_mm, const std::string& where) {
  if (!valid_normal_blend(near_mm, far_mm))
    throw Error(fmt::format(
        "{}: expected 0 <= normal_near_mm < normal_far_mm (finite; 0 and 0: off), got {} and {}",
        where, near_mm, far_mm));
}

void validate_fallback(const Fallback& f, const std::string& where) {
  if (f.law.depth_mm.empty() && f.support.points.empty()) return;
  const DepthLaw& l = f.law;
  if (l.depth_mm.size() != l.force_n.size() || l.depth_mm.size() < 2)
    throw Error(fmt::format("{}: expected at least 2 depth-law knots with one force each", where));
  for (std::size_t k = 0; k < l.depth_mm.size(); ++k) {
    if (!std::isfinite(l.depth_mm[k]) || !std::isfinite(l.force_n[k]) || !(l.depth_mm[k] > 0) ||
        l.force_n[k] < 0 || (k > 0 && !(l.depth_mm[k] > l.depth_mm[k - 1])) ||
        (k > 0 && l.force_n[k] < l.force_n[k - 1]))
      throw Error(fmt::format(
          "{}: expected depth-law knots with increasing depth > 0 mm and non-decreasing force "
          ">= 0 N (knot {})",
          where, k));
  }
  if (!(l.slope_n_per_mm >= 0) || !std::isfinite(l.slope_n_per_mm))
    throw Error(fmt::format("{}: expected a depth-law slope >= 0 N/mm", where));
  if (!(f.support.cell_mm > 0) || !std::isfinite(f.support.cell_mm) || f.support.points.empty())
    throw Error(fmt::format("{}: expected support points and a cell > 0 mm", where));
  for (const Vec3& x : f.support.points)
    if (!x.allFinite() || x.cwiseAbs().maxCoeff() > 1e6)
      throw Error(fmt::format("{}: expected finite support points within 1e6 mm", where));
  if (!(f.near_mm >= 0) || !(f.far_mm > f.near_mm) || !std::isfinite(f.far_mm))
    throw Error(fmt::format("{}: expected 0 <= near_mm < far_mm (finite), got {} and {}", where,
                            f.near_mm, f.far_mm));
  validate_normal_blend(f.normal_near_mm, f.normal_far_mm, where);
}

}  // namespace inhap::datadriven
