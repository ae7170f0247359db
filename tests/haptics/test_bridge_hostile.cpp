// The device bridge against a hostile or broken local sender: the session is bound to its peer,
// implausible numbers are counted faults, a zeroed force is flagged (docs/bridge.md).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "inhap/haptics/bridge_device.hpp"
#include "inhap/haptics/bridge_protocol.hpp"

namespace inhap::haptics {
namespace {

// A raw UDP sender with its own port (another local process, as far as the bridge can tell).
class Sender {
 public:
  explicit Sender(std::uint16_t port) : fd_(socket(AF_INET, SOCK_DGRAM, 0)) {
    to_.sin_family = AF_INET;
    to_.sin_port = htons(port);
    inet_pton(AF_INET, "127.0.0.1", &to_.sin_addr);
  }
  ~Sender() { close(fd_); }
  void send_bytes(const std::vector<std::uint8_t>& b) {
    sendto(fd_, b.data(), b.size(), 0, reinterpret_cast<const sockaddr*>(&to_), sizeof to_);
  }
  // The next datagram within 0.5 s (empty when none).
  std::vector<std::uint8_t> receive_bytes() {
    pollfd pfd{fd_, POLLIN, 0};
    if (poll(&pfd, 1, 500) != 1) return {};
    std::vector<std::uint8_t> b(kMaxPacketBytes + 64);
    const ssize_t n = recv(fd_, b.data(), b.size(), 0);
    b.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
    return b;
  }
  void send(std::uint32_t session, std::uint32_t seq, double t, Vec3 p) {
    StatePacket s;
    s.session = session;
    s.sequence = seq;
    s.device_time_s = t;
    s.position_mm = p;
    std::uint8_t b[kMaxPacketBytes];
    const std::size_t n = encode(s, BridgeKey(), b);
    sendto(fd_, b, n, 0, reinterpret_cast<const sockaddr*>(&to_), sizeof to_);
  }
  // The next force packet within 0.5 s (status 0xFFFFFFFF when none).
  ForcePacket receive() {
    ForcePacket f;
    f.status = 0xFFFFFFFFu;
    pollfd pfd{fd_, POLLIN, 0};
    if (poll(&pfd, 1, 500) != 1) return f;
    std::uint8_t b[kMaxPacketBytes];
    const ssize_t n = recv(fd_, b, sizeof b, 0);
    if (n > 0) (void)decode({b, static_cast<std::size_t>(n)}, BridgeKey(), f);
    return f;
  }

