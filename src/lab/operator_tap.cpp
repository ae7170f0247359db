// The tapping operator (thesis ch. 3): a person tapping random surface points with the stylus.
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <optional>

#include "operator_common.hpp"

namespace inhap::lab {

namespace {

using detail::log_uniform;
using detail::min_jerk;

/// Whole-object mode: the slowest approach, mm/s (TapOptions::min_speed when higher).
constexpr double kRoundMinSpeed = 30.0;

class TapOperator final : public HandOperator {
 public:
  TapOperator(const Scene& scene, std::uint64_t seed, TapOptions o)
      : scene_(scene), opt_(o), rng_(seed), tremor_(rng_), perception_(0.1, 1000.0) {}

  std::string name() const override { return "tap"; }

  void begin(SimDevice& dev) override {
    radius_ = dev.probe_radius();
    if (opt_.whole_object) init_spots();
    hand_ = detail::random_hand(rng_, dev.params());
    perception_ = detail::Perception(rng_.uniform(0.08, 0.12), dev.info().servo_rate_hz);
    dev.attach_hand(hand_);
    target_ = detail::rest_point(scene_, radius_, 25.0);
    dev.place(target_);
    dev.set_hand_target(target_);
    tremor_.start(dev.time());
    plan_next(dev.time());
  }

  void step(SimDevice& dev) override {
    const double t = dev.time() + 1.0 / dev.info().servo_rate_hz;  // target for the tick's end
    perception_.push(dev.contact().normal_force);
    update(t);
    dev.set_hand_target(target_ + tremor_.at(t));
  }

 private:
  enum class Phase { kTransit, kApproach, kDwell, kRetract, kPause };

  /// Whole-object mode: the reachable surface samples the spots come from.
  void init_spots() {
    const auto all = sample_object_surface(scene_.object, opt_.candidates, rng_.next_u64());
    for (const SurfaceSample& c : all)
      if (reachable(scene_.object, radius_, c.point, c.normal, opt_.reach)) pool_.push_back(c);
    gap_.assign(pool_.size(), std::numeric_limits<double>::infinity());
    const Vec3 size = scene_.object.shape().bounds().size();
    spacing_ = 0.2 * std::max({size.x(), size.y(), size.z(), 1.0});
  }

  /// The unvisited candidate nearest the hand at least `spacing_` from every earlier tap.
  std::optional<detail::SurfaceSpot> next_whole_object_spot() {
    if (pool_.empty()) return std::nullopt;
    for (int pass = 0; pass < 60; ++pass) {
      std::size_t best = pool_.size();
      double best_d = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < pool_.size(); ++i) {
        if (gap_[i] < spacing_) continue;
        const double d = (pool_[i].point - target_).squaredNorm();
        if (d < best_d) best_d = d, best = i;
      }
      if (best < pool_.size()) {
        const SurfaceSample& c = pool_[best];
        for (std::size_t i = 0; i < pool_.size(); ++i)
          if (pool_[i].normal.dot(c.normal) > 0)
            gap_[i] = std::min(gap_[i], (pool_[i].point - c.point).norm());
        return detail::SurfaceSpot{c.point + radius_ * c.normal, c.normal};
      }
      spacing_ *= 0.8;
    }
    return std::nullopt;
  }

