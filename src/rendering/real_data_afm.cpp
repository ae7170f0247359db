// The AFM "protein-on-mica" model of thesis fig. 5.3a / 5.7a from a WSxM topography: levelled,
// resampled to 256 x 256 cells (131,072 triangles), heights scaled, and a halo stiffness map
// derived from the topography (docs/real-data.md, "AFM halo map"). Units: mm, N/mm.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "inhap/core/error.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/rendering/real_data.hpp"

namespace inhap::rendering {

namespace {

double quantile(std::vector<double> v, double q) {
  const auto i = static_cast<std::size_t>(std::floor(q * double(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(i), v.end());
  return v[i];
}

// Scan-line levelling after the plane: each row's median is taken as the substrate of that row.
void level_rows(Grid& g) {
  std::vector<double> row(std::size_t(g.width));
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) row[std::size_t(x)] = g.at(x, y);
    const double m = quantile(row, 0.5);
    for (int x = 0; x < g.width; ++x) g.at(x, y) -= m;
  }
}

// Connected components (4-neighbour) of the mask; returns the label grid (-1 outside) and the
// pixel lists.
std::vector<std::vector<int>> components(const std::vector<char>& mask, int n,
                                         std::vector<int>& label) {
  label.assign(mask.size(), -1);
  std::vector<std::vector<int>> comps;
  std::vector<int> stack;
  for (int s = 0; s < n * n; ++s) {
    if (!mask[std::size_t(s)] || label[std::size_t(s)] >= 0) continue;
    const int id = int(comps.size());
    comps.emplace_back();
    stack.push_back(s);
    label[std::size_t(s)] = id;
    while (!stack.empty()) {
      const int p = stack.back();
      stack.pop_back();
      comps.back().push_back(p);
      const int x = p % n, y = p / n;
      const int nb[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[1] < 0 || q[0] >= n || q[1] >= n) continue;
        const int j = q[1] * n + q[0];
        if (mask[std::size_t(j)] && label[std::size_t(j)] < 0) {
          label[std::size_t(j)] = id;
          stack.push_back(j);
        }
      }
    }
  }
  return comps;
}

// Distance (mm) from every sample to the nearest feature sample, exact within `reach` samples,
// `reach * spacing` beyond.
std::vector<double> feature_distance(const std::vector<char>& feature, int n, double spacing,
                                     int reach) {
  std::vector<double> d(feature.size(), reach * spacing);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      if (!feature[std::size_t(y * n + x)]) continue;
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= n || qy >= n) continue;
          double& v = d[std::size_t(qy * n + qx)];
          v = std::min(v, spacing * std::hypot(dx, dy));
        }
    }
  return d;
}

double afm_raised_cosine(double r, double radius) {
  return r >= radius ? 0.0 : 0.5 * (1.0 + std::cos(std::numbers::pi * r / radius));
}

// A stroke through the centroid of one feature, along x (or y), over the feature, its halo and
// 3 mm of mica on both sides; marks A (halo entered) and B (halo left) from the stiffness map.
DataStroke feature_stroke(const std::vector<int>& comp, int n, double spacing, bool along_x,
                          const Grid& k, double k_max, const std::string& name) {
  double cx = 0, cy = 0;
  int lo = n, hi = -1;
  for (int p : comp) {
    cx += p % n;
    cy += p / n;
  }
  cx /= double(comp.size());
  cy /= double(comp.size());
  for (int p : comp) {
    const int a = along_x ? p % n : p / n, b = along_x ? p / n : p % n;
    if (std::abs(b - (along_x ? cy : cx)) <= 1.0) {
      lo = std::min(lo, a);
      hi = std::max(hi, a);
    }
  }
  if (hi < 0) lo = hi = int(std::lround(along_x ? cx : cy));
  DataStroke s;
  s.name = name;
  const double side = (n - 1) * spacing, margin = 7.0;  // halo 4 mm + 3 mm of mica
  const double a0 = std::max(0.5, lo * spacing - margin),
               a1 = std::min(side - 0.5, hi * spacing + margin);
  const double b = (along_x ? cy : cx) * spacing;
  s.from = along_x ? Vec2(a0, b) : Vec2(b, a0);
  s.to = along_x ? Vec2(a1, b) : Vec2(b, a1);
  // Marks: first and last sample along the line that is softer than the mica.
  const double len = a1 - a0;
  double first = -1, last = -1;
  for (double u = 0; u <= len; u += 0.1) {
    const double a = (a0 + u) / spacing;
    const int ia = std::clamp(int(std::lround(a)), 0, n - 1),
              ib = std::clamp(int(std::lround(b / spacing)), 0, n - 1);
    const double kv = along_x ? k.at(ia, ib) : k.at(ib, ia);
    if (kv < k_max - 0.05) {
      if (first < 0) first = u;
      last = u;
    }
  }
  if (first >= 0) {
    s.marks.push_back({"A", first, "halo entered: soft ring around the raised feature"});
    s.marks.push_back({"B", last, "halo left: back onto the stiff mica"});
  }
  return s;
}

}  // namespace