 private:
  int fd_;
  sockaddr_in to_{};
};

BridgeOptions options() {
  BridgeOptions o;
  o.port = 0;
  o.timeout_s = 0.002;
  o.spin_s = 0;
  return o;
}

void sleep_ms(int ms) {
  std::this_thread::sleep_for(std::chrono::milliseconds(ms));
}

// Before, any local process took the session over after a device gap of 2 ms or more.
TEST(BridgeHostile, AnotherSenderCannotTakeTheSessionInAGap) {
  BridgeOptions o = options();
  o.rebind_s = 0.3;
  BridgeDevice dev(o);
  Sender owner(dev.port()), intruder(dev.port());
  owner.send(1, 1, 0.0, {0, 0, 1});
  ASSERT_TRUE(dev.connect(2.0));
  dev.tick();  // no state within 2 ms: faulted
  ASSERT_TRUE(dev.faulted());
  sleep_ms(5);
  intruder.send(2, 1, 0.0, {0, 0, -7.5});
  dev.tick();
  EXPECT_EQ(dev.position().z(), 1.0);
  EXPECT_EQ(dev.session(), 1u);
  EXPECT_GE(dev.stats().foreign_peer, 1u);
  // The same session from the owner goes on.
  owner.send(1, 2, 0.001, {0, 0, 0.5});
  dev.tick();
  EXPECT_EQ(dev.position().z(), 0.5);
  EXPECT_FALSE(dev.faulted());
  // After the owner has been silent for rebind_s, a new device may join.
  sleep_ms(350);
  intruder.send(3, 1, 0.0, {0, 0, 2.0});
  dev.tick();
  EXPECT_EQ(dev.session(), 3u);
  EXPECT_EQ(dev.position().z(), 2.0);
}

// Before, p = 1e300 was accepted (0 N for the next 297 ticks while inside) and t = 1e300 held
// every later row of a recording back as out of order.
TEST(BridgeHostile, ImplausiblePositionsAndTimesAreCountedFaults) {
  BridgeDevice dev(options());
  Sender s(dev.port());
  s.send(1, 1, 0.0, {0, 0, 1});
  ASSERT_TRUE(dev.connect(2.0));
  s.send(1, 2, 0.001, {0, 0, 1e300});
  dev.tick();
  EXPECT_EQ(dev.position().z(), 1.0);
  EXPECT_EQ(dev.stats().out_of_range, 1u);
  s.send(1, 3, 1e300, {0, 0, 2});
  dev.tick();
  EXPECT_EQ(dev.stats().out_of_range, 2u);
  s.send(1, 4, 1e9, {0, 0, 2});  // plausible alone, but 1e9 s ahead within a millisecond
  dev.tick();
  EXPECT_EQ(dev.stats().bad_time, 1u);
  s.send(1, 5, -1.0, {0, 0, 2});  // backwards
  dev.tick();
  EXPECT_EQ(dev.stats().bad_time, 2u);
  EXPECT_EQ(dev.time(), 0.0);
  s.send(1, 6, 0.006, {0, 0, 3});
  dev.tick();
  EXPECT_EQ(dev.position().z(), 3.0);
  EXPECT_EQ(dev.time(), 0.006);
  StatePacket p;
  std::uint8_t b[kMaxPacketBytes];
  p.position_mm = {0, 2e4, 0};
  EXPECT_EQ(decode({b, encode(p, BridgeKey(), b)}, BridgeKey(), p), DecodeResult::kOutOfRange);
}

// Before, a force zeroed by the loop's watchdog (after the device came back) or by a non-finite
// renderer output went out as a plain 0 N.
TEST(BridgeHostile, AZeroedForceIsFlagged) {
  BridgeDevice dev(options());
  Sender s(dev.port());
  s.send(1, 1, 0.0, {0, 0, 1});
  ASSERT_TRUE(dev.connect(2.0));
  dev.command_force({0, 0, 1});
  s.send(1, 2, 0.001, {0, 0, 1});
  dev.tick();
  ForcePacket f = s.receive();
  EXPECT_EQ(f.status & kStatusZeroed, 0u);
  EXPECT_EQ(f.force_n.z(), 1.0);
  dev.command_force({std::nan(""), 0, 0});
  s.send(1, 3, 0.002, {0, 0, 1});
  dev.tick();
  f = s.receive();
  EXPECT_EQ(f.sequence, 2u);
  EXPECT_NE(f.status & kStatusZeroed, 0u);
  dev.set_zeroed(true);
  dev.command_force(Vec3::Zero());
  s.send(1, 4, 0.003, {0, 0, 1});
  dev.tick();
  f = s.receive();
  EXPECT_EQ(f.sequence, 3u);
  EXPECT_NE(f.status & kStatusZeroed, 0u);
  dev.command_force({0, 0, 0.5});  // the flag is for one tick
  dev.tick();
  f = s.receive();
  EXPECT_EQ(f.sequence, 4u);
  EXPECT_EQ(f.status & kStatusZeroed, 0u);
}

// With a key, a session starts with a handshake (a nonce from each side) and its states carry a
// tag with that session's key. Before, the tag used the shared key alone: a recorded session
// replayed after a gap took the session over (the real client lost 292 ticks).
TEST(BridgeHostile, AReplayedKeyedSessionIsUseless) {
  BridgeOptions o = options();
  o.key = "lab secret";
  o.rebind_s = 0.1;
  BridgeDevice dev(o);
  const BridgeKey shared(o.key);
  Sender device(dev.port()), intruder(dev.port());
  std::vector<std::vector<std::uint8_t>> recorded;
  auto keep_and_send = [&](const std::uint8_t* b, std::size_t n) {
    recorded.emplace_back(b, b + n);
    device.send_bytes(recorded.back());
  };
  std::uint8_t b[kMaxPacketBytes];
  HelloPacket h;
  h.session = 7;
  for (std::size_t i = 0; i < kNonceBytes; ++i) h.nonce[i] = static_cast<std::uint8_t>(i * 7 + 1);
  bool connected = false;
  std::thread server([&] { connected = dev.connect(2.0); });
  keep_and_send(b, encode(h, shared, b));
  const auto welcome_bytes = device.receive_bytes();
  WelcomePacket w;
  ASSERT_EQ(decode(welcome_bytes, shared, w), DecodeResult::kOk);
  EXPECT_EQ(w.client_nonce, h.nonce);
  const BridgeKey k = session_key(shared, 7, h.nonce, w.server_nonce);
  StatePacket s;
  s.session = 7;
  s.sequence = 1;
  s.position_mm = {0, 0, 1};
  keep_and_send(b, encode(s, k, b));
  server.join();
  ASSERT_TRUE(connected);
  for (std::uint32_t i = 2; i <= 5; ++i) {
    s.sequence = i;
    s.device_time_s = 1e-3 * i;
    s.position_mm = {0, 0, 1.0 - 0.1 * i};
    keep_and_send(b, encode(s, k, b));
    dev.tick();
  }
  EXPECT_EQ(dev.stats().accepted, 5u);
  EXPECT_NEAR(dev.position().z(), 0.5, 1e-12);
  // A state signed with the shared key alone (the old protocol) is refused.
  s.sequence = 6;
  device.send_bytes(std::vector<std::uint8_t>(b, b + encode(s, shared, b)));
  dev.tick();
  EXPECT_EQ(dev.stats().accepted, 5u);
  // While the device is live, a replay from another sender is refused outright.
  intruder.send_bytes(recorded.front());
  dev.tick();
  EXPECT_GE(dev.stats().foreign_peer, 1u);
  // The device goes silent; after rebind_s the whole recording is replayed by another sender.
  sleep_ms(150);
  const auto bad_auth = dev.stats().bad_auth;
  for (const auto& d : recorded) {
    intruder.send_bytes(d);
    dev.tick();
  }
  EXPECT_EQ(dev.stats().accepted, 5u) << "no replayed state was taken";
  EXPECT_EQ(dev.stats().bad_auth - bad_auth, recorded.size() - 1);
  EXPECT_NEAR(dev.position().z(), 0.5, 1e-12);
  EXPECT_TRUE(dev.faulted());
}

}  // namespace
}  // namespace inhap::haptics
