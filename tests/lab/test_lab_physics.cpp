// The virtual lab's "must show" physics, end to end through the simulated device and the
// device-side controllers, against answers computed from the scene parameters.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/lab/control.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::lab {
namespace {

constexpr double kR = 8.0, kTop = 25.0;

ContactLaw law() {
  ContactLaw l;
  l.k = 0.35, l.exponent = 1.5, l.damping = 0.004, l.k_t = 0.5, l.mu = 1.2, l.creep = 0.02;
  return l;
}

SoftObject planar(std::vector<Inclusion> inc = {}) {
  return SoftObject(CylinderShape{Vec3::Zero(), 50, kTop}, law(), std::move(inc));
}

double smooth(double s) {
  return s <= 0 ? 0 : s >= 1 ? 1 : 0.5 - 0.5 * std::cos(M_PI * s);
}

const Mat3 kZ = Vec3(0, 0, 1).asDiagonal();
const Mat3 kXY = Vec3(1, 1, 0).asDiagonal();

/// Normal load -F(t) along z (closed loop on the compensated sensor) plus PID on x, y.
std::unique_ptr<TickProtocol> press_and_move(const DeviceInfo& info, double force,
                                             PidPositionControl::Trajectory xy, double seconds) {
  std::vector<std::unique_ptr<TickProtocol>> parts;
  parts.push_back(std::make_unique<ForceProfileControl>(
      info, [force](double t) { return Vec3(0, 0, -force * smooth(t / 0.5)); }, seconds, 20.0, kZ));
  PidGains g;
  g.i_limit = 5;
  parts.push_back(std::make_unique<PidPositionControl>(info, std::move(xy), seconds, g, kXY));
  return std::make_unique<CompositeProtocol>(std::move(parts));
}

TEST(LabPhysics, DragUnderConstantNormalLoadSettlesAtMu) {
  SimDevice dev(planar());
  const Vec3 start(-15, 0, kTop + kR + 0.3);
  dev.place(start);
  // Drag at 2 mm/s from t = 1 s; the pre-sliding spring stretches to mu f_N / k_t = 7.2 mm
  // before gross sliding, so steady sliding is judged over t = 7..10 s.
  const double v = 2.0;  // mm/s
  auto proto = press_and_move(
      dev.info(), 3.0, [&](double t) { return Vec3(start.x() + v * std::max(0.0, t - 1.0), 0, 0); },
      10.0);
  const LabRecording lab = run_palpation(dev, *proto, 10.0);
  double fn = 0, ft = 0, sn = 0, st = 0;
  int n = 0;
  for (std::size_t i = 0; i < lab.truth.size(); ++i) {
    if (lab.truth.t[i] < 7.0) continue;
    ASSERT_EQ(lab.truth.contact[i], 1);
    fn += lab.truth.force[i].z(), ft += lab.truth.force[i].head<2>().norm();
    sn += lab.rec.f[i].z(), st += lab.rec.f[i].head<2>().norm();
    ++n;
  }
  const double ratio = ft / fn, sensor_ratio = st / sn;
  std::printf(
      "drag at %.0f mm/s, f_N %.3f N: |f_T|/f_N = %.4f (truth), %.4f (sensor), mu = 1.2 "
      "(errors %.2f %%, %.2f %%)\n",
      v, fn / n, ratio, sensor_ratio, 100 * (ratio / 1.2 - 1), 100 * (sensor_ratio / 1.2 - 1));
  EXPECT_NEAR(fn / n, 3.0, 0.03);
  EXPECT_NEAR(ratio / 1.2, 1.0, 0.03);
  EXPECT_NEAR(sensor_ratio / 1.2, 1.0, 0.03);
  // The anchor slid along with the probe over the last three seconds.
  const std::size_t last = lab.truth.size() - 1, mid = last - 3000;
  EXPECT_NEAR(lab.truth.anchor[last].x() - lab.truth.anchor[mid].x(), 3 * v, 0.1);
}

TEST(LabPhysics, PreSlidingForceGrowsLinearlyWithLateralDisplacement) {
  SimDevice dev(planar());
  const Vec3 start(0, 0, kTop + kR + 0.3);
  dev.place(start);
  // 3 N normal; then 3 mm sideways at 1 mm/s (elastic limit mu f_N / k_t = 7.2 mm).
  auto proto = press_and_move(
      dev.info(), 3.0, [](double t) { return Vec3(std::clamp(t - 1.5, 0.0, 3.0), 0, 0); }, 5.0);
  const LabRecording lab = run_palpation(dev, *proto, 5.0);
  // Least-squares line of the tangential sensor force against the encoder displacement.
  double su = 0, sf = 0, suu = 0, suf = 0, sff = 0;
  int n = 0;
  Vec3 p0 = Vec3::Zero(), a0 = Vec3::Zero();
  for (std::size_t i = 0; i < lab.rec.size(); ++i) {
    const double t = lab.rec.t[i];
    if (t < 1.4) continue;
    if (n == 0) p0 = lab.rec.p[i], a0 = lab.truth.anchor[i];
    const double u = lab.rec.p[i].x() - p0.x(), f = -lab.rec.f[i].x();
    su += u, sf += f, suu += u * u, suf += u * f, sff += f * f;
    ++n;
    EXPECT_NEAR((lab.truth.anchor[i] - a0).norm(), 0.0, 1e-9);  // stuck: the anchor stays put
  }
  const double cov = suf / n - su / n * sf / n, var_u = suu / n - su / n * su / n;
  const double var_f = sff / n - sf / n * sf / n;
  const double slope = cov / var_u, r2 = cov * cov / (var_u * var_f);
  std::printf("pre-sliding: slope %.4f N/mm (k_t = 0.5), R^2 = %.5f, range %.2f mm\n", slope, r2,
              lab.rec.p.back().x() - p0.x());
  EXPECT_NEAR(slope, 0.5, 0.5 * 0.02);
  EXPECT_GT(r2, 0.999);
}

/// Presses `force` N straight down at (x, y) until steady; returns the depth below the top.
double indentation(const SoftObject& obj, double x, double y, double force) {
  SimDevice dev(obj);
  dev.place(Vec3(x, y, kTop + kR + 0.3));
  ForceProfileControl ctl(
      dev.info(), [force](double t) { return Vec3(0, 0, -force * smooth(t / 0.5)); }, 2.5, 20.0);
  const LabRecording lab = run_palpation(dev, ctl, 2.5);
  double z = 0;
  int n = 0;
  for (std::size_t i = lab.rec.size() - 200; i < lab.rec.size(); ++i) z += lab.rec.p[i].z(), ++n;
  return kTop + kR - z / n;
}

TEST(LabPhysics, IndentationAt3NIsDeeperOverASoftInclusion) {
  const double factor = 0.4, r = 10, d = 6;  // blob 6 mm below the top, 0.4x stiffness
  const SoftObject obj = planar({{Vec3(0, 0, kTop - d), r, factor, 1.0}});
  const double over = indentation(obj, 0, 0, 3.0), away = indentation(obj, 35, 0, 3.0);
  const double s_over = 1 + (factor - 1) * std::exp(-d * d / (r * r));
  const double s_away = 1 + (factor - 1) * std::exp(-(35.0 * 35 + d * d) / (r * r));
  const double want_over = std::pow(3.0 / (0.35 * s_over), 1 / 1.5);
  const double want_away = std::pow(3.0 / (0.35 * s_away), 1 / 1.5);
  std::printf(
      "indentation at 3 N: %.3f mm over the inclusion (expected %.3f), %.3f mm away "
      "(expected %.3f); ratio %.4f (expected %.4f)\n",
      over, want_over, away, want_away, over / away, want_over / want_away);
  EXPECT_NEAR(over / want_over, 1.0, 0.015);
  EXPECT_NEAR(away / want_away, 1.0, 0.015);
  EXPECT_NEAR((over / away) / (want_over / want_away), 1.0, 0.02);
}

TEST(LabPhysics, LoadingUnloadingCycleThroughTheDeviceCreatesNoEnergy) {
  for (double lateral : {0.0, 1.0, 3.0}) {  // the last one slides
    SimDevice dev(planar());
    dev.place(Vec3(0, 0, kTop + kR + 0.2));
    ForceProfileControl ctl(
        dev.info(),
        [lateral](double t) {
          const double s = std::sin(M_PI * std::clamp(t / 2.0, 0.0, 1.0));
          return Vec3(lateral * s, 0, -4.0 * s);
        },
        3.0);
    double work = 0, peak = 0;
    Vec3 x_prev = dev.truth().position, f_prev = dev.contact().force;
    while (!ctl.done()) {
      dev.command_force(ctl.step(dev.time(), dev.position(), dev.force_sensor()));
      dev.tick();
      const Vec3 x = dev.truth().position, f = dev.contact().force;
      work += 0.5 * (f + f_prev).dot(x - x_prev);
      peak = std::max(peak, f.norm());
      x_prev = x, f_prev = f;
    }
    EXPECT_FALSE(dev.contact().in_contact && dev.contact().normal_force > 0.05);
    std::printf("cycle (lateral %.0f N): work by the object on the probe %.3g N mm\n", lateral,
                work);
    EXPECT_LT(work, 1e-4 * peak * 5.0) << "lateral " << lateral;
  }
}

TEST(LabPhysics, PlasticDisplacementGrowsWithPlateauOnlyPastTheLimit) {
  // Thesis 4.3.2 / Table 4.1: f_N = 1 N, f_T below and above mu f_N, plateau 100 vs 600 ms.
  auto u_plastic = [](double ft, double plateau) {
    SimDevice dev(planar());
    const Vec3 pc(0, 0, kTop + kR);  // touching, unloaded: the initial contact centre
    dev.place(pc);
    const double tn = 0.3, tt = 0.3, end = 2 * tn + 2 * tt + plateau;
    ForceProfileControl ctl(
        dev.info(),
        [=](double t) {
          const double n = smooth(t / tn) * smooth((end - t) / tn);
          const double tg = smooth((t - tn) / tt) * smooth((end - tn - t) / tt);
          return Vec3(ft * tg, 0, -1.0 * n);
        },
        end + 0.3);
    run_palpation(dev, ctl, end + 0.3);
    return (dev.position() - pc).head<2>().norm();  // p_r - p_c, tangential part
  };
  const double below = 0.7 * 1.2, above = 1.15 * 1.2;
  const double b100 = u_plastic(below, 0.1), b600 = u_plastic(below, 0.6);
  const double a100 = u_plastic(above, 0.1), a600 = u_plastic(above, 0.6);
  std::printf("u_p (mm): f_T %.2f N: %.3f / %.3f; f_T %.2f N: %.3f / %.3f (100 / 600 ms)\n", below,
              b100, b600, above, a100, a600);
  EXPECT_LT(std::abs(b600 - b100), 0.02);
  EXPECT_LT(b100, 0.2);
  EXPECT_GT(a600 - a100, 0.5);
}

TEST(LabPhysics, TappingObjectsSpanTheThesisStiffnessRangeAt5N) {
  std::vector<double> k;
  for (const auto& name : tapping_scene_names()) {
    const Scene s = builtin_scene(name);
    const auto spot = s.object.shape().drop(s.region.center.x(), s.region.center.y(), kR);
    ASSERT_TRUE(spot.has_value());
    const Vec3 n = s.object.query(*spot).normal;
    SimDevice dev(s.object);
    dev.place(*spot + 0.3 * n);
    ForceProfileControl ctl(
        dev.info(), [n](double t) { return Vec3(-5.0 * smooth(t / 0.5) * n); }, 2.5, 20.0);
    const LabRecording lab = run_palpation(dev, ctl, 2.5);
    double depth = 0;
    for (std::size_t i = lab.rec.size() - 200; i < lab.rec.size(); ++i)
      depth += (*spot - lab.rec.p[i]).dot(n) / 200;
    const ContactLaw& m = s.object.material();
    const double want = 5.0 / std::pow(5.0 / m.k, 1.0 / m.exponent);
    std::printf("%-20s stiffness at 5 N: %.3f N/mm (expected %.3f)\n", name.c_str(), 5 / depth,
                want);
    EXPECT_NEAR(5 / depth / want, 1.0, 0.03) << name;
    k.push_back(5 / depth);
  }
  EXPECT_LT(*std::min_element(k.begin(), k.end()), 0.35);
  EXPECT_GT(*std::max_element(k.begin(), k.end()), 2.5);
}

}  // namespace
}  // namespace inhap::lab
