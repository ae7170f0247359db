// Surface, normals, proxy and friction estimated from a recording (see estimate.hpp).
// Units: mm, N, s.
#include "inhap/datadriven/estimate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "inhap/core/cancel.hpp"
#include "inhap/core/error.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/proxy_track.hpp"

namespace inhap::datadriven {

namespace {

// Exponents of the depth-force law d = b f_n^gamma tried: 0.4 to 1.2 in steps of 0.05 (Hertz is
// 2/3, a linear spring 1).
constexpr int kGammaSteps = 17;
double gamma_candidate(int k) {
  return (8 + k) / 20.0;  // exact at 1
}
constexpr double kLevelsN[] = {0.25, 0.5, 1.0, 2.0, 4.0, 8.0};  // f_N levels of the cone sys

double estimate_median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// A contact sample in the plane frame: plane coordinates (u, v), position s along the axis and
// normal force f_n along it.
struct PlaneSample {
  double u, v, s, fn;
  double slope = 1.0;  ///< 1 / cos of the local surface's tilt from the axis (depth along it)
};

// The cells' fit of s = h - b fn^gamma (least squares in h and b, b >= 0) on every sample of the
// 3 x 3 block around the cell. Returns false when the block cannot be fitted.
struct CellFit {
  double h = 0, b = 0, sse = 0;
  std::size_t n = 0;
};

// With `b_prior` > 0 the slope is shrunk towards it (ridge): a block whose forces span little
// (relative spread of f_n^gamma well under `prior_spread`) takes the recording's depth law and
// only its offset h from the data, so a few samples at one force cannot tilt the surface.
bool fit_cell(std::vector<const PlaneSample*>& block, double gamma, const EstimateParams& prm,
              CellFit& out, double b_prior = 0.0, double prior_spread = 0.0) {
  if (block.size() < static_cast<std::size_t>(prm.min_cell_samples)) return false;
  const auto [lo, hi] =
      std::minmax_element(block.begin(), block.end(),
                          [](const PlaneSample* a, const PlaneSample* b) { return a->fn < b->fn; });
  if ((*hi)->fn - (*lo)->fn < prm.min_force_spread_n) return false;
  const std::size_t n = block.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = block[i]->slope * std::pow(block[i]->fn, gamma), y = block[i]->s;
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double dn = static_cast<double>(n), den = dn * sxx - sx * sx;
  if (!(den > 1e-12)) return false;
  double ds_dx = (dn * sxy - sx * sy) / den;  // ds/dx = -b
  if (b_prior > 0) {
    // Centred sums: Sxx = sum (x - mean)^2, Sxy likewise; ridge weight kappa = n (spread mean)^2.
    const double mx = sx / dn, cxx = sxx - dn * mx * mx, cxy = sxy - sx * sy / dn;
    const double kappa = dn * prior_spread * prior_spread * mx * mx;
    ds_dx = (cxy - kappa * b_prior) / (cxx + kappa);
  }
  ds_dx = std::min(ds_dx, 0.0);
  out.b = -ds_dx;
  out.h = (sy - ds_dx * sx) / dn;
  out.sse = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r =
        block[i]->s - (out.h - out.b * block[i]->slope * std::pow(block[i]->fn, gamma));
    out.sse += r * r;
  }
  out.n = n;
  return true;
}

// The value a plane fitted (least squares) to the known cells within `r` cells of (x, y) takes
// at (x, y); the mean of those cells when they do not span a plane. False: none known.
bool plane_extrapolate(const Grid& h, const std::vector<char>& known, int x, int y, int r,
                       double& out) {
  const int W = h.width, H = h.height;
  double n = 0, sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, syy = 0, sxz = 0, syz = 0;
  for (int yy = std::max(0, y - r); yy <= std::min(H - 1, y + r); ++yy)
    for (int xx = std::max(0, x - r); xx <= std::min(W - 1, x + r); ++xx) {
      if (!known[std::size_t(yy) * W + xx]) continue;
      const double dx = xx - x, dy = yy - y, z = h.at(xx, yy);
      n += 1, sx += dx, sy += dy, sz += z, sxx += dx * dx, sxy += dx * dy, syy += dy * dy;
      sxz += dx * z, syz += dy * z;
    }
  if (n == 0) return false;
  out = sz / n;
  if (n < 6) return true;
  // Centred normal equations of z = a + b dx + c dy; a is the value at the cell itself.
  const double mx = sx / n, my = sy / n, mz = sz / n;
  const double cxx = sxx - n * mx * mx, cxy = sxy - n * mx * my, cyy = syy - n * my * my;
  const double cxz = sxz - n * mx * mz, cyz = syz - n * my * mz;
  const double det = cxx * cyy - cxy * cxy;
  if (!(det > 1e-6 * (cxx * cyy + 1e-12))) return true;
  const double b = (cxz * cyy - cyz * cxy) / det, c = (cyz * cxx - cxz * cxy) / det;
  out = mz - b * mx - c * my;
  if (!std::isfinite(out)) out = mz;
  return true;
}

// Each cell's 3 x 3 neighbourhood (clamped at the edges) reduced to its mean, or its largest
// value with `largest`.
Grid mean3x3(const Grid& h, bool largest = false) {
  const int W = h.width, H = h.height;
  Grid out(W, H, 0.0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      double acc = largest ? h.at(x, y) : 0.0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const double v = h.at(std::clamp(x + dx, 0, W - 1), std::clamp(y + dy, 0, H - 1));
          acc = largest ? std::max(acc, v) : acc + v;
        }
      out.at(x, y) = largest ? acc : acc / 9;
    }
  return out;
}

