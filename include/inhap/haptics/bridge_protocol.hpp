// The inhap device bridge: versioned little-endian UDP datagrams exchanged once per servo tick
// between a device client (beside the vendor SDK) and inhap. See docs/bridge.md.
//
// Units: positions mm, forces N, time s.
//
// device -> inhap (StatePacket): magic, version, kind 1, flags, session, sequence, device time,
//   probe position, raw sensor force (valid if flags has kHasSensorForce), buttons.
// inhap -> device (ForcePacket): magic, version, kind 2, flags, session, sequence echoed, force,
//   status bits.
// With a shared key, a handshake starts every session: the device sends a hello with a random
// nonce, inhap answers a welcome with a nonce of its own, both signed with the shared key; the
// session's key is HMAC-SHA256(shared key, label | session | both nonces) and every state and
// force of the session carries an HMAC-SHA256 tag with it (flag kSigned). A receiver with a key
// drops every packet whose tag does not verify, or that is unsigned, and a recorded session is
// useless later: its states verify only with that session's key.
//
// Encoding and decoding never allocate and never throw: they are called on the servo thread.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "inhap/core/types.hpp"

namespace inhap::haptics {

inline constexpr std::uint32_t kBridgeMagic = 0x42504849;  ///< "IHPB" little-endian
inline constexpr std::uint16_t kBridgeVersion = 1;
inline constexpr std::uint16_t kBridgeDefaultPort = 47110;

enum class PacketKind : std::uint8_t { kState = 1, kForce = 2, kHello = 3, kWelcome = 4 };

/// Packet flag bits.
inline constexpr std::uint8_t kHasSensorForce = 1;  ///< state: sensor_force_n is a reading
inline constexpr std::uint8_t kSigned = 2;          ///< an HMAC-SHA256 tag follows the body

/// Force-packet status bits.
inline constexpr std::uint32_t kStatusContact = 1;   ///< the renderer is in contact
inline constexpr std::uint32_t kStatusZeroed = 2;    ///< force zeroed by a guard or watchdog
inline constexpr std::uint32_t kStatusStopping = 4;  ///< inhap is stopping; force is zero

/// Plausibility limits of a state: a finite number beyond these is no reading of a device (a
/// corrupt or hostile datagram) and the state is refused (DecodeResult::kOutOfRange).
inline constexpr double kMaxPositionMm = 1e4;    ///< |p_i|, mm (10 m)
inline constexpr double kMaxSensorForceN = 1e4;  ///< |f_i|, N
inline constexpr double kMaxDeviceTimeS = 1e10;  ///< |t|, s (317 years)

inline constexpr std::size_t kStateBodyBytes = 76;
inline constexpr std::size_t kForceBodyBytes = 44;
inline constexpr std::size_t kTagBytes = 32;
inline constexpr std::size_t kNonceBytes = 32;
inline constexpr std::size_t kHelloBodyBytes = 16 + kNonceBytes;        ///< header, nonce
inline constexpr std::size_t kWelcomeBodyBytes = 16 + 2 * kNonceBytes;  ///< header, both nonces
inline constexpr std::size_t kMaxPacketBytes = kWelcomeBodyBytes + kTagBytes;

struct StatePacket {
  std::uint32_t session = 0;
  std::uint32_t sequence = 0;
  double device_time_s = 0.0;
  Vec3 position_mm = Vec3::Zero();
  Vec3 sensor_force_n = Vec3::Zero();
  bool has_sensor_force = false;
  std::uint32_t buttons = 0;
};

struct ForcePacket {
  std::uint32_t session = 0;
  std::uint32_t sequence = 0;  ///< the state packet's sequence this answers
  Vec3 force_n = Vec3::Zero();
  std::uint32_t status = 0;
};

/// Handshake (with a key only; always signed with the shared key): the device's hello ...
struct HelloPacket {
  std::uint32_t session = 0;
  std::array<std::uint8_t, kNonceBytes> nonce{};  ///< the device's, random per hello
};
/// ... and inhap's welcome, which echoes the device's nonce.
struct WelcomePacket {
  std::uint32_t session = 0;
  std::array<std::uint8_t, kNonceBytes> client_nonce{}, server_nonce{};
};

/// A shared key for HMAC-SHA256 (any length; empty = unsigned, loopback only).
class BridgeKey {
 public:
  BridgeKey() = default;
  explicit BridgeKey(std::string_view secret);
  bool empty() const { return !set_; }
  /// HMAC-SHA256 of data into tag.
  void sign(std::span<const std::uint8_t> data, std::uint8_t* tag) const;
  /// Constant-time check of a tag.
  bool verify(std::span<const std::uint8_t> data, const std::uint8_t* tag) const;

 private:
  std::array<std::uint8_t, 64> block_{};  ///< the key as HMAC uses it (hashed if > 64 bytes)
  bool set_ = false;
};

enum class DecodeResult : std::uint8_t {
  kOk,
  kTooShort,    ///< fewer bytes than the packet kind needs
  kBadMagic,    ///< not an inhap bridge datagram
  kBadVersion,  ///< another protocol version
  kBadKind,     ///< not the kind this side receives
  kBadLength,   ///< length does not match the kind and flags
  kNonFinite,   ///< a NaN or infinite number
  kUnsigned,    ///< this side has a key and the packet carries no tag
  kBadTag,      ///< the tag does not verify
  kOutOfRange,  ///< a finite number beyond the plausibility limits (kMaxPositionMm, ...)
};
const char* to_string(DecodeResult r);

/// The kind byte of a datagram with the bridge's magic and version (0 for anything else).
std::uint8_t packet_kind(std::span<const std::uint8_t> bytes);

/// The key of one session: HMAC-SHA256(shared, "inhap bridge session key v1" | session (u32 LE)
/// | client nonce | server nonce), used as an HMAC key for the session's states and forces.
BridgeKey session_key(const BridgeKey& shared, std::uint32_t session,
                      const std::array<std::uint8_t, kNonceBytes>& client_nonce,
                      const std::array<std::uint8_t, kNonceBytes>& server_nonce);

/// Writes a packet into out (at least kMaxPacketBytes) and returns its length in bytes. Signs it
/// when key is not empty. Non-finite numbers are written as zero.
std::size_t encode(const StatePacket& p, const BridgeKey& key, std::uint8_t* out);
std::size_t encode(const ForcePacket& p, const BridgeKey& key, std::uint8_t* out);
std::size_t encode(const HelloPacket& p, const BridgeKey& key, std::uint8_t* out);
std::size_t encode(const WelcomePacket& p, const BridgeKey& key, std::uint8_t* out);

DecodeResult decode(std::span<const std::uint8_t> bytes, const BridgeKey& key, StatePacket& out);
DecodeResult decode(std::span<const std::uint8_t> bytes, const BridgeKey& key, ForcePacket& out);
/// Hello and welcome need a key (kUnsigned without one).
DecodeResult decode(std::span<const std::uint8_t> bytes, const BridgeKey& key, HelloPacket& out);
DecodeResult decode(std::span<const std::uint8_t> bytes, const BridgeKey& key, WelcomePacket& out);

}  // namespace inhap::haptics
