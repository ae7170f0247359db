// The lab device behind the UDP bridge (`inhap lab device`): it stops by itself when inhap goes
// silent after the join (a crashed inhap, a lost "stopping" datagram) instead of simulating all
// its seconds with a wait per tick.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "inhap/core/error.hpp"
#include "inhap/eval/lab_device.hpp"
#include "inhap/haptics/bridge_device.hpp"

namespace inhap::eval {
namespace {

struct DeviceRun {
  LabDeviceResult result;
  double wall_s = 0;
};

// inhap's side: join, answer `answered` ticks, then fall silent (no "stopping").
DeviceRun run_against_silent_inhap(double silence_stop_s, int answered) {
  haptics::BridgeOptions bo;
  bo.port = 0;
  bo.timeout_s = 5.0;
  haptics::BridgeDevice inhap(bo);
  LabDeviceOptions o;
  o.scene = "planar";
  o.operator_name = "none";
  o.seconds = 3600;  // far more than the test waits: only the silence can end it
  o.port = inhap.port();
  o.lockstep = true;
  o.answer_timeout_s = 0.2;
  o.connect_timeout_s = 20;
  o.silence_stop_s = silence_stop_s;
  DeviceRun run;
  std::thread device([&] {
    const auto t0 = std::chrono::steady_clock::now();
    run.result = run_lab_device(o);
    run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  });
  EXPECT_TRUE(inhap.connect(20.0));
  for (int i = 0; i < answered; ++i) {
    inhap.command_force(Vec3::Zero());
    inhap.tick();
  }
  device.join();  // inhap says nothing more
  return run;
}

TEST(LabDevice, StopsWhenInhapFallsSilentAfterTheJoin) {
  const DeviceRun r = run_against_silent_inhap(1.0, 50);
  EXPECT_TRUE(r.result.silent);
  EXPECT_FALSE(r.result.stopped);
  EXPECT_GE(r.result.answered, 50);
  EXPECT_GE(r.result.timeouts, 1);
  // One answer time-out after the silence began is past silence_stop_s = 1 s: a tick or a few,
  // not the hour of simulated ticks (each would wait 0.2 s).
  EXPECT_LT(r.result.ticks, 100);
  EXPECT_NE(lab_device_summary(r.result).find("inhap went silent"), std::string::npos);
}

TEST(LabDevice, RefusesANegativeSilence) {
  LabDeviceOptions o;
  o.silence_stop_s = -1;
  EXPECT_THROW(run_lab_device(o), Error);
}

}  // namespace
}  // namespace inhap::eval
