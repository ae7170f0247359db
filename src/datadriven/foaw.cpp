// FOAW best-fit velocity estimation (see include/inhap/datadriven/foaw.hpp). Units: mm, mm/s, s.
#include "inhap/datadriven/foaw.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "inhap/core/error.hpp"

namespace inhap::datadriven {

void FoawParams::validate() const {
  if (!(dt_s > 0) || !std::isfinite(dt_s))
    throw Error(fmt::format("FOAW: expected a sample period dt_s > 0 s, got {}", dt_s));
  if (max_window < 1 || max_window >= kFoawMaxWindow)
    throw Error(fmt::format("FOAW: expected a window cap in 1..{}, got {}", kFoawMaxWindow - 1,
                            max_window));
  if (!(noise_bound_mm >= 0) || !std::isfinite(noise_bound_mm))
    throw Error(fmt::format("FOAW: expected a noise bound >= 0 mm, got {}", noise_bound_mm));
}

FoawParams FoawParams::at_period(double period_s) const noexcept {
  if (!(period_s > 0) || !std::isfinite(period_s) || !(dt_s > 0)) return *this;
  if (std::abs(period_s - dt_s) <= 0.01 * dt_s) return *this;  // the same rate, give or take jitter
  FoawParams p = *this;
  const double samples = std::round(max_window * dt_s / period_s);
  p.max_window = static_cast<int>(std::clamp(samples, 1.0, double(kFoawMaxWindow - 1)));
  p.dt_s = period_s;
  return p;
}

namespace {

// Sample y_{k-i} of one axis relative to y_k.
inline double rel(const FoawState& s, int i, int axis, double yk) {
  int idx = s.head - i;
  if (idx < 0) idx += kFoawMaxWindow;
  return s.buffer[static_cast<std::size_t>(idx)][axis] - yk;
}

// Best-fit FOAW slope for one axis; writes the accepted window length.
double axis_slope(const FoawParams& prm, const FoawState& s, int axis, int& window) {
  const int n_max = std::min(prm.max_window, s.count - 1);
  const double yk = s.buffer[static_cast<std::size_t>(s.head)][axis];
  double s0 = 0.0, s1 = 0.0;  // sums of y_{k-i}-y_k and i*(y_{k-i}-y_k), i = 0..n
  double best = 0.0;
  window = 0;
  for (int n = 1; n <= n_max; ++n) {
    const double yn = rel(s, n, axis, yk);
    s0 += yn;
    s1 += n * yn;
    const double denom = prm.dt_s * n * (n + 1.0) * (n + 2.0) / 6.0;
    const double b = (n * s0 - 2.0 * s1) / denom;
    // Inside the band means strictly inside: a deviation equal to d (up to rounding of the
    // differences of quantised positions, 1e-12 relative) ends the window.
    const double bound = prm.noise_bound_mm * (1.0 - 1e-12) - 1e-15;
    bool inside = true;
    for (int j = 1; j < n && inside; ++j) {
      const double dev = rel(s, j, axis, yk) + b * j * prm.dt_s;  // y_{k-j} - (y_k - b j T)
      inside = std::fabs(dev) < bound;
    }
    if (!inside) break;
    best = b;
    window = n;
  }
  return best;
}

}  // namespace

Vec3 foaw_step(const FoawParams& params, FoawState& state, const Vec3& p) {
  if (!p.allFinite()) {
    state.reset();
    return Vec3::Zero();
  }
  state.head = (state.head + 1) % kFoawMaxWindow;
  state.buffer[static_cast<std::size_t>(state.head)] = p;
  if (state.count < kFoawMaxWindow) ++state.count;
  Vec3 v;
  for (int a = 0; a < 3; ++a)
    v[a] = axis_slope(params, state, a, state.window[static_cast<std::size_t>(a)]);
  if (!v.allFinite()) v.setZero();
  state.velocity = v;
  return v;
}

}  // namespace inhap::datadriven
