// Cooperative cancellation of long library calls (training, estimation, experiments): a caller
// that wants to stop a call from another thread (a Ctrl-C watcher, a GUI button) gives the
// calling thread a CancelFlag with CancelScope; the call's long loops poll it with
// check_cancel(), which throws inhap::Cancelled once the flag is set. The library's worker
// pools carry the flag of the thread that started them into their threads (adopt_cancel).
// Without a scope check_cancel() is one thread-local load. Never called from a servo step.
#pragma once

#include <atomic>
#include <exception>

namespace inhap {

/// Thrown by check_cancel() once the flag of the current call is set. Not an inhap::Error (no
/// handler of bad input swallows it).
class Cancelled : public std::exception {
 public:
  const char* what() const noexcept override { return "cancelled"; }
};

/// Set from any thread; read by the call's threads.
class CancelFlag {
 public:
  void request() noexcept { set_.store(true, std::memory_order_relaxed); }
  bool requested() const noexcept { return set_.load(std::memory_order_relaxed); }

 private:
  std::atomic<bool> set_{false};
};

/// The flag of the calling thread (nullptr: none).
const CancelFlag* current_cancel() noexcept;

/// Installs `flag` for the calling thread while it lives (the previous one is restored).
class CancelScope {
 public:
  explicit CancelScope(const CancelFlag* flag) noexcept;
  ~CancelScope();
  CancelScope(const CancelScope&) = delete;
  CancelScope& operator=(const CancelScope&) = delete;

 private:
  const CancelFlag* previous_;
};

/// Throws Cancelled when the calling thread's flag is set.
inline void check_cancel() {
  const CancelFlag* f = current_cancel();
  if (f && f->requested()) throw Cancelled();
}

}  // namespace inhap
