// The force envelope of the training data (see envelope.hpp). Units: mm, N.
#include "inhap/datadriven/envelope.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "inhap/core/error.hpp"

namespace inhap::datadriven {

namespace {
constexpr int kMaxCells = 200;      // per axis
constexpr int kMaxDepthBins = 100;  // 50 mm at 0.5 mm

// floor(x) clamped to [lo, hi] before the conversion (no overflow for a huge x; NaN gives lo).
int clamped_index(double x, int lo, int hi) {
  if (!(x >= lo)) return lo;
  if (x >= hi) return hi;
  return static_cast<int>(std::floor(x));
}
}  // namespace

ForceEnvelope make_force_envelope(const std::vector<Vec3>& q, const std::vector<Vec3>& p,
                                  const std::vector<Vec3>& f, double cell_mm,
                                  double depth_step_mm) {
  ForceEnvelope e;
  e.cell_mm = cell_mm;
  e.depth_step_mm = depth_step_mm;
  if (q.empty() || q.size() != p.size() || q.size() != f.size()) return e;
  Box3 box;
  double key_max = 0;
  for (std::size_t i = 0; i < q.size(); ++i)
    if (q[i].allFinite() && p[i].allFinite() && f[i].allFinite()) {
      box.extend(q[i]);
      key_max = std::max(key_max, (q[i] - p[i]).norm());
    }
  if (box.empty()) return e;
  for (int a = 0; a < 3; ++a)
    e.dims[a] = clamped_index(box.size()[a] / cell_mm, 0, kMaxCells - 1) + 1;
  e.origin = box.min;
  e.cell_mm = std::max(cell_mm, (box.size() / double(kMaxCells - 1)).maxCoeff());
  e.depth_bins = clamped_index(key_max / depth_step_mm, 0, kMaxDepthBins - 1) + 1;
  const std::size_t nb = std::size_t(e.depth_bins);
  const auto deepest_of = [nb](const float* v) {
    int d = -1;
    for (std::size_t b = 0; b < nb; ++b)
      if (v[b] >= 0) d = static_cast<int>(b);
    return d;
  };
  const std::size_t ncell = std::size_t(e.dims[0]) * e.dims[1] * e.dims[2];
  std::vector<float> own(ncell * nb, -1.0f);  // per cell and bin: samples of that cell only
  e.global.assign(nb, 0.0f);
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (!q[i].allFinite() || !p[i].allFinite() || !f[i].allFinite()) continue;
    std::size_t c = 0;
    for (int a = 2; a >= 0; --a) {
      const int k = clamped_index((q[i][a] - e.origin[a]) / e.cell_mm, 0, e.dims[a] - 1);
      c = c * std::size_t(e.dims[a]) + std::size_t(k);
    }
    const auto b = static_cast<std::size_t>(
        clamped_index((q[i] - p[i]).norm() / depth_step_mm, 0, static_cast<int>(nb) - 1));
    const float m = float(f[i].norm());
    own[c * nb + b] = std::max(own[c * nb + b], m);
    e.global[b] = std::max(e.global[b], m);
  }
  // Cumulative over depth: bin b holds what was seen at depth bins <= b + 1.
  const auto cumulate = [nb](float* v) {
    float run = -1.0f;
    std::vector<float> c(nb);
    for (std::size_t b = 0; b < nb; ++b) c[b] = run = std::max(run, v[b]);
    for (std::size_t b = 0; b < nb; ++b) v[b] = c[std::min(b + 1, nb - 1)];
  };
  for (float& g : e.global) g = g > 0 ? g : -1.0f;
  e.global_deepest = deepest_of(e.global.data());
  for (float& g : e.global) g = std::max(g, 0.0f);
  cumulate(e.global.data());
  e.f_max.assign(ncell * nb, std::numeric_limits<float>::quiet_NaN());
  e.deepest.assign(ncell, -1);
  const int X = e.dims[0], Y = e.dims[1], Z = e.dims[2];
  std::vector<float> block(nb);
  for (int z = 0; z < Z; ++z)
    for (int y = 0; y < Y; ++y)
      for (int x = 0; x < X; ++x) {
        std::fill(block.begin(), block.end(), -1.0f);
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int xx = x + dx, yy = y + dy, zz = z + dz;
              if (xx < 0 || yy < 0 || zz < 0 || xx >= X || yy >= Y || zz >= Z) continue;
              const std::size_t c = (std::size_t(zz) * Y + yy) * X + xx;
              for (std::size_t b = 0; b < nb; ++b) block[b] = std::max(block[b], own[c * nb + b]);
            }
        const std::size_t c = (std::size_t(z) * Y + y) * X + x;
        e.deepest[c] = static_cast<std::int16_t>(deepest_of(block.data()));
        cumulate(block.data());
        for (std::size_t b = 0; b < nb; ++b)
          if (block[b] >= 0) e.f_max[c * nb + b] = block[b];
      }
  return e;
}

