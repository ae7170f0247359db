#include "inhap/friction/sys_model.hpp"
#include "inhap/core/stats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "inhap/core/error.hpp"
#include "inhap/friction/shape_query.hpp"

namespace inhap::friction {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Distinct values (sorted) with a relative tolerance.
std::vector<double> distinct(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (double x : v)
    if (out.empty() || std::abs(x - out.back()) > 1e-6 * std::max(1.0, std::abs(x)))
      out.push_back(x);
  return out;
}

std::size_t index_of(const std::vector<double>& levels, double x) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < levels.size(); ++i)
    if (std::abs(levels[i] - x) < std::abs(levels[best] - x)) best = i;
  return best;
}

bool usable(const CycleRecord& c) {
  return c.status == CycleStatus::kOk || c.status == CycleStatus::kUnsettled ||
         c.status == CycleStatus::kSlipCapped;
}

double wrap_angle(double a) {
  a = std::fmod(a, kTwoPi);
  return a < 0 ? a + kTwoPi : a;
}

// |f_t| / f_n of the measured reaction force decomposed at the normal n (NaN when f_n <= 0).
double force_ratio(const CycleRecord& c, const Vec3& n) {
  const double fn = c.f_meas.dot(n);
  if (!(fn > 1e-6)) return std::numeric_limits<double>::quiet_NaN();
  return (c.f_meas - fn * n).norm() / fn;
}

// The step's force ratio at n_c (anchor) and at the shape's normal under the displaced probe
// p_c + u_meas (probe; n_c without a shape).
void contact_ratios(const CycleRecord& c, const ShapeQuery* shape, BorderStep& st) {
  Vec3 n = c.nc, point;
  if (shape) {
    Vec3 nn;
    if (shape->closest(c.pc + c.u_meas, point, nn) && nn.allFinite()) n = nn;
  }
  st.ratio_anchor = force_ratio(c, c.nc);
  st.ratio_probe = force_ratio(c, n);
}

// Borders of one reference point from its steps (see fit_sys).
void fit_point(SysPoint& p, std::size_t nl, std::size_t nk, double plateau_gap,
               const FitOptions& opt) {
  std::vector<double> slopes, stiff;
  for (SysBorder& b : p.borders) {
    b.result = find_elastic_border(b.steps, opt.border);
    if (b.result.growth_slope > 0) slopes.push_back(b.result.growth_slope);
  }
  const double slope = median(slopes, 0.0);
  for (SysBorder& b : p.borders)
    if (b.result.growth_slope == 0 && slope > 0)
      b.result = find_elastic_border(b.steps, opt.border, slope);
  // Borders beyond the force range: same f_T / f_N as the highest measured level.
  for (std::size_t k = 0; k < nk; ++k)
    for (std::size_t j = 1; j < nl; ++j) {
      BorderResult& r = p.borders[j * nk + k].result;
      if (!r.no_sliding) continue;
      for (std::size_t i = j; i-- > 0;) {
        const SysBorder& lower = p.borders[i * nk + k];
        if (lower.result.no_sliding || lower.result.extrapolated) continue;
        const double fn = p.borders[j * nk + k].f_normal;
        const double f = lower.result.f_limit / lower.f_normal * fn;
        const double load = lower.result.f_limit_load / lower.f_normal * fn;
        if (f > r.f_limit) {
          if (r.f_limit_load > 0) r.radius *= load / r.f_limit_load;
          r.f_limit = f;
          r.f_limit_load = load;
          r.ratio_limit = f / fn;
          r.extrapolated = true;
        }
        break;
      }
    }
  for (const SysBorder& b : p.borders)
    if (b.result.radius > 0 && !b.result.no_sliding)
      stiff.push_back(b.result.f_limit_load / b.result.radius);
  p.tangential_stiffness = median(stiff, 0.0);
  p.creep_viscosity = slope > 0 ? std::max(0.0, plateau_gap / slope - opt.load_damping) : 0.0;
}

}  // namespace

const char* to_string(ForceFrame f) {
  switch (f) {
    case ForceFrame::kAnchor:
      return "anchor";
    case ForceFrame::kProbe:
      return "probe";
    case ForceFrame::kAuto:
      break;
  }
  return "auto";
}

ForceFrame force_frame_from_string(const std::string& s) {
  if (s == "auto") return ForceFrame::kAuto;
  if (s == "anchor") return ForceFrame::kAnchor;
  if (s == "probe") return ForceFrame::kProbe;
  throw Error(fmt::format("expected a force frame auto|anchor|probe, got '{}'", s));
}

