// The simulated device: saturation, NaN safety, encoder, sensor model, hand, determinism.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/lab/sim_device.hpp"

namespace inhap::lab {
namespace {

SoftObject small_block() {
  return SoftObject(BoxShape{Vec3(0, 0, 10), Vec3(20, 20, 10)}, ContactLaw{});
}

DeviceParams quiet() {
  DeviceParams p;
  p.noise = false;
  p.gravity = false;
  p.inertia = false;
  return p;
}

TEST(SimDevice, ForceSaturatesAtTheDeviceLimitByVectorNorm) {
  // Free space, constant 10 N (x) and (10, 10, 0) N commands for 20 ms: the probe accelerates
  // as under 6.2 N minus joint friction: v(t) = (F - f_c) / b (1 - exp(-b t / m)).
  const DeviceParams p = quiet();
  for (const Vec3& cmd : {Vec3(10, 0, 0), Vec3(10, 10, 0)}) {
    SimDevice dev(small_block(), p);
    dev.place(Vec3(0, 0, 100));
    for (int i = 0; i < 20; ++i) {
      dev.command_force(cmd);
      dev.tick();
    }
    const double t = 0.02, b = p.viscous_n_s_per_mm * 1e3;                             // N s/m
    const double v_si = (6.2 - p.coulomb_n) / b * (1 - std::exp(-b * t / p.mass_kg));  // m/s
    EXPECT_NEAR(dev.truth().velocity.norm(), v_si * 1e3, 1e-3 * v_si * 1e3);
    EXPECT_NEAR(dev.truth().velocity.normalized().dot(cmd.normalized()), 1.0, 1e-12);
    EXPECT_NEAR(dev.truth().motor_force.norm(), 6.2, 1e-12);
  }
}

TEST(SimDevice, NaNCommandGivesZeroForceAndNoNaNState) {
  SimDevice dev(small_block(), quiet());
  dev.place(Vec3(0, 0, 25));  // in contact with the block (probe radius 8, top at 20)
  for (int i = 0; i < 50; ++i) {
    dev.command_force(i % 2 ? Vec3(NAN, 0, 1) : Vec3(0, INFINITY, 0));
    dev.tick();
    EXPECT_TRUE(all_finite(dev.truth().position));
    EXPECT_TRUE(all_finite(dev.truth().velocity));
    EXPECT_TRUE(all_finite(dev.position()));
    EXPECT_TRUE(all_finite(dev.force_sensor()));
    EXPECT_EQ(dev.truth().motor_force, Vec3::Zero());
  }
  dev.command_force(Vec3(0, 0, -2));  // still works afterwards
  dev.tick();
  EXPECT_EQ(dev.truth().motor_force, Vec3(0, 0, -2));
}

TEST(SimDevice, EncoderQuantisesTo10Micrometres) {
  DeviceParams p = quiet();
  p.coulomb_n = 0;
  SimDevice dev(small_block(), p);
  dev.place(Vec3(1.23456, -7.891011, 60.00049));
  for (int i = 0; i < 200; ++i) {
    dev.command_force(Vec3(0.3, -0.2, 0.1));
    dev.tick();
    const Vec3 e = dev.position(), x = dev.truth().position;
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(e[k] / 0.01, std::round(e[k] / 0.01), 1e-6);
      EXPECT_LE(std::abs(e[k] - x[k]), 0.005 + 1e-9);
    }
  }
}

TEST(SimDevice, RawSensorHoldsToolWeightInertiaAndNoise) {
  DeviceParams p;
  p.noise = false;
  {
    SimDevice dev(small_block(), p);  // at rest in free air: weight only
    dev.tick();
    EXPECT_NEAR((dev.force_sensor() - Vec3(0, 0, -0.01 * 9.81)).norm(), 0, 1e-12);
  }
  {
    p.gravity = false;  // accelerated in free air: -m_tool a (a = mean over the tick)
    SimDevice dev(small_block(), p);
    for (int i = 0; i < 5; ++i) {
      dev.command_force(Vec3(2, 0, 0));
      dev.tick();
      const Vec3 expect = -0.01 * 1e-3 * dev.truth().acceleration;
      EXPECT_NEAR((dev.force_sensor() - expect).norm(), 0, 1e-12);
      // Analytic mean acceleration over tick i: (v(t_i) - v(t_i-1)) / T with
      // v(t) = (F - f_c) / b (1 - exp(-b t / m)) (SI units).
      const double b = p.viscous_n_s_per_mm * 1e3, m = p.mass_kg;
      auto v = [&](double t) { return (2.0 - p.coulomb_n) / b * (1 - std::exp(-b * t / m)); };
      const double a_si = (v((i + 1) * 1e-3) - v(i * 1e-3)) / 1e-3;
      EXPECT_NEAR(dev.force_sensor().x(), -0.01 * a_si, 1e-3 * 0.01 * a_si);
    }
  }
  {
    p.inertia = false;
    p.noise = true;  // noise only: zero mean, sigma 0.005 N per axis
    SimDevice dev(small_block(), p);
    double sum = 0, sum2 = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      dev.tick();
      sum += dev.force_sensor().y();
      sum2 += dev.force_sensor().y() * dev.force_sensor().y();
    }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(mean, 0, 4 * 0.005 / std::sqrt(n));
    EXPECT_NEAR(sd, 0.005, 0.005 * 0.03);
  }
}

