// The free-exploration operator (thesis 4.4.1): pushes, deep pushes, strokes, rubbing circles
// and a final sliding-only passage, with person-like force regulation.
//
// The hand target is kept on the surface normal below the "cursor" (the point of the region
// the person is working on): target = spot(cursor) - depth * n. While touching, depth follows
// a feed-forward guess of the depth needed for the reference force (the person's idea of the
// object's softness and of their own hand compliance) plus an integral correction driven by
// the delayed perceived normal force.
#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>
#include <vector>

#include "operator_common.hpp"

namespace inhap::lab {

namespace {

using detail::min_jerk;
using detail::smoothstep;

struct Segment {
  enum Kind { kAirMove, kTouch, kPress, kSlide, kCircle, kLift } kind;
  double duration = 0;  ///< s (touch and lift: time-out)
  Vec2 to = Vec2::Zero();
  double force = 0;  ///< reference force at the segment's end (press/slide/circle), N
  double radius = 0, freq = 0, speed = 0;
};

class ExploreOperator final : public HandOperator {
 public:
  ExploreOperator(const Scene& scene, std::uint64_t seed, double seconds, ExploreOptions o)
      : scene_(scene),
        opt_(o),
        seconds_(seconds),
        rng_(seed),
        tremor_(rng_),
        perception_(0.1, 1000.0) {}

  std::string name() const override { return opt_.coverage ? "explore-coverage" : "explore"; }

  void begin(SimDevice& dev) override {
    if (opt_.coverage) make_spots(false);
    radius_ = dev.probe_radius();
    dt_ = 1.0 / dev.info().servo_rate_hz;
    hand_ = detail::random_hand(rng_, dev.params());
    perception_ = detail::Perception(rng_.uniform(0.08, 0.12), dev.info().servo_rate_hz);
    belief_ = rng_.uniform(0.8, 1.2);
    clearance_ = rng_.uniform(8.0, 14.0);
    dev.attach_hand(hand_);
    cursor_ = scene_.region.center;
    depth_ = -clearance_;
    spot_ =
        detail::spot_at(scene_.object, radius_, cursor_)
            .value_or(detail::SurfaceSpot{detail::rest_point(scene_, radius_, 0), Vec3::UnitZ()});
    push_dir_ = spot_.normal;
    const Vec3 start = spot_.center - depth_ * push_dir_;
    target_ = start;
    dev.place(start);
    dev.set_hand_target(start);
    tremor_.start(dev.time());
    t_start_ = dev.time();
    seg_t0_ = t_start_;
  }

  void step(SimDevice& dev) override {
    const double t = dev.time() + dt_;
    perception_.push(dev.contact().normal_force);
    if (queue_.empty()) plan(t);
    free_target_.reset();
    run_segment(t);
    if (free_target_) {
      target_ = *free_target_;
    } else {
      follow_surface();
      // A person presses along a direction that turns smoothly (time constant 0.15 s), not
      // along the exact local normal, which jumps across creases (e.g. between ridges).
      push_dir_ = (push_dir_ + (dt_ / 0.15) * (spot_.normal - push_dir_)).normalized();
      const Vec3 want = spot_.center - depth_ * push_dir_;
      const double step = 400.0 * dt_;  // a hand moves at most 400 mm/s
      const Vec3 d = want - target_;
      target_ += d.norm() > step ? Vec3(d * (step / d.norm())) : d;
    }
    dev.set_hand_target(target_ + tremor_.at(t));
  }

 private:
  /// Depth below the surface spot the person expects to need for force f.
  double feed_forward(double f) const {
    const ContactLaw law = scene_.object.law_at(spot_.center);
    return belief_ * law.depth_at(f) + f / hand_.stiffness_n_per_mm;
  }

  void move_depth_toward(double want, double rate) {
    const double step = rate * dt_;
    depth_ += std::clamp(want - depth_, -step, step);
  }

