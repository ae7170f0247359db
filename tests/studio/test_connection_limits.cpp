// ConnectionLimits (connection_limits.hpp): the per-address and total caps on pending
// connections close the oldest that has waited long enough, never a young one; the per-address
// cap on all connections refuses a new one. Ids are plain addresses of a local array.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "inhap/studio/connection_limits.hpp"

using inhap::studio::ConnectionLimits;
using namespace std::chrono_literals;

namespace {

struct Closed {
  std::vector<std::pair<std::string, int>> evicted, refused;
};

ConnectionLimits make(Closed& c) {
  return ConnectionLimits([&c](const std::string& a, int port, bool refuse) {
    (refuse ? c.refused : c.evicted).emplace_back(a, port);
  });
}

}  // namespace

TEST(ConnectionLimits, PendingPastThePerAddressCapClosesTheOldestOfThatAddress) {
  Closed c;
  auto lim = make(c);
  int ids[64];
  const auto t0 = ConnectionLimits::Clock::time_point{} + 10s;
  const std::size_t cap = ConnectionLimits::kPendingPerAddress;
  for (std::size_t i = 0; i < cap; ++i)
    EXPECT_TRUE(lim.opened(&ids[i], "127.0.0.1", int(1000 + i), t0 + i * 1ms));
  EXPECT_EQ(lim.pending("127.0.0.1"), cap);
  EXPECT_TRUE(c.evicted.empty());
  // One more, 1 s later: the first (port 1000) goes, the newcomer stays.
  EXPECT_TRUE(lim.opened(&ids[cap], "127.0.0.1", 2000, t0 + 1s));
  ASSERT_EQ(c.evicted.size(), 1u);
  EXPECT_EQ(c.evicted[0], std::make_pair(std::string("127.0.0.1"), 1000));
  EXPECT_EQ(lim.pending("127.0.0.1"), cap);
  EXPECT_EQ(lim.evicted(), 1u);
  // Another address is not affected by this one's cap.
  EXPECT_TRUE(lim.opened(&ids[cap + 1], "127.0.0.2", 3000, t0 + 1s));
  EXPECT_EQ(c.evicted.size(), 1u);
  // A connection whose request arrived is no longer pending and is never closed by the cap.
  lim.arrived(&ids[1]);
  EXPECT_EQ(lim.pending("127.0.0.1"), cap - 1);
  EXPECT_TRUE(lim.opened(&ids[cap + 2], "127.0.0.1", 2001, t0 + 2s));
  EXPECT_EQ(c.evicted.size(), 1u) << "back at the cap: nothing closed";
  EXPECT_TRUE(lim.opened(&ids[cap + 3], "127.0.0.1", 2002, t0 + 2s));
  ASSERT_EQ(c.evicted.size(), 2u);
  EXPECT_EQ(c.evicted[1].second, 1002) << "the oldest pending, not the one that arrived (1001)";
}

TEST(ConnectionLimits, YoungPendingConnectionsAreNeverClosed) {
  Closed c;
  auto lim = make(c);
  int ids[64];
  const auto t0 = ConnectionLimits::Clock::time_point{} + 10s;
  // A burst of 40 pages within 40 ms: over both caps, but nobody has waited 100 ms.
  for (int i = 0; i < 40; ++i)
    EXPECT_TRUE(lim.opened(&ids[i], "127.0.0.1", 1000 + i, t0 + i * 1ms));
  EXPECT_TRUE(c.evicted.empty());
  EXPECT_EQ(lim.pending(), 40u);
  // Later the burst's oldest are closed down to the per-address cap at the next connection.
  EXPECT_TRUE(lim.opened(&ids[40], "127.0.0.1", 2000, t0 + 500ms));
  EXPECT_EQ(c.evicted.size(), 41u - ConnectionLimits::kPendingPerAddress);
  EXPECT_EQ(lim.pending(), ConnectionLimits::kPendingPerAddress);
}

