// inhap studio: connection limits per client address (connection_limits.hpp).
#include "inhap/studio/connection_limits.hpp"

#include <arpa/inet.h>
#include <dirent.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace inhap::studio {

std::size_t ConnectionLimits::count(std::string_view address, bool pending_only) const {
  std::size_t n = 0;
  for (const auto& [id, c] : conns_)
    if (!c.closing && (!pending_only || c.pending) && (address.empty() || c.address == address))
      ++n;
  return n;
}

bool ConnectionLimits::evict_oldest(std::string_view address, std::size_t cap,
                                    Clock::time_point now) {
  if (count(address, true) <= cap) return false;
  Conn* oldest = nullptr;
  for (auto& [id, c] : conns_)
    if (!c.closing && c.pending && (address.empty() || c.address == address) &&
        now - c.since >= kMinPendingAge && (!oldest || c.since < oldest->since))
      oldest = &c;
  if (!oldest) return false;  // all of them young: a burst of pages, not a slow client
  oldest->closing = true;
  ++evicted_;
  close_(oldest->address, oldest->port, false);
  return true;
}

bool ConnectionLimits::opened(const void* id, const std::string& address, int port,
                              Clock::time_point now) {
  std::lock_guard lock(mu_);
  // Pages and requests being answered; pending connections have their own caps, and a flood of
  // young ones must not refuse the page load that follows it.
  if (count(address, false) - count(address, true) >= kConnectionsPerAddress) {
    conns_[id] = Conn{address, port, now, false, true};  // listed until civetweb closes it
    ++refused_;
    close_(address, port, true);
    return false;
  }
  conns_[id] = Conn{address, port, now, true, false};
  trim_locked(now);
  return true;
}

void ConnectionLimits::trim(Clock::time_point now) {
  std::lock_guard lock(mu_);
  trim_locked(now);
}

void ConnectionLimits::trim_locked(Clock::time_point now) {
  std::vector<std::string> over;  // addresses over their cap
  for (const auto& [id, c] : conns_)
    if (!c.closing && c.pending && std::find(over.begin(), over.end(), c.address) == over.end() &&
        count(c.address, true) > kPendingPerAddress)
      over.push_back(c.address);
  for (const std::string& a : over)
    while (evict_oldest(a, kPendingPerAddress, now)) {
    }
  while (evict_oldest({}, kPendingTotal, now)) {
  }
}

void ConnectionLimits::arrived(const void* id) {
  std::lock_guard lock(mu_);
  if (const auto it = conns_.find(id); it != conns_.end()) it->second.pending = false;
}

void ConnectionLimits::closed(const void* id) {
  std::lock_guard lock(mu_);
  conns_.erase(id);
}

std::size_t ConnectionLimits::pending(std::string_view address) const {
  std::lock_guard lock(mu_);
  return count(address, true);
}

std::size_t ConnectionLimits::connections(std::string_view address) const {
  std::lock_guard lock(mu_);
  return count(address, false);
}

std::uint64_t ConnectionLimits::evicted() const {
  std::lock_guard lock(mu_);
  return evicted_;
}

std::uint64_t ConnectionLimits::refused() const {
  std::lock_guard lock(mu_);
  return refused_;
}

bool shutdown_peer_socket(const std::string& address, int port, int local_port, bool refuse) {
  in_addr want{};
  if (inet_pton(AF_INET, address.c_str(), &want) != 1) return false;
  DIR* dir = opendir("/proc/self/fd");
  if (!dir) return false;
  bool found = false;
  while (const dirent* e = readdir(dir)) {
    char* end = nullptr;
    const long fd = std::strtol(e->d_name, &end, 10);
    if (end == e->d_name || *end != '\0' || fd < 0 || fd == dirfd(dir)) continue;
    sockaddr_in peer{}, local{};
    socklen_t len = sizeof peer;
    if (getpeername(int(fd), reinterpret_cast<sockaddr*>(&peer), &len) != 0 || len != sizeof peer ||
        peer.sin_family != AF_INET || peer.sin_port != htons(uint16_t(port)) ||
        peer.sin_addr.s_addr != want.s_addr)
      continue;
    len = sizeof local;
    if (getsockname(int(fd), reinterpret_cast<sockaddr*>(&local), &len) != 0 ||
        local.sin_port != htons(uint16_t(local_port)))
      continue;
    if (refuse) {
      static const char kBusy[] =
          "HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain\r\nContent-Length: "
          "44\r\nConnection: close\r\n\r\n503: too many connections from this address\n";
      (void)send(int(fd), kBusy, sizeof kBusy - 1, MSG_NOSIGNAL | MSG_DONTWAIT);
    }
    shutdown(int(fd), SHUT_RDWR);
    found = true;
    break;
  }
  closedir(dir);
  return found;
}

}  // namespace inhap::studio