// Fills unfitted cells (mask 0) front by front, each with the plane through the known cells
// around it (so a curved surface's slope carries on past the data instead of levelling off),
// then smooths every cell.
void fill_and_smooth(Grid& h, std::vector<char> known, int passes) {
  const int W = h.width, H = h.height;
  constexpr int kPlaneRadius = 3;  // cells: a 7 x 7 window
  for (int it = 0; it < 4 * (W + H); ++it) {
    bool any = false;
    std::vector<char> next = known;
    Grid filled = h;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        if (known[std::size_t(y) * W + x]) continue;
        bool touches = false;
        for (int dy = -1; dy <= 1 && !touches; ++dy)
          for (int dx = -1; dx <= 1 && !touches; ++dx) {
            const int xx = x + dx, yy = y + dy;
            touches = xx >= 0 && yy >= 0 && xx < W && yy < H && known[std::size_t(yy) * W + xx];
          }
        double v = 0;
        if (touches && plane_extrapolate(h, known, x, y, kPlaneRadius, v))
          filled.at(x, y) = v, next[std::size_t(y) * W + x] = 1, any = true;
      }
    h = std::move(filled);
    known.swap(next);
    if (!any) break;
  }
  for (int pass = 0; pass < passes; ++pass) h = mean3x3(h);
}

// The plane frame around `axis`.
void plane_frame(const Vec3& axis, SurfaceEstimate& s) {
  s.axis = axis;
  const SurfaceFrame fr = surface_frame(s.axis);
  s.e1 = fr.t0;
  s.e2 = fr.t1;
}

// The normal of the least-squares plane through the fitted heights (u, v, h) in world axes.
Vec3 plane_normal(const SurfaceEstimate& s, const std::vector<Vec3>& uvh) {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Vec3 b = Vec3::Zero();
  for (const Vec3& x : uvh) {
    const Vec3 r(x.x(), x.y(), 1.0);
    a += r * r.transpose();
    b += r * x.z();
  }
  const Vec3 c = a.ldlt().solve(b);
  const Vec3 n = -c.x() * s.e1 - c.y() * s.e2 + s.axis;
  return c.allFinite() && n.norm() > 1e-9 ? Vec3(n.normalized()) : s.axis;
}

}  // namespace

