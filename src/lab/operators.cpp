// Operator registry, the free-air operator and the recording driver.
#include <fmt/format.h>

#include <cmath>

#include "inhap/core/error.hpp"
#include "operator_common.hpp"

namespace inhap::lab {

namespace {

/// Moves the probe between random points of a box above the object with minimum-jerk strokes
/// (20-80 mm, peak speed 20-250 mm/s), pausing briefly in between: free motion with tapping-like
/// accelerations, never touching.
class AirOperator final : public HandOperator {
 public:
  AirOperator(const Scene& scene, std::uint64_t seed) : scene_(scene), rng_(seed), tremor_(rng_) {}
  std::string name() const override { return "air"; }

  void begin(SimDevice& dev) override {
    dt_ = 1.0 / dev.info().servo_rate_hz;
    const Box3 b = scene_.object.shape().bounds();
    lo_ = Vec3(scene_.region.center.x() - scene_.region.radius - 20,
               scene_.region.center.y() - scene_.region.radius - 20,
               (b.empty() ? 0.0 : b.max.z()) + dev.probe_radius() + 20.0);
    hi_ = Vec3(scene_.region.center.x() + scene_.region.radius + 20,
               scene_.region.center.y() + scene_.region.radius + 20, lo_.z() + 60.0);
    dev.attach_hand(detail::random_hand(rng_, dev.params()));
    target_ = from_ = to_ = 0.5 * (lo_ + hi_);
    dev.place(target_);
    dev.set_hand_target(target_);
    tremor_.start(dev.time());
    t0_ = dev.time();
    duration_ = 0.2;
    moving_ = false;
  }

  void step(SimDevice& dev) override {
    const double t = dev.time() + dt_;
    const double tau = t - t0_;
    if (moving_) target_ = from_ + detail::min_jerk(tau / duration_) * (to_ - from_);
    if (tau >= duration_) {
      t0_ = t;
      moving_ = !moving_;
      if (moving_) {
        from_ = target_;
        // A stroke of 20-80 mm toward a random point of the box, peak speed 20-250 mm/s
        // (peak acceleration up to ~5 m/s^2, as when tapping).
        Vec3 goal;
        for (int k = 0; k < 3; ++k) goal[k] = rng_.uniform(lo_[k], hi_[k]);
        const Vec3 dir = (goal - from_).normalized();
        to_ = (from_ + rng_.uniform(20.0, 80.0) * dir).cwiseMax(lo_).cwiseMin(hi_);
        const double peak = detail::log_uniform(rng_, 20.0, 250.0);
        duration_ = std::max(0.15, 1.875 * (to_ - from_).norm() / peak);
      } else {
        duration_ = rng_.uniform(0.0, 0.3);
      }
    }
    dev.set_hand_target(target_ + tremor_.at(t));
  }

 private:
  Scene scene_;
  Rng rng_;
  detail::Tremor tremor_;
  double dt_ = 1e-3, t0_ = 0, duration_ = 0;
  bool moving_ = false;
  Vec3 lo_, hi_, target_, from_, to_;
};

std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t stream) {
  Rng r(seed ^ (0x5851f42d4c957f2dull * (stream + 1)));
  return r.next_u64();
}

}  // namespace

std::vector<std::string> operator_names() {
  return {"tap", "explore", "air"};
}

std::unique_ptr<HandOperator> make_air_operator(const Scene& scene, std::uint64_t seed) {
  return std::make_unique<AirOperator>(scene, seed);
}

std::unique_ptr<HandOperator> make_operator(std::string_view name, const Scene& scene,
                                            std::uint64_t seed, double seconds) {
  if (name == "tap") return make_tap_operator(scene, seed);
  if (name == "explore") return make_explore_operator(scene, seed, seconds);
  if (name == "air") return make_air_operator(scene, seed);
  throw Error(fmt::format("unknown operator '{}': expected tap, explore or air", name));
}

LabRecording record(SimDevice& device, HandOperator& op, double seconds, const Progress& progress) {
  if (!(std::isfinite(seconds) && seconds > 0 && seconds <= 24 * 3600))
    throw Error(fmt::format("recording length: expected 0 < seconds <= 86400, got {}", seconds));
  const double rate = device.info().servo_rate_hz;
  const long ticks = std::lround(seconds * rate);
  TickLogger log(device, static_cast<std::size_t>(ticks));
  op.begin(device);
  const long every = std::max(1L, static_cast<long>(rate));
  for (long i = 0; i < ticks; ++i) {
    log.sample();
    op.step(device);
    device.tick();
    if (progress && (i + 1) % every == 0) progress("recording", double(i + 1) / ticks, 0.0);
  }
  return log.take();
}

RecordSetup make_record_setup(const Scene& scene, const RecordSpec& spec) {
  RecordSetup s;
  s.params.probe = spec.probe;
  s.params.noise = spec.noise;
  s.params.gravity = spec.gravity;
  s.params.inertia = spec.inertia;
  s.params.seed = derive_seed(spec.seed, 0);
  s.params.physics = spec.physics;
  s.device = std::make_unique<SimDevice>(scene.object, s.params);
  const std::uint64_t op_seed = derive_seed(spec.seed, 1);
  if (spec.operator_name == "tap")
    s.op = make_tap_operator(scene, op_seed, spec.tap);
  else if (spec.operator_name == "explore")
    s.op = make_explore_operator(scene, op_seed, spec.seconds, spec.explore);
  else
    s.op = make_operator(spec.operator_name, scene, op_seed, spec.seconds);
  return s;
}

std::vector<std::string> record_comments(const Scene& scene, const RecordSpec& spec,
                                         const RecordSetup& setup) {
  const DeviceParams& dp = setup.params;
  return {
      fmt::format("inhap virtual lab: scene {}, operator {}, {:g} s, seed {}, probe {} (radius "
                  "{:g} mm), physics {}",
                  scene.name,
                  setup.op->name() + (spec.operator_name == "tap" && spec.tap.whole_object
                                          ? std::string(" (whole object)")
                                          : std::string()),
                  spec.seconds, spec.seed, spec.probe.kind == ProbeKind::kTip ? "tip" : "sphere",
                  spec.probe.radius_mm, to_string(spec.physics)),
      fmt::format("device: tool mass {:g} kg, gravity (0, 0, {:g}) mm/s^2, sensor noise {}, "
                  "gravity {}, inertia {}",
                  dp.tool_mass_kg, dp.gravity_mm_s2.z(), spec.noise ? "on" : "off",
                  spec.gravity ? "on" : "off", spec.inertia ? "on" : "off")};
}

LabRecording record_scene(const Scene& scene, const RecordSpec& spec, const Progress& progress) {
  RecordSetup setup = make_record_setup(scene, spec);
  LabRecording lab = record(*setup.device, *setup.op, spec.seconds, progress);
  lab.comments = record_comments(scene, spec, setup);
  return lab;
}

}  // namespace inhap::lab
