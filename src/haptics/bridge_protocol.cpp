// Bridge datagrams: little-endian encoding and HMAC-SHA256 (libsodium). See bridge_protocol.hpp.
#include "inhap/haptics/bridge_protocol.hpp"

#include <sodium.h>

#include <cmath>
#include <cstring>

namespace inhap::haptics {
namespace {

// Little-endian writers and readers, byte by byte (independent of the host's byte order).
void put_u16(std::uint8_t* o, std::uint16_t v) {
  o[0] = static_cast<std::uint8_t>(v);
  o[1] = static_cast<std::uint8_t>(v >> 8);
}
void put_u32(std::uint8_t* o, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) o[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
void put_f64(std::uint8_t* o, double v) {
  if (!std::isfinite(v)) v = 0.0;
  std::uint64_t u;
  std::memcpy(&u, &v, 8);
  for (int i = 0; i < 8; ++i) o[i] = static_cast<std::uint8_t>(u >> (8 * i));
}
std::uint16_t get_u16(const std::uint8_t* b) {
  return static_cast<std::uint16_t>(b[0] | (b[1] << 8));
}
std::uint32_t get_u32(const std::uint8_t* b) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(b[i]) << (8 * i);
  return v;
}
double get_f64(const std::uint8_t* b) {
  std::uint64_t u = 0;
  for (int i = 0; i < 8; ++i) u |= static_cast<std::uint64_t>(b[i]) << (8 * i);
  double v;
  std::memcpy(&v, &u, 8);
  return v;
}
void put_vec(std::uint8_t* o, const Vec3& v) {
  for (int i = 0; i < 3; ++i) put_f64(o + 8 * i, v[i]);
}
Vec3 get_vec(const std::uint8_t* b) {
  return {get_f64(b), get_f64(b + 8), get_f64(b + 16)};
}

std::size_t put_header(std::uint8_t* o, PacketKind kind, std::uint8_t flags, std::uint32_t session,
                       std::uint32_t sequence) {
  put_u32(o, kBridgeMagic);
  put_u16(o + 4, kBridgeVersion);
  o[6] = static_cast<std::uint8_t>(kind);
  o[7] = flags;
  put_u32(o + 8, session);
  put_u32(o + 12, sequence);
  return 16;
}

std::size_t finish(std::size_t body, const BridgeKey& key, std::uint8_t* out) {
  if (key.empty()) return body;
  key.sign({out, body}, out + body);
  return body + kTagBytes;
}

// Checks the header and the tag; on success, flags holds the packet's flags.
DecodeResult check(std::span<const std::uint8_t> b, const BridgeKey& key, PacketKind kind,
                   std::size_t body, std::uint8_t& flags) {
  if (b.size() < 8) return DecodeResult::kTooShort;
  if (get_u32(b.data()) != kBridgeMagic) return DecodeResult::kBadMagic;
  if (get_u16(b.data() + 4) != kBridgeVersion) return DecodeResult::kBadVersion;
  if (b[6] != static_cast<std::uint8_t>(kind)) return DecodeResult::kBadKind;
  flags = b[7];
  const bool is_signed = (flags & kSigned) != 0;
  const std::size_t want = body + (is_signed ? kTagBytes : 0);
  if (b.size() < body) return DecodeResult::kTooShort;
  if (b.size() != want) return DecodeResult::kBadLength;
  if (!key.empty()) {
    if (!is_signed) return DecodeResult::kUnsigned;
    if (!key.verify({b.data(), body}, b.data() + body)) return DecodeResult::kBadTag;
  }
  return DecodeResult::kOk;
}

}  // namespace

BridgeKey::BridgeKey(std::string_view secret) {
  if (secret.empty()) return;
  if (sodium_init() < 0) return;  // cannot happen with libsodium >= 1.0.0 on a sane system
  if (secret.size() > block_.size()) {
    crypto_hash_sha256(block_.data(), reinterpret_cast<const unsigned char*>(secret.data()),
                       secret.size());
  } else {
    std::memcpy(block_.data(), secret.data(), secret.size());
  }
  set_ = true;
}

void BridgeKey::sign(std::span<const std::uint8_t> data, std::uint8_t* tag) const {
  crypto_auth_hmacsha256_state st;
  crypto_auth_hmacsha256_init(&st, block_.data(), block_.size());
  crypto_auth_hmacsha256_update(&st, data.data(), data.size());
  crypto_auth_hmacsha256_final(&st, tag);
}

bool BridgeKey::verify(std::span<const std::uint8_t> data, const std::uint8_t* tag) const {
  std::uint8_t want[kTagBytes];
  sign(data, want);
  return sodium_memcmp(want, tag, kTagBytes) == 0;
}

const char* to_string(DecodeResult r) {
  switch (r) {
    case DecodeResult::kOk:
      return "ok";
    case DecodeResult::kTooShort:
      return "too short";
    case DecodeResult::kBadMagic:
      return "bad magic";
    case DecodeResult::kBadVersion:
      return "unsupported version";
    case DecodeResult::kBadKind:
      return "wrong packet kind";
    case DecodeResult::kBadLength:
      return "wrong length";
    case DecodeResult::kNonFinite:
      return "non-finite number";
    case DecodeResult::kUnsigned:
      return "unsigned packet (a key is set)";
    case DecodeResult::kBadTag:
      return "HMAC tag does not verify";
    case DecodeResult::kOutOfRange:
      return "number out of range";
  }
  return "?";
}

std::size_t encode(const StatePacket& p, const BridgeKey& key, std::uint8_t* out) {
  std::uint8_t flags = p.has_sensor_force ? kHasSensorForce : 0;
  if (!key.empty()) flags |= kSigned;
  std::size_t o = put_header(out, PacketKind::kState, flags, p.session, p.sequence);
  put_f64(out + o, p.device_time_s);
  put_vec(out + o + 8, p.position_mm);
  put_vec(out + o + 32, p.has_sensor_force ? p.sensor_force_n : Vec3::Zero());
  put_u32(out + o + 56, p.buttons);
  return finish(kStateBodyBytes, key, out);
}

std::size_t encode(const ForcePacket& p, const BridgeKey& key, std::uint8_t* out) {
  const std::uint8_t flags = key.empty() ? 0 : kSigned;
  std::size_t o = put_header(out, PacketKind::kForce, flags, p.session, p.sequence);
  put_vec(out + o, p.force_n);
  put_u32(out + o + 24, p.status);
  return finish(kForceBodyBytes, key, out);
}

DecodeResult decode(std::span<const std::uint8_t> b, const BridgeKey& key, StatePacket& out) {
  std::uint8_t flags = 0;
  const DecodeResult r = check(b, key, PacketKind::kState, kStateBodyBytes, flags);
  if (r != DecodeResult::kOk) return r;
  StatePacket p;
  p.session = get_u32(b.data() + 8);
  p.sequence = get_u32(b.data() + 12);
  p.device_time_s = get_f64(b.data() + 16);
  p.position_mm = get_vec(b.data() + 24);
  p.has_sensor_force = (flags & kHasSensorForce) != 0;
  p.sensor_force_n = get_vec(b.data() + 48);
  p.buttons = get_u32(b.data() + 72);
  if (!std::isfinite(p.device_time_s) || !p.position_mm.allFinite() ||
      !p.sensor_force_n.allFinite())
    return DecodeResult::kNonFinite;
  if (std::abs(p.device_time_s) > kMaxDeviceTimeS ||
      p.position_mm.cwiseAbs().maxCoeff() > kMaxPositionMm ||
      p.sensor_force_n.cwiseAbs().maxCoeff() > kMaxSensorForceN)
    return DecodeResult::kOutOfRange;
  out = p;
  return DecodeResult::kOk;
}

std::uint8_t packet_kind(std::span<const std::uint8_t> b) {
  if (b.size() < 8 || get_u32(b.data()) != kBridgeMagic || get_u16(b.data() + 4) != kBridgeVersion)
    return 0;
  return b[6];
}

BridgeKey session_key(const BridgeKey& shared, std::uint32_t session,
                      const std::array<std::uint8_t, kNonceBytes>& client_nonce,
                      const std::array<std::uint8_t, kNonceBytes>& server_nonce) {
  static constexpr char kLabel[] = "inhap bridge session key v1";
  std::uint8_t in[sizeof kLabel - 1 + 4 + 2 * kNonceBytes];
  std::memcpy(in, kLabel, sizeof kLabel - 1);
  std::size_t o = sizeof kLabel - 1;
  put_u32(in + o, session);
  std::memcpy(in + o + 4, client_nonce.data(), kNonceBytes);
  std::memcpy(in + o + 4 + kNonceBytes, server_nonce.data(), kNonceBytes);
  std::uint8_t k[kTagBytes];
  shared.sign({in, sizeof in}, k);
  return BridgeKey(std::string_view(reinterpret_cast<const char*>(k), sizeof k));
}

std::size_t encode(const HelloPacket& p, const BridgeKey& key, std::uint8_t* out) {
  const std::size_t o = put_header(out, PacketKind::kHello, kSigned, p.session, 0);
  std::memcpy(out + o, p.nonce.data(), kNonceBytes);
  return finish(kHelloBodyBytes, key, out);
}

std::size_t encode(const WelcomePacket& p, const BridgeKey& key, std::uint8_t* out) {
  const std::size_t o = put_header(out, PacketKind::kWelcome, kSigned, p.session, 0);
  std::memcpy(out + o, p.client_nonce.data(), kNonceBytes);
  std::memcpy(out + o + kNonceBytes, p.server_nonce.data(), kNonceBytes);
  return finish(kWelcomeBodyBytes, key, out);
}

DecodeResult decode(std::span<const std::uint8_t> b, const BridgeKey& key, HelloPacket& out) {
  std::uint8_t flags = 0;
  if (key.empty()) return DecodeResult::kUnsigned;
  const DecodeResult r = check(b, key, PacketKind::kHello, kHelloBodyBytes, flags);
  if (r != DecodeResult::kOk) return r;
  out.session = get_u32(b.data() + 8);
  std::memcpy(out.nonce.data(), b.data() + 16, kNonceBytes);
  return DecodeResult::kOk;
}

DecodeResult decode(std::span<const std::uint8_t> b, const BridgeKey& key, WelcomePacket& out) {
  std::uint8_t flags = 0;
  if (key.empty()) return DecodeResult::kUnsigned;
  const DecodeResult r = check(b, key, PacketKind::kWelcome, kWelcomeBodyBytes, flags);
  if (r != DecodeResult::kOk) return r;
  out.session = get_u32(b.data() + 8);
  std::memcpy(out.client_nonce.data(), b.data() + 16, kNonceBytes);
  std::memcpy(out.server_nonce.data(), b.data() + 16 + kNonceBytes, kNonceBytes);
  return DecodeResult::kOk;
}

DecodeResult decode(std::span<const std::uint8_t> b, const BridgeKey& key, ForcePacket& out) {
  std::uint8_t flags = 0;
  const DecodeResult r = check(b, key, PacketKind::kForce, kForceBodyBytes, flags);
  if (r != DecodeResult::kOk) return r;
  ForcePacket p;
  p.session = get_u32(b.data() + 8);
  p.sequence = get_u32(b.data() + 12);
  p.force_n = get_vec(b.data() + 16);
  p.status = get_u32(b.data() + 40);
  if (!p.force_n.allFinite()) return DecodeResult::kNonFinite;
  out = p;
  return DecodeResult::kOk;
}

}  // namespace inhap::haptics