void EstimateParams::validate() const {
  if (!(cell_mm > 0) || !std::isfinite(cell_mm) || !(margin_mm >= 0) || min_cell_samples < 3 ||
      !(contact_threshold_n >= 0) || smooth_passes < 0 || radii.empty() ||
      !(slope_prior_spread >= 0) || !std::isfinite(slope_prior_spread))
    throw Error("surface estimate: cell and margin must be positive mm, at least 3 samples a cell");
  if (!(hold_quantile >= 0 && hold_quantile < 1))
    throw Error(
        fmt::format("surface estimate: hold quantile must be in [0, 1), got {}", hold_quantile));
  for (double s : radii)
    if (!(s > 0) || !std::isfinite(s))
      throw Error(fmt::format("friction estimate: radii must be positive, got {}", s));
  for (double t : relaxation_s)
    if (!(t >= 0) || !std::isfinite(t))
      throw Error(fmt::format("friction estimate: relaxation times must be >= 0 s, got {}", t));
}

double SurfaceEstimate::height_at(double u, double v) const {
  const double x = std::clamp(u / cell_mm - 0.5, 0.0, double(height.width - 1));
  const double y = std::clamp(v / cell_mm - 0.5, 0.0, double(height.height - 1));
  const int x0 = std::min(int(x), height.width - 2), y0 = std::min(int(y), height.height - 2);
  const double fx = x - x0, fy = y - y0;
  return (1 - fy) * ((1 - fx) * height.at(x0, y0) + fx * height.at(x0 + 1, y0)) +
         fy * ((1 - fx) * height.at(x0, y0 + 1) + fx * height.at(x0 + 1, y0 + 1));
}

double SurfaceEstimate::depth(const Vec3& p) const {
  const Vec3 d = p - origin;
  return height_at(d.dot(e1), d.dot(e2)) - d.dot(axis);
}

double SurfaceEstimate::depth_for_force(double f_n) const {
  return b_median * std::pow(std::max(f_n, 0.0), gamma);
}

double SurfaceEstimate::force_at_depth(double d) const {
  if (!(d > 0) || !(b_median > 0)) return 0.0;
  return std::pow(d / b_median, 1.0 / gamma);
}

