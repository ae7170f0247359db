// The device bridge: datagram encoding, authentication, and BridgeDevice against the C client
// over loopback (docs/bridge.md).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/haptics/bridge_device.hpp"
#include "inhap/haptics/bridge_protocol.hpp"
#include "inhap_bridge.h"

namespace inhap::haptics {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes encoded(const StatePacket& p, const BridgeKey& key) {
  Bytes b(kMaxPacketBytes);
  b.resize(encode(p, key, b.data()));
  return b;
}

StatePacket sample_state() {
  StatePacket p;
  p.session = 0xDEADBEEF;
  p.sequence = 42;
  p.device_time_s = 1.25;
  p.position_mm = {1.5, -2.25, 1e-3};
  p.sensor_force_n = {0.1, 0.2, -3.5};
  p.has_sensor_force = true;
  p.buttons = 5;
  return p;
}

TEST(BridgeProtocol, StateRoundTripsBitExactlyWithAndWithoutKey) {
  for (const std::string secret : {"", "lab key"}) {
    const BridgeKey key(secret);
    const Bytes b = encoded(sample_state(), key);
    EXPECT_EQ(b.size(), kStateBodyBytes + (secret.empty() ? 0 : kTagBytes));
    StatePacket q;
    ASSERT_EQ(decode(b, key, q), DecodeResult::kOk) << secret;
    const StatePacket p = sample_state();
    EXPECT_EQ(q.session, p.session);
    EXPECT_EQ(q.sequence, p.sequence);
    EXPECT_EQ(q.device_time_s, p.device_time_s);
    EXPECT_EQ(q.position_mm, p.position_mm);
    EXPECT_EQ(q.sensor_force_n, p.sensor_force_n);
    EXPECT_TRUE(q.has_sensor_force);
    EXPECT_EQ(q.buttons, p.buttons);
  }
}

TEST(BridgeProtocol, LayoutIsLittleEndianAsDocumented) {
  const Bytes b = encoded(sample_state(), BridgeKey());
  EXPECT_EQ(b[0], 'I');
  EXPECT_EQ(b[1], 'H');
  EXPECT_EQ(b[2], 'P');
  EXPECT_EQ(b[3], 'B');
  EXPECT_EQ(b[4], 1);  // version, low byte first
  EXPECT_EQ(b[5], 0);
  EXPECT_EQ(b[6], 1);    // kind: state
  EXPECT_EQ(b[12], 42);  // sequence
  double t;
  std::memcpy(&t, b.data() + 16, 8);  // this host is little-endian (x86-64)
  EXPECT_EQ(t, 1.25);
}

TEST(BridgeProtocol, ForceRoundTrips) {
  const BridgeKey key("k");
  ForcePacket p;
  p.session = 7;
  p.sequence = 9;
  p.force_n = {0.5, -1.0, 2.0};
  p.status = kStatusContact;
  Bytes b(kMaxPacketBytes);
  b.resize(encode(p, key, b.data()));
  ForcePacket q;
  ASSERT_EQ(decode(b, key, q), DecodeResult::kOk);
  EXPECT_EQ(q.force_n, p.force_n);
  EXPECT_EQ(q.status, p.status);
  EXPECT_EQ(q.sequence, 9u);
  StatePacket wrong_kind;
  EXPECT_EQ(decode(b, key, wrong_kind), DecodeResult::kBadKind);
}

TEST(BridgeProtocol, MalformedPacketsAreNamedAndNeverDecoded) {
  const BridgeKey none;
  const Bytes good = encoded(sample_state(), none);
  StatePacket q;
  EXPECT_EQ(decode({good.data(), 5}, none, q), DecodeResult::kTooShort);
  EXPECT_EQ(decode({good.data(), 60}, none, q), DecodeResult::kTooShort);
  Bytes longer = good;
  longer.push_back(0);
  EXPECT_EQ(decode(longer, none, q), DecodeResult::kBadLength);
  Bytes bad = good;
  bad[0] ^= 1;
  EXPECT_EQ(decode(bad, none, q), DecodeResult::kBadMagic);
  bad = good;
  bad[4] = 2;
  EXPECT_EQ(decode(bad, none, q), DecodeResult::kBadVersion);
  bad = good;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(bad.data() + 24, &nan, 8);
  EXPECT_EQ(decode(bad, none, q), DecodeResult::kNonFinite);
  bad = good;
  bad[7] |= kSigned;  // claims a tag it does not carry
  EXPECT_EQ(decode(bad, none, q), DecodeResult::kBadLength);
}

TEST(BridgeProtocol, WithAKeyUnsignedOrTamperedPacketsAreRejected) {
  const BridgeKey key("secret"), other("Secret");
  StatePacket q;
  EXPECT_EQ(decode(encoded(sample_state(), BridgeKey()), key, q), DecodeResult::kUnsigned);
  EXPECT_EQ(decode(encoded(sample_state(), other), key, q), DecodeResult::kBadTag);
  Bytes b = encoded(sample_state(), key);
  for (std::size_t i = 8; i < kStateBodyBytes; i += 7) {  // any flipped body bit
    Bytes t = b;
    t[i] ^= 0x10;
    EXPECT_EQ(decode(t, key, q), DecodeResult::kBadTag) << "byte " << i;
  }
  // Random datagrams never pass.
  Rng rng(3);
  for (int i = 0; i < 2000; ++i) {
    Bytes r(1 + rng.below(120 + 1));
    for (auto& c : r) c = static_cast<std::uint8_t>(rng.below(255 + 1));
    if (i % 2 == 0 && r.size() >= 8) std::memcpy(r.data(), b.data(), 8);
    EXPECT_NE(decode(r, key, q), DecodeResult::kOk);
  }
}

TEST(BridgeProtocol, CClientHmacMatchesLibsodiumAndRfc4231) {
  // RFC 4231 test case 1: key = 0x0b x 20, data = "Hi There".
  unsigned char block[64] = {};
  std::memset(block, 0x0b, 20);
  const std::string data = "Hi There";
  unsigned char tag[32];
  inhap_bridge_hmac_sha256(block, reinterpret_cast<const unsigned char*>(data.data()), data.size(),
                           tag);
  const char* want = "b0344c61d8db38535ca8afceaf0bf12b881dc200c9833da726e9376c2e32cff7";
  char hex[65];
  for (int i = 0; i < 32; ++i) std::snprintf(hex + 2 * i, 3, "%02x", tag[i]);
  EXPECT_STREQ(hex, want);
  // The same tag as the library's (libsodium) for random data and keys of every length class.
  Rng rng(5);
  for (int i = 0; i < 50; ++i) {
    std::string secret(1 + rng.below(100 + 1), 'x');
    for (auto& c : secret) c = static_cast<char>((1 + rng.below(255)));
    Bytes msg(rng.below(300 + 1));
    for (auto& c : msg) c = static_cast<std::uint8_t>(rng.below(255 + 1));
    inhap_bridge client;
    ASSERT_EQ(inhap_bridge_open(&client, "127.0.0.1", 9, secret.c_str()), 0);
    unsigned char a[32], b[32];
    inhap_bridge_hmac_sha256(client.key, msg.data(), msg.size(), a);
    inhap_bridge_close(&client);
    BridgeKey(secret).sign(msg, b);
    EXPECT_EQ(std::memcmp(a, b, 32), 0) << "key length " << secret.size();
  }
}

TEST(BridgeDevice, ANonLoopbackAddressNeedsAKey) {
  BridgeOptions o;
  o.listen = "0.0.0.0";
  o.port = 0;
  EXPECT_THROW(BridgeDevice{o}, Error);
  o.listen = "not-an-address";
  EXPECT_THROW(BridgeDevice{o}, Error);
  o.listen = "127.0.0.1";
  EXPECT_NO_THROW(BridgeDevice{o});
}

// A device process in a thread: the C client sends positions along a line and records the
// forces it gets back.
struct ClientRun {
  std::vector<double> z, fz;
  inhap_bridge_stats stats{};
};

// spin_us < 0: the client's default busy-wait; pace_us > 0: sleep this long between ticks (a
// device at 1 kHz) instead of sending the next state at once; trailing: one more state at the
// end, unanswered, so that the server's last wait ends at once instead of timing out.
ClientRun run_client(std::uint16_t port, const char* key, int ticks, int stop_after = -1,
                     long spin_us = -1, int pace_us = 0, bool trailing = false) {
  ClientRun r;
  inhap_bridge c;
  if (inhap_bridge_open(&c, "127.0.0.1", port, key) != 0) return r;
  if (spin_us >= 0) c.spin_us = spin_us;
  for (int i = 0; i < ticks && i != stop_after; ++i) {
    if (pace_us > 0) std::this_thread::sleep_for(std::chrono::microseconds(pace_us));
    const double p[3] = {0.0, 0.0, 2.0 - 0.01 * i};
    double f[3];
    std::uint32_t status = 0;
    inhap_bridge_exchange(&c, 1e-3 * i, p, nullptr, 0, f, &status, 200000);
    r.z.push_back(p[2]);
    r.fz.push_back(f[2]);
  }
  if (trailing) {
    const double p[3] = {0.0, 0.0, 2.0};
    double f[3];
    inhap_bridge_exchange(&c, 1e-3 * ticks, p, nullptr, 0, f, nullptr, 1000);
  }
  r.stats = c.stats;
  inhap_bridge_close(&c);
  return r;
}

// The renderer of these tests: a wall at z = 0 with 0.5 N/mm.
Vec3 wall(const Vec3& p) {
  return {0.0, 0.0, p.z() < 0 ? -0.5 * p.z() : 0.0};
}

// With and without a key, with and without busy-waiting on either side, a client that sends
// at once and one paced at 1 kHz (the server then sleeps until the window around the expected
// arrival): every tick answered with its own force.
TEST(BridgeDevice, EveryTickTheClientGetsTheForceForItsOwnPosition) {
  for (int run = 0; run < 8; ++run) {
    const char* key = run & 1 ? "shared secret" : "";
    const bool spin = run & 2, paced = run & 4;
    SCOPED_TRACE(testing::Message()
                 << "key " << (run & 1) << " spin " << spin << " paced " << paced);
    BridgeOptions o;
    o.port = 0;
    o.key = key;
    o.timeout_s = 2.0;  // generous: a loaded CI machine may stall the client thread
    o.spin_s = spin ? 50e-6 : 0.0;
    BridgeDevice dev(o);
    const int n = 400;
    ClientRun r;
    std::thread client(
        [&] { r = run_client(dev.port(), key, n, -1, spin ? -1 : 0, paced ? 1000 : 0, true); });
    ASSERT_TRUE(dev.connect(5.0));
    for (int i = 0; i < n; ++i) {
      dev.command_force(wall(dev.position()));
      dev.tick();
      if (dev.faulted()) break;
    }
    client.join();
    ASSERT_EQ(r.fz.size(), static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) EXPECT_EQ(r.fz[i], wall({0, 0, r.z[i]}).z()) << "tick " << i;
    EXPECT_EQ(r.stats.answered, static_cast<std::uint64_t>(n));
    EXPECT_EQ(dev.stats().accepted, static_cast<std::uint64_t>(n + 1));  // and the trailing one
    EXPECT_EQ(dev.stats().malformed + dev.stats().bad_auth + dev.stats().lost, 0u);
    EXPECT_FALSE(dev.faulted());
  }
}

TEST(BridgeDevice, AFloodOfMalformedDatagramsChangesNothing) {
  BridgeOptions o;
  o.port = 0;
  o.key = "k";
  o.timeout_s = 2.0;
  BridgeDevice dev(o);
  const int n = 300;
  std::atomic<bool> done{false};
  std::atomic<long> flooded{0};
  std::thread flood([&] {
    const int s = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(dev.port());
    inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
    Rng rng(11);
    StatePacket forged = sample_state();
    const BridgeKey wrong("not the key");
    std::uint8_t buf[kMaxPacketBytes];
    while (!done) {
      std::size_t len;
      if (flooded % 3 == 0) {
        forged.position_mm = {0, 0, -100};  // would command a large force if trusted
        len = encode(forged, wrong, buf);
      } else {
        len = 1 + rng.below(kMaxPacketBytes);
        for (std::size_t i = 0; i < len; ++i)
          buf[i] = static_cast<std::uint8_t>(rng.below(255 + 1));
      }
      sendto(s, buf, len, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
      ++flooded;
      std::this_thread::sleep_for(std::chrono::microseconds(50));
    }
    close(s);
  });
  ClientRun r;
  std::thread client([&] { r = run_client(dev.port(), "k", n); });
  ASSERT_TRUE(dev.connect(5.0));
  for (int i = 0; i < n && !dev.faulted(); ++i) {
    dev.command_force(wall(dev.position()));
    dev.tick();
  }
  client.join();
  done = true;
  flood.join();
  ASSERT_EQ(r.fz.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) EXPECT_EQ(r.fz[i], wall({0, 0, r.z[i]}).z()) << "tick " << i;
  EXPECT_GT(flooded.load(), 100);
  EXPECT_GT(dev.stats().malformed + dev.stats().bad_auth, 50u);
  EXPECT_EQ(dev.stats().accepted, static_cast<std::uint64_t>(n));
}

TEST(BridgeDevice, ADeadClientFaultsTheDeviceAndTheForceGoesToZero) {
  BridgeOptions o;
  o.port = 0;
  o.timeout_s = 0.3;  // longer than any stall of the client thread on a loaded machine
  BridgeDevice dev(o);
  ClientRun r;
  std::thread client([&] { r = run_client(dev.port(), "", 1000, 250); });  // dies at tick 250
  ASSERT_TRUE(dev.connect(5.0));
  int ticks = 0;
  while (!dev.faulted() && ticks < 2000) {
    dev.command_force(wall(dev.position()));
    dev.tick();
    ++ticks;
  }
  client.join();
  EXPECT_TRUE(dev.faulted());
  EXPECT_EQ(ticks, 250);
  EXPECT_EQ(dev.stats().timeouts, 1u);
}

TEST(BridgeDevice, OutOfOrderAndForeignPacketsAreDroppedAndCounted) {
  BridgeOptions o;
  o.port = 0;
  BridgeDevice dev(o);
  const int s = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(dev.port());
  inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
  auto send = [&](std::uint32_t session, std::uint32_t seq, double z) {
    StatePacket p;
    p.session = session;
    p.sequence = seq;
    p.position_mm = {0, 0, z};
    std::uint8_t b[kMaxPacketBytes];
    const std::size_t n = encode(p, BridgeKey(), b);
    sendto(s, b, n, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
  };
  send(1, 10, 1.0);
  ASSERT_TRUE(dev.connect(2.0));
  EXPECT_EQ(dev.position().z(), 1.0);
  send(1, 9, -5.0);   // older: dropped
  send(2, 50, -5.0);  // another session while this one is live: dropped
  send(1, 13, 3.0);   // two lost (11, 12)
  dev.tick();
  EXPECT_EQ(dev.position().z(), 3.0);
  EXPECT_EQ(dev.stats().out_of_order, 1u);
  EXPECT_EQ(dev.stats().foreign_session, 1u);
  EXPECT_EQ(dev.stats().lost, 2u);
  close(s);
}

TEST(BridgeDevice, CommandedForceIsFiniteAndClampedToTheDeviceLimit) {
  BridgeOptions o;
  o.port = 0;
  o.info.max_force_n = 3.0;
  o.timeout_s = 0.1;
  BridgeDevice dev(o);
  std::vector<double> got;
  std::thread client([&] {
    inhap_bridge c;
    inhap_bridge_open(&c, "127.0.0.1", dev.port(), nullptr);
    for (int i = 0; i < 3; ++i) {
      const double p[3] = {0, 0, 0};
      double f[3];
      inhap_bridge_exchange(&c, 0.001 * i, p, nullptr, 0, f, nullptr, 500000);
      got.push_back(std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
    }
    inhap_bridge_close(&c);
  });
  ASSERT_TRUE(dev.connect(5.0));
  dev.command_force({0, 0, 1e9});
  dev.tick();
  dev.command_force({std::nan(""), 0, 0});
  dev.tick();
  dev.command_force({0, 1.0, 0});
  dev.tick();
  client.join();
  ASSERT_EQ(got.size(), 3u);
  EXPECT_DOUBLE_EQ(got[0], 3.0);
  EXPECT_EQ(got[1], 0.0);
  EXPECT_DOUBLE_EQ(got[2], 1.0);
}

}  // namespace
}  // namespace inhap::haptics

namespace inhap::haptics {
namespace {

TEST(BridgeDeviceFlag, UdpAndUdpPortParseAndNothingElseDoes) {
  EXPECT_EQ(parse_udp_device("udp"), kBridgeDefaultPort);
  EXPECT_EQ(parse_udp_device("udp:1"), 1);
  EXPECT_EQ(parse_udp_device("udp:65535"), 65535);
  for (const char* bad :
       {"udp:", "udp:0", "udp:65536", "udp:12x", "udp:-5", "udp:1.5", "tcp:5", "lab:planar", ""})
    EXPECT_FALSE(parse_udp_device(bad).has_value()) << bad;
}

}  // namespace
}  // namespace inhap::haptics