  void plan_next(double t) {
    detail::SurfaceSpot spot{};
    bool found = false;
    if (opt_.whole_object) {
      if (const auto s = next_whole_object_spot()) spot = *s, found = true;
    }
    const double min_nz = std::cos(opt_.max_tilt_deg * M_PI / 180.0);
    for (int attempt = 0; attempt < 100 && !found; ++attempt) {
      const auto s =
          detail::spot_at(scene_.object, radius_, detail::random_in_region(rng_, scene_.region));
      if (s && s->normal.z() >= min_nz) spot = *s, found = true;
    }
    if (!found) spot = {detail::rest_point(scene_, radius_, 0.0), Vec3::UnitZ()};
    // Approach direction: the normal, tilted up to 12 degrees like a hand would.
    Vec3 w = spot.normal.unitOrthogonal();
    const double roll = rng_.uniform(0, 2 * M_PI);
    w = std::cos(roll) * w + std::sin(roll) * spot.normal.cross(w);
    const double tilt = rng_.uniform(0, 12.0) * M_PI / 180.0;
    u_ = (std::cos(tilt) * spot.normal + std::sin(tilt) * w).normalized();
    if (opt_.whole_object) {
      const Vec3 x = spot.center - radius_ * spot.normal;
      if (!reachable(scene_.object, radius_, x, u_, opt_.reach)) u_ = spot.normal;
    } else if (u_.z() < 0.3) {
      u_ = spot.normal;
    }

    // Going round an object a person taps briskly: no approach slower than 30 mm/s.
    const double slowest =
        opt_.whole_object ? std::max(opt_.min_speed, kRoundMinSpeed) : opt_.min_speed;
    speed_ = log_uniform(rng_, slowest, std::max(slowest, opt_.max_speed));
    peak_ = rng_.uniform(opt_.min_force, opt_.max_force);
    ramp_t_ = std::max(0.02, speed_ / 4000.0);
    const double ramp_s = 0.5 * speed_ * ramp_t_;
    // Going round an object a person keeps the stylus closer and moves on sooner (>= 1 tap/s).
    const double h0 =
        ramp_s + (opt_.whole_object ? 3.0 + rng_.uniform(0.0, 5.0) : 5.0 + rng_.uniform(0.0, 8.0));
    believed_ = h0 + std::clamp(rng_.normal(0.0, 0.7), -2.0, 2.0);
    const ContactLaw law = scene_.object.law_at(spot.center);
    plan_depth_ = std::max(
        1.0, rng_.uniform(0.85, 1.15) * (law.depth_at(peak_) + peak_ / hand_.stiffness_n_per_mm));
    // A tilted approach must not pass through another part of the object (think of an ear
    // above the point): otherwise come straight down, which drop() found to be free.
    const double retract = rng_.uniform(0.0, 5.0);
    if (!opt_.whole_object && !approach_is_clear(spot.center, h0 + retract)) u_ = Vec3::UnitZ();
    start_ = spot.center + h0 * u_;
    retract_to_ = start_ + retract * u_;
    phase_ = Phase::kTransit;
    t0_ = t;
    const double speed = rng_.uniform(150.0, 350.0);
    if (opt_.whole_object) {
      path_ = around_path(start_, spot.center + opt_.reach.stylus_length_mm * u_, speed);
      way_out_ = spot.center + opt_.reach.stylus_length_mm * u_;
      last_u_ = u_;
      has_way_out_ = true;
    } else {
      path_ = detail::over_path(scene_.object, radius_, target_, start_, speed);
    }
  }

  /// Whole-object mode: from the last tap's retraction point to `to` (the next approach start)
  /// straight when clear; else out along the last approach line, across and in along the next
  /// one, as short a way out as is clear (10, 20, 35 mm, then the full stylus length); else
  /// over the object.
  detail::Path around_path(const Vec3& to, const Vec3& to_out, double speed) const {
    detail::Path p;
    p.reset(target_);
    if (detail::clear_segment(scene_.object, radius_, target_, to)) {
      p.add(to, speed);
      return p;
    }
    const double full = opt_.reach.stylus_length_mm;
    if (has_way_out_) {
      const Vec3 last_in = way_out_ - full * last_u_, next_in = to_out - full * u_;
      for (const double out : {10.0, 20.0, 35.0}) {
        if (out >= full) break;
        const Vec3 a = last_in + std::max(out, (target_ - last_in).dot(last_u_)) * last_u_;
        const Vec3 b = next_in + std::max(out, (to - next_in).dot(u_)) * u_;
        if (!segment_clear(scene_.object, radius_, a, b, 0.0)) continue;
        p.add(a, speed);
        p.add(b, speed);
        p.add(to, speed);
        return p;
      }
    }
    const Vec3 from_out = has_way_out_ ? way_out_ : target_;
    p.add(from_out, speed);
    if (!segment_clear(scene_.object, radius_, from_out, to_out, 0.0)) {
      const double z =
          std::max({detail::safe_height(scene_.object, radius_), from_out.z(), to_out.z()});
      p.add(Vec3(from_out.x(), from_out.y(), z), speed);
      p.add(Vec3(to_out.x(), to_out.y(), z), speed);
    }
    p.add(to_out, speed);
    p.add(to, speed);
    return p;
  }