TriMesh SurfaceEstimate::mesh() const {
  TriMesh m;
  const int W = height.width, H = height.height;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      m.positions.push_back(origin + (x + 0.5) * cell_mm * e1 + (y + 0.5) * cell_mm * e2 +
                            height.at(x, y) * axis);
  // (e1, e2, axis) is right-handed: counter-clockwise in (u, v) faces +axis.
  for (int y = 0; y + 1 < H; ++y)
    for (int x = 0; x + 1 < W; ++x) {
      const std::int32_t a = y * W + x, b = a + 1, c = a + W, d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  m.compute_normals();
  return m;
}

namespace {

// The outward normal of `s` at the world point p (from the height field's slope).
Vec3 normal_at(const SurfaceEstimate& s, const Vec3& p) {
  const Vec3 d = p - s.origin;
  const double u = d.dot(s.e1), v = d.dot(s.e2), h = 0.5 * s.cell_mm;
  const double du = (s.height_at(u + h, v) - s.height_at(u - h, v)) / (2 * h);
  const double dv = (s.height_at(u, v + h) - s.height_at(u, v - h)) / (2 * h);
  const Vec3 n = s.axis - du * s.e1 - dv * s.e2;
  return n.allFinite() && n.norm() > 1e-9 ? Vec3(n.normalized()) : s.axis;
}

// The height field around `axis` (see the file comment); `uvh` gets the fitted cells' centres
// and heights. With `prev` (an earlier estimate about the same axis) each sample's normal force
// and depth are taken along that surface's local normal, not the axis: on a slope tilted by t
// the depth along the axis is the normal depth / cos t.
SurfaceEstimate surface_about(const Recording& rec, const std::vector<std::size_t>& idx,
                              const EstimateParams& prm, const Vec3& axis, const std::string& path,
                              std::vector<Vec3>& uvh, const SurfaceEstimate* prev = nullptr) {
  SurfaceEstimate s;
  s.cell_mm = prm.cell_mm;
  plane_frame(axis, s);
  double umin = 1e300, vmin = 1e300, umax = -1e300, vmax = -1e300;
  std::vector<PlaneSample> ps;
  ps.reserve(idx.size());
  for (std::size_t i : idx) {
    const Vec3& p = rec.p[i];
    // A force that pulls along -axis (by more than half the contact threshold, not noise) does
    // not press this surface: a tool's weight left in the readings while it hangs in the air
    // (-0.1 N for 10 g), adhesion on lifting off.
    if (rec.f[i].dot(s.axis) < -0.5 * prm.contact_threshold_n) continue;
    if (prev) {
      const Vec3 n = normal_at(*prev, p);
      const double c = std::max(n.dot(s.axis), 0.5);  // tilts beyond 60 degrees: capped
      ps.push_back(
          {p.dot(s.e1), p.dot(s.e2), p.dot(s.axis), std::max(rec.f[i].dot(n), 0.0), 1.0 / c});
    } else {
      // A force pulling away (adhesion, a mostly tangential push) counts as zero normal force,
      // not as a NaN of pow() that would void its whole block.
      ps.push_back({p.dot(s.e1), p.dot(s.e2), p.dot(s.axis), std::max(rec.f[i].dot(s.axis), 0.0)});
    }
    umin = std::min(umin, ps.back().u), umax = std::max(umax, ps.back().u);
    vmin = std::min(vmin, ps.back().v), vmax = std::max(vmax, ps.back().v);
  }
  umin -= prm.margin_mm, vmin -= prm.margin_mm, umax += prm.margin_mm, vmax += prm.margin_mm;
  const int W = std::clamp(int(std::ceil((umax - umin) / prm.cell_mm)), 2, 2000);
  const int H = std::clamp(int(std::ceil((vmax - vmin) / prm.cell_mm)), 2, 2000);
  s.origin = umin * s.e1 + vmin * s.e2;
  std::vector<std::vector<const PlaneSample*>> cells(std::size_t(W) * H);
  for (PlaneSample& q : ps) {
    q.u -= umin, q.v -= vmin;
    const int x = std::clamp(int(q.u / prm.cell_mm), 0, W - 1);
    const int y = std::clamp(int(q.v / prm.cell_mm), 0, H - 1);
    cells[std::size_t(y) * W + x].push_back(&q);
  }
  const auto block_of = [&](int x, int y) {
    std::vector<const PlaneSample*> b;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
        const auto& c = cells[std::size_t(yy) * W + xx];
        b.insert(b.end(), c.begin(), c.end());
      }
    return b;
  };
  // gamma: the smallest summed residual over the cells that every exponent can fit.
  double best_sse = 1e300;
  for (int k = 0; k < kGammaSteps; ++k) {
    const double g = gamma_candidate(k);
    double sse = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        if (cells[std::size_t(y) * W + x].empty()) continue;
        std::vector<const PlaneSample*> b = block_of(x, y);
        CellFit f;
        if (fit_cell(b, g, prm, f)) sse += f.sse;
      }
    if (sse < best_sse) best_sse = sse, s.gamma = g;
  }
  s.height = Grid(W, H, 0.0);
  std::vector<char> known(std::size_t(W) * H, 0);
  std::vector<double> bs;
  // The recording's depth law first (median slope of the free fits), then every cell's fit with
  // its slope shrunk towards it.
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      if (cells[std::size_t(y) * W + x].empty()) continue;
      std::vector<const PlaneSample*> b = block_of(x, y);
      CellFit f;
      if (fit_cell(b, s.gamma, prm, f)) bs.push_back(f.b);
    }
  const double b0 = estimate_median(bs);
  bs.clear();
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      if (cells[std::size_t(y) * W + x].empty()) continue;
      std::vector<const PlaneSample*> b = block_of(x, y);
      CellFit f;
      if (!fit_cell(b, s.gamma, prm, f, b0, prm.slope_prior_spread)) continue;
      s.height.at(x, y) = f.h;
      uvh.emplace_back((x + 0.5) * prm.cell_mm, (y + 0.5) * prm.cell_mm, f.h);
      known[std::size_t(y) * W + x] = 1;
      bs.push_back(f.b);
      ++s.cells_fitted;
    }
  if (s.cells_fitted == 0)
    throw ParseError(path, 1,
                     fmt::format("surface estimate: expected places pressed with a force range of "
                                 "at least {} N, found none (cells of {} mm)",
                                 prm.min_force_spread_n, prm.cell_mm));
  s.cells_filled = std::size_t(W) * H - s.cells_fitted;
  s.b_median = estimate_median(bs);
  fill_and_smooth(s.height, std::move(known), prm.smooth_passes);
  return s;
}

