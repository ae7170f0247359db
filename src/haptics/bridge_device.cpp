// BridgeDevice: inhap::Device over the UDP bridge (POSIX sockets). See bridge_device.hpp.
#include "inhap/haptics/bridge_device.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <ctime>
#include <string>
#include <utility>

#include <sodium.h>

#include "inhap/core/error.hpp"

namespace inhap::haptics {
namespace {

double monotonic_s() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

std::optional<std::uint16_t> parse_udp_device(std::string_view d) {
  if (d == "udp") return kBridgeDefaultPort;
  if (d.substr(0, 4) != "udp:") return std::nullopt;
  const std::string_view num = d.substr(4);
  unsigned port = 0;
  const auto [end, ec] = std::from_chars(num.data(), num.data() + num.size(), port);
  if (ec != std::errc() || end != num.data() + num.size() || port < 1 || port > 65535)
    return std::nullopt;
  return static_cast<std::uint16_t>(port);
}

bool is_loopback(const std::string& ipv4) {
  in_addr a{};
  if (inet_pton(AF_INET, ipv4.c_str(), &a) != 1) return false;
  return (ntohl(a.s_addr) >> 24) == 127;
}

BridgeDevice::BridgeDevice(BridgeOptions options) : options_(std::move(options)) {
  in_addr addr{};
  if (inet_pton(AF_INET, options_.listen.c_str(), &addr) != 1)
    throw Error("bridge: '" + options_.listen + "' is not an IPv4 address (e.g. 127.0.0.1)");
  if (!is_loopback(options_.listen) && options_.key.empty())
    throw Error("bridge: listening on " + options_.listen +
                " (not loopback) needs a shared key (--key), so nothing else on the network can "
                "drive the arm");
  if (!(options_.info.max_force_n > 0.0) || options_.info.max_force_n > kForceCeilingN)
    throw Error("bridge: the device force limit must be in (0, " + std::to_string(kForceCeilingN) +
                "] N");
  if (!(options_.timeout_s > 0.0) || !std::isfinite(options_.timeout_s))
    throw Error("bridge: the time-out must be a positive number of seconds");
  key_ = BridgeKey(options_.key);
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0)
    throw Error(std::string("bridge: cannot open a UDP socket: ") + std::strerror(errno));
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_port = htons(options_.port);
  sa.sin_addr = addr;
  if (bind(fd_, reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0) {
    const int e = errno;
    close(fd_);
    fd_ = -1;
    throw Error("bridge: cannot listen on " + options_.listen + ":" +
                std::to_string(options_.port) + ": " + std::strerror(e));
  }
  socklen_t len = sizeof sa;
  getsockname(fd_, reinterpret_cast<sockaddr*>(&sa), &len);
  bound_port_ = ntohs(sa.sin_port);
}

BridgeDevice::~BridgeDevice() {
  if (fd_ >= 0) {
    if (have_peer_) stop();
    close(fd_);
  }
}

bool BridgeDevice::connect(double timeout_s) {
  const bool got = wait_state(timeout_s);
  faulted_ = !got;
  return session_locked_;
}

void BridgeDevice::command_force(const Vec3& force) {
  nonfinite_ = !force.allFinite();
  if (nonfinite_) {
    command_.setZero();
    return;
  }
  const double n = force.norm();
  // The device's limit, never past the hard ceiling of any profile.
  const double limit = effective_force_limit(options_.info.max_force_n, kForceCeilingN);
  command_ = (n > limit && n > 0.0) ? Vec3(force * (limit / n)) : force;
}

void BridgeDevice::tick() {
  if (faulted_) {
    send_force(Vec3::Zero(), status_ | kStatusZeroed);
  } else {
    send_force(command_, status_ | (zeroed_ || nonfinite_ ? kStatusZeroed : 0u));
  }
  command_.setZero();
  zeroed_ = nonfinite_ = false;
  // The deadline runs from the last state's arrival, not from this call: a loop that took part of
  // the period to render does not stretch the fault detection.
  const double left = faulted_
                          ? options_.timeout_s
                          : std::max(0.0, last_arrival_s_ + options_.timeout_s - monotonic_s());
  if (wait_state(left)) {
    faulted_ = false;
  } else {
    faulted_ = true;
    ++stats_.timeouts;
  }
}

void BridgeDevice::stop() {
  send_force(Vec3::Zero(), kStatusStopping | kStatusZeroed);
}

void BridgeDevice::send_force(const Vec3& f, std::uint32_t status) {
  if (!have_peer_ || fd_ < 0) return;
  ForcePacket p;
  p.session = state_.session;
  p.sequence = state_.sequence;
  p.force_n = f;
  p.status = status;
  // With a key, the session's own (a force tagged with the shared key alone would be replayable).
  const std::size_t n = encode(p, key_.empty() ? key_ : session_key_, buffer_);
  const ssize_t r = sendto(fd_, buffer_, n, MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(peer_),
                           sizeof(sockaddr_in));
  if (r == static_cast<ssize_t>(n)) ++stats_.sent;
}

bool BridgeDevice::same_peer(const void* from_addr, const unsigned char* peer_bytes) const {
  const auto& from = *static_cast<const sockaddr_in*>(from_addr);
  const auto& peer = *reinterpret_cast<const sockaddr_in*>(peer_bytes);
  return from.sin_addr.s_addr == peer.sin_addr.s_addr && from.sin_port == peer.sin_port;
}

bool BridgeDevice::accept(const StatePacket& p, const void* from, double now) {
  const bool same_peer = have_peer_ && this->same_peer(from, peer_);
  // The session belongs to its peer (address and port) until that peer has been silent for
  // rebind_s: no other local process can take it over in a gap.
  const bool peer_gone = now - last_arrival_s_ >= options_.rebind_s;
  if (session_locked_ && !same_peer && !peer_gone) {
    ++stats_.foreign_peer;
    return false;
  }
  if (!session_locked_ || !same_peer || (p.session != state_.session && faulted_)) {
    // First contact, the bound peer silent for rebind_s, or the same peer back with a new
    // session after a fault.
    session_locked_ = true;
    state_ = p;
    return true;
  }
  if (p.session != state_.session) {
    ++stats_.foreign_session;
    return false;
  }
  if (p.sequence <= state_.sequence) {
    ++stats_.out_of_order;
    return false;
  }
  // Device time never runs backwards, nor faster than the wall clock (with 1 s of slack): a
  // time far ahead would hold a recording's later rows back as out of order.
  if (!(p.device_time_s >= state_.device_time_s) ||
      p.device_time_s - state_.device_time_s > 2.0 * (now - last_arrival_s_) + 1.0) {
    ++stats_.bad_time;
    return false;
  }
  stats_.lost += p.sequence - state_.sequence - 1;
  state_ = p;
  return true;
}

bool BridgeDevice::wait_state(double timeout_s) {
  const double deadline = monotonic_s() + timeout_s;
  bool got = false;
  for (;;) {
    // Drain what is there.
    for (;;) {
      sockaddr_in from{};
      socklen_t flen = sizeof from;
      const ssize_t n = recvfrom(fd_, buffer_, sizeof buffer_, MSG_DONTWAIT,
                                 reinterpret_cast<sockaddr*>(&from), &flen);
      if (n < 0) break;  // EAGAIN (or an error: treated as nothing received)
      ++stats_.received;
      const std::span<const std::uint8_t> bytes(buffer_, static_cast<std::size_t>(n));
      if (!key_.empty() && packet_kind(bytes) == static_cast<std::uint8_t>(PacketKind::kHello)) {
        on_hello(bytes, &from, monotonic_s());
        continue;
      }
      StatePacket p;
      bool fresh = false;
      const DecodeResult r = decode_state(bytes, &from, p, fresh);
      if (r == DecodeResult::kUnsigned || r == DecodeResult::kBadTag) {
        ++stats_.bad_auth;
        continue;
      }
      if (r == DecodeResult::kOutOfRange) {
        ++stats_.out_of_range;
        continue;
      }
      if (r != DecodeResult::kOk) {
        ++stats_.malformed;
        continue;
      }
      if (fresh) {  // the first state of a new handshake: a new session of that peer
        session_key_ = pending_key_;
        have_pending_ = false;
        session_locked_ = false;
      }
      if (!accept(p, &from, monotonic_s())) continue;
      if (got) ++stats_.superseded;
      got = true;
      note_arrival(monotonic_s());
      ++stats_.accepted;
      std::memcpy(peer_, &from, sizeof from);
      have_peer_ = true;
    }
    if (got) return true;
    const double now = monotonic_s();
    if (now >= deadline) return false;
    const double due = last_arrival_s_ + period_s_;
    if (period_s_ > 0 && options_.spin_s > 0 && now >= due - options_.spin_s &&
        now < due + options_.spin_s)
      continue;  // inside the window: poll again without sleeping
    // Sleep until the window opens (or the deadline); a datagram wakes it earlier.
    const double until = period_s_ > 0 && now < due - options_.spin_s
                             ? std::min(deadline, due - options_.spin_s)
                             : deadline;
    if (sleep_until_readable(until - now) == 0 && until >= deadline) return false;
  }
}

void BridgeDevice::on_hello(std::span<const std::uint8_t> bytes, const void* from, double now) {
  HelloPacket h;
  const DecodeResult r = decode(bytes, key_, h);
  if (r == DecodeResult::kUnsigned || r == DecodeResult::kBadTag) {
    ++stats_.bad_auth;
    return;
  }
  if (r != DecodeResult::kOk) {
    ++stats_.malformed;
    return;
  }
  // Another sender than the bound peer may start a session only once that one has been silent
  // for rebind_s (as for states).
  if (session_locked_ && !(have_peer_ && same_peer(from, peer_)) &&
      now - last_arrival_s_ < options_.rebind_s) {
    ++stats_.foreign_peer;
    return;
  }
  WelcomePacket w;
  w.session = h.session;
  w.client_nonce = h.nonce;
  randombytes_buf(w.server_nonce.data(), kNonceBytes);
  pending_key_ = session_key(key_, h.session, h.nonce, w.server_nonce);
  std::memcpy(pending_peer_, from, sizeof(sockaddr_in));
  pending_session_ = h.session;
  have_pending_ = true;
  const std::size_t n = encode(w, key_, buffer_);
  if (sendto(fd_, buffer_, n, MSG_DONTWAIT, static_cast<const sockaddr*>(from),
             sizeof(sockaddr_in)) == static_cast<ssize_t>(n))
    ++stats_.handshakes;
}

DecodeResult BridgeDevice::decode_state(std::span<const std::uint8_t> bytes, const void* from,
                                        StatePacket& p, bool& fresh) {
  fresh = false;
  if (key_.empty()) return decode(bytes, key_, p);
  DecodeResult r = DecodeResult::kBadTag;
  // The session's key counts only from the bound peer: another sender, even with a recording
  // of the session, starts with a handshake of its own.
  if (session_locked_ && !session_key_.empty() && have_peer_ && same_peer(from, peer_))
    r = decode(bytes, session_key_, p);
  if (r == DecodeResult::kBadTag && have_pending_ && same_peer(from, pending_peer_)) {
    r = decode(bytes, pending_key_, p);
    if (r == DecodeResult::kOk && p.session != pending_session_) r = DecodeResult::kBadTag;
    fresh = r == DecodeResult::kOk;
  }
  return r;
}

int BridgeDevice::sleep_until_readable(double seconds) const {
  pollfd pfd{fd_, POLLIN, 0};
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(seconds);
  ts.tv_nsec = static_cast<long>((seconds - static_cast<double>(ts.tv_sec)) * 1e9);
  return ppoll(&pfd, 1, &ts, nullptr);  // > 0 readable, 0 time-out, < 0 interrupted
}

void BridgeDevice::note_arrival(double now) {
  const double gap = now - last_arrival_s_;
  // Gaps over 0.1 s (the first state, a pause) say nothing about the device's rate.
  if (last_arrival_s_ > 0 && gap > 0 && gap < 0.1)
    period_s_ = period_s_ > 0 ? 0.875 * period_s_ + 0.125 * gap : gap;
  last_arrival_s_ = now;
}

}  // namespace inhap::haptics
