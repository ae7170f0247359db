// Self-calibrated offline force compensation; see offline_compensation.hpp.
#include "inhap/contact/offline_compensation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace inhap {

std::vector<Vec3> estimate_acceleration(std::span<const double> t, std::span<const Vec3> p,
                                        std::size_t h) {
  const std::size_t n = std::min(t.size(), p.size());
  std::vector<Vec3> a(n, Vec3::Zero());
  if (n < 3) return a;
  h = std::max<std::size_t>(1, h);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t lo = i > h ? i - h : 0, hi = std::min(n - 1, i + h);
    while (hi - lo < 2) {  // need three samples for a parabola
      if (lo > 0)
        --lo;
      else
        ++hi;
    }
    // Least squares of p(t) = c0 + c1 s + c2 s^2 with s = t - t_i (scaled for conditioning).
    const double scale = 1.0 / std::max(t[hi] - t[lo], 1e-12);
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d B = Eigen::Matrix3d::Zero();  // columns: x, y, z right-hand sides
    for (std::size_t j = lo; j <= hi; ++j) {
      const double s = (t[j] - t[i]) * scale;
      const Eigen::Vector3d row(1, s, s * s);
      A += row * row.transpose();
      B += row * p[j].transpose();
    }
    const Eigen::Matrix3d c = A.ldlt().solve(B);
    a[i] = 2.0 * c.row(2).transpose() * scale * scale;
    if (!a[i].allFinite()) a[i].setZero();
  }
  return a;
}

std::vector<Vec3> apply_offline_compensation(std::span<const Vec3> raw,
                                             std::span<const Vec3> acceleration,
                                             const OfflineCompensation& c) {
  std::vector<Vec3> f(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i)
    f[i] = raw[i] - c.offset + 1e-3 * c.mass_kg * acceleration[i];
  return f;
}

OfflineCompensation fit_offline_compensation(std::span<const double> t, std::span<const Vec3> p,
                                             std::span<const Vec3> raw,
                                             const OfflineCompensationOptions& o) {
  OfflineCompensation c;
  const std::size_t n = std::min({t.size(), p.size(), raw.size()});
  if (n < 8) return c;
  const std::vector<Vec3> acc = estimate_acceleration(t.first(n), p.first(n), o.half_window);
  std::vector<char> use(n, 1);
  std::vector<double> res(n), tmp;
  for (std::size_t it = 0; it <= o.iterations; ++it) {
    // Unknowns (bx, by, bz, m): raw_k = b_k - 1e-3 m a_k, k = x, y, z.
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    Eigen::Vector4d rhs = Eigen::Vector4d::Zero();
    std::size_t used = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!use[i] || !raw[i].allFinite()) continue;
      ++used;
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector4d row = Eigen::Vector4d::Zero();
        row[k] = 1;
        row[3] = -1e-3 * acc[i][k];
        A += row * row.transpose();
        rhs += row * raw[i][k];
      }
    }
    if (used < 8) break;
    const Eigen::Vector4d x = A.ldlt().solve(rhs);
    if (!x.allFinite()) break;
    c.offset = x.head<3>();
    c.mass_kg = x[3];
    c.free_samples = used;
    // Residual magnitudes of every sample; cut at median + k * 1.4826 MAD of the used ones.
    tmp.clear();
    double sq = 0;
    for (std::size_t i = 0; i < n; ++i) {
      res[i] = (raw[i] - c.offset + 1e-3 * c.mass_kg * acc[i]).norm();
      if (use[i]) tmp.push_back(res[i]), sq += res[i] * res[i];
    }
    c.residual_rms = std::sqrt(sq / static_cast<double>(used));
    auto mid = tmp.begin() + static_cast<std::ptrdiff_t>(tmp.size() / 2);
    std::nth_element(tmp.begin(), mid, tmp.end());
    const double med = *mid;
    for (double& v : tmp) v = std::abs(v - med);
    std::nth_element(tmp.begin(), mid, tmp.end());
    const double cut = std::max(o.min_reject_n, med + o.reject_sigmas * 1.4826 * *mid);
    for (std::size_t i = 0; i < n; ++i) use[i] = res[i] <= cut;
  }
  return c;
}

}  // namespace inhap
