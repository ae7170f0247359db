// inhap studio: connection limits per client address (server.hpp). civetweb 1.15 (Debian 12)
// has a request time-out and a total of worker threads, but no per-client limit: a connection
// holds a worker from the moment it is accepted, and before its request has arrived nothing
// tells a page from a client that never sends one (no token yet). So the server counts, per
// client address and in all:
//  - pending connections (accepted, request not arrived yet): past kPendingPerAddress for one
//    address or kPendingTotal for all, the oldest that has waited at least kMinPendingAge is
//    closed (a page's request follows its connect within milliseconds; a slow or silent client
//    is the one that waits), when a connection opens and on trim() (the server calls it every
//    50 ms: with every worker held, no connection opens);
//  - the connections of an address whose request has arrived (requests being answered, open
//    pages): with kConnectionsPerAddress of them, a new connection is refused at once (503,
//    closed).
// The limits are kept below civetweb's worker count (Server), so workers stay free for the
// pages. Closing is done by the caller's action, under this object's lock: a connection stays
// listed until closed() is called for it, before civetweb closes its socket.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <string_view>

namespace inhap::studio {

class ConnectionLimits {
 public:
  using Clock = std::chrono::steady_clock;
  /// What to do to a connection of (address, port): refuse = a new one over the per-address
  /// limit (tell the client 503), else a pending one closed to make room.
  using CloseAction = std::function<void(const std::string& address, int port, bool refuse)>;
  static constexpr std::size_t kPendingPerAddress = 8, kPendingTotal = 32;
  static constexpr std::size_t kConnectionsPerAddress = 96;
  static constexpr std::chrono::milliseconds kMinPendingAge{100};

  explicit ConnectionLimits(CloseAction close) : close_(std::move(close)) {}

  /// A new connection `id` from (address, port), its request not arrived yet. Runs the close
  /// action for what the limits close (this one when refused). Returns false when refused.
  bool opened(const void* id, const std::string& address, int port, Clock::time_point now);
  bool opened(const void* id, const std::string& address, int port) {
    return opened(id, address, port, Clock::now());
  }
  /// Closes the oldest pending connections (of at least kMinPendingAge) while an address or all
  /// together are over their caps.
  void trim(Clock::time_point now);
  void trim() { trim(Clock::now()); }
  /// Its request arrived: no longer pending.
  void arrived(const void* id);
  /// civetweb is closing it (before its socket is closed).
  void closed(const void* id);

  std::size_t pending(std::string_view address = {}) const;      ///< all when empty
  std::size_t connections(std::string_view address = {}) const;  ///< all when empty
  std::uint64_t evicted() const;  ///< pending connections closed to make room, so far
  std::uint64_t refused() const;  ///< connections refused, so far

 private:
  struct Conn {
    std::string address;
    int port = 0;
    Clock::time_point since;
    bool pending = true;
    bool closing = false;  ///< closed by a limit; not counted
  };
  std::size_t count(std::string_view address, bool pending_only) const;  // under mu_
  bool evict_oldest(std::string_view address, std::size_t cap, Clock::time_point now);
  void trim_locked(Clock::time_point now);

  CloseAction close_;
  mutable std::mutex mu_;
  std::map<const void*, Conn> conns_;
  std::uint64_t evicted_ = 0, refused_ = 0;
};

/// Shuts down this process's accepted TCP socket whose peer is (address, port) and whose local
/// port is `local_port` (IPv4; found among /proc/self/fd). refuse: writes a 503 reply first.
/// The socket stays open for its owner to close. False when no such socket was found.
bool shutdown_peer_socket(const std::string& address, int port, int local_port, bool refuse);

}  // namespace inhap::studio
