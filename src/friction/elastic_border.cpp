#include "inhap/friction/elastic_border.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "inhap/core/error.hpp"

namespace inhap::friction {

std::vector<int> weighted_kmeans(std::span<const Vec2> points,
                                 std::span<const double> sample_weight, const Vec2& feature_weight,
                                 std::vector<Vec2>& centers, int max_iterations) {
  const std::size_t n = points.size(), k = centers.size();
  std::vector<int> label(n, -1);
  if (k == 0) return label;
  auto dist = [&](const Vec2& a, const Vec2& b) {
    const Vec2 d = a - b;
    return feature_weight.x() * d.x() * d.x() + feature_weight.y() * d.y() * d.y();
  };
  for (int it = 0; it < max_iterations; ++it) {
    bool changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      int best = 0;
      double bd = std::numeric_limits<double>::infinity();
      for (std::size_t c = 0; c < k; ++c) {
        const double d = dist(points[i], centers[c]);
        if (d < bd) {  // ties go to the lower index: deterministic
          bd = d;
          best = static_cast<int>(c);
        }
      }
      if (label[i] != best) changed = true;
      label[i] = best;
    }
    if (!changed && it > 0) break;
    for (std::size_t c = 0; c < k; ++c) {
      Vec2 sum = Vec2::Zero();
      double w = 0;
      for (std::size_t i = 0; i < n; ++i)
        if (label[i] == static_cast<int>(c)) {
          const double s = sample_weight.empty() ? 1.0 : sample_weight[i];
          sum += s * points[i];
          w += s;
        }
      if (w > 0) centers[c] = sum / w;  // an empty cluster keeps its centre
    }
  }
  return label;
}

namespace {

// Tangential elastic displacement per newton of f_T from the elastic steps (least squares
// through the origin), or from the first step when no step is elastic.
double radius_per_newton(std::span<const BorderStep> s, std::size_t split) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < split; ++i) {
    num += s[i].radius * s[i].f_tangential;
    den += s[i].f_tangential * s[i].f_tangential;
  }
  if (den > 0) return num / den;
  return s[0].f_tangential > 0 ? s[0].radius / s[0].f_tangential : 0.0;
}

// Measured force ratio at the commanded load f: line through the last (up to 3) elastic steps
// with a known ratio (proportional with one), NaN without any.
double ratio_at(std::span<const BorderStep> s, std::size_t split, double f) {
  double sf = 0, sr = 0, sff = 0, sfr = 0, m = 0;
  double f1 = 0, r1 = 0;
  for (std::size_t i = split; i-- > 0 && m < 3;) {
    if (!std::isfinite(s[i].ratio)) continue;
    sf += s[i].f_tangential;
    sr += s[i].ratio;
    sff += s[i].f_tangential * s[i].f_tangential;
    sfr += s[i].f_tangential * s[i].ratio;
    f1 = s[i].f_tangential;
    r1 = s[i].ratio;
    m += 1;
  }
  if (m == 0) return std::numeric_limits<double>::quiet_NaN();
  const double det = m * sff - sf * sf;
  if (m >= 2 && det > 1e-12) {
    const double b = (m * sfr - sf * sr) / det, a = (sr - b * sf) / m;
    return a + b * f;
  }
  return f1 > 0 ? r1 * f / f1 : std::numeric_limits<double>::quiet_NaN();
}

double mean_depth(std::span<const BorderStep> s, std::size_t split) {
  const std::size_t n = split > 0 ? split : s.size();
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) sum += s[i].depth;
  return sum / static_cast<double>(n);
}

}  // namespace

