// Simulated constant-force stroke (see stroke.hpp). Units: mm, N, s.
#include "inhap/rendering/stroke.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "inhap/core/device.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"

namespace inhap::rendering {

std::optional<Algorithm> parse_algorithm(std::string_view s) {
  if (s == "tca") return Algorithm::kTCA;
  if (s == "cba") return Algorithm::kCBA;
  return std::nullopt;
}

namespace {

void check(const StrokeOptions& o, const Model& model) {
  auto fail = [](const char* what, double v) {
    throw Error(fmt::format("stroke: expected {}, got {}", what, v));
  };
  if (!o.from.allFinite() || !o.to.allFinite()) throw Error("stroke: expected finite --from/--to");
  if (!(o.force_n > 0) || o.force_n > model.params().force_limit_n)
    throw Error(fmt::format("stroke: expected a force in (0, {}] N (the force limit), got {}",
                            model.params().force_limit_n, o.force_n));
  if (!(o.speed_mm_s > 0) || !std::isfinite(o.speed_mm_s)) fail("speed > 0 mm/s", o.speed_mm_s);
  if (!(o.approach_speed_mm_s > 0)) fail("approach speed > 0 mm/s", o.approach_speed_mm_s);
  if (!(o.force_time_constant_s > 0)) fail("force time constant > 0 s", o.force_time_constant_s);
  if (!(o.max_vertical_speed_mm_s > 0))
    fail("max vertical speed > 0 mm/s", o.max_vertical_speed_mm_s);
  if (!(o.rate_hz > 0) || !std::isfinite(o.rate_hz)) fail("rate > 0 Hz", o.rate_hz);
  if (!(o.tremor_n >= 0) || !std::isfinite(o.tremor_n)) fail("tremor >= 0 N", o.tremor_n);
  if (!(o.settle_s >= 0)) fail("settle time >= 0 s", o.settle_s);
  if (!(o.timeout_s > 0)) fail("timeout > 0 s", o.timeout_s);
}

enum class Phase { kApproach, kSettle, kStroke, kLift, kDone };

constexpr double kSaturated = 0.999;  // |f| at this fraction of the limit counts as clamped
constexpr double kMaxSettleS = 60.0;  // contact time allowed to reach the force, s

}  // namespace

std::vector<StrokeSample> simulate_stroke(const Model& model, Algorithm algorithm,
                                          const StrokeOptions& o) {
  check(o, model);
  const double dt = 1.0 / o.rate_hz;
  const Box3 box = model.index().bounds();
  const double floor_z = box.min.z() - 10.0;
  const double vmax = o.max_vertical_speed_mm_s;
  const Vec2 dir2 = o.to - o.from;
  const double length = dir2.norm();

  Rng rng(o.seed);
  const double alpha = std::exp(-2 * M_PI * 10.0 * dt);  // tremor: first-order 10 Hz low pass
  double tremor = 0;

  State st;
  std::vector<StrokeSample> out;
  Vec3 p(o.from.x(), o.from.y(), box.max.z() + o.clearance_mm);
  Phase phase = Phase::kApproach;
  double settled = 0, travelled = 0;
  int free_ticks = 0;
  double contact_time = 0;
  const double limit = effective_force_limit(model.params().force_limit_n);
  const auto max_ticks = static_cast<long>(o.timeout_s * o.rate_hz);
  for (long n = 0; phase != Phase::kDone; ++n) {
    if (n > max_ticks)
      throw Error(
          fmt::format("stroke: not finished after {} s of simulated time (timeout)", o.timeout_s));
    const Vec3 f = step(model, st, p, algorithm);
    out.push_back({n * dt, p, st.ihip.point, st.cihip, f, st.k, st.s, st.t, st.collision});

    tremor = alpha * tremor + std::sqrt(1 - alpha * alpha) * o.tremor_n * rng.normal();
    const double target = o.force_n + tremor;
    // Vertical regulation: descend in free space, track the force in contact. While the force
    // is clamped at the device's limit it says nothing about the depth (on a stiff mesh the
    // first millisecond of contact saturates it): the hand then goes by the depth below the
    // constrained proxy, aiming at the depth of the wanted force (target / k).
    double vz = -o.approach_speed_mm_s;
    if (st.collision) {
      const double k = std::max(st.k, model.params().min_stiffness);
      const bool saturated = f.norm() >= kSaturated * limit;
      const double err = saturated ? k * (st.cihip - p).norm() - target : f.norm() - target;
      vz = std::clamp(err / (k * o.force_time_constant_s), -vmax, vmax);
      contact_time += dt;
    }
    switch (phase) {
      case Phase::kApproach:
        if (st.collision) phase = Phase::kSettle;
        if (p.z() < floor_z)
          throw Error(fmt::format("stroke: no surface below ({}, {}) mm", o.from.x(), o.from.y()));
        break;
      case Phase::kSettle:
        settled =
            (st.collision && std::abs(f.norm() - o.force_n) < 0.05 * o.force_n) ? settled + dt : 0;
        if (settled >= o.settle_s) phase = Phase::kStroke;
        if (phase == Phase::kSettle && contact_time > o.settle_s + kMaxSettleS)
          throw Error(fmt::format(
              "stroke: the hand cannot hold {} N at ({}, {}) mm: after {} s in contact the force "
              "is {:.3f} N",
              o.force_n, o.from.x(), o.from.y(), kMaxSettleS, f.norm()));
        break;
      case Phase::kStroke:
        travelled = std::min(length, travelled + o.speed_mm_s * dt);
        if (length > 0) {
          const Vec2 xy = o.from + (travelled / length) * dir2;
          p.x() = xy.x();
          p.y() = xy.y();
        }
        if (travelled >= length) phase = Phase::kLift;
        break;
      case Phase::kLift:
        vz = o.approach_speed_mm_s;
        free_ticks = st.collision ? 0 : free_ticks + 1;
        if (free_ticks >= 10) phase = Phase::kDone;
        break;
      case Phase::kDone:
        break;
    }
    // Never wander off below the mesh in free space (in contact the force regulation decides
    // the depth: a soft map needs F / k, tens of mm, below the lowest vertex).
    if (p.z() < floor_z && !st.collision && phase != Phase::kLift) vz = std::max(vz, 0.0);
    p.z() += vz * dt;
  }
  return out;
}

}  // namespace inhap::rendering
