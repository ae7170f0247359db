// Two-segment knee fit; see include/inhap/contact/knee.hpp and docs/shape-modeling.md.
#include "inhap/contact/knee.hpp"

#include <cmath>
#include <limits>

namespace inhap {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Sums over one segment in scaled time s in [0, 1] and mean-free force h.
struct Sums {
  double n = 0, s = 0, ss = 0, h = 0, hs = 0;
  void add(double si, double hi) {
    n += 1;
    s += si;
    ss += si * si;
    h += hi;
    hs += hi * si;
  }
  Sums minus(const Sums& o) const { return {n - o.n, s - o.s, ss - o.ss, h - o.h, hs - o.hs}; }
};

/// Minimises over G for a knee at scaled time c in (0, 1), segment 1 = samples with s <= c
/// (sums `a`), segment 2 = the rest (sums `b`). Returns -B^T G (the SSE minus sum h^2), or
/// +inf when the normal equations are singular; writes G when asked.
double reduced_sse(double c, const Sums& a, const Sums& b, Vec3* g) {
  if (!(c > 0.0 && c < 1.0)) return kInf;
  const double ic = 1.0 / c, id = 1.0 / (1.0 - c);
  const double ic2 = ic * ic, id2 = id * id;
  // Segment 1: basis (c - s)/c and s/c. Segment 2: (1 - s)/(1 - c) and (s - c)/(1 - c).
  const double a11 = (c * c * a.n - 2 * c * a.s + a.ss) * ic2;
  const double a12 = (c * a.s - a.ss) * ic2;
  const double a22 = a.ss * ic2 + (b.n - 2 * b.s + b.ss) * id2;
  const double a23 = (-c * b.n + (1 + c) * b.s - b.ss) * id2;
  const double a33 = (b.ss - 2 * c * b.s + c * c * b.n) * id2;
  const double b1 = (c * a.h - a.hs) * ic;
  const double b2 = a.hs * ic + (b.h - b.hs) * id;
  const double b3 = (b.hs - c * b.h) * id;
  // Adjugate of the symmetric tridiagonal A.
  const double c11 = a22 * a33 - a23 * a23, c12 = -a12 * a33, c13 = a12 * a23;
  const double c22 = a11 * a33, c23 = -a11 * a23, c33 = a11 * a22 - a12 * a12;
  const double det = a11 * c11 + a12 * c12;
  if (!(det > 1e-12 * std::abs(a11 * a22 * a33))) return kInf;
  const double g1 = (c11 * b1 + c12 * b2 + c13 * b3) / det;
  const double g2 = (c12 * b1 + c22 * b2 + c23 * b3) / det;
  const double g3 = (c13 * b1 + c23 * b2 + c33 * b3) / det;
  if (g) *g = Vec3(g1, g2, g3);
  return -(b1 * g1 + b2 * g2 + b3 * g3);
}

struct Prepared {
  bool ok = false;
  double t0 = 0, span = 1, mean = 0, sum_h2 = 0;
  Sums total;
};

Prepared prepare(std::span<const double> t, std::span<const double> f) {
  Prepared p;
  const std::size_t n = t.size();
  if (n < 4 || f.size() != n) return p;
  double mean = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(t[i]) || !std::isfinite(f[i])) return p;
    if (i > 0 && !(t[i] > t[i - 1])) return p;
    mean += f[i];
  }
  p.t0 = t[0];
  p.span = t[n - 1] - t[0];
  p.mean = mean / static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double h = f[i] - p.mean;
    p.total.add((t[i] - p.t0) / p.span, h);
    p.sum_h2 += h * h;
  }
  p.ok = true;
  return p;
}

/// Golden-section search of reduced_sse on [lo, hi] with a fixed partition.
double golden(double lo, double hi, const Sums& a, const Sums& b, double& best_c) {
  constexpr double r = 0.6180339887498949;
  double x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo);
  double e1 = reduced_sse(x1, a, b, nullptr), e2 = reduced_sse(x2, a, b, nullptr);
  for (int it = 0; it < 48 && hi - lo > 1e-12; ++it) {
    if (e1 <= e2) {
      hi = x2;
      x2 = x1;
      e2 = e1;
      x1 = hi - r * (hi - lo);
      e1 = reduced_sse(x1, a, b, nullptr);
    } else {
      lo = x1;
      x1 = x2;
      e1 = e2;
      x2 = lo + r * (hi - lo);
      e2 = reduced_sse(x2, a, b, nullptr);
    }
  }
  best_c = e1 <= e2 ? x1 : x2;
  return std::min(e1, e2);
}

}  // namespace

KneeFit fit_knee(std::span<const double> t, std::span<const double> f, const KneeOptions& options) {
  KneeFit fit;
  const Prepared p = prepare(t, f);
  if (!p.ok) return fit;
  const std::size_t n = t.size();
  auto s_of = [&](std::size_t i) { return (t[i] - p.t0) / p.span; };

  // Exact minimum over the sample times: knee at s_k, segment 1 = samples 0..k.
  Sums seg1;
  seg1.add(0.0, f[0] - p.mean);
  double best = kInf, best_c = 0;
  std::size_t best_k = 0;
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double sk = s_of(k);
    seg1.add(sk, f[k] - p.mean);
    const double e = reduced_sse(sk, seg1, p.total.minus(seg1), nullptr);
    if (e < best) {
      best = e;
      best_c = sk;
      best_k = k;
    }
  }
  if (!(best < kInf)) return fit;

  if (options.refine) {
    // Partition P_j (segment 1 = samples 0..j) is exact for c in [s_j, s_{j+1}].
    auto sums_upto = [&](std::size_t j) {
      Sums a;
      for (std::size_t i = 0; i <= j; ++i) a.add(s_of(i), f[i] - p.mean);
      return a;
    };
    for (std::size_t j : {best_k - 1, best_k}) {
      const Sums a = sums_upto(j);
      double c = 0;
      const double e = golden(s_of(j), s_of(j + 1), a, p.total.minus(a), c);
      if (e < best) {
        best = e;
        best_c = c;
      }
    }
  }

  fit.tc = p.t0 + best_c * p.span;
  std::size_t idx = best_k;
  while (idx > 0 && t[idx] > fit.tc) --idx;
  while (idx + 2 < n && t[idx + 1] <= fit.tc) ++idx;
  fit.index = idx;
  Vec3 g;
  fit.sse = knee_sse_at(t, f, fit.tc, &g);
  fit.g0 = g[0];
  fit.gc = g[1];
  fit.gd = g[2];
  fit.valid = std::isfinite(fit.sse);
  return fit;
}

double knee_sse_at(std::span<const double> t, std::span<const double> f, double tc, Vec3* g) {
  const Prepared p = prepare(t, f);
  if (!p.ok) return kInf;
  const double c = (tc - p.t0) / p.span;
  Sums a;
  for (std::size_t i = 0; i < t.size() && (t[i] - p.t0) / p.span <= c; ++i)
    a.add((t[i] - p.t0) / p.span, f[i] - p.mean);
  Vec3 gl;
  const double e = reduced_sse(c, a, p.total.minus(a), &gl);
  if (!(e < kInf)) return kInf;
  if (g) *g = gl + Vec3::Constant(p.mean);
  return std::max(0.0, p.sum_h2 + e);
}

}  // namespace inhap
