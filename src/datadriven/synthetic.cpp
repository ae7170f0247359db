// Synthetic planar soft object with a closed-form force law (see synthetic.hpp).
#include "inhap/datadriven/synthetic.hpp"

#include <algorithm>
#include <cmath>

#include "inhap/core/random.hpp"

namespace inhap::datadriven {

double SyntheticObject::stiffness(double x, double y) const {
  const double dx = x - blob_x, dy = y - blob_y;
  return k0 + k1 * std::exp(-(dx * dx + dy * dy) / (2 * blob_sigma * blob_sigma));
}

Vec3 SyntheticObject::force(const Vec3& p, const Vec3& v, const Vec3& q) const {
  const double d = std::max(0.0, -p.z());
  if (d <= 0) return Vec3::Zero();
  const double k = stiffness(q.x(), q.y());
  const double fz = std::max(0.0, k * std::pow(d, exponent) * (1.0 + damping * (-v.z())));
  Vec3 f(kt * k * (q.x() - p.x()), kt * k * (q.y() - p.y()), fz);
  return f;
}

Vec3 SyntheticObject::update_proxy(const Vec3& p, const Vec3& q_prev, bool was_contact) const {
  const double d = std::max(0.0, -p.z());
  if (d <= 0 || !was_contact) return Vec3(p.x(), p.y(), 0.0);
  const double k = stiffness(q_prev.x(), q_prev.y());
  const double fn = k * std::pow(d, exponent);
  Vec2 u(q_prev.x() - p.x(), q_prev.y() - p.y());
  const double ft = kt * k * u.norm(), limit = mu * fn;
  if (ft > limit && ft > 0) u *= limit / ft;  // slide: radial return onto the cone
  return Vec3(p.x() + u.x(), p.y() + u.y(), 0.0);
}

namespace {

// Smooth path through random waypoints (x, y, z); smoothstep blending between them.
class Path {
 public:
  Path(const SyntheticParams& prm, Rng& rng) : prm_(prm), rng_(rng) {
    a_ = draw();
    b_ = draw();
    t1_ = rng_.uniform(prm_.min_move_s, prm_.max_move_s);
  }
  // Position at time t (t must not decrease between calls by more than the current move).
  Vec3 at(double t) {
    while (t >= t1_) {
      a_ = b_;
      b_ = draw();
      t0_ = t1_;
      t1_ += rng_.uniform(prm_.min_move_s, prm_.max_move_s);
    }
    return eval(a_, b_, t0_, t1_, t);
  }
  Vec3 velocity(double t) const {
    const double u = (t - t0_) / (t1_ - t0_);
    return (b_ - a_) * (6 * u * (1 - u)) / (t1_ - t0_);
  }

 private:
  static Vec3 eval(const Vec3& a, const Vec3& b, double t0, double t1, double t) {
    const double u = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
    return a + (b - a) * (u * u * (3 - 2 * u));
  }
  Vec3 draw() {
    const double z = rng_.uniform(-prm_.max_depth, 0.25 * prm_.max_depth);
    return Vec3(rng_.uniform(-prm_.extent, prm_.extent), rng_.uniform(-prm_.extent, prm_.extent),
                z);
  }
  const SyntheticParams& prm_;
  Rng& rng_;
  Vec3 a_, b_;
  double t0_ = 0, t1_ = 0;
};

}  // namespace

Recording synthetic_recording(const SyntheticParams& prm, const SyntheticObject& obj) {
  Rng rng(prm.seed);
  Rng noise(prm.seed ^ 0x5deece66dull);
  Path path(prm, rng);
  Recording rec;
  const std::size_t n = prm.samples;
  rec.t.resize(n);
  rec.p.resize(n);
  rec.f.resize(n);
  std::vector<double> qx(n), qy(n), qz(n), contact(n), tfx(n), tfy(n), tfz(n);
  Vec3 q = Vec3::Zero();
  bool was_contact = false;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * prm.dt;
    const Vec3 p = path.at(t);
    const Vec3 v = path.velocity(t);
    const bool c = p.z() < 0;
    q = obj.update_proxy(p, q, was_contact);
    was_contact = c;
    const Vec3 f = c ? obj.force(p, v, q) : Vec3::Zero();
    rec.t[i] = t;
    for (int a = 0; a < 3; ++a) rec.p[i][a] = std::round(p[a] / prm.quantum) * prm.quantum;
    rec.f[i] = f + Vec3(noise.normal(0, prm.noise), noise.normal(0, prm.noise),
                        noise.normal(0, prm.noise));
    qx[i] = q.x();
    qy[i] = q.y();
    qz[i] = q.z();
    contact[i] = c ? 1.0 : 0.0;
    tfx[i] = f.x();
    tfy[i] = f.y();
    tfz[i] = f.z();
  }
  rec.set_extra("qx", std::move(qx));
  rec.set_extra("qy", std::move(qy));
  rec.set_extra("qz", std::move(qz));
  rec.set_extra("contact", std::move(contact));
  rec.set_extra("tfx", std::move(tfx));
  rec.set_extra("tfy", std::move(tfy));
  rec.set_extra("tfz", std::move(tfz));
  return rec;
}

}  // namespace inhap::datadriven