std::size_t SysModel::point_index(int id) const {
  std::string ids;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].id == id) return i;
    if (i) ids += ',';
    ids += std::to_string(points[i].id);
  }
  throw Error(fmt::format("expected a reference point id in {{{}}}, got {}", ids, id));
}

void SysModel::rebuild(const std::vector<Tri>* triangles) {
  const std::size_t nl = f_normal_levels.size(), nk = angles.size();
  if (points.empty()) throw Error("sliding yield surfaces: expected at least one reference point");
  if (nl < 1 || nl > static_cast<std::size_t>(YieldSurface::kMaxLevels) || nk < 1 ||
      nk > static_cast<std::size_t>(YieldSurface::kMaxDirections))
    throw Error(fmt::format(
        "sliding yield surfaces: expected 1..{} levels and 1..{} directions, got {} and {}",
        YieldSurface::kMaxLevels, YieldSurface::kMaxDirections, nl, nk));
  std::vector<Vec3> positions;
  Vec3 axis = Vec3::Zero();
  for (SysPoint& p : points) {
    if (p.borders.size() != nl * nk)
      throw Error(
          fmt::format("reference point {}: expected {} borders ({} levels x {} directions), got {}",
                      p.id, nl * nk, nl, nk, p.borders.size()));
    std::vector<double> depth(nl * nk), radius(nl * nk), fn(nl * nk), ft(nl * nk);
    for (std::size_t k = 0; k < nk; ++k) {
      double prev = 0.0;
      for (std::size_t j = 0; j < nl; ++j) {
        const BorderResult& r = p.borders[j * nk + k].result;
        // Depth must grow with f_N; noise that breaks this is clamped (1 um steps).
        const double d = std::max(r.depth, prev + 1e-3);
        depth[j * nk + k] = d;
        radius[j * nk + k] = std::max(0.0, r.radius);
        fn[j * nk + k] = f_normal_levels[j];
        ft[j * nk + k] = std::max(0.0, r.f_limit);
        prev = d;
      }
    }
    p.gs = YieldSurface::make(angles, static_cast<int>(nl), depth, radius);
    p.fs = YieldSurface::make(angles, static_cast<int>(nl), fn, ft);
    positions.push_back(p.position);
    axis += p.normal;
  }
  if (!(axis.norm() > 1e-6)) throw Error("sliding yield surfaces: reference normals cancel out");
  reference_mesh = (triangles && !triangles->empty())
                       ? ReferenceMesh::from_triangles(positions, axis, *triangles)
                       : ReferenceMesh::build(positions, axis);
}

