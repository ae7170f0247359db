#include "inhap/lab/soft_contact.hpp"

#include <cmath>

namespace inhap::lab {

Vec3 project_to_offset(const SoftObject& object, double probe_radius, const Vec3& q) {
  const SurfaceQuery s = object.query(q);
  return s.closest + probe_radius * s.normal;
}

namespace {

/// The closest surface counts as the entry side when its normal is within 60 degrees of it.
constexpr double kSameSideCos = 0.5;
/// ... and never when it faces away (more than 90 degrees) from the normal the episode began
/// with: a proxy that slips round a thin rim (the base of a bunny's ear) would otherwise take
/// the side memory with it, step by step, onto the far side.
constexpr double kEntrySideCos = 0.0;

void leave_contact(ContactState& st) {
  st.in_contact = false;
  st.slipping = false;
  st.side_plane = false;
  st.delta = 0;
  st.normal_force = 0;
  st.force.setZero();
}

/// Moves the proxy onto the offset surface near q and remembers the side under it, unless that
/// side faces away from the episode's entry normal (the side memory stays where it was).
void set_proxy(const SoftObject& object, double radius, ContactState& st, const Vec3& q,
               bool first) {
  const SurfaceQuery s = object.query(q);
  st.proxy = s.closest + radius * s.normal;
  if (first) st.entry_normal = s.normal;
  if (first || s.normal.dot(st.entry_normal) >= kEntrySideCos) {
    st.side_normal = s.normal;
    st.side_point = s.closest;
  }
}

void begin_contact(const SoftObject& object, double radius, ContactState& st, const Vec3& p,
                   double delta, double t) {
  double frac = 1.0;  // where delta crossed 0 between the previous and this evaluation
  if (st.has_prev && st.prev_delta <= 0 && delta > st.prev_delta)
    frac = -st.prev_delta / (delta - st.prev_delta);
  st.start_point = st.has_prev ? Vec3(st.prev_point + frac * (p - st.prev_point)) : p;
  st.start_time = st.has_prev ? st.prev_time + frac * (t - st.prev_time) : t;
  set_proxy(object, radius, st, st.start_point, true);
  st.law = object.law_at(st.proxy);
  st.in_contact = true;
  ++st.episode;
}

}  // namespace

Vec3 contact_step(const SoftObject& object, double probe_radius, ContactState& st, const Vec3& p,
                  const Vec3& v, double t, double dt) {
  if (!all_finite(p) || !all_finite(v) || !std::isfinite(t) || !std::isfinite(dt)) {
    const auto episode = st.episode;
    st.reset();
    st.episode = episode;
    return Vec3::Zero();
  }
  const SurfaceQuery s = object.query(p);
  Vec3 n = s.normal;
  double delta = probe_radius - s.distance;
  st.side_plane = false;
  if (st.in_contact && (s.normal.dot(st.side_normal) < kSameSideCos ||
                        s.normal.dot(st.entry_normal) < kEntrySideCos)) {
    // Past the middle of a thin part (or under a rim): measure from the entry side's plane.
    n = st.side_normal;
    delta = probe_radius - (p - st.side_point).dot(n);
    st.side_plane = true;
  }
  if (!(delta > 0)) {
    if (st.in_contact) leave_contact(st);
  } else {
    if (!st.in_contact) begin_contact(object, probe_radius, st, p, delta, t);
    const ContactLaw law = st.law;  // copy: a slip may move the proxy onto other material
    const double rate = -n.dot(v);
    const double fn =
        std::max(0.0, law.k * std::pow(delta, law.exponent) * (1.0 + law.damping * rate));
    const Vec3 u = p - st.proxy;
    Vec3 ut = u - u.dot(n) * n;
    const double ut_len = ut.norm();
    const double limit = law.mu * fn;
    st.slipping = law.k_t * ut_len > limit;
    if (st.slipping) {
      // Implicit slip: c_v (|u_t| - |u_t'|) / dt = k_t |u_t'| - mu f_n.
      const double cdt = dt > 0 ? law.creep / dt : 1e300;
      const double len_new = (cdt * ut_len + limit) / (cdt + law.k_t);
      const Vec3 ut_new = ut * (len_new / ut_len);
      set_proxy(object, probe_radius, st, st.proxy + (ut - ut_new), false);
      if (!object.inclusions().empty()) st.law = object.law_at(st.proxy);
      ut = ut_new;
    }
    st.normal = n;
    st.delta = delta;
    st.normal_force = fn;
    st.force = fn * n - law.k_t * ut;
  }
  st.has_prev = true;
  st.prev_delta = delta;
  st.prev_time = t;
  st.prev_point = p;
  return st.force;
}

}  // namespace inhap::lab