  void regulate(double f_ref) {
    const double err = f_ref - perception_.force();
    integ_ = std::clamp(integ_ + 5.0 * err * dt_, -10.0, 10.0);
    if (perception_.force() > opt_.max_force + 0.3) integ_ -= 20.0 * dt_;  // too hard: ease off
    move_depth_toward(feed_forward(f_ref) + integ_, 80.0);
    f_ref_ = f_ref;
  }

  /// Keeps the spot on the surface being worked on: the cursor's point at the spot's height,
  /// projected onto the probe-centre offset surface (not the topmost surface under the cursor,
  /// which may be another part of the object, like an ear above the back).
  void follow_surface() {
    const SurfaceQuery q = scene_.object.query(Vec3(cursor_.x(), cursor_.y(), spot_.center.z()));
    if (!std::isfinite(q.distance)) return;
    spot_.center = q.closest + radius_ * q.normal;
    spot_.normal = q.normal;
  }

  /// Moves the hand freely along a path that clears the object; true when it has arrived.
  bool air_move(const Segment& s, double tau) {
    if (!seg_started_) {
      seg_started_ = true;
      goal_ = detail::spot_at(scene_.object, radius_, s.to).value_or(spot_);
      air_path_ = detail::over_path(scene_.object, radius_, target_,
                                    goal_.center + clearance_ * goal_.normal, s.speed);
    }
    free_target_ = air_path_.at(tau);
    if (tau < air_path_.duration()) return false;
    cursor_ = s.to;
    spot_ = goal_;
    push_dir_ = goal_.normal;
    depth_ = -clearance_;
    return true;
  }

  void next_segment(double t) {
    seg_started_ = false;
    queue_.pop_front();
    seg_t0_ = t;
    seg_from_ = cursor_;
    f_from_ = f_ref_;
  }

  void run_segment(double t) {
    const Segment& s = queue_.front();
    const double tau = t - seg_t0_;
    const double ramp = smoothstep(tau / std::min(0.3, s.duration));
    bool done = tau >= s.duration;
    switch (s.kind) {
      case Segment::kAirMove:  // over the object (not through it) to above the next spot
        done = air_move(s, tau);
        break;
      case Segment::kTouch:
        depth_ += s.speed * dt_;
        if (perception_.force() > 0.08) {
          touching_ = true;
          f_ref_ = 0.1;
          integ_ = depth_ - feed_forward(f_ref_);
          done = true;
        } else if (depth_ > 40.0) {  // nothing there: give up this gesture
          queue_.clear();
          queue_.push_back({Segment::kLift, 2.0});
          seg_t0_ = t;
          return;
        }
        break;
      case Segment::kPress:
        regulate(f_from_ + smoothstep(tau / s.duration) * (s.force - f_from_));
        break;
      case Segment::kSlide:
        cursor_ = seg_from_ + min_jerk(tau / s.duration) * (s.to - seg_from_);
        regulate(f_from_ + ramp * (s.force - f_from_));
        break;
      case Segment::kCircle: {  // spiral out, circle, spiral back in: smooth at both ends
        const double r = s.radius * smoothstep(tau / 0.4) * smoothstep((s.duration - tau) / 0.4);
        const double a = 2 * M_PI * s.freq * tau;
        cursor_ = seg_from_ + r * Vec2(std::cos(a), std::sin(a));
        regulate(f_from_ + ramp * (s.force - f_from_));
        break;
      }
      case Segment::kLift:
        touching_ = false;
        integ_ = 0;
        f_ref_ = 0;
        move_depth_toward(-clearance_, 60.0);
        done = done || depth_ <= -clearance_ + 1e-9;
        break;
    }
    if (done) next_segment(t);
  }

  Vec2 slide_goal() {
    Vec2 goal = cursor_;
    for (int i = 0; i < 20 && (goal - cursor_).norm() < 20.0; ++i)
      goal = detail::random_in_region(rng_, scene_.region);
    return goal;
  }

  void add_slide(double force) {
    const Vec2 goal = slide_goal();
    const double v = rng_.uniform(8.0, 35.0);  // mean speed, mm/s
    queue_.push_back({Segment::kSlide, std::max(0.4, (goal - cursor_).norm() / v), goal, force});
  }

