// The 25 shape-stiffness models of the TCA-MESH user study and an AFM-like timing surface.
// Units: mm, N/mm, N.
#include "inhap/rendering/datasets.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/heightmap.hpp"

namespace inhap::rendering {

const char* to_string(ShapeClass c) {
  switch (c) {
    case ShapeClass::kFlat:
      return "flat";
    case ShapeClass::kBump:
      return "bump";
    case ShapeClass::kHole:
      return "hole";
  }
  return "?";
}

const char* to_string(StiffnessClass c) {
  switch (c) {
    case StiffnessClass::kSame:
      return "same";
    case StiffnessClass::kHarder:
      return "harder";
    case StiffnessClass::kSofter:
      return "softer";
  }
  return "?";
}

ShapeClass true_shape_class(int model) {
  const int h = shape_index(model);
  return h == 0 ? ShapeClass::kFlat : h <= 2 ? ShapeClass::kBump : ShapeClass::kHole;
}

StiffnessClass true_stiffness_class(int model) {
  const int k = stiffness_index(model);
  return k == 0   ? StiffnessClass::kSame
         : k <= 2 ? StiffnessClass::kSofter
                  : StiffnessClass::kHarder;
}

namespace {

/// Raised cosine: 1 at r = 0, 0 at r >= radius, C1 everywhere.
double raised_cosine(double r, double radius) {
  return r >= radius ? 0.0 : 0.5 * (1.0 + std::cos(std::numbers::pi * r / radius));
}

void check_model(int model) {
  if (model < 0 || model >= kNumModels)
    throw Error(fmt::format("model index must be 0..24, got {}", model));
}

}  // namespace

double model_height(const DatasetParams& p, int model, double r) {
  check_model(model);
  const int h = shape_index(model);
  if (h == 0) return 0.0;
  double profile;
  if (h == 1 || h == 3) {
    profile = raised_cosine(r, p.shape_radius_mm);
  } else {  // flat top (bottom) with a straight wall: slope discontinuities at both rims
    const double r0 = p.sharp_top_radius_mm, r1 = p.shape_radius_mm;
    profile = r <= r0 ? 1.0 : r >= r1 ? 0.0 : (r1 - r) / (r1 - r0);
  }
  return (h <= 2 ? 1.0 : -1.0) * p.height_mm * profile;
}

double model_stiffness(const DatasetParams& p, int model, double r) {
  check_model(model);
  const int k = stiffness_index(model);
  if (k == 0) return p.k_surround;
  const double centre = k <= 2 ? p.k_soft : p.k_hard;
  const double w = (k == 1 || k == 3) ? raised_cosine(r, p.smooth_stiffness_radius_mm)
                                      : (r < p.sharp_stiffness_radius_mm ? 1.0 : 0.0);
  return p.k_surround + (centre - p.k_surround) * w;
}

int Layout::cell_of(int model) const {
  for (int c = 0; c < kNumModels; ++c)
    if (model_at_cell[c] == model) return c;
  return -1;
}

Layout identity_layout() {
  Layout l;
  for (int c = 0; c < kNumModels; ++c) l.model_at_cell[c] = c;
  return l;
}

Layout shuffled_layout(std::uint64_t seed) {
  Layout l = identity_layout();
  Rng rng(seed);
  for (int i = kNumModels - 1; i > 0; --i) {
    const auto j = static_cast<int>(rng.below(static_cast<std::uint64_t>(i) + 1));
    std::swap(l.model_at_cell[i], l.model_at_cell[j]);
  }
  return l;
}

// ---------------------------------------------------------------------------------------------
StudySurface::StudySurface(const DatasetParams& params, const Layout& layout)
    : params_(params), layout_(layout) {
  if (params.cells != kGridCells)
    throw Error(
        fmt::format("the study array is {0}x{0} cells, got cells = {1}", kGridCells, params.cells));
  if (!(params.cell_mm > 0) || !(params.spacing_mm > 0))
    throw Error(fmt::format("cell size and spacing must be > 0 mm, got {} and {}", params.cell_mm,
                            params.spacing_mm));
  const double side = params.cells * params.cell_mm;
  const double steps = side / params.spacing_mm;
  if (std::abs(steps - std::round(steps)) > 1e-9)
    throw Error(fmt::format("surface side {} mm is not a multiple of the spacing {} mm", side,
                            params.spacing_mm));
  if (!(params.k_soft > 0 && params.k_surround > 0 && params.k_hard > 0))
    throw Error("stiffness values must be > 0 N/mm");
  std::array<bool, kNumModels> seen{};
  for (int m : layout.model_at_cell) {
    if (m < 0 || m >= kNumModels || seen[m])
      throw Error("layout must be a permutation of the models 0..24");
    seen[m] = true;
  }
  n_ = static_cast<int>(std::round(steps)) + 1;
  height_.resize(std::size_t(n_) * n_);
  stiffness_.resize(height_.size());
  for (int y = 0; y < n_; ++y)
    for (int x = 0; x < n_; ++x) {
      const double px = x * params.spacing_mm, py = y * params.spacing_mm;
      height_[std::size_t(y) * n_ + x] = analytic_height(px, py);
      stiffness_[std::size_t(y) * n_ + x] = analytic_stiffness(px, py);
    }
}

TriMesh StudySurface::mesh() const {
  Grid h(n_, n_), k(n_, n_);
  h.values = height_;
  k.values = stiffness_;
  return grid_to_mesh(h, params_.spacing_mm, &k);
}

Vec2 StudySurface::cell_centre(int cell) const {
  const int row = cell / params_.cells, col = cell % params_.cells;
  return {(col + 0.5) * params_.cell_mm, (row + 0.5) * params_.cell_mm};
}

int StudySurface::cell_at(double x, double y) const {
  const double side = params_.cells * params_.cell_mm;
  if (!(x >= 0 && y >= 0 && x <= side && y <= side)) return -1;
  const int col = std::min(params_.cells - 1, static_cast<int>(x / params_.cell_mm));
  const int row = std::min(params_.cells - 1, static_cast<int>(y / params_.cell_mm));
  return row * params_.cells + col;
}

int StudySurface::model_at(double x, double y) const {
  const int c = cell_at(x, y);
  return c < 0 ? -1 : layout_.model_at_cell[c];
}

double StudySurface::analytic_height(double x, double y) const {
  const int c = cell_at(x, y);
  if (c < 0) return 0.0;
  const Vec2 o = cell_centre(c);
  return model_height(params_, layout_.model_at_cell[c], std::hypot(x - o.x(), y - o.y()));
}

double StudySurface::analytic_stiffness(double x, double y) const {
  const int c = cell_at(x, y);
  if (c < 0) return params_.k_surround;
  const Vec2 o = cell_centre(c);
  return model_stiffness(params_, layout_.model_at_cell[c], std::hypot(x - o.x(), y - o.y()));
}

double StudySurface::interpolate(const std::vector<double>& v, double x, double y) const {
  const double gx = std::clamp(x / params_.spacing_mm, 0.0, double(n_ - 1));
  const double gy = std::clamp(y / params_.spacing_mm, 0.0, double(n_ - 1));
  const int ix = std::min(n_ - 2, static_cast<int>(gx)),
            iy = std::min(n_ - 2, static_cast<int>(gy));
  const double fx = gx - ix, fy = gy - iy;
  const double a = v[std::size_t(iy) * n_ + ix], b = v[std::size_t(iy) * n_ + ix + 1];
  const double c = v[std::size_t(iy + 1) * n_ + ix], d = v[std::size_t(iy + 1) * n_ + ix + 1];
  // Same checkerboard diagonals as grid_to_mesh: (a, b, d) + (a, d, c) on even cells,
  // (a, b, c) + (b, d, c) on odd ones.
  if ((ix + iy) % 2 == 0) {
    if (fx >= fy) return a + fx * (b - a) + fy * (d - b);
    return a + fy * (c - a) + fx * (d - c);
  }
  if (fx + fy <= 1.0) return a + fx * (b - a) + fy * (c - a);
  return d + (1.0 - fx) * (c - d) + (1.0 - fy) * (b - d);
}

double StudySurface::mesh_height(double x, double y) const {
  return interpolate(height_, x, y);
}
double StudySurface::mesh_stiffness(double x, double y) const {
  return interpolate(stiffness_, x, y);
}

// ---------------------------------------------------------------------------------------------
ShapeClass classify_height_contrast(double contrast_mm, double threshold_mm) {
  if (contrast_mm > threshold_mm) return ShapeClass::kBump;
  if (contrast_mm < -threshold_mm) return ShapeClass::kHole;
  return ShapeClass::kFlat;
}

double predicted_contrast(const DatasetParams& p, int model, double force_n, Algorithm algorithm,
                          const ShapePerception& perception, double a_s, double step_mm) {
  check_model(model);
  if (!(force_n > 0) || !(step_mm > 0))
    throw Error("predicted_contrast: force and step must be > 0");
  const double u0 = -perception.surround_outer_mm - 0.5, u1 = perception.surround_outer_mm + 0.5;
  const auto steps = static_cast<long>(std::ceil((u1 - u0) / step_mm));
  double sum_c = 0, sum_a = 0, sum_b = 0;
  long n_c = 0, n_a = 0, n_b = 0;
  double s = 0, k_prev = model_stiffness(p, model, std::abs(u0));
  double z = model_height(p, model, std::abs(u0)) - force_n / k_prev;  // settled at the start
  for (long i = 1; i <= steps; ++i) {
    const double u = u0 + (u1 - u0) * double(i) / double(steps);
    const double h = model_height(p, model, std::abs(u)),
                 k = model_stiffness(p, model, std::abs(u));
    if (algorithm == Algorithm::kCBA) {
      z = h - force_n / k;
    } else {
      const double x = h - z;                        // penetration of the last HIP, mm
      const double ds = (k_prev - k) / k * (x + s);  // eq. 5.4
      const double d = a_s * step_mm;                // eq. 5.11 with d_s = lateral travel
      const double dr = s > d ? -d : s < -d ? d : -s;
      s += ds + dr;             // eq. 5.13
      z = h + s - force_n / k;  // force constancy: k (x + s) = F
    }
    k_prev = k;
    const double a = std::abs(u);
    if (a <= perception.centre_half_mm) {
      sum_c += z;
      ++n_c;
    } else if (a >= perception.surround_inner_mm && a <= perception.surround_outer_mm) {
      (u < 0 ? sum_a : sum_b) += z;
      ++(u < 0 ? n_a : n_b);
    }
  }
  if (n_c == 0 || n_a == 0 || n_b == 0) throw Error("predicted_contrast: empty perception window");
  return sum_c / n_c - 0.5 * (sum_a / n_a + sum_b / n_b);
}

std::vector<int> thesis_cba_confusions() {
  return {1, 2, 3, 4, 6, 7, 11, 12, 18, 19, 23, 24};
}

// ---------------------------------------------------------------------------------------------
TriMesh afm_like_surface(std::uint64_t seed, int n, double size_mm) {
  if (n < 2 || !(size_mm > 0))
    throw Error(
        fmt::format("afm_like_surface: need n >= 2 and size > 0, got {} and {}", n, size_mm));
  Rng rng(seed);
  struct Patch {
    double x, y, r;
  };
  std::vector<Patch> patches;
  for (int i = 0; i < 9; ++i)
    patches.push_back({rng.uniform(0.15, 0.85) * size_mm, rng.uniform(0.15, 0.85) * size_mm,
                       rng.uniform(0.05, 0.09) * size_mm});
  const double halo = 0.04 * size_mm, spacing = size_mm / (n - 1);
  const double protein_period = 0.025 * size_mm;
  Grid h(n, n, 0.0), k(n, n, 1.0);  // mica: flat and stiff
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double px = x * spacing, py = y * spacing;
      double height = 0.0, stiff = 1.0;
      for (const Patch& pa : patches) {
        const double r = std::hypot(px - pa.x, py - pa.y);
        if (r < pa.r) {  // membrane with a periodic array of proteins
          const double bumps = 0.25 * (1 + std::cos(2 * std::numbers::pi * px / protein_period)) *
                               (1 + std::cos(2 * std::numbers::pi * py / protein_period));
          height = std::max(height, 2.0 + 0.3 * bumps);
          stiff = std::min(stiff, 0.6);
        } else if (r < pa.r + halo) {  // halo of dissociated lipids: lower and soft
          const double w = raised_cosine(r - pa.r, halo);
          if (0.8 * w > 1e-9 && height < 2.0) {
            height = std::max(height, 0.8 * w + 0.0);
            stiff = std::min(stiff, 1.0 - (1.0 - 0.15) * std::min(1.0, 2.0 * w));
          }
        }
      }
      h.at(x, y) = height;
      k.at(x, y) = stiff;
    }
  return grid_to_mesh(h, spacing, &k);
}

}  // namespace inhap::rendering