// Raises the surface where it leaves the samples pressing there above it: a sample that presses
// (f . axis above the contact threshold) lies under the undeformed surface. Per cell, the
// `hold_quantile` quantile of the pressing samples' height above the surface (cells with at least
// 4 of them; 0 where they are under it); that lift is spread to the 8 neighbours (the largest)
// and smoothed by three 3 x 3 mean passes, so the normals stay smooth.
void hold_pressing_samples(const Recording& rec, const std::vector<std::size_t>& idx,
                           const EstimateParams& prm, SurfaceEstimate& s) {
  if (!(prm.hold_quantile > 0)) return;
  const int W = s.height.width, H = s.height.height;
  std::vector<std::vector<double>> above(std::size_t(W) * H);
  for (std::size_t i : idx) {
    if (!(rec.f[i].dot(s.axis) > prm.contact_threshold_n)) continue;
    const Vec3 d = rec.p[i] - s.origin;
    const int x = std::clamp(int(d.dot(s.e1) / s.cell_mm), 0, W - 1);
    const int y = std::clamp(int(d.dot(s.e2) / s.cell_mm), 0, H - 1);
    above[std::size_t(y) * W + x].push_back(-s.depth(rec.p[i]));
  }
  Grid lift(W, H, 0.0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      std::vector<double>& v = above[std::size_t(y) * W + x];
      if (v.size() < 4) continue;
      const auto k = v.begin() + std::ptrdiff_t(prm.hold_quantile * double(v.size() - 1));
      std::nth_element(v.begin(), k, v.end());
      if (*k > 0) lift.at(x, y) = *k, ++s.cells_raised;
    }
  if (s.cells_raised == 0) return;
  lift = mean3x3(lift, true);
  for (int k = 0; k < 3; ++k) lift = mean3x3(lift);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      s.height.at(x, y) += lift.at(x, y);
      s.raised_max_mm = std::max(s.raised_max_mm, lift.at(x, y));
    }
}

}  // namespace

SurfaceEstimate estimate_surface(const Recording& rec, const EstimateParams& prm,
                                 const std::string& path) {
  prm.validate();
  std::vector<std::size_t> idx;
  Vec3 mean_force = Vec3::Zero();
  for (std::size_t i = 0; i < rec.size(); ++i)
    if (rec.f[i].norm() > prm.contact_threshold_n) idx.push_back(i), mean_force += rec.f[i];
  if (idx.size() < static_cast<std::size_t>(4 * prm.min_cell_samples))
    throw ParseError(path, 1,
                     fmt::format("surface estimate: expected at least {} samples with |f| above "
                                 "{} N, got {}",
                                 4 * prm.min_cell_samples, prm.contact_threshold_n, idx.size()));
  // First about the mean force (friction tilts it), then about the normal of the plane through
  // that surface, twice.
  Vec3 axis = mean_force.norm() > 1e-12 ? Vec3(mean_force.normalized()) : Vec3::UnitZ();
  std::vector<Vec3> uvh;
  SurfaceEstimate s = surface_about(rec, idx, prm, axis, path, uvh);
  for (int pass = 0; pass < 2; ++pass) {
    const Vec3 n = plane_normal(s, uvh);
    if (n.dot(axis) > std::cos(0.2 * std::numbers::pi / 180)) break;
    axis = n;
    uvh.clear();
    s = surface_about(rec, idx, prm, axis, path, uvh);
  }
  // Once more with each sample's normal force and depth along the local normal of that surface
  // (a second such pass changes the lab dome's surface by 0.01 mm).
  const SurfaceEstimate about_axis = s;
  uvh.clear();
  s = surface_about(rec, idx, prm, axis, path, uvh, &about_axis);
  hold_pressing_samples(rec, idx, prm, s);
  return s;
}

