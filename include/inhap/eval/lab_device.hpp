// The virtual lab as a bridge device: a simulated device (and, optionally, one of the lab's
// simulated operators holding it) behind the C bridge client (clients/c/inhap_bridge.h), so
// `inhap serve`, `inhap record` and `inhap sys palpate --device udp` can be tried, tested and
// timed without hardware, across a real process and socket boundary (docs/bridge.md).
//
// Units: mm, N, s.
//
// Every tick the client sends the device's state (time, encoder position, raw sensor force),
// waits for inhap's force, commands it, lets the operator move the hand and advances the
// device. With an operator and the same scene, seed and physics, the device and operator are
// those of `inhap lab record` (lab::make_record_setup), so a recording made through the bridge
// carries the same samples as the direct one. Without an operator ("none") the hand is detached
// and the probe placed at `place`, as `inhap sys palpate` sets up the lab device.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "inhap/core/types.hpp"
#include "inhap/eval/progress.hpp"
#include "inhap/lab/sim_device.hpp"

namespace inhap::eval {

struct LabDeviceOptions {
  std::string scene = "planar";       ///< built-in scene
  std::string scene_file;             ///< or a scene JSON file
  std::string operator_name = "tap";  ///< tap | explore | air | none (hand detached)
  double seconds = 60.0;              ///< simulated seconds to run (ticks = seconds x rate)
  std::uint64_t seed = 1;             ///< as `inhap lab record --seed` (none: the noise seed)
  std::string physics = "builtin";    ///< builtin | mujoco
  lab::ProbeSpec probe;               ///< probe of the simulated device
  std::optional<Vec3> place;          ///< start position of the probe centre (operator none), mm
  std::string host = "127.0.0.1";     ///< where inhap listens
  std::uint16_t port = 47110;
  std::string key;  ///< shared secret (HMAC-SHA256); empty on loopback
  /// Wait for every answer (up to answer_timeout_s, default then 2 s) and run as fast as the
  /// exchange allows: a deterministic session for tests. Otherwise the client keeps the device's
  /// 1 kHz pace with a real clock and goes on with zero force when inhap does not answer in time
  /// (as a real device callback must).
  bool lockstep = false;
  double answer_timeout_s = 0.002;  ///< s (lockstep: 2 s when left at this default)
  double connect_timeout_s = 30.0;  ///< keep sending the first state this long, s
  /// After the join: stop when inhap has not answered for this long (wall clock), as when it
  /// crashed or its "stopping" datagram was lost, s; 0: never (run all `seconds`).
  double silence_stop_s = 10.0;
  std::string out;    ///< optional: the device side's own recording + truth
  Progress progress;  ///< empty: silent
};

struct LabDeviceResult {
  long ticks = 0;          ///< ticks run
  long answered = 0;       ///< forces received in time
  long timeouts = 0;       ///< ticks with no answer in time (zero force)
  bool stopped = false;    ///< inhap said it was stopping (status bit 2)
  bool silent = false;     ///< stopped because inhap went silent for silence_stop_s
  double max_force_n = 0;  ///< largest force inhap commanded, N
};

/// Runs the lab device until `seconds` are simulated, inhap stops, or inhap has been silent for
/// silence_stop_s. Throws inhap::Error when the socket cannot be opened, no inhap answers within
/// connect_timeout_s, or the scene is invalid.
LabDeviceResult run_lab_device(const LabDeviceOptions& options);

/// The lines `inhap lab device` prints before and after the session.
std::string lab_device_banner(const LabDeviceOptions& o);
std::string lab_device_summary(const LabDeviceResult& r);

}  // namespace inhap::eval