  bool approach_is_clear(const Vec3& touch, double length) const {
    const Vec3 far = touch + length * u_;
    const Vec3 above(far.x(), far.y(),
                     std::max(far.z(), detail::safe_height(scene_.object, radius_)));
    return detail::clear_segment(scene_.object, radius_, touch + 0.5 * u_, far) &&
           detail::clear_segment(scene_.object, radius_, far, above);
  }

  double retract_s() {
    return opt_.whole_object ? rng_.uniform(0.12, 0.25) : rng_.uniform(0.2, 0.4);
  }

  void begin_move(double t, Phase phase, const Vec3& to, double duration) {
    phase_ = phase;
    t0_ = t;
    from_ = target_;
    to_ = to;
    duration_ = duration;
  }

  /// Distance travelled along -u since the approach began.
  double approach_path(double tau, bool& finished) const {
    const double v = speed_, ta = ramp_t_, sa = 0.5 * v * ta;
    const double tb = std::max(0.0, (believed_ - sa) / v);
    const double tc = 2.0 * plan_depth_ / v, decel = v * v / (2.0 * plan_depth_);
    finished = false;
    if (tau < ta) return 0.5 * v * (tau - ta / M_PI * std::sin(M_PI * tau / ta));
    if (tau < ta + tb) return sa + v * (tau - ta);
    const double s0 = sa + v * tb;
    const double tcc = tau - ta - tb;
    if (tcc < tc) return s0 + v * tcc - 0.5 * decel * tcc * tcc;
    finished = true;
    return s0 + plan_depth_;
  }

  void update(double t) {
    const double tau = t - t0_;
    switch (phase_) {
      case Phase::kTransit:
        target_ = path_.at(tau);
        if (tau >= path_.duration()) phase_ = Phase::kApproach, t0_ = t;
        break;
      case Phase::kRetract:
        target_ = from_ + min_jerk(tau / duration_) * (to_ - from_);
        if (tau >= duration_)
          phase_ = Phase::kPause, t0_ = t,
          duration_ = opt_.whole_object ? rng_.uniform(0.02, 0.12) : rng_.uniform(0.05, 0.3);
        break;
      case Phase::kApproach: {
        bool finished;
        target_ = start_ - approach_path(tau, finished) * u_;
        if (perception_.force() > 1.4 * peak_ + 0.3) {  // felt too hard: pull back now
          begin_move(t, Phase::kRetract, retract_to_, retract_s());
        } else if (finished) {
          phase_ = Phase::kDwell, t0_ = t,
          duration_ = opt_.whole_object ? rng_.uniform(0.03, 0.12) : rng_.uniform(0.05, 0.25);
        }
        break;
      }
      case Phase::kDwell:
        if (tau >= duration_) begin_move(t, Phase::kRetract, retract_to_, retract_s());
        break;
      case Phase::kPause:
        if (tau >= duration_) plan_next(t);
        break;
    }
  }

  Scene scene_;
  TapOptions opt_;
  Rng rng_;
  detail::Tremor tremor_;
  detail::Perception perception_;
  HandParams hand_;
  double radius_ = 0;
  Phase phase_ = Phase::kPause;
  double t0_ = 0, duration_ = 0;
  Vec3 target_ = Vec3::Zero(), from_ = Vec3::Zero(), to_ = Vec3::Zero();
  Vec3 start_ = Vec3::Zero(), retract_to_ = Vec3::Zero(), u_ = Vec3::UnitZ();
  detail::Path path_;
  // Whole-object mode.
  std::vector<SurfaceSample> pool_;
  std::vector<double> gap_;  ///< distance of each candidate to the nearest earlier tap, mm
  double spacing_ = 0;
  Vec3 way_out_ = Vec3::Zero(), last_u_ = Vec3::UnitZ();  ///< last approach: far end, direction
  bool has_way_out_ = false;
  double speed_ = 100, peak_ = 2, ramp_t_ = 0.05, believed_ = 10, plan_depth_ = 5;
};

}  // namespace

std::unique_ptr<HandOperator> make_tap_operator(const Scene& scene, std::uint64_t seed,
                                                TapOptions options) {
  return std::make_unique<TapOperator>(scene, seed, options);
}

}  // namespace inhap::lab
