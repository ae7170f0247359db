// Local stiffness prior f_n ~ k(q) d^alpha: backfitting of a smoothed ln k map and one exponent
// (see stiffness_prior.hpp). Units: mm, N.
#include "inhap/datadriven/stiffness_prior.hpp"

#include <fmt/format.h>
#include <Eigen/Dense>

#include <algorithm>
#include <limits>

#include "inhap/core/error.hpp"

namespace inhap::datadriven {

void StiffnessPriorParams::validate() const {
  if (!(cell > 0) || !std::isfinite(cell))
    throw Error(fmt::format("stiffness map: expected a cell > 0 mm, got {}", cell));
  if (!(sigma > 0) || !std::isfinite(sigma))
    throw Error(fmt::format("stiffness map: expected a smoothing radius > 0 mm, got {}", sigma));
  if (!(min_depth > 0) || !(min_force > 0))
    throw Error("stiffness map: expected a minimum depth and force > 0");
  if (!(prior_weight > 0))
    throw Error(fmt::format("stiffness map: expected a prior weight > 0, got {}", prior_weight));
  if (iterations < 1) throw Error(fmt::format("stiffness map: expected >= 1 iterations"));
}

namespace {

// Separable Gaussian blur (truncated at 3 sigma, zero outside the grid) of a grid, in place.
void blur(std::vector<double>& g, const std::array<int, 3>& dims, double sigma_cells) {
  const int r = std::max(1, static_cast<int>(std::ceil(3 * sigma_cells)));
  std::vector<double> w(static_cast<std::size_t>(2 * r + 1));
  for (int k = -r; k <= r; ++k)
    w[static_cast<std::size_t>(k + r)] = std::exp(-0.5 * k * k / (sigma_cells * sigma_cells));
  const std::array<std::size_t, 3> stride{
      1, static_cast<std::size_t>(dims[0]),
      static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1])};
  std::vector<double> line, out;
  for (int a = 0; a < 3; ++a) {
    const int n = dims[static_cast<std::size_t>(a)];
    if (n < 2) continue;
    const std::size_t s = stride[static_cast<std::size_t>(a)];
    line.resize(static_cast<std::size_t>(n));
    out.resize(static_cast<std::size_t>(n));
    for (std::size_t base = 0; base < g.size(); ++base) {
      // base runs over nodes whose index along axis a is 0
      if ((base / s) % static_cast<std::size_t>(n) != 0) continue;
      for (int i = 0; i < n; ++i)
        line[static_cast<std::size_t>(i)] = g[base + s * static_cast<std::size_t>(i)];
      for (int i = 0; i < n; ++i) {
        double acc = 0;
        for (int k = std::max(-r, -i); k <= std::min(r, n - 1 - i); ++k)
          acc += w[static_cast<std::size_t>(k + r)] * line[static_cast<std::size_t>(i + k)];
        out[static_cast<std::size_t>(i)] = acc;
      }
      for (int i = 0; i < n; ++i)
        g[base + s * static_cast<std::size_t>(i)] = out[static_cast<std::size_t>(i)];
    }
  }
}

// The 8 nodes around q (clamped into the grid) and their trilinear weights; returns how many
// (nodes along a single-node axis are skipped).
int trilinear(const StiffnessPrior& m, const Vec3& q, std::size_t idx[8], double wt[8]) {
  double t[3];
  std::size_t i0[3];
  for (int a = 0; a < 3; ++a) {
    const int n = m.dims[static_cast<std::size_t>(a)];
    double g = std::clamp((q[a] - m.origin[a]) / m.cell, 0.0, static_cast<double>(n - 1));
    int i = std::min(static_cast<int>(g), std::max(n - 2, 0));
    i0[a] = static_cast<std::size_t>(i);
    t[a] = n > 1 ? g - i : 0.0;
  }
  const auto nx = static_cast<std::size_t>(m.dims[0]);
  const std::size_t nxy = nx * static_cast<std::size_t>(m.dims[1]);
  int k = 0;
  for (int c = 0; c < 8; ++c) {
    double w = 1;
    std::size_t id = 0;
    bool ok = true;
    for (int a = 0; a < 3; ++a) {
      const int bit = (c >> a) & 1;
      if (bit && m.dims[static_cast<std::size_t>(a)] < 2) ok = false;
      w *= bit ? t[a] : 1 - t[a];
      id += (i0[a] + static_cast<std::size_t>(bit)) * (a == 0 ? 1 : a == 1 ? nx : nxy);
    }
    if (!ok || w == 0) continue;
    idx[k] = id;
    wt[k++] = w;
  }
  return k;
}