friction::SysModel cone_sys(const SurfaceEstimate& s, double radius_per_n, double mu,
                            double tau_s) {
  friction::SysModel m;
  m.f_normal_levels.assign(std::begin(kLevelsN), std::end(kLevelsN));
  for (int k = 0; k < 8; ++k) m.angles.push_back(k * std::numbers::pi / 4);
  m.plateaus = {0.1, 0.6};
  m.tangent_reference = s.e1;
  const double U = s.height.width * s.cell_mm, V = s.height.height * s.cell_mm;
  int id = 0;
  // The corners and the centre of the surface's region (four triangles, none degenerate).
  const std::array<std::pair<double, double>, 5> at{
      {{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}, {0.5, 0.5}}};
  for (const auto& [fx, fy] : at) {
    friction::SysPoint p;
    p.id = id++;
    const double u = fx * U, v = fy * V;
    p.position = s.origin + u * s.e1 + v * s.e2 + s.height_at(u, v) * s.axis;
    p.normal = s.axis;
    for (double fn : m.f_normal_levels)
      for (int k = 0; k < 8; ++k) {
        friction::SysBorder b;
        b.f_normal = fn;
        b.direction = k;
        b.result.f_limit = mu * fn;
        b.result.depth = std::max(s.depth_for_force(fn), 1e-3);
        b.result.radius = radius_per_n * fn;
        friction::BorderStep st;
        st.f_tangential = b.result.f_limit;
        st.depth = b.result.depth;
        st.radius = b.result.radius;
        b.steps.push_back(st);
        b.result.labels.push_back(0);
        b.result.split = 1;
        p.borders.push_back(std::move(b));
      }
    // A tangential spring mu / c N/mm; the excess beyond g_s relaxes in tau (Duvaut-Lions).
    p.tangential_stiffness = mu / radius_per_n;
    p.creep_viscosity = tau_s * p.tangential_stiffness;
    m.points.push_back(std::move(p));
  }
  m.rebuild();
  return m;
}

namespace {

// Tangential force residual of the cone `radius_per_n`: f_t ~ mu f_n u_t / r over the samples in
// contact (measured and geometric).
FrictionEstimate fit_radius(const Recording& rec, const SurfaceEstimate& s,
                            const friction::ShapeQuery& shape, double radius_per_n, double tau_s,
                            double threshold) {
  check_cancel();  // one proxy track per candidate: the estimate's long part
  const friction::SysModel sys = cone_sys(s, radius_per_n, 1.0, tau_s);
  const friction::ProxyColumns pc = friction::proxy_track({.sys = &sys, .shape = &shape}, rec);
  double sgg = 0, sfg = 0, sff = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < rec.size(); ++i) {
    if (!pc.contact[i] || rec.f[i].norm() <= threshold) continue;
    const Vec3& nn = pc.n[i];
    const double fn = rec.f[i].dot(nn);
    const Vec3 ft = rec.f[i] - fn * nn;
    const Vec3 d = pc.q[i] - rec.p[i];
    const Vec3 ut = d - d.dot(nn) * nn;
    const double r = radius_per_n * std::max(s.force_at_depth(d.dot(nn)), 1e-3);
    const Vec3 g = std::max(fn, 0.0) * ut / r;
    sgg += g.squaredNorm(), sfg += ft.dot(g), sff += ft.squaredNorm(), ++n;
  }
  FrictionEstimate e;
  e.radius_per_n = radius_per_n;
  e.tau_s = tau_s;
  e.samples = n;
  if (n == 0) return e;
  e.mu = sgg > 0 ? std::max(sfg / sgg, 0.0) : 0.0;
  const double sse = sff - 2 * e.mu * sfg + e.mu * e.mu * sgg;
  e.rmse_t_n = std::sqrt(std::max(sse, 0.0) / double(n));
  e.rmse_t0_n = std::sqrt(sff / double(n));
  return e;
}

