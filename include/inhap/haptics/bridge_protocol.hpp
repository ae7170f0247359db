// The inhap device bridge: versioned little-endian UDP datagrams exchanged once per servo tick
// between a device client (beside the vendor SDK) and inhap. See docs/bridge.md.
//
// Units: positions mm, forces N, time s.
//
// device -> inhap (StatePacket): magic, version, kind 1, flags, session, sequence, device time,
//   probe position, raw sensor force (valid if flags has kHasSensorForce), buttons.
// inhap -> device (ForcePacket): magic, version, kind 2, flags, session, sequence echoed, force,
//   status bits.
// With a shared key, every packet carries an HMAC-SHA256 of all bytes before it (flag kSigned);
// a receiver with a key drops every packet whose tag does not verify, or that is unsigned.
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

enum class PacketKind : std::uint8_t { kState = 1, kForce = 2 };

/// Packet flag bits.
inline constexpr std::uint8_t kHasSensorForce = 1;  ///< state: sensor_force_n is a reading
inline constexpr std::uint8_t kSigned = 2;          ///< an HMAC-SHA256 tag follows the body

/// Force-packet status bits.
inline constexpr std::uint32_t kStatusContact = 1;   ///< the renderer is in contact
inline constexpr std::uint32_t kStatusZeroed = 2;    ///< force zeroed by a guard or watchdog
inline constexpr std::uint32_t kStatusStopping = 4;  ///< inhap is stopping; force is zero

inline constexpr std::size_t kStateBodyBytes = 76;
inline constexpr std::size_t kForceBodyBytes = 44;
inline constexpr std::size_t kTagBytes = 32;
inline constexpr std::size_t kMaxPacketBytes = kStateBodyBytes + kTagBytes;

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
};
const char* to_string(DecodeResult r);

/// Writes a packet into out (at least kMaxPacketBytes) and returns its length in bytes. Signs it
/// when key is not empty. Non-finite numbers are written as zero.
std::size_t encode(const StatePacket& p, const BridgeKey& key, std::uint8_t* out);
std::size_t encode(const ForcePacket& p, const BridgeKey& key, std::uint8_t* out);

DecodeResult decode(std::span<const std::uint8_t> bytes, const BridgeKey& key, StatePacket& out);
DecodeResult decode(std::span<const std::uint8_t> bytes, const BridgeKey& key, ForcePacket& out);

}  // namespace inhap::haptics
