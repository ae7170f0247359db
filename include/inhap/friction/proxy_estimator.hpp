// Proxy estimation with the elastic displacement limit surface g_s (thesis 4.3.1,
// eq. 4.12-4.23). Units: mm.
//
// State: contact point p_c, proxy q (on the undeformed probe-centre surface), elastic
// displacement u^e = p - q and the g_s interpolated at q. Each tick, with u = p - p_c:
//   trial u* = u^e(n-1) + delta u = p - q(n-1)                                  (eq. 4.17)
//   u* inside g_s  -> elastic: u^e = u*, q unchanged;
//   u* outside     -> return mapping: u^e = the point of g_s at the same depth along the
//                     tangential direction of u* (radial return in the tangent plane), the
//                     plastic increment delta u^p = u* - u^e moves the proxy, q += delta u^p
//                     (eq. 4.23), q is projected back onto the surface and g_s is
//                     re-interpolated (re-centred) at the new q; repeated up to
//                     max_iterations times while u^e is still outside the new g_s.
// Contact starts when p enters the shape (geometric contact: the closest surface point q0 with
// its outward normal n has (q0 - p).n > 0); then p_c = q = q0. It ends when the depth of p
// below the tangent plane at q is <= 0. Out of contact the output proxy is p itself.
//
// proxy_step() allocates nothing, throws nothing and does no I/O; NaN or absurd positions reset
// the state (no contact).
#pragma once

#include "inhap/core/types.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/friction/yield_surface.hpp"

namespace inhap::friction {

/// The undeformed contact surface in probe-centre coordinates (the surface the probe centre
/// touches: the object's surface offset by the probe radius).
class ShapeQuery {
 public:
  virtual ~ShapeQuery() = default;
  /// Closest point of the surface to p and the outward unit normal there; false when none.
  virtual bool closest(const Vec3& p, Vec3& point, Vec3& normal) const noexcept = 0;
};

/// An infinite plane (tests, flat objects).
class PlaneShape final : public ShapeQuery {
 public:
  PlaneShape(const Vec3& point, const Vec3& normal) : point_(point), normal_(normal.normalized()) {}
  bool closest(const Vec3& p, Vec3& point, Vec3& normal) const noexcept override {
    point = p - (p - point_).dot(normal_) * normal_;
    normal = normal_;
    return true;
  }

 private:
  Vec3 point_, normal_;
};

struct ProxyModel {
  const SysModel* sys = nullptr;      ///< sliding yield surfaces (not owned)
  const ShapeQuery* shape = nullptr;  ///< undeformed surface (not owned)
  int max_iterations = 3;             ///< return-mapping passes per tick
  double max_depth = 100.0;           ///< mm; deeper trial displacements are absurd -> reset
  double max_coordinate = 1e5;        ///< mm; larger |p| is absurd -> reset
};

struct ProxyState {
  bool contact = false;
  Vec3 pc = Vec3::Zero();  ///< contact point p_c
  Vec3 q = Vec3::Zero();   ///< proxy
  Vec3 ue = Vec3::Zero();  ///< elastic displacement u^e = p - q
  Vec3 n = Vec3::UnitZ(), t0 = Vec3::UnitX(), t1 = Vec3::UnitY();  ///< frame at q
  YieldSurface gs;                                                 ///< g_s interpolated at q
  int hint = -1;                                                   ///< last reference triangle
};

struct ProxyOutput {
  bool contact = false;
  bool sliding = false;    ///< the proxy moved this tick
  Vec3 q = Vec3::Zero();   ///< proxy (p when out of contact)
  Vec3 ue = Vec3::Zero();  ///< elastic displacement p - q
  double depth = 0;        ///< depth of p below the tangent plane at q, mm
};

inline void reset(ProxyState& s) {
  s.contact = false;
  s.hint = -1;
  s.ue.setZero();
}

/// Interpolates g_s at the surface point x (barycentric over the reference triangulation).
void interpolate_gs(const SysModel& sys, const Vec3& x, int& hint, YieldSurface& out) noexcept;

/// One servo tick: probe centre position p (mm) -> proxy.
ProxyOutput proxy_step(const ProxyModel& model, ProxyState& state, const Vec3& p) noexcept;

}  // namespace inhap::friction