RealDataset load_afm(const std::string& top_path, const RealDataOptions& o) {
  if (o.afm_cells < 8) throw Error(fmt::format("afm: expected >= 8 cells, got {}", o.afm_cells));
  Grid raw = read_wsxm_top(top_path);
  if (raw.width < 2 || raw.height < 2)
    throw Error(fmt::format("{}: expected at least 2 x 2 samples", top_path));
  level_plane(raw);
  level_rows(raw);
  const int n = o.afm_cells + 1;
  const double spacing = o.cube_mm / o.afm_cells;
  Grid g = resample_bilinear(raw, n);
  const double base = quantile(g.values, 0.5), top = quantile(g.values, 0.999);
  const double span = std::max(top - base, 1e-12);
  Grid h(n, n), k(n, n, o.k_max);
  std::vector<char> mask(std::size_t(n) * n, 0);
  for (std::size_t i = 0; i < g.values.size(); ++i) {
    const double v = (g.values[i] - base) / span;  // 0 substrate, 1 tallest features
    h.values[i] = o.afm_height_mm * v;
    mask[i] = v > o.afm_feature_level;
  }
  // Features: components of at least 3 x 3 samples (smaller ones are noise).
  std::vector<int> label;
  std::vector<std::vector<int>> comps = components(mask, n, label);
  std::vector<char> feature(mask.size(), 0);
  std::vector<std::size_t> kept;
  for (std::size_t c = 0; c < comps.size(); ++c) {
    if (comps[c].size() < 9) continue;
    kept.push_back(c);
    for (int p : comps[c]) feature[std::size_t(p)] = 1;
  }
  const int reach = int(std::ceil(o.afm_halo_mm / spacing)) + 1;
  const std::vector<double> d = feature_distance(feature, n, spacing, reach);
  for (std::size_t i = 0; i < k.values.size(); ++i)
    k.values[i] = feature[i]
                      ? o.afm_k_feature
                      : o.k_max - (o.k_max - o.afm_k_halo) * afm_raised_cosine(d[i], o.afm_halo_mm);
  for (double& v : k.values) v = std::max(v, o.k_floor);

  RealDataset ds;
  ds.name = "afm";
  ds.file = top_path;
  ds.mesh = grid_to_mesh(h, spacing, &k);
  ds.scale = o.cube_mm / double(raw.width - 1);  // mm per pixel of the file, in x and y
  ds.stiffness_from = fmt::format(
      "halo map from the topography: mica {} N/mm, {} features ({} N/mm) each with a {} mm soft "
      "ring from {} N/mm back to {} N/mm",
      o.k_max, kept.size(), o.afm_k_feature, o.afm_halo_mm, o.afm_k_halo, o.k_max);
  // Strokes across the two largest features.
  std::sort(kept.begin(), kept.end(),
            [&](std::size_t a, std::size_t b) { return comps[a].size() > comps[b].size(); });
  for (std::size_t i = 0; i < std::min<std::size_t>(2, kept.size()); ++i) {
    // Across the feature: along x when it is taller (in y) than wide, else along y.
    int x0 = n, x1 = -1, y0 = n, y1 = -1;
    for (int p : comps[kept[i]]) {
      x0 = std::min(x0, p % n);
      x1 = std::max(x1, p % n);
      y0 = std::min(y0, p / n);
      y1 = std::max(y1, p / n);
    }
    ds.strokes.push_back(feature_stroke(comps[kept[i]], n, spacing, y1 - y0 >= x1 - x0, k, o.k_max,
                                        fmt::format("afm feature {}", i + 1)));
  }
  if (ds.strokes.empty()) throw Error(fmt::format("{}: no raised feature found", top_path));
  return ds;
}

}  // namespace inhap::rendering