double ForceEnvelope::limit(const Vec3& q, double key) const noexcept {
  if (empty()) return std::numeric_limits<double>::infinity();
  if (!q.allFinite() || !std::isfinite(key)) return 0.0;
  const std::size_t nb = global.size();
  const auto b =
      static_cast<std::size_t>(clamped_index(key / depth_step_mm, 0, static_cast<int>(nb) - 1));
  double env = global[b];
  int deep = global_deepest;
  bool inside = true;
  std::size_t c = 0;
  for (int a = 2; a >= 0; --a) {
    const double u = (q[a] - origin[a]) / cell_mm;
    if (!(u >= -1.0 && u < dims[a] + 1.0)) inside = false;
    const int k = clamped_index(u, 0, dims[a] - 1);
    c = c * std::size_t(dims[a]) + std::size_t(k);
  }
  if (inside && c * nb + b < f_max.size() && !std::isnan(f_max[c * nb + b])) {
    env = f_max[c * nb + b];
    deep = deepest[c];
  }
  if (deep >= 0 && static_cast<int>(b) > deep)  // deeper than the data went here: Hertzian growth
    env *= std::pow(static_cast<double>(b + 1) / static_cast<double>(deep + 1), 1.5);
  return (1.0 + margin_rel) * env + margin_n;
}

void validate_envelope(const ForceEnvelope& e, const std::string& where) {
  if (e.empty()) return;
  const auto bad = [&](const std::string& what) {
    throw Error(fmt::format("{}: force envelope: {}", where, what));
  };
  if (!(e.cell_mm > 0) || !(e.depth_step_mm > 0) || !std::isfinite(e.cell_mm) ||
      !std::isfinite(e.depth_step_mm))
    bad("expected positive finite cell and depth step (mm)");
  if (!(e.margin_rel >= 0) || !(e.margin_n >= 0) || !std::isfinite(e.margin_rel) ||
      !std::isfinite(e.margin_n))
    bad("expected non-negative finite margins");
  if (!e.origin.allFinite()) bad("expected a finite origin");
  for (int a = 0; a < 3; ++a)
    if (e.dims[a] < 1 || e.dims[a] > kMaxCells)
      bad(fmt::format("expected 1..{} cells per axis", kMaxCells));
  if (e.depth_bins < 1 || e.depth_bins > kMaxDepthBins ||
      e.global.size() != std::size_t(e.depth_bins))
    bad(fmt::format("expected 1..{} depth bins", kMaxDepthBins));
  if (e.f_max.size() != std::size_t(e.dims[0]) * e.dims[1] * e.dims[2] * e.depth_bins)
    bad("expected dims x depth bins values");
  for (float v : e.global)
    if (!(v >= 0) || !std::isfinite(v)) bad("expected finite non-negative forces");
  if (e.deepest.size() != std::size_t(e.dims[0]) * e.dims[1] * e.dims[2])
    bad("expected one deepest bin per cell");
  for (int d : e.deepest)
    if (d < -1 || d >= e.depth_bins) bad("expected deepest bins in -1..depth_bins - 1");
  if (e.global_deepest < -1 || e.global_deepest >= e.depth_bins)
    bad("expected global_deepest in -1..depth_bins - 1");
  for (float v : e.f_max)
    if (!std::isnan(v) && (!(v >= 0) || !std::isfinite(v)))
      bad("expected finite non-negative forces");
}

}  // namespace inhap::datadriven