// Trilinear splat of value v (weight 1) at q into sum / count.
void splat(const StiffnessPrior& m, const Vec3& q, double v, std::vector<double>& sum,
           std::vector<double>& count) {
  std::size_t idx[8];
  double wt[8];
  const int k = trilinear(m, q, idx, wt);
  for (int c = 0; c < k; ++c) {
    sum[idx[c]] += wt[c] * v;
    count[idx[c]] += wt[c];
  }
}

// Gaussian-weighted local-linear fit (radius sigma_mm) of values v_i over q at every node,
// shrunk towards to[j] with the weight of prior_weight samples: where the data lie on one side
// of a node (a gap at the rim of the explored region) the value follows their trend instead of
// their mean. The slope is ridge-regularised (so a direction the data do not span, e.g. z on a
// flat object, keeps the local mean) and the result is clamped to the range of v widened by half
// its span.
void smooth_linear(const StiffnessPrior& m, const std::vector<Vec3>& qs,
                   const std::vector<double>& v, double sigma_mm, double prior_weight,
                   const std::vector<double>& to, std::vector<double>& out) {
  // Moments about the grid's centre: 1, x (3), x x^T (6), v, v x (3).
  constexpr int kMoments = 14;
  const std::size_t nodes = to.size();
  const Vec3 centre =
      m.origin + 0.5 * m.cell * Vec3(m.dims[0] - 1.0, m.dims[1] - 1.0, m.dims[2] - 1.0);
  std::vector<std::vector<double>> g(kMoments, std::vector<double>(nodes, 0.0));
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < qs.size(); ++i) {
    const Vec3 x = qs[i] - centre;
    const double mom[kMoments] = {1,
                                  x.x(),
                                  x.y(),
                                  x.z(),
                                  x.x() * x.x(),
                                  x.x() * x.y(),
                                  x.x() * x.z(),
                                  x.y() * x.y(),
                                  x.y() * x.z(),
                                  x.z() * x.z(),
                                  v[i],
                                  v[i] * x.x(),
                                  v[i] * x.y(),
                                  v[i] * x.z()};
    std::size_t idx[8];
    double wt[8];
    const int k = trilinear(m, qs[i], idx, wt);
    for (int c = 0; c < k; ++c)
      for (int a = 0; a < kMoments; ++a) g[static_cast<std::size_t>(a)][idx[c]] += wt[c] * mom[a];
    lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
  }
  const double margin = 0.5 * (hi - lo);  // how far beyond the data's range a trend may go
  for (auto& grid : g) blur(grid, m.dims, sigma_mm / m.cell);
  out.resize(nodes);
  const auto nx = static_cast<std::size_t>(m.dims[0]), ny = static_cast<std::size_t>(m.dims[1]);
  for (std::size_t j = 0; j < nodes; ++j) {
    const Vec3 node =
        m.origin + m.cell * Vec3(static_cast<double>(j % nx), static_cast<double>((j / nx) % ny),
                                 static_cast<double>(j / (nx * ny)));
    const Vec3 c = node - centre;
    auto at = [&](int a) { return g[static_cast<std::size_t>(a)][j]; };
    // Moments about the node: S0, S1 = sum w (x - c), S2 = sum w (x - c)(x - c)^T, T0, T1.
    const double s0 = at(0);
    const Vec3 m1(at(1), at(2), at(3));
    Eigen::Matrix3d m2;
    m2 << at(4), at(5), at(6), at(5), at(7), at(8), at(6), at(8), at(9);
    const Vec3 s1 = m1 - s0 * c;
    const Eigen::Matrix3d s2 =
        m2 - m1 * c.transpose() - c * m1.transpose() + s0 * c * c.transpose();
    const double t0 = at(10);
    const Vec3 t1 = Vec3(at(11), at(12), at(13)) - t0 * c;
    Eigen::Matrix4d a;
    Eigen::Vector4d b;
    a(0, 0) = s0 + prior_weight;
    a.block<1, 3>(0, 1) = s1.transpose();
    a.block<3, 1>(1, 0) = s1;
    // Ridge on the slope, small against the spread of the data a node sees even through the
    // kernel's tail ((sigma / 7)^2 per sample; at a rim the data within reach lie in a strip).
    a.block<3, 3>(1, 1) =
        s2 + Eigen::Matrix3d::Identity() * (0.02 * (s0 + prior_weight) * sigma_mm * sigma_mm);
    b(0) = t0 + prior_weight * to[j];
    b.tail<3>() = t1;
    const double value = a.ldlt().solve(b)(0);
    out[j] = std::isfinite(value) ? std::clamp(value, lo - margin, hi + margin) : to[j];
  }
}

