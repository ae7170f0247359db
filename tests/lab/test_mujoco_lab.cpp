// The MuJoCo lab backend (physics.hpp, docs/lab-mujoco.md) against known answers: static
// indentation vs MuJoCo's documented soft-contact law for the solref/solimp the backend sets,
// |f_T|/f_N while sliding vs mu, and recordings with truth. Skipped when the build has no MuJoCo.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "inhap/core/error.hpp"
#include "inhap/lab/control.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::lab {
namespace test_mujoco_lab {

constexpr double kR = 8.0, kTop = 25.0;

#define REQUIRE_MUJOCO() \
  if (!mujoco_available()) GTEST_SKIP() << "this build has no MuJoCo"

ContactLaw law() {
  ContactLaw l;
  l.k = 0.35, l.exponent = 1.5, l.damping = 0.004, l.k_t = 0.5, l.mu = 1.2, l.creep = 0.02;
  return l;
}

SoftObject planar() {
  return SoftObject(CylinderShape{Vec3::Zero(), 50, kTop}, law());
}

DeviceParams mujoco_device() {
  DeviceParams dp;
  dp.physics = Physics::kMujoco;
  dp.noise = false;
  dp.max_force_n = 20;  // a lab device strong enough for the 8 N indentation
  return dp;
}

// MuJoCo's impedance sigmoid d(r) (documented with solimp; r and width in the same unit).
double impedance(const MujocoParams& p, double r) {
  const double x = r / p.solimp_width_mm;
  if (x >= 1) return p.solimp_dmax;
  if (x <= 0) return p.solimp_d0;
  const double y =
      x <= p.solimp_mid
          ? std::pow(x, p.solimp_power) / std::pow(p.solimp_mid, p.solimp_power - 1)
          : 1 - std::pow(1 - x, p.solimp_power) / std::pow(1 - p.solimp_mid, p.solimp_power - 1);
  return p.solimp_d0 + y * (p.solimp_dmax - p.solimp_d0);
}

// The documented static law F = (K / w) d(r)^2 r / (1 - d(r)) with K calibrated so that the
// device depth at 5 N (contact r5 + coupling 5 / k_n) is the scene law's depth: F(r) relative to
// F(r5) = 5 N. Returns the device depth (mm) at force f by bisection on r.
double documented_depth(const MujocoParams& p, double depth5, double f) {
  const double kn = p.coupling_normal_n_per_mm, r5 = depth5 - 5.0 / kn;
  const auto g = [&](double r) {
    const double d = impedance(p, r);
    return d * d * r / (1 - d);
  };
  double lo = 0, hi = 50;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (5.0 * g(mid) / g(r5) < f ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi) + f / kn;
}

// Presses f N straight down (commanded force, no joint friction) until static; device depth.
double indentation(double f) {
  DeviceParams dp = mujoco_device();
  dp.coulomb_n = 0;
  dp.viscous_n_s_per_mm = 0.01;  // settles faster; no force at rest
  SimDevice dev(planar(), dp);
  dev.place(Vec3(0, 0, kTop + kR + 0.2));
  for (int i = 0; i < 2500; ++i) {
    dev.command_force(Vec3(0, 0, -f * std::min(1.0, i / 500.0)));
    dev.tick();
  }
  EXPECT_TRUE(dev.contact().in_contact);
  EXPECT_NEAR(dev.contact().force.z(), f, 0.01 * f);
  return kTop + kR - dev.truth().position.z();
}

TEST(MujocoLab, StaticIndentationFollowsTheDocumentedSoftContactLaw) {
  REQUIRE_MUJOCO();
  const MujocoParams p;
  const double depth5 = law().depth_at(5.0);
  // 8 N sinks the probe centre below the top face (the top is a MuJoCo plane: MuJoCo's
  // sphere-box contact was lost there, docs/lab-mujoco.md).
  bool below_top = false;
  for (double f : {1.0, 2.0, 4.0, 5.0, 8.0}) {
    const double got = indentation(f), want = documented_depth(p, depth5, f);
    below_top = below_top || want > kR;
    std::printf("MuJoCo indentation at %.1f N: %.4f mm, documented law %.4f mm\n", f, got, want);
    EXPECT_NEAR(got, want, 0.01 * want + 0.01) << f << " N";
  }
  EXPECT_TRUE(below_top);
  // The law stiffens with depth: the secant stiffness at 5 N exceeds that at 1 N.
  EXPECT_GT(5.0 / documented_depth(p, depth5, 5.0), 1.5 / documented_depth(p, depth5, 1.0));
}

// Out of contact the device and the probe body are two masses joined by the coupling spring:
// a force F for a time T must leave the pair moving at F T / (m_device + m_probe), and without
// friction or force that momentum must stay. (The coupling once gave the probe body a force
// evaluated after the device had moved, a net force k_n v dt on the pair: the free device
// accelerated away at about 25/s and the closed-loop drag below diverged.)
TEST(MujocoLab, FreeDeviceConservesMomentum) {
  REQUIRE_MUJOCO();
  DeviceParams dp = mujoco_device();
  dp.coulomb_n = 0, dp.viscous_n_s_per_mm = 0;
  SimDevice dev(planar(), dp);
  dev.place(Vec3(0, 0, kTop + kR + 20));
  const double f = 0.1, t_push = 0.1;  // N, s
  const int pushes = static_cast<int>(std::lround(t_push * dp.servo_rate_hz));
  for (int i = 0; i < pushes; ++i) {
    dev.command_force(Vec3(f, 0, 0));
    dev.tick();
  }
  // F T / m in kg -> m/s; * 1e3 -> mm/s.
  const double want = f * t_push / (dp.mass_kg + dp.mujoco.probe_mass_kg) * 1e3;
  EXPECT_NEAR(dev.truth().velocity.x(), want, 0.01 * want);
  for (int i = 0; i < 1000; ++i) dev.tick();
  EXPECT_FALSE(dev.contact().in_contact);
  EXPECT_NEAR(dev.truth().velocity.x(), want, 0.01 * want) << "after 1 s coasting";
  EXPECT_NEAR(dev.truth().velocity.z(), 0.0, 1e-6);
}

const Mat3 kZ = Vec3(0, 0, 1).asDiagonal();
const Mat3 kXY = Vec3(1, 1, 0).asDiagonal();

double smooth(double s) {
  return s <= 0 ? 0 : s >= 1 ? 1 : 0.5 - 0.5 * std::cos(M_PI * s);
}

// Closed-loop drag (force control on the compensated sensor in z, PID in x, y), as the
// palpation protocol drives the device. This diverged by t = 7 s until the coupling force on
// the probe body and on the device were made equal and opposite (docs/lab-mujoco.md, Quirks).
TEST(MujocoLab, SlidingFrictionRatioIsMu) {
  REQUIRE_MUJOCO();
  SimDevice dev(planar(), mujoco_device());
  const Vec3 start(-15, 0, kTop + kR + 0.3);
  dev.place(start);
  const double v = 2.0, force = 3.0;  // mm/s, N
  std::vector<std::unique_ptr<TickProtocol>> parts;
  parts.push_back(std::make_unique<ForceProfileControl>(
      dev.info(), [force](double t) { return Vec3(0, 0, -force * smooth(t / 0.5)); }, 10.0, 20.0,
      kZ));
  PidGains g;
  g.i_limit = 5;
  parts.push_back(std::make_unique<PidPositionControl>(
      dev.info(), [&](double t) { return Vec3(start.x() + v * std::max(0.0, t - 1.0), 0, 0); },
      10.0, g, kXY));
  CompositeProtocol proto(std::move(parts));
  const LabRecording lab = run_palpation(dev, proto, 10.0);
  double fn = 0, ft = 0;
  int n = 0;
  for (std::size_t i = 0; i < lab.truth.size(); ++i) {
    if (lab.truth.t[i] < 7.0) continue;
    ASSERT_EQ(lab.truth.contact[i], 1)
        << "t = " << lab.truth.t[i] << " s, p = " << lab.rec.p[i].transpose()
        << ", f = " << lab.rec.f[i].transpose();
    fn += lab.truth.force[i].z(), ft += lab.truth.force[i].head<2>().norm();
    ++n;
  }
  const double ratio = ft / fn;
  std::printf("MuJoCo drag at %.0f mm/s, f_N %.3f N: |f_T|/f_N = %.4f, mu = 1.2\n", v, fn / n,
              ratio);
  EXPECT_NEAR(fn / n, force, 0.05);
  EXPECT_NEAR(ratio / 1.2, 1.0, 0.03);
  // The anchor (probe body) slid along with the device over the last three seconds.
  const std::size_t last = lab.truth.size() - 1, mid = last - 3000;
  EXPECT_NEAR(lab.truth.anchor[last].x() - lab.truth.anchor[mid].x(), 3 * v, 0.2);
}

TEST(MujocoLab, RecordsTheDomeWithTruthAndRejectsShapesItCannotRepresent) {
  REQUIRE_MUJOCO();
  RecordSpec spec;
  spec.seconds = 4;
  spec.physics = Physics::kMujoco;
  const LabRecording lab = record_scene(builtin_scene("dome"), spec);
  ASSERT_EQ(lab.rec.size(), 4000u);
  std::size_t contact = 0;
  double fmax = 0;
  for (std::size_t i = 0; i < lab.truth.size(); ++i) {
    ASSERT_TRUE(all_finite(lab.rec.p[i]) && all_finite(lab.rec.f[i])) << i;
    if (!lab.truth.contact[i]) continue;
    ++contact;
    ASSERT_TRUE(all_finite(lab.truth.anchor[i]) && std::isfinite(lab.truth.k[i])) << i;
    fmax = std::max(fmax, lab.truth.force[i].norm());
  }
  EXPECT_GT(contact, 500u);
  EXPECT_GT(fmax, 1.0);
  EXPECT_NE(lab.comments.front().find("physics mujoco"), std::string::npos);
  DeviceParams dp;
  dp.physics = Physics::kMujoco;
  EXPECT_THROW(SimDevice(builtin_scene("ridged-silicone").object, dp), Error);
}

}  // namespace test_mujoco_lab
}  // namespace inhap::lab