TEST(SimDevice, HandPullsTheProbeToItsTarget) {
  DeviceParams p = quiet();
  SimDevice dev(small_block(), p);
  dev.place(Vec3(0, 0, 60));
  HandParams h;
  dev.attach_hand(h);
  const Vec3 target(12, -5, 70);
  for (int i = 0; i < 1500; ++i) {
    dev.set_hand_target(target);
    dev.tick();
  }
  // At rest, only the joint's Coulomb friction can hold the probe off the target.
  EXPECT_LE((dev.truth().position - target).norm(), p.coulomb_n / h.stiffness_n_per_mm + 1e-6);
  EXPECT_LT(dev.truth().velocity.norm(), 1e-6);
  dev.detach_hand();
  const Vec3 here = dev.truth().position;
  dev.set_hand_target(Vec3(100, 100, 100));  // ignored without a hand
  for (int i = 0; i < 100; ++i) dev.tick();
  EXPECT_NEAR((dev.truth().position - here).norm(), 0, 1e-9);
}

TEST(SimDevice, SameSeedSameReadings) {
  DeviceParams p;
  p.seed = 42;
  SimDevice a(small_block(), p), b(small_block(), p);
  p.seed = 43;
  SimDevice c(small_block(), p);
  bool differ = false;
  for (int i = 0; i < 500; ++i) {
    for (SimDevice* d : {&a, &b, &c}) {
      d->command_force(Vec3(0, 0, -0.5 * std::sin(i * 0.01)));
      d->tick();
    }
    EXPECT_EQ(a.force_sensor(), b.force_sensor());
    EXPECT_EQ(a.position(), b.position());
    differ = differ || a.force_sensor() != c.force_sensor();
  }
  EXPECT_TRUE(differ);
}

TEST(SimDevice, InfoExportsWhatCompensationNeeds) {
  DeviceParams p;
  p.tool_mass_kg = 0.02;
  p.probe = ProbeSpec::tip();
  SimDevice dev(small_block(), p);
  EXPECT_EQ(dev.info().tool_mass_kg, 0.02);
  EXPECT_EQ(dev.info().probe_radius_mm, 0.0);
  EXPECT_EQ(dev.info().max_force_n, 6.2);
  EXPECT_EQ(dev.info().gravity_mm_s2, Vec3(0, 0, -9810));
  EXPECT_EQ(dev.info().servo_rate_hz, 1000.0);
}

}  // namespace
}  // namespace inhap::lab
