// BridgeDevice: the inhap side of the device bridge (docs/bridge.md). A device client beside the
// vendor SDK sends its state every servo tick over UDP; BridgeDevice implements inhap::Device on
// top of that, so every tick-based procedure (palpation, recording, rendering) runs on a real
// device unchanged.
//
// Units: positions mm, forces N, time s.
//
// Pacing: the device paces the loop. tick() answers the last state with the commanded force and
// waits (poll) for the next state until `timeout_s` after the last one arrived (default two
// periods: one period after the next state was due); if none comes, the device is *faulted*:
// position and sensor hold their last values, the next forces sent are zero (status
// kStatusZeroed) until a state arrives again. Late, lost, out-of-order, foreign and malformed
// datagrams are counted in BridgeStats and never trusted. tick() and the accessors do not
// allocate and do not throw.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "inhap/core/device.hpp"
#include "inhap/haptics/bridge_protocol.hpp"

namespace inhap::haptics {

struct BridgeOptions {
  std::string listen = "127.0.0.1";         ///< IPv4 address to bind; non-loopback needs a key
  std::uint16_t port = kBridgeDefaultPort;  ///< UDP port; 0 = any free port (see port())
  std::string key;                          ///< shared secret for HMAC-SHA256; empty = unsigned
  DeviceInfo info;  ///< what the client's device is (rate, force limit, ...)
  /// No new state for this long after the last one -> fault, zero force. Default: two servo
  /// periods at 1 kHz, i.e. one period after the next state was due.
  double timeout_s = 0.002;
  /// Busy-wait window around the next state's expected arrival (the last arrival plus the
  /// smoothed time between states), s: the servo thread sleeps until this long before it, then
  /// polls without sleeping until this long after it, then sleeps again. A sleeping thread woken
  /// by a datagram from another core costs a wake-up (about 8 us in this virtual machine); the
  /// window costs at most twice this per period of CPU. 0: always sleep.
  double spin_s = 50e-6;
  /// The session is bound to the address and port of its first accepted state: states from any
  /// other sender are refused (foreign_peer) until the bound one has been silent this long, s.
  double rebind_s = 1.0;
};

struct BridgeStats {
  std::uint64_t received = 0;         ///< datagrams read
  std::uint64_t accepted = 0;         ///< states used
  std::uint64_t malformed = 0;        ///< failed to decode (length, magic, version, NaN, ...)
  std::uint64_t bad_auth = 0;         ///< unsigned or wrong HMAC tag while a key is set
  std::uint64_t out_of_order = 0;     ///< sequence not newer than the last accepted
  std::uint64_t foreign_session = 0;  ///< another session while the current one is live
  std::uint64_t foreign_peer = 0;     ///< another sender (address, port) than the bound one
  std::uint64_t out_of_range = 0;     ///< finite but implausible p, f or t (kOutOfRange)
  std::uint64_t bad_time = 0;         ///< device time backwards or ahead of the wall clock
  std::uint64_t handshakes = 0;       ///< welcomes sent (with a key: one per hello accepted)
  std::uint64_t lost = 0;             ///< sequence numbers skipped
  std::uint64_t superseded = 0;       ///< states replaced by a newer one in the same wait
  std::uint64_t timeouts = 0;         ///< ticks with no state within timeout_s
  std::uint64_t sent = 0;             ///< force packets sent
};

class BridgeDevice final : public Device {
 public:
  /// Binds the socket. Throws inhap::Error if the address is invalid, the port is taken, or a
  /// non-loopback address is given without a key.
  explicit BridgeDevice(BridgeOptions options);
  ~BridgeDevice() override;
  BridgeDevice(const BridgeDevice&) = delete;
  BridgeDevice& operator=(const BridgeDevice&) = delete;

  /// Waits up to timeout_s for the first state and locks its session. False on time-out.
  bool connect(double timeout_s);

  const DeviceInfo& info() const override { return options_.info; }
  double time() const override { return state_.device_time_s; }
  Vec3 position() const override { return state_.position_mm; }
  Vec3 force_sensor() const override { return state_.sensor_force_n; }
  /// Clamped to info().max_force_n; NaN or infinite gives zero.
  void command_force(const Vec3& force) override;
  /// Status bits sent with the next force (kStatusContact from the renderer).
  void set_status(std::uint32_t status) { status_ = status; }
  /// The next force was zeroed by a guard (the servo loop's watchdog, a non-finite output):
  /// it goes out with kStatusZeroed.
  void set_zeroed(bool zeroed) { zeroed_ = zeroed; }
  /// Sends the force for the last state, then waits for the next state.
  void tick() override;
  /// Sends zero force with kStatusStopping (call before closing).
  void stop();

  bool connected() const { return session_locked_; }
  bool faulted() const override { return faulted_; }
  bool self_paced() const override { return true; }
  std::uint32_t buttons() const { return state_.buttons; }
  std::uint32_t session() const { return state_.session; }
  const BridgeStats& stats() const { return stats_; }
  std::uint16_t port() const { return bound_port_; }

 private:
  bool wait_state(double timeout_s);               // true if a state was accepted
  int sleep_until_readable(double seconds) const;  // ppoll's result
  void note_arrival(double now);                   // last arrival and the smoothed period
  bool accept(const StatePacket& p, const void* from, double now);
  bool same_peer(const void* from, const unsigned char* peer) const;
  void on_hello(std::span<const std::uint8_t> bytes, const void* from, double now);
  // Decodes a state with the session's key, or with the key of a handshake that peer just made
  // (then that handshake's key becomes the session's: `fresh`).
  DecodeResult decode_state(std::span<const std::uint8_t> bytes, const void* from, StatePacket& p,
                            bool& fresh);
  void send_force(const Vec3& f, std::uint32_t status);

  BridgeOptions options_;
  BridgeKey key_;          ///< the shared key (empty: unsigned, loopback only)
  BridgeKey session_key_;  ///< with a key: the current session's, from its handshake
  BridgeKey pending_key_;  ///< with a key: of the last hello, until that peer's first state
  alignas(8) unsigned char pending_peer_[16] = {};
  std::uint32_t pending_session_ = 0;
  bool have_pending_ = false;
  int fd_ = -1;
  std::uint16_t bound_port_ = 0;
  // The client's address (sockaddr_in) of the last accepted state.
  alignas(8) unsigned char peer_[16] = {};
  bool have_peer_ = false;
  StatePacket state_;
  bool session_locked_ = false;
  bool faulted_ = false;
  double last_arrival_s_ = 0;  ///< monotonic time the last state was accepted, s
  double period_s_ = 0;        ///< smoothed time between accepted states, s (0: not known yet)
  Vec3 command_ = Vec3::Zero();
  std::uint32_t status_ = 0;
  bool zeroed_ = false;     ///< set_zeroed()
  bool nonfinite_ = false;  ///< command_force() got a non-finite force
  BridgeStats stats_;
  std::uint8_t buffer_[kMaxPacketBytes + 64] = {};
};

/// The port of a `--device` value "udp" (the default port) or "udp:PORT" (PORT 1-65535);
/// nullopt for anything else.
std::optional<std::uint16_t> parse_udp_device(std::string_view device);

/// True for 127.0.0.0/8 (the only addresses allowed without a key).
bool is_loopback(const std::string& ipv4);

}  // namespace inhap::haptics