namespace {

using StepPair = std::pair<const CycleRecord*, const CycleRecord*>;  // short, long plateau

// The cycle of a step whose force and displacement to use: of two cycles measured in their
// plateaus (t_measurement >= 0), the one measured nearer the protocol's point, 90 ms into the
// plateau (ProfileRates::measurement_offset), so that every step is compared at the same point of
// its loading history; otherwise, and within 2 ms (a tie), the short-plateau cycle (the lab
// measures both at 90 ms, to a tick; a cycle that slipped during its ramp was measured then), as
// before the column existed.
const CycleRecord& measured_cycle(const CycleRecord& s, const CycleRecord& l) {
  const double ref = ProfileRates{}.measurement_offset;
  constexpr double kTie_s = 2e-3;  // servo ticks (1 ms) apart is the same point
  const bool both_in_plateau = s.t_measurement_s >= 0 && l.t_measurement_s >= 0;
  return both_in_plateau &&
                 std::abs(l.t_measurement_s - ref) + kTie_s < std::abs(s.t_measurement_s - ref)
             ? l
             : s;
}

BorderStep make_step(double ft, const CycleRecord& s, const CycleRecord& l, const FitOptions& opt) {
  BorderStep st;
  st.f_tangential = ft;
  st.u_short = s.up_tangential();
  st.u_long = l.up_tangential();
  st.capped = s.status == CycleStatus::kSlipCapped || l.status == CycleStatus::kSlipCapped;
  st.f_normal = s.f_normal;
  const CycleRecord& m = measured_cycle(s, l);
  st.depth = -m.u_meas.dot(m.nc);
  contact_ratios(m, opt.shape, st);
  if (opt.shape) {  // geometric depth: from the undeformed surface, not from p_c
    const double d0 = opt.shape->depth(m.pc);
    if (std::isfinite(d0)) st.depth += d0;
  }
  st.radius = (m.u_meas - m.u_meas.dot(m.nc) * m.nc).norm();
  return st;
}

// Angles of the K directions of one point from its t_0, snapped to the nominal 2 pi k / K
// (avoids 2 pi - epsilon for k = 0).
std::vector<double> direction_angles(int id, const std::vector<Vec3>& tsum, const Vec3& t0,
                                     const Vec3& t1, double tolerance) {
  const std::size_t nk = tsum.size();
  std::vector<double> angles(nk);
  for (std::size_t k = 0; k < nk; ++k) {
    if (!(tsum[k].norm() > 0))
      throw Error(fmt::format("sys fit: reference point {} has no cycles in direction {}", id, k));
    angles[k] = wrap_angle(std::atan2(tsum[k].dot(t1), tsum[k].dot(t0)));
    const double nominal = kTwoPi * static_cast<double>(k) / static_cast<double>(nk);
    double d = std::abs(angles[k] - nominal);
    d = std::min(d, kTwoPi - d);
    if (d <= tolerance) angles[k] = nominal;
  }
  return angles;
}

void check_angles(const SysModel& m, int id, const std::vector<double>& angles, double tolerance) {
  for (std::size_t k = 0; k < angles.size(); ++k) {
    double d = std::abs(angles[k] - m.angles[k]);
    d = std::min(d, kTwoPi - d);
    if (d > tolerance)
      throw Error(
          fmt::format("sys fit: reference point {}: expected direction {} at {:.3f} rad "
                      "from t_0 (as at point {}), got {:.3f} rad",
                      id, k, m.angles[k], m.points.front().id, angles[k]));
  }
}

// One reference point from its cycles; sets m.angles from the first point.
SysPoint build_point(int id, const std::vector<const CycleRecord*>& list, SysModel& m,
                     std::size_t nk, bool two_plateaus, const FitOptions& opt) {
  const std::size_t nl = m.f_normal_levels.size();
  SysPoint p;
  p.id = id;
  Vec3 nsum = Vec3::Zero(), psum = Vec3::Zero();
  for (const CycleRecord* c : list) {
    nsum += c->nc;
    psum += c->reference;
  }
  p.normal = nsum.normalized();
  p.position = psum / static_cast<double>(list.size());
  Vec3 t0, t1;
  tangent_basis(p.normal, opt.tangent_reference, t0, t1);
  // Group by (level, direction), then f_T.
  std::vector<std::map<double, StepPair>> groups(nl * nk);
  std::vector<Vec3> tsum(nk, Vec3::Zero());
  for (const CycleRecord* c : list) {
    const std::size_t j = index_of(m.f_normal_levels, c->f_normal);
    const std::size_t k = static_cast<std::size_t>(c->direction);
    tsum[k] += c->tdir;
    StepPair& slot = groups[j * nk + k][std::round(c->f_tangential * 1e6) / 1e6];
    const bool is_short =
        std::abs(c->t_plateau - m.plateaus[0]) <= std::abs(c->t_plateau - m.plateaus[1]);
    (is_short ? slot.first : slot.second) = c;
  }
  const std::vector<double> angles = direction_angles(id, tsum, t0, t1, opt.angle_tolerance);
  if (m.angles.empty())
    m.angles = angles;
  else
    check_angles(m, id, angles, opt.angle_tolerance);
  for (std::size_t j = 0; j < nl; ++j)
    for (std::size_t k = 0; k < nk; ++k) {
      SysBorder b;
      b.f_normal = m.f_normal_levels[j];
      b.direction = static_cast<int>(k);
      for (const auto& [ft, pair] : groups[j * nk + k]) {
        const CycleRecord* l = two_plateaus ? pair.second : pair.first;
        if (pair.first && l) b.steps.push_back(make_step(ft, *pair.first, *l, opt));
      }
      if (b.steps.empty())
        throw Error(
            fmt::format("sys fit: reference point {} has no complete f_T step at f_N = {} N, "
                        "direction {} (one cycle per plateau is needed)",
                        id, b.f_normal, k));
      p.borders.push_back(std::move(b));
    }
  return p;
}

// Every step's ratio from the frame f (kAnchor or kProbe).
void use_frame(std::vector<SysPoint>& points, ForceFrame f) {
  for (SysPoint& p : points)
    for (SysBorder& b : p.borders)
      for (BorderStep& st : b.steps)
        st.ratio = f == ForceFrame::kAnchor ? st.ratio_anchor : st.ratio_probe;
}

// How much the limit ratio f_T / f_N depends on f_N: median over (point, direction) of
// |ln(ratio at the highest measured level / ratio at the lowest)| (NaN: no pair to compare).
double level_dependence(const SysModel& m) {
  const std::size_t nl = m.f_normal_levels.size(), nk = m.angles.size();
  std::vector<double> d;
  for (std::size_t i = 0; i < m.points.size(); ++i)
    for (std::size_t k = 0; k < nk; ++k) {
      double lo = std::numeric_limits<double>::quiet_NaN(), hi = lo;
      int levels = 0;
      for (std::size_t j = 0; j < nl; ++j) {
        const BorderResult& r = m.border(i, j, k).result;
        if (r.no_sliding || r.extrapolated || !(r.ratio_limit > 0)) continue;
        if (levels++ == 0) lo = r.ratio_limit;
        hi = r.ratio_limit;
      }
      if (levels >= 2) d.push_back(std::abs(std::log(hi / lo)));
    }
  return d.empty() ? std::numeric_limits<double>::quiet_NaN() : median(d, 0.0);
}

// Fits every point's borders in the frame of opt.force_frame (kAuto: the one whose limits
// depend least on f_N; a tie or nothing to compare keeps kProbe).
void fit_points(SysModel& m, const FitOptions& opt) {
  const std::size_t nl = m.f_normal_levels.size(), nk = m.angles.size();
  const double gap = m.plateaus[1] - m.plateaus[0];
  auto fit_all = [&](ForceFrame f) {
    use_frame(m.points, f);
    for (SysPoint& p : m.points) fit_point(p, nl, nk, gap, opt);
    m.force_frame = f;
  };
  if (opt.force_frame != ForceFrame::kAuto) return fit_all(opt.force_frame);
  fit_all(ForceFrame::kAnchor);
  const double anchor = level_dependence(m);
  std::vector<SysPoint> anchored = m.points;  // kept rather than fitted a third time
  fit_all(ForceFrame::kProbe);
  const double probe = level_dependence(m);
  if (std::isfinite(anchor) && (!std::isfinite(probe) || anchor < probe)) {
    m.points = std::move(anchored);
    m.force_frame = ForceFrame::kAnchor;
  }
}

// The slip viscosity is a property of the material, and one point's estimate rests on the
// 1-3 sliding steps of a few sweeps: every point takes the median over all points. A material
// without creep (hard Coulomb friction, e.g. the MuJoCo lab) then gets 0 everywhere even when a
// few points' sweeps were slowed by the device, and the proxy estimator's return stays
// rate-independent there instead of trailing the anchor.
void pool_creep(SysModel& m) {
  std::vector<double> c;
  for (const SysPoint& p : m.points) c.push_back(p.creep_viscosity);
  const double pooled = median(c, 0.0);
  for (SysPoint& p : m.points) p.creep_viscosity = pooled;
}

}  // namespace