// The pressing samples of `rec` and how many of them the estimated surface leaves in the air.
void count_pressing(const Recording& rec, double threshold_n, RecordingEstimate& e) {
  std::vector<double> fn;
  for (std::size_t i = 0; i < rec.size(); ++i) {
    const double f = rec.f[i].dot(e.surface.axis);
    if (!(f > threshold_n) || !rec.p[i].allFinite()) continue;
    fn.push_back(f);
    if (e.surface.depth(rec.p[i]) < 0) ++e.pressing_above;
  }
  e.pressing_samples = fn.size();
  if (fn.empty()) return;
  std::sort(fn.begin(), fn.end());
  const auto at = [&](double q) { return fn[std::size_t(q * double(fn.size() - 1))]; };
  e.pressing_fn_p5 = at(0.05), e.pressing_fn_p95 = at(0.95);
}

}  // namespace

RecordingEstimate estimate_recording(const Recording& rec, const EstimateParams& prm,
                                     const std::string& path) {
  RecordingEstimate e;
  e.surface = estimate_surface(rec, prm, path);
  e.mesh = e.surface.mesh();
  for (std::size_t i = 0; i < rec.size(); ++i)
    if (e.surface.depth(rec.p[i]) < -RecordingEstimate::kAirMm && rec.f[i].allFinite())
      e.air_force += rec.f[i], ++e.air_samples;
  if (e.air_samples) e.air_force /= double(e.air_samples);
  count_pressing(rec, prm.contact_threshold_n, e);
  const friction::MeshSurface shape(e.mesh, 0.0);
  bool first = true;
  const auto consider = [&](double radius_per_n, double tau_s) {
    const FrictionEstimate f =
        fit_radius(rec, e.surface, shape, radius_per_n, tau_s, prm.contact_threshold_n);
    if (f.samples == 0) return;
    if (first || f.rmse_t_n < e.friction.rmse_t_n) e.friction = f;
    first = false;
  };
  std::vector<double> grid = prm.radii;
  std::sort(grid.begin(), grid.end());
  for (double radius_per_n : grid) consider(radius_per_n, 0.0);
  // The relaxation time at the best radius, then the radius refined at that time.
  if (!first)
    for (double tau : prm.relaxation_s) consider(e.friction.radius_per_n, tau);
  // Then the geometric midpoints next to the best radius (at that time), twice, and the same for
  // the time (at that radius).
  const auto refine = [&](std::vector<double> values, const auto& best_of, const auto& try_at) {
    std::sort(values.begin(), values.end());
    for (int pass = 0; pass < 2 && !first; ++pass) {
      const double best = best_of();
      if (!(best > 0)) return;  // a time of 0 (rate-independent) has no geometric neighbours
      const auto it = std::lower_bound(values.begin(), values.end(), best);
      const double lo = it == values.begin() ? best / 1.5 : *std::prev(it);
      const double hi =
          it == values.end() || std::next(it) == values.end() ? best * 1.5 : *std::next(it);
      const double a = std::sqrt(lo * best), b = std::sqrt(best * hi);
      try_at(a);
      try_at(b);
      values.insert(std::upper_bound(values.begin(), values.end(), a), a);
      values.insert(std::upper_bound(values.begin(), values.end(), b), b);
    }
  };
  const double tau = e.friction.tau_s;
  refine(
      grid, [&] { return e.friction.radius_per_n; }, [&](double c) { consider(c, tau); });
  const double radius = e.friction.radius_per_n;
  refine(
      prm.relaxation_s, [&] { return e.friction.tau_s; }, [&](double t) { consider(radius, t); });
  if (first)
    throw ParseError(path, 1,
                     "friction estimate: expected samples in contact with the estimated surface, "
                     "found none");
  e.sys = cone_sys(e.surface, e.friction.radius_per_n, e.friction.mu, e.friction.tau_s);
  return e;
}

