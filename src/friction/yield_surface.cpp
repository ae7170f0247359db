#include "inhap/friction/yield_surface.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "inhap/core/error.hpp"

namespace inhap::friction {

namespace {
constexpr double kYieldTwoPi = 2.0 * std::numbers::pi;
}

YieldSurface YieldSurface::make(std::span<const double> angles, int levels,
                                std::span<const double> level, std::span<const double> radius) {
  const int k = static_cast<int>(angles.size());
  if (k < 1 || k > kMaxDirections)
    throw Error(fmt::format("yield surface: expected 1..{} directions, got {}", kMaxDirections, k));
  if (levels < 1 || levels > kMaxLevels)
    throw Error(fmt::format("yield surface: expected 1..{} levels, got {}", kMaxLevels, levels));
  const std::size_t n = static_cast<std::size_t>(k) * static_cast<std::size_t>(levels);
  if (level.size() != n || radius.size() != n)
    throw Error(fmt::format("yield surface: expected {} levels and radii, got {} and {}", n,
                            level.size(), radius.size()));
  YieldSurface s;
  s.k_ = k;
  s.l_ = levels;
  for (int i = 0; i < k; ++i) {
    if (!(angles[i] >= 0.0 && angles[i] < kYieldTwoPi) || (i > 0 && !(angles[i] > angles[i - 1])))
      throw Error(fmt::format(
          "yield surface: expected increasing angles in [0, 2 pi), got {} at {}", angles[i], i));
    s.angle_[i] = angles[i];
  }
  for (int j = 0; j < levels; ++j)
    for (int i = 0; i < k; ++i) {
      const double lv = level[j * k + i], r = radius[j * k + i];
      if (!std::isfinite(lv) || !(lv > 0.0) || (j > 0 && !(lv > s.level_[j - 1][i])))
        throw Error(fmt::format(
            "yield surface: expected levels > 0 increasing with the level index, got {} at level "
            "{} direction {}",
            lv, j, i));
      if (!std::isfinite(r) || r < 0.0)
        throw Error(fmt::format(
            "yield surface: expected radius >= 0, got {} at level {} direction {}", r, j, i));
      s.level_[j][i] = lv;
      s.radius_[j][i] = r;
    }
  return s;
}

double YieldSurface::direction_radius(int k, double lv) const noexcept {
  if (!(lv > 0.0)) return 0.0;
  double l0 = 0.0, r0 = 0.0;
  for (int j = 0; j < l_; ++j) {
    const double l1 = level_[j][k], r1 = radius_[j][k];
    if (lv <= l1) return r0 + (r1 - r0) * (lv - l0) / (l1 - l0);
    l0 = l1;
    r0 = r1;
  }
  return r0 * lv / l0;  // beyond the last vertex: cone through the apex
}

double YieldSurface::radius_at(double lv, double theta) const noexcept {
  if (k_ == 0) return 0.0;
  if (k_ == 1) return direction_radius(0, lv);
  double t = std::fmod(theta, kYieldTwoPi);
  if (t < 0) t += kYieldTwoPi;
  int a = k_ - 1, b = 0;  // sector [angle_[a], angle_[b]] (wrapping by default)
  double ta = angle_[k_ - 1], tb = angle_[0] + kYieldTwoPi;
  if (t < angle_[0]) {
    ta -= kYieldTwoPi;
    tb -= kYieldTwoPi;
  } else {
    for (int i = 0; i + 1 < k_; ++i)
      if (t < angle_[i + 1]) {
        a = i;
        b = i + 1;
        ta = angle_[i];
        tb = angle_[i + 1];
        break;
      }
  }
  const double w = (t - ta) / (tb - ta);
  return (1.0 - w) * direction_radius(a, lv) + w * direction_radius(b, lv);
}

double YieldSurface::excess(const Vec3& local) const noexcept {
  const double rho = std::hypot(local.x(), local.y());
  return rho - radius_at(local.z(), std::atan2(local.y(), local.x()));
}

Vec3 YieldSurface::radial_return(const Vec3& local) const noexcept {
  const double rho = std::hypot(local.x(), local.y());
  if (!(rho > 0.0)) return local;
  const double r = radius_at(local.z(), std::atan2(local.y(), local.x()));
  return Vec3(local.x() * r / rho, local.y() * r / rho, local.z());
}

std::optional<double> YieldSurface::intersect_ray(const Vec3& origin, const Vec3& dir,
                                                  double max_s) const noexcept {
  if (!(max_s > 0.0) || !origin.allFinite() || !dir.allFinite() || dir.squaredNorm() == 0.0)
    return std::nullopt;
  constexpr int kSamples = 256;
  double s_prev = 0.0, e_prev = excess(origin);
  for (int i = 1; i <= kSamples; ++i) {
    const double s = max_s * i / kSamples;
    const double e = excess(origin + s * dir);
    if (e == 0.0) return s;
    if (e_prev != 0.0 && (e > 0.0) != (e_prev > 0.0)) {
      double lo = s_prev, hi = s;
      const bool lo_out = e_prev > 0.0;
      while (hi - lo > 1e-12 * max_s) {
        const double mid = 0.5 * (lo + hi);
        ((excess(origin + mid * dir) > 0.0) == lo_out ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    }
    s_prev = s;
    e_prev = e;
  }
  return std::nullopt;
}

bool YieldSurface::same_layout(const YieldSurface& o) const noexcept {
  if (k_ != o.k_ || l_ != o.l_) return false;
  for (int i = 0; i < k_; ++i)
    if (std::abs(angle_[i] - o.angle_[i]) > 1e-9) return false;
  return true;
}

void YieldSurface::blend(std::span<const YieldSurface* const> surfaces,
                         std::span<const double> weights) noexcept {
  if (surfaces.empty()) return;
  const YieldSurface& first = *surfaces[0];
  k_ = first.k_;
  l_ = first.l_;
  angle_ = first.angle_;
  for (int j = 0; j < l_; ++j)
    for (int i = 0; i < k_; ++i) {
      double lv = 0, r = 0;
      for (std::size_t s = 0; s < surfaces.size(); ++s) {
        lv += weights[s] * surfaces[s]->level_[j][i];
        r += weights[s] * surfaces[s]->radius_[j][i];
      }
      level_[j][i] = lv;
      radius_[j][i] = r;
    }
}

TriMesh YieldSurface::to_mesh(int subdivisions) const {
  TriMesh m;
  if (k_ == 0) return m;
  const int sub = std::max(k_ < 3 ? 8 : 1, subdivisions);
  const int ring = k_ * sub;
  m.positions.push_back(Vec3::Zero());
  double last = 0;
  for (int j = 0; j < l_; ++j)
    for (int i = 0; i < k_; ++i) {
      const int i1 = (i + 1) % k_;
      const double a0 = angle_[i], a1 = i1 == 0 ? angle_[0] + kYieldTwoPi : angle_[i1];
      for (int s = 0; s < sub; ++s) {
        const double w = static_cast<double>(s) / sub;
        const double a = (1 - w) * a0 + w * (k_ == 1 ? a0 + kYieldTwoPi : a1);
        const double lv = (1 - w) * level_[j][i] + w * level_[j][i1];
        const double r = (1 - w) * radius_[j][i] + w * radius_[j][i1];
        m.positions.emplace_back(r * std::cos(a), r * std::sin(a), lv);
        if (j == l_ - 1) last += lv / ring;
      }
    }
  m.positions.emplace_back(0.0, 0.0, last);
  const int cap = static_cast<int>(m.positions.size()) - 1;
  auto v = [&](int j, int i) { return 1 + j * ring + (i % ring); };
  for (int i = 0; i < ring; ++i) m.triangles.push_back({0, v(0, i + 1), v(0, i)});
  for (int j = 0; j + 1 < l_; ++j)
    for (int i = 0; i < ring; ++i) {
      m.triangles.push_back({v(j, i), v(j, i + 1), v(j + 1, i + 1)});
      m.triangles.push_back({v(j, i), v(j + 1, i + 1), v(j + 1, i)});
    }
  for (int i = 0; i < ring; ++i) m.triangles.push_back({cap, v(l_ - 1, i), v(l_ - 1, i + 1)});
  return m;
}

}  // namespace inhap::friction