SysModel fit_sys(std::span<const CycleRecord> cycles, const FitOptions& opt) {
  std::vector<const CycleRecord*> use;
  for (const CycleRecord& c : cycles)
    if (usable(c)) use.push_back(&c);
  if (use.empty())
    throw Error(
        "sys fit: expected at least one usable cycle (status ok, unsettled or slip capped)");
  SysModel m;
  m.tangent_reference = opt.tangent_reference;
  m.border_options = opt.border;
  std::vector<double> fns, tps;
  int max_dir = 0;
  for (const CycleRecord* c : use) {
    fns.push_back(c->f_normal);
    tps.push_back(c->t_plateau);
    max_dir = std::max(max_dir, c->direction);
  }
  m.f_normal_levels = distinct(fns);
  const std::vector<double> plateaus = distinct(tps);
  m.plateaus = {plateaus.front(), plateaus.back()};
  std::map<int, std::vector<const CycleRecord*>> by_point;
  for (const CycleRecord* c : use) by_point[c->point].push_back(c);
  for (const auto& [id, list] : by_point)
    m.points.push_back(
        build_point(id, list, m, static_cast<std::size_t>(max_dir) + 1, plateaus.size() > 1, opt));
  for (std::size_t k = 1; k < m.angles.size(); ++k)
    if (!(m.angles[k] > m.angles[k - 1]))
      throw Error("sys fit: expected direction indices in increasing angle order around n_c");
  fit_points(m, opt);
  pool_creep(m);
  m.rebuild();
  return m;
}

std::vector<TableRow> table_4_1(const SysModel& m, int point_id, double f_normal, int direction) {
  const std::size_t i = m.point_index(point_id);
  if (direction < 0 || static_cast<std::size_t>(direction) >= m.angles.size())
    throw Error(
        fmt::format("expected a direction in 0..{}, got {}", m.angles.size() - 1, direction));
  const SysBorder& b =
      m.border(i, index_of(m.f_normal_levels, f_normal), static_cast<std::size_t>(direction));
  std::vector<TableRow> rows;
  for (std::size_t s = 0; s < b.steps.size(); ++s)
    rows.push_back({b.steps[s].f_tangential, b.steps[s].u_short, b.steps[s].u_long,
                    b.steps[s].growth(), s >= b.result.split ? 1 : 0});
  return rows;
}

}  // namespace inhap::friction
