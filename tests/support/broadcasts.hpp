// Test support: a studio session's broadcasts, kept for waiting on (tests/studio).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace inhap::test {

struct Broadcasts {
  /// The session's broadcast callback: keeps the message (a JSON object, or null if unparsable).
  void add(const std::string& m) {
    std::lock_guard l(mu);
    msgs.push_back(nlohmann::json::parse(m, nullptr, false));
    cv.notify_all();
  }
  /// The next broadcast of type `type` satisfying pred, waiting up to `s` seconds (null if none).
  template <class Pred>
  nlohmann::json wait(const std::string& type, double s, Pred pred) {
    std::unique_lock l(mu);
    nlohmann::json found;
    cv.wait_for(l, std::chrono::duration<double>(s), [&] {
      for (std::size_t i = seen; i < msgs.size(); ++i)
        if (msgs[i].is_object() && msgs[i].value("type", "") == type && pred(msgs[i])) {
          found = msgs[i];
          seen = i + 1;
          return true;
        }
      return false;
    });
    return found;
  }
  nlohmann::json wait(const std::string& type, double s) {
    return wait(type, s, [](const nlohmann::json&) { return true; });
  }
  std::mutex mu;
  std::condition_variable cv;
  std::vector<nlohmann::json> msgs;
  std::size_t seen = 0;  ///< messages before this index are consumed by wait()
};

}  // namespace inhap::test
