#include "inhap/friction/proxy_estimator.hpp"

#include <array>
#include <limits>

#include "inhap/geometry/surface_frame.hpp"

namespace inhap::friction {

namespace {

constexpr double kNoBound = std::numeric_limits<double>::infinity();

void set_frame(ProxyState& s, const Vec3& n, const Vec3& reference) noexcept {
  s.frame = surface_frame(n, reference);
}

ProxyOutput no_contact(ProxyState& s, const Vec3& p) noexcept {
  s.reset();  // keeps shape_hint: it is only a hint
  ProxyOutput out;
  out.q = p.allFinite() ? p : Vec3::Zero();
  return out;
}

}  // namespace

void interpolate_gs(const SysModel& sys, const Vec3& x, int& hint, YieldSurface& out,
                    double* tau) noexcept {
  const ReferenceMesh::Location loc = sys.reference_mesh.locate(x, hint);
  hint = loc.triangle;
  const std::array<const YieldSurface*, 3> s = {
      &sys.points[loc.vertex[0]].gs, &sys.points[loc.vertex[1]].gs, &sys.points[loc.vertex[2]].gs};
  const std::array<double, 3> w = {loc.weight.x(), loc.weight.y(), loc.weight.z()};
  out.blend(s, w);
  if (tau)
    *tau = w[0] * sys.points[loc.vertex[0]].creep_tau() +
           w[1] * sys.points[loc.vertex[1]].creep_tau() +
           w[2] * sys.points[loc.vertex[2]].creep_tau();
}

ProxyOutput proxy_step(const ProxyModel& m, ProxyState& s, const Vec3& p, double dt) noexcept {
  if (!m.sys || !m.shape || m.sys->points.empty() || !p.allFinite() ||
      p.cwiseAbs().maxCoeff() > m.max_coordinate_mm)
    return no_contact(s, p);
  const SysModel& sys = *m.sys;
  if (!s.contact) {
    Vec3 c, n;
    if (!m.shape->closest(p, c, n, kNoBound, s.shape_hint) || !c.allFinite() || !n.allFinite())
      return no_contact(s, p);
    if (!((c - p).dot(n) > 0.0)) return no_contact(s, p);
    s.contact = true;
    s.pc = s.q = c;
    s.hint = -1;
    set_frame(s, n, sys.tangent_reference);
    interpolate_gs(sys, c, s.hint, s.gs, &s.tau);
  }
  const bool viscous = m.creep && s.tau > 0.0 && dt > 0.0;
  ProxyOutput out;
  out.contact = true;
  for (int it = 0;; ++it) {
    const Vec3 trial = p - s.q;  // u* = u^e(n-1) + delta u
    const Vec3 local = to_gs(s.frame, trial);
    if (!(local.z() > 0.0)) return no_contact(s, p);  // left the surface
    if (local.z() > m.max_depth_mm) return no_contact(s, p);
    if (s.gs.excess(local) <= m.tolerance_mm || it >= m.max_iterations || (viscous && it > 0)) {
      s.ue = trial;
      out.depth = local.z();
      break;
    }
    // Return mapping onto g_s; the plastic increment u* - u^e moves the proxy.
    Vec3 back = s.gs.radial_return(local);
    if (viscous) {
      const double r = dt / s.tau;
      back = (local + r * back) / (1.0 + r);
    }
    const Vec3 ue = from_gs(s.frame, back);
    Vec3 q = p - ue;
    Vec3 c, n;
    // q lies in the tangent plane at the old proxy, close to the surface: a bounded search first.
    const double bound = 1.0 + (q - s.q).norm();
    if ((m.shape->closest(q, c, n, bound, s.shape_hint) ||
         m.shape->closest(q, c, n, kNoBound, s.shape_hint)) &&
        c.allFinite() && n.allFinite()) {
      q = c;
      set_frame(s, n, sys.tangent_reference);
    }
    s.q = q;
    out.sliding = true;
    interpolate_gs(sys, s.q, s.hint, s.gs, &s.tau);  // re-centre g_s at the new proxy
  }
  out.q = s.q;
  out.ue = s.ue;
  out.n = s.frame.n;
  return out;
}

}  // namespace inhap::friction