// Grid over the samples' bounding box padded by 2 sigma, coarser cells if it would exceed
// 500,000 nodes: sets origin, cell and dims, and sizes log_k.
void place_grid(const std::vector<Vec3>& qs, const StiffnessPriorParams& prm, StiffnessPrior& m) {
  Vec3 lo = qs[0], hi = qs[0];
  for (const Vec3& x : qs) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  lo.array() -= 2 * prm.sigma;
  hi.array() += 2 * prm.sigma;
  m.cell = prm.cell;
  auto count_nodes = [&] {
    std::size_t total = 1;
    for (int a = 0; a < 3; ++a) {
      m.dims[static_cast<std::size_t>(a)] =
          static_cast<int>(std::ceil((hi[a] - lo[a]) / m.cell)) + 1;
      total *= static_cast<std::size_t>(m.dims[static_cast<std::size_t>(a)]);
    }
    return total;
  };
  while (count_nodes() > 500'000) m.cell *= 1.25;
  m.origin = lo;
  m.log_k.assign(static_cast<std::size_t>(m.dims[0]) * static_cast<std::size_t>(m.dims[1]) *
                     static_cast<std::size_t>(m.dims[2]),
                 0.0);
}

// Initial exponent: the pooled slope of ln f against ln d (with an intercept), in [0.5, 3].
double initial_exponent(const std::vector<double>& lu, const std::vector<double>& lf) {
  const auto n = static_cast<double>(lu.size());
  double mu = 0, mf = 0;
  for (std::size_t i = 0; i < lu.size(); ++i) mu += lu[i], mf += lf[i];
  mu /= n, mf /= n;
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < lu.size(); ++i)
    sxy += (lu[i] - mu) * (lf[i] - mf), sxx += (lu[i] - mu) * (lu[i] - mu);
  return std::clamp(sxx > 0 ? sxy / sxx : 1.0, 0.5, 3.0);
}

}  // namespace