  void add_circles(double force) {
    const double f = rng_.uniform(0.5, 1.5);
    queue_.push_back({Segment::kCircle, rng_.uniform(1.5, 4.0) / f, Vec2::Zero(), force,
                      rng_.uniform(4.0, 10.0), f});
  }

  /// Lift (if touching), move above a new point (random unless given), touch, load to `force`.
  void add_approach(double force, double load_time, std::optional<Vec2> to = std::nullopt) {
    if (touching_) queue_.push_back({Segment::kLift, 2.0});
    const Vec2 xy = to ? *to : detail::random_in_region(rng_, scene_.region);
    queue_.push_back({Segment::kAirMove, 0.0, xy, 0, 0, 0, rng_.uniform(100.0, 250.0)});
    queue_.push_back({Segment::kTouch, 10.0, Vec2::Zero(), 0, 0, 0, rng_.uniform(15.0, 40.0)});
    queue_.push_back({Segment::kPress, load_time, Vec2::Zero(), force});
  }

  /// Coverage mode: a hexagonal grid over the region (lattice points up to half a cell outside
  /// pulled onto the rim) with about coverage_share * seconds / seconds_per_spot spots, in
  /// serpentine row order; `shift` moves it by half a cell (later passes).
  void make_spots(bool shift) {
    const Region& r = scene_.region;
    const double per_spot = std::max(0.5, opt_.seconds_per_spot) + 1.5 * opt_.stroke_probability;
    const double n = std::max(4.0, opt_.coverage_share * seconds_ / per_spot);
    double h = r.radius;  // spacing: n cells of area sqrt(3)/2 h^2 fill the disc of R + h/2
    for (int it = 0; it < 8; ++it)
      h = (r.radius + 0.5 * h) * std::sqrt(M_PI / (n * std::sqrt(3.0) / 2));
    const double dy = h * std::sqrt(3.0) / 2, o = shift ? 0.5 : 0.0;
    spots_.clear();
    const int rows = static_cast<int>(std::ceil(r.radius / dy)) + 1;
    for (int j = -rows, k = 0; j <= rows; ++j) {
      std::vector<Vec2> row;
      for (int i = -rows - 1; i <= rows + 1; ++i) {
        // Lattice points up to half a cell outside the region are pulled onto its rim, so the
        // rim gets pressed too.
        const Vec2 d((i + o + 0.5 * (j & 1)) * h, (j + o) * dy);
        const double dn = d.norm();
        if (dn <= r.radius + 0.5 * h)
          row.push_back(r.center + (dn > r.radius ? Vec2(d * (r.radius / dn)) : d));
      }
      if (row.empty()) continue;
      if (k++ & 1) std::reverse(row.begin(), row.end());
      spots_.insert(spots_.end(), row.begin(), row.end());
    }
    next_spot_ = 0;
  }

  void plan_coverage() {
    if (next_spot_ >= spots_.size()) make_spots(++passes_ & 1);
    const Vec2 xy = spots_[next_spot_++];
    const double f_slide = rng_.uniform(opt_.coverage_force_min, opt_.coverage_force_max);
    if (!touching_ || coverage_count_++ % 4 == 0) {
      add_approach(f_slide, rng_.uniform(0.3, 0.5), xy);
    } else {
      const double v = rng_.uniform(12.0, 35.0);
      queue_.push_back({Segment::kSlide, std::max(0.3, (xy - cursor_).norm() / v), xy, f_slide});
    }
    // Load, hold, unload: about 1.2 s at the default 2 s per spot (scaled with it, 0.4 s at least
    // for the load).
    const double deep = rng_.uniform(0.8, 0.95) * opt_.max_force;
    const double s = std::clamp(opt_.seconds_per_spot / 2.0, 0.5, 2.0);
    queue_.push_back(
        {Segment::kPress, std::max(0.3, s * rng_.uniform(0.4, 0.7)), Vec2::Zero(), deep});
    queue_.push_back({Segment::kPress, s * rng_.uniform(0.1, 0.3), Vec2::Zero(), deep});
    queue_.push_back(
        {Segment::kPress, std::max(0.2, s * rng_.uniform(0.25, 0.4)), Vec2::Zero(), f_slide});
    // Now and then a long stroke at the usual random speed (8-35 mm/s mean: the random
    // exploration's strokes cross the region fast), from which the next spot is reached.
    if (rng_.uniform() < opt_.stroke_probability)
      add_slide(rng_.uniform(opt_.coverage_force_min, opt_.coverage_force_max));
  }