namespace {

// 2-D features: log-compressed (a probe that slid off the object must not squash every other
// step into one corner), divided by their largest value over the sweep (at least that of the
// floor, so a sweep of pure noise is not blown up into two clusters).
std::vector<Vec2> features(std::span<const BorderStep> steps, const BorderOptions& o) {
  std::vector<Vec2> x(steps.size());
  double max_a = std::log1p(1.0), max_b = std::log1p(1.0);
  for (std::size_t i = 0; i < steps.size(); ++i) {
    x[i] = Vec2(std::log1p(std::max(0.0, steps[i].u_short) / o.floor_up),
                std::log1p(std::max(0.0, steps[i].growth()) / o.floor_growth));
    max_a = std::max(max_a, x[i].x());
    max_b = std::max(max_b, x[i].y());
  }
  for (Vec2& v : x) v = Vec2(v.x() / max_a, v.y() / max_b);
  return x;
}

// Index of the first sliding step from the k-means labels (steps.size(): none).
std::size_t border_split(std::span<const BorderStep> steps, const std::vector<int>& labels,
                         const BorderOptions& o) {
  const std::size_t n = steps.size();
  // Monotone split with the fewest disagreements (ties: the later split, since sliding
  // persists at higher loads while a lone noisy step does not).
  std::size_t best = n, best_cost = std::numeric_limits<std::size_t>::max();
  for (std::size_t s = 0; s <= n; ++s) {
    std::size_t cost = 0;
    for (std::size_t i = 0; i < n; ++i) cost += (i < s) == (labels[i] == 1);
    if (cost <= best_cost) {
      best_cost = cost;
      best = s;
    }
  }
  if (best == n) return n;
  // The sliding side must actually grow on the long plateau (or have moved much more).
  double g = 0, up_elastic = 0, up_sliding = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i >= best) g = std::max(g, steps[i].growth());
    double& m = i < best ? up_elastic : up_sliding;
    m = std::max(m, steps[i].u_short);
  }
  if (g < o.min_sliding_growth && !(best > 0 && up_sliding > 3.0 * up_elastic + o.floor_up))
    return n;
  // A step just past the limit creeps only a little, and the 2-means (dominated by the much
  // larger growth of the later steps) puts it with the elastic ones: move every step before the
  // border whose plateau growth is above the noise floor to the sliding side.
  while (best > 0 && steps[best - 1].growth() >= o.min_sliding_growth) --best;
  return best;
}

// Border load in [f_T of the last elastic step, f_T of the first sliding step]: zero of the
// least-squares line growth = a + b f_T through the first sliding steps whose growth is not a
// lower bound (capped by max_slip); with one such step, a line of known slope; else the middle.
double refine_border(std::span<const BorderStep> steps, std::size_t best, const BorderOptions& o,
                     double known_slope, double& slope) {
  const std::size_t n = steps.size();
  const double f_hi = steps[best].f_tangential;
  const double f_lo = best >= 1 ? steps[best - 1].f_tangential : 0.0;
  double f = 0.5 * (f_lo + f_hi);
  slope = 0;
  if (!o.refine) return f;
  double sf = 0, sg = 0, sff = 0, sfg = 0, m = 0;
  std::size_t first = n;
  for (std::size_t i = best; i < n && m < std::max(2, o.refine_points); ++i) {
    if (steps[i].capped) continue;
    if (first == n) first = i;
    sf += steps[i].f_tangential;
    sg += steps[i].growth();
    sff += steps[i].f_tangential * steps[i].f_tangential;
    sfg += steps[i].f_tangential * steps[i].growth();
    m += 1;
  }
  const double det = m * sff - sf * sf;
  if (m >= 2 && det > 0) {
    const double b = (m * sfg - sf * sg) / det, a = (sg - b * sf) / m;
    if (b > 0) {
      slope = b;
      return std::clamp(-a / b, f_lo, f_hi);
    }
  }
  if (known_slope > 0 && first < n)
    f = std::clamp(steps[first].f_tangential - steps[first].growth() / known_slope, f_lo, f_hi);
  return f;
}

}  // namespace

BorderResult find_elastic_border(std::span<const BorderStep> steps, const BorderOptions& o,
                                 double known_slope) {
  const std::size_t n = steps.size();
  if (n == 0) throw Error("elastic border: expected at least one f_T step");
  for (std::size_t i = 1; i < n; ++i)
    if (!(steps[i].f_tangential > steps[i - 1].f_tangential))
      throw Error("elastic border: expected steps ordered by increasing f_T");
  const std::vector<Vec2> x = features(steps, o);
  // Initial centres: the smallest-load step (elastic) and the largest-load step (sliding).
  std::vector<Vec2> centers = {x.front(), x.back()};
  if (n == 1) centers[1] = Vec2(1.0, 1.0);
  BorderResult r;
  r.labels = weighted_kmeans(x, {}, Vec2(o.weight_up, o.weight_growth), centers, o.max_iterations);
  const std::size_t best = border_split(steps, r.labels, o);
  r.split = best;
  if (best == n) {
    r.no_sliding = true;
    r.f_limit_load = steps[n - 1].f_tangential;
  } else {
    r.all_sliding = best == 0;
    r.f_limit_load = refine_border(steps, best, o, known_slope, r.growth_slope);
  }
  r.f_limit = r.f_limit_load;
  r.ratio_limit = ratio_at(steps, best, r.f_limit_load);
  if (std::isfinite(r.ratio_limit) && steps[0].f_normal > 0)
    r.f_limit = r.ratio_limit * steps[0].f_normal;
  r.radius = radius_per_newton(steps, best) * r.f_limit_load;
  r.depth = mean_depth(steps, best);
  return r;
}

}  // namespace inhap::friction