StiffnessPrior fit_stiffness_prior(const std::vector<Vec3>& q, const std::vector<double>& depth,
                                   const std::vector<double>& normal_force,
                                   const StiffnessPriorParams& prm) {
  prm.validate();
  if (depth.size() != q.size() || normal_force.size() != q.size())
    throw Error("stiffness map: expected q, depth and normal force of equal length");
  std::vector<Vec3> qs;
  std::vector<double> lu, lf;
  for (std::size_t i = 0; i < q.size(); ++i)
    if (q[i].allFinite() && depth[i] >= prm.min_depth && normal_force[i] >= prm.min_force &&
        std::isfinite(depth[i]) && std::isfinite(normal_force[i])) {
      qs.push_back(q[i]);
      lu.push_back(std::log(depth[i]));
      lf.push_back(std::log(normal_force[i]));
    }
  StiffnessPrior m;
  const std::size_t n = qs.size();
  if (n < 10) return m;
  m.fitted_samples = n;
  place_grid(qs, prm, m);
  const std::size_t nodes = m.log_k.size();
  m.exponent = initial_exponent(lu, lf);
  std::vector<double> sum(nodes), count(nodes), lk(n), first(nodes), coarse(nodes);
  // Gaussian-weighted mean (radius sigma_mm) of values v_i over q, shrunk towards to[j] with
  // the weight of prior_weight samples.
  auto smooth = [&](const std::vector<double>& v, double sigma_mm, const std::vector<double>& to,
                    std::vector<double>& out) {
    std::fill(sum.begin(), sum.end(), 0.0);
    std::fill(count.begin(), count.end(), 0.0);
    for (std::size_t i = 0; i < n; ++i) splat(m, qs[i], v[i], sum, count);
    blur(sum, m.dims, sigma_mm / m.cell);
    blur(count, m.dims, sigma_mm / m.cell);
    out.resize(nodes);
    for (std::size_t j = 0; j < nodes; ++j)
      out[j] = (sum[j] + prm.prior_weight * to[j]) / (count[j] + prm.prior_weight);
  };
  for (int it = 0; it < prm.iterations; ++it) {
    // ln k map given the exponent: a pyramid of smoothing radii (9, 3.75, 1.5 mm at sigma =
    // 1.5; local-linear fits at the two coarse levels, a local mean at the finest), each level
    // shrunk towards the next coarser one (the coarsest towards the global mean), so that a gap
    // in the data is filled from the data around it along their trend, not from the whole
    // object; then the residuals are smoothed and added ("twicing", Tukey), which removes most
    // of the smoothing's bias where ln k is curved.
    double global = 0;
    for (std::size_t i = 0; i < n; ++i) {
      lk[i] = lf[i] - m.exponent * lu[i];
      global += lk[i];
    }
    global /= static_cast<double>(n);
    std::fill(coarse.begin(), coarse.end(), global);
    for (double f : {6.0, 2.5}) {
      smooth_linear(m, qs, lk, f * prm.sigma, prm.prior_weight, coarse, first);
      coarse.swap(first);
    }
    smooth(lk, prm.sigma, coarse, first);
    m.log_k = first;
    for (std::size_t i = 0; i < n; ++i) lk[i] -= m.log_stiffness(qs[i]);
    std::fill(coarse.begin(), coarse.end(), 0.0);
    smooth(lk, prm.sigma, coarse, m.log_k);
    // Rounded to 1e-6 (0.0001 % of k): short in a model file, bit-identical when read back.
    for (std::size_t j = 0; j < nodes; ++j)
      m.log_k[j] = std::round(1e6 * (first[j] + m.log_k[j])) / 1e6;
    // Exponent given the map: slope through the origin.
    double num = 0, den = 0;
    for (std::size_t i = 0; i < n; ++i) {
      num += lu[i] * (lf[i] - m.log_stiffness(qs[i]));
      den += lu[i] * lu[i];
    }
    if (it + 1 < prm.iterations && den > 0) m.exponent = std::clamp(num / den, 0.5, 3.0);
  }
  return m;
}

void validate_stiffness_prior(const StiffnessPrior& m, const std::string& where) {
  if (m.log_k.empty()) return;
  const std::size_t nodes = static_cast<std::size_t>(std::max(m.dims[0], 0)) *
                            static_cast<std::size_t>(std::max(m.dims[1], 0)) *
                            static_cast<std::size_t>(std::max(m.dims[2], 0));
  if (m.dims[0] < 1 || m.dims[1] < 1 || m.dims[2] < 1 || nodes != m.log_k.size())
    throw Error(fmt::format("{}: expected {} x {} x {} = {} ln k values, got {}", where, m.dims[0],
                            m.dims[1], m.dims[2], nodes, m.log_k.size()));
  if (!(m.exponent > 0 && m.exponent <= 3) || !(m.cell > 0) || !m.origin.allFinite())
    throw Error(
        fmt::format("{}: expected an exponent in (0, 3], a cell > 0 and a finite origin", where));
  for (double v : m.log_k)
    if (!std::isfinite(v)) throw Error(fmt::format("{}: expected finite ln k values", where));
}

}  // namespace inhap::datadriven