  void plan(double t) {
    if (opt_.coverage && t < t_start_ + opt_.coverage_share * seconds_) return plan_coverage();
    const double slide_from = t_start_ + (1.0 - opt_.sliding_fraction) * seconds_;
    if (t >= slide_from - 1.5) {  // sliding-only passage: never leave the surface
      if (!touching_) add_approach(rng_.uniform(0.7, 2.5), rng_.uniform(0.3, 0.6));
      const double f = rng_.uniform(0.7, 2.5);
      if (rng_.uniform() < 0.6)
        add_slide(f);
      else
        add_circles(f);
      return;
    }
    const double pick = rng_.uniform();
    if (pick < 0.3) {  // push
      const double f = rng_.uniform(1.0, std::min(4.0, opt_.max_force));
      add_approach(f, rng_.uniform(0.3, 0.8));
      queue_.push_back({Segment::kPress, rng_.uniform(0.2, 0.8), Vec2::Zero(), f});
    } else if (pick < 0.45) {  // deep push
      const double f = rng_.uniform(0.8, 0.95) * opt_.max_force;
      add_approach(f, rng_.uniform(0.6, 1.2));
      queue_.push_back({Segment::kPress, rng_.uniform(0.3, 1.0), Vec2::Zero(), f});
    } else if (pick < 0.75) {  // stroke (and sometimes back)
      const double f = rng_.uniform(0.5, 3.0);
      add_approach(f, rng_.uniform(0.3, 0.5));
      add_slide(f);
      if (rng_.uniform() < 0.5) add_slide(f);
    } else {  // rubbing circles
      const double f = rng_.uniform(0.5, 3.0);
      add_approach(f, rng_.uniform(0.3, 0.5));
      add_circles(f);
    }
    queue_.push_back({Segment::kPress, rng_.uniform(0.3, 0.6), Vec2::Zero(), 0.1});
    queue_.push_back({Segment::kLift, 2.0});
  }

  Scene scene_;
  ExploreOptions opt_;
  double seconds_;
  Rng rng_;
  detail::Tremor tremor_;
  detail::Perception perception_;
  HandParams hand_;
  double radius_ = 0, dt_ = 1e-3, belief_ = 1, clearance_ = 10;
  std::deque<Segment> queue_;
  detail::SurfaceSpot spot_{Vec3::Zero(), Vec3::UnitZ()};
  Vec3 push_dir_ = Vec3::UnitZ();
  Vec3 target_ = Vec3::Zero();       // hand target without tremor
  std::optional<Vec3> free_target_;  // set while the hand moves freely (air moves)
  detail::Path air_path_;
  detail::SurfaceSpot goal_{Vec3::Zero(), Vec3::UnitZ()};
  bool seg_started_ = false;
  Vec2 cursor_ = Vec2::Zero(), seg_from_ = Vec2::Zero();
  double t_start_ = 0, seg_t0_ = 0, f_from_ = 0, f_ref_ = 0, depth_ = 0, integ_ = 0;
  bool touching_ = false;
  std::vector<Vec2> spots_;  // coverage mode: grid of the current pass, in visiting order
  std::size_t next_spot_ = 0;
  int passes_ = 0, coverage_count_ = 0;
};

}  // namespace

std::unique_ptr<HandOperator> make_explore_operator(const Scene& scene, std::uint64_t seed,
                                                    double seconds, ExploreOptions options) {
  return std::make_unique<ExploreOperator>(scene, seed, seconds, options);
}

}  // namespace inhap::lab
