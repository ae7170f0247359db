// Proxy estimation with the elastic displacement limit surface g_s (thesis 4.3.1,
// eq. 4.12-4.23). Units: mm, s.
//
// State: contact point p_c, proxy q (on the undeformed probe-centre surface), elastic
// displacement u^e = p - q and the g_s interpolated at q. Each tick, with u = p - p_c:
//   trial u* = u^e(n-1) + delta u = p - q(n-1)                                  (eq. 4.17)
//   u* inside g_s  -> elastic: u^e = u*, q unchanged;
//   u* outside     -> return mapping: P(u*) = the point of g_s at the same depth along the
//                     tangential direction of u* (radial return in the tangent plane);
//                     rate-independent (thesis): u^e = P(u*); with creep (the reference points
//                     measured a slip viscosity, relaxation time tau = c_v / k_t, and dt > 0):
//                     u^e = (u* + dt/tau P(u*)) / (1 + dt/tau) (Duvaut-Lions, backward Euler:
//                     the excess beyond g_s relaxes with time constant tau, so a probe sliding at
//                     speed v leads the proxy by the static range plus v tau, as slip under
//                     viscous creep does). The plastic increment delta u^p = u* - u^e moves the
//                     proxy, q += delta u^p (eq. 4.23); q is projected back onto the surface and
//                     g_s is re-interpolated (re-centred) at the new q; the rate-independent
//                     return is repeated up to max_iterations times while u^e is still outside
//                     by more than tolerance.
// Contact starts when p enters the shape (geometric contact: the closest surface point q0 with
// its outward normal n has (q0 - p).n > 0); then p_c = q = q0. It ends when the depth of p
// below the tangent plane at q is <= 0. Out of contact the output proxy is p itself.
//
// proxy_step() allocates nothing, throws nothing and does no I/O; NaN or absurd positions reset
// the state (no contact).
#pragma once

#include "inhap/core/types.hpp"
#include "inhap/friction/shape_query.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/friction/yield_surface.hpp"

namespace inhap::friction {

struct ProxyModel {
  const SysModel* sys = nullptr;      ///< sliding yield surfaces (not owned)
  const ShapeQuery* shape = nullptr;  ///< undeformed surface (not owned)
  int max_iterations = 3;             ///< return-mapping passes per tick
  double tolerance_mm = 1e-3;         ///< mm outside g_s still accepted as on it (ends the passes)
  double max_depth_mm = 100.0;        ///< mm; deeper trial displacements are absurd -> reset
  double max_coordinate_mm = 1e5;     ///< mm; larger |p| is absurd -> reset
  bool creep = true;                  ///< use the measured slip viscosity (else rate-independent)
};

struct ProxyState {
  bool contact = false;
  Vec3 pc = Vec3::Zero();  ///< contact point p_c
  Vec3 q = Vec3::Zero();   ///< proxy
  Vec3 ue = Vec3::Zero();  ///< elastic displacement u^e = p - q
  SurfaceFrame frame;      ///< at q: outward normal n, t0 = SysModel::tangent_reference projected
  YieldSurface gs;         ///< g_s interpolated at q
  double tau = 0;          ///< creep relaxation time interpolated at q, s
  int hint = -1;           ///< last reference triangle
  std::int32_t shape_hint = -1;  ///< ShapeQuery warm start (reset() keeps it: any value is safe)

  /// Back to the initial state as far as the next step can tell: out of contact (q, frame, g_s
  /// and tau are set afresh at the next contact onset; the shape hint is kept, any value is safe).
  /// Cheap on purpose: it runs on every tick out of contact.
  void reset() noexcept {
    contact = false;
    hint = -1;
    ue.setZero();
  }
};

struct ProxyOutput {
  bool contact = false;
  bool sliding = false;    ///< the proxy moved this tick
  Vec3 q = Vec3::Zero();   ///< proxy (p when out of contact)
  Vec3 ue = Vec3::Zero();  ///< elastic displacement p - q
  double depth = 0;        ///< depth of p below the tangent plane at q, mm
  Vec3 n = Vec3::UnitZ();  ///< outward unit surface normal at q (+z out of contact)
};

/// Interpolates g_s (and the creep relaxation time, when `tau` is given) at the surface point
/// x: barycentric over the reference triangulation, nearest triangle outside it.
void interpolate_gs(const SysModel& sys, const Vec3& x, int& hint, YieldSurface& out,
                    double* tau = nullptr) noexcept;

/// One servo tick: probe centre position p (mm), dt = time since the previous tick (s; <= 0:
/// rate-independent return) -> proxy.
ProxyOutput proxy_step(const ProxyModel& model, ProxyState& state, const Vec3& p,
                       double dt = 0.0) noexcept;

}  // namespace inhap::friction