TEST(ConnectionLimits, TotalPendingCapAcrossAddresses) {
  Closed c;
  auto lim = make(c);
  int ids[64];
  const auto t0 = ConnectionLimits::Clock::time_point{} + 10s;
  // Slow clients on several loopback addresses, each under its own cap.
  int k = 0;
  for (int a = 2; a <= 5; ++a)
    for (int i = 0; i < 10; ++i, ++k)
      lim.opened(&ids[k], "127.0.0." + std::to_string(a), 1000 + k, t0 + k * 1ms);
  EXPECT_EQ(lim.pending(), 40u);  // young
  lim.opened(&ids[k], "127.0.0.9", 5000, t0 + 1s);
  EXPECT_EQ(lim.pending(), ConnectionLimits::kPendingTotal);
  ASSERT_EQ(c.evicted.size(), 41u - ConnectionLimits::kPendingTotal);
  EXPECT_EQ(c.evicted[0].second, 1000);  // the oldest overall
}

TEST(ConnectionLimits, AllConnectionsPastThePerAddressCapAreRefused) {
  Closed c;
  auto lim = make(c);
  std::vector<int> ids(ConnectionLimits::kConnectionsPerAddress + 2);
  const auto t0 = ConnectionLimits::Clock::time_point{} + 10s;
  for (std::size_t i = 0; i < ConnectionLimits::kConnectionsPerAddress; ++i) {
    ASSERT_TRUE(lim.opened(&ids[i], "127.0.0.1", int(1000 + i), t0));
    lim.arrived(&ids[i]);  // open pages
  }
  EXPECT_FALSE(lim.opened(&ids[ids.size() - 2], "127.0.0.1", 9000, t0));
  ASSERT_EQ(c.refused.size(), 1u);
  EXPECT_EQ(c.refused[0].second, 9000);
  EXPECT_EQ(lim.refused(), 1u);
  EXPECT_TRUE(lim.opened(&ids.back(), "127.0.0.2", 9001, t0)) << "another address";
  // A page closes: room for one more.
  lim.closed(&ids[ids.size() - 2]);
  lim.closed(&ids[0]);
  EXPECT_TRUE(lim.opened(&ids[ids.size() - 2], "127.0.0.1", 9002, t0));
}

// With every worker held no connection opens: trim() (the server's 50 ms timer) closes the
// pending connections over the caps once they are old enough.
TEST(ConnectionLimits, TrimClosesWhatIsOverTheCapsOnceOldEnough) {
  Closed c;
  auto lim = make(c);
  int ids[64];
  const auto t0 = ConnectionLimits::Clock::time_point{} + 10s;
  for (int i = 0; i < 20; ++i) lim.opened(&ids[i], "127.0.0.1", 1000 + i, t0);
  for (int i = 20; i < 25; ++i) lim.opened(&ids[i], "127.0.0.2", 1000 + i, t0);
  lim.trim(t0 + 50ms);
  EXPECT_TRUE(c.evicted.empty());
  lim.trim(t0 + ConnectionLimits::kMinPendingAge);
  EXPECT_EQ(c.evicted.size(), 20u - ConnectionLimits::kPendingPerAddress);
  EXPECT_EQ(lim.pending("127.0.0.1"), ConnectionLimits::kPendingPerAddress);
  EXPECT_EQ(lim.pending("127.0.0.2"), 5u);
  for (const auto& [address, port] : c.evicted) EXPECT_EQ(address, "127.0.0.1");
  // Evicted connections stay listed (not counted) until civetweb closes them.
  lim.closed(&ids[0]);
  EXPECT_EQ(lim.connections(), ConnectionLimits::kPendingPerAddress + 5u);
}

// The refusal counts pages and requests being answered, not pending connections: a flood of
// young connections without a request does not refuse the page load right after it.
TEST(ConnectionLimits, PendingConnectionsDoNotCountTowardsTheRefusal) {
  Closed c;
  auto lim = make(c);
  std::vector<int> ids(ConnectionLimits::kConnectionsPerAddress + 1);
  const auto t0 = ConnectionLimits::Clock::time_point{} + 10s;
  for (std::size_t i = 0; i < ConnectionLimits::kConnectionsPerAddress; ++i)
    ASSERT_TRUE(lim.opened(&ids[i], "127.0.0.1", int(1000 + i), t0));
  EXPECT_TRUE(lim.opened(&ids.back(), "127.0.0.1", 9000, t0 + 1ms));
  EXPECT_TRUE(c.refused.empty());
}
