// Local stiffness prior f_n ~ k(q) d^alpha: backfitting of a smoothed ln k map and one exponent
// (see stiffness_map.hpp). Units: mm, N.
#include "inhap/datadriven/stiffness_map.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "inhap/core/error.hpp"

namespace inhap::dd {

void StiffnessMapParams::validate() const {
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

// Trilinear splat of value v (weight 1) at q into sum / count.
void splat(const StiffnessMap& m, const Vec3& q, double v, std::vector<double>& sum,
           std::vector<double>& count) {
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
  for (int c = 0; c < 8; ++c) {
    double w = 1;
    std::size_t idx = 0;
    bool ok = true;
    for (int a = 0; a < 3; ++a) {
      const int bit = (c >> a) & 1;
      if (bit && m.dims[static_cast<std::size_t>(a)] < 2) ok = false;
      w *= bit ? t[a] : 1 - t[a];
      idx += (i0[a] + static_cast<std::size_t>(bit)) * (a == 0 ? 1 : a == 1 ? nx : nxy);
    }
    if (!ok || w == 0) continue;
    sum[idx] += w * v;
    count[idx] += w;
  }
}

// Grid over the samples' bounding box padded by 2 sigma, coarser cells if it would exceed
// 500,000 nodes: sets origin, cell and dims, and sizes log_k.
void place_grid(const std::vector<Vec3>& qs, const StiffnessMapParams& prm, StiffnessMap& m) {
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

StiffnessMap fit_stiffness_map(const std::vector<Vec3>& q, const std::vector<double>& depth,
                               const std::vector<double>& normal_force,
                               const StiffnessMapParams& prm) {
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
  StiffnessMap m;
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
    // 1.5), each level shrunk towards the next coarser one (the coarsest towards the global
    // mean), so that a gap in the data is filled from the data around it, not from the whole
    // object; then the residuals are smoothed and added ("twicing", Tukey), which removes
    // most of the smoothing's bias where ln k is curved.
    double global = 0;
    for (std::size_t i = 0; i < n; ++i) {
      lk[i] = lf[i] - m.exponent * lu[i];
      global += lk[i];
    }
    global /= static_cast<double>(n);
    std::fill(coarse.begin(), coarse.end(), global);
    for (double f : {6.0, 2.5}) {
      smooth(lk, f * prm.sigma, coarse, first);
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

void validate_stiffness_map(const StiffnessMap& m, const std::string& where) {
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

}  // namespace inhap::dd