std::string estimate_warning(const RecordingEstimate& e) {
  if (e.air_samples < 50 || !(e.air_force.norm() > 0.03)) return {};
  // A surface that leaves pressing samples in the air (estimate_contact_warning) says nothing
  // about the force in the air.
  if (!estimate_contact_warning(e).empty()) return {};
  return fmt::format(
      "warning: {} samples more than {:g} mm above the estimated surface (in the air) average a "
      "force of ({:.3f}, {:.3f}, {:.3f}) N, not zero: an uncompensated tool weight or a sensor "
      "offset? It bends the depth-force law and the surface (`inhap record` / `inhap studio` "
      "--tool-mass, or subtract the offset)",
      e.air_samples, RecordingEstimate::kAirMm, e.air_force.x(), e.air_force.y(), e.air_force.z());
}

std::string estimate_contact_warning(const RecordingEstimate& e) {
  if (e.pressing_samples < 50) return {};
  const double share = double(e.pressing_above) / double(e.pressing_samples);
  const bool above = share > 0.05;
  const bool narrow = e.pressing_fn_p95 - e.pressing_fn_p5 < RecordingEstimate::kNarrowForceN;
  if (!above && !narrow) return {};
  const std::string what =
      above ? fmt::format(
                  "{:.0f} % of the {} samples pressing with more than the contact "
                  "threshold lie above the estimated surface, so the model renders no "
                  "force there; their normal force spans",
                  100 * share, e.pressing_samples)
            : fmt::format("the {} samples pressing with more than the contact threshold span only",
                          e.pressing_samples);
  return fmt::format(
      "warning: {} {:.2f}-{:.2f} N (5-95 %), a depth of {:.2f}-{:.2f} mm by the fitted law: a "
      "force-controlled exploration at one light force? The surface and the depth-force law are "
      "poorly determined from it; presses over a wider force range make them measurable. Compare "
      "the model with the nearest-neighbour baselines (`inhap model eval`, `inhap eval "
      "recordings`)",
      what, e.pressing_fn_p5, e.pressing_fn_p95, e.surface.depth_for_force(e.pressing_fn_p5),
      e.surface.depth_for_force(e.pressing_fn_p95));
}

std::string estimate_note(const RecordingEstimate& e) {
  const SurfaceEstimate& s = e.surface;
  const std::string raised = s.cells_raised
                                 ? fmt::format(
                                       ", {} cells raised by up to {:.2f} mm to hold the samples "
                                       "pressing there",
                                       s.cells_raised, s.raised_max_mm)
                                 : std::string();
  return fmt::format(
      "estimated from the recording: surface ({} x {} cells of {:g} mm, {} fitted, push axis "
      "({:.2f}, {:.2f}, {:.2f}), depth law d = {:.3f} f_n^{:.2f} mm{}), normals from it, proxy on "
      "it, "
      "friction mu = {:.3f} with g_s radius {:.2f} mm/N x f_n, slip relaxation {:.3g} s "
      "(tangential "
      "RMS {:.3f} -> {:.3f} N)",
      s.height.width, s.height.height, s.cell_mm, s.cells_fitted, s.axis.x(), s.axis.y(),
      s.axis.z(), s.b_median, s.gamma, raised, e.friction.mu, e.friction.radius_per_n,
      e.friction.tau_s, e.friction.rmse_t0_n, e.friction.rmse_t_n);
}

}  // namespace inhap::datadriven
