// Shared helpers of the `inhap` Python module (pybind11): numpy checks that raise TypeError
// instead of copying, zero-copy views of library storage, progress callbacks that release and
// re-take the GIL and stop a call on Ctrl-C, and JSON text -> Python objects.
// Units follow the library: mm, N, s, N/mm.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "inhap/core/cancel.hpp"
#include "inhap/core/progress.hpp"
#include "inhap/core/types.hpp"

namespace inhap::py {

namespace pyb = pybind11;

/// Thrown (in C++) when the user pressed Ctrl-C or a progress callback raised: the call unwinds
/// and the module turns it into the pending Python exception (KeyboardInterrupt, ...).
struct Interrupted : std::exception {
  const char* what() const noexcept override { return "interrupted"; }
};

/// A float64 array checked for dtype, C order and shape (cols 0: 1-D of any length; rows 0: any
/// number of rows). TypeError naming `name` otherwise; never copies.
pyb::array checked(const pyb::handle& obj, const char* name, std::size_t cols,
                   std::size_t rows = 0);

// The library's points are Vec3 (Eigen::Vector3d): three packed doubles, so the rows of a
// checked (N, 3) float64 C-order array are Vec3s in place. Said here once, checked by the
// compiler.
static_assert(sizeof(Vec3) == 3 * sizeof(double) && alignof(Vec3) <= alignof(double),
              "Vec3 must be three packed doubles for zero-copy (N, 3) arrays");

/// N x 3 float64 C-order array (checked) as Vec3 (the library's point layout): used in place.
inline const Vec3* as_vec3(const pyb::array& a) {
  return reinterpret_cast<const Vec3*>(a.data());
}
inline const double* as_doubles(const pyb::array& a) {
  return static_cast<const double*>(a.data());
}
/// The same as the spans the library takes (N rows, no copy).
inline std::span<const Vec3> vec3_span(const pyb::array& a) {
  return {as_vec3(a), static_cast<std::size_t>(a.shape(0))};
}
inline std::span<const double> double_span(const pyb::array& a) {
  return {as_doubles(a), static_cast<std::size_t>(a.shape(0))};
}

/// A numpy view of library storage kept alive by `owner` (no copy). Writable.
pyb::array view(std::vector<Vec3>& v, pyb::handle owner);
pyb::array view(std::vector<double>& v, pyb::handle owner);
/// Column `c` of N x 3 storage as a strided 1-D view.
pyb::array column_view(std::vector<Vec3>& v, int c, pyb::handle owner);

/// Copies into new numpy arrays (results the library returns by value).
pyb::array to_numpy(const std::vector<Vec3>& v);
pyb::array to_numpy(const std::vector<double>& v);
std::vector<Vec3> to_vec3(const pyb::handle& obj, const char* name);
std::vector<double> to_doubles(const pyb::handle& obj, const char* name);

/// The library's progress for a Python `progress` argument: True = a tqdm bar when tqdm is
/// installed (silent otherwise), False/None = silent, a callable = called as
/// progress(what, fraction, eta_s). It owns the call's CancelFlag (inhap/core/cancel.hpp): Ctrl-C
/// (seen by poll() on the waiting thread) or an exception of the callable sets it, and the
/// library stops at its next check_cancel(); a progress call on the working thread then also
/// throws Interrupted.
class ProgressBridge {
 public:
  explicit ProgressBridge(pyb::object progress);
  ~ProgressBridge();
  ProgressBridge(const ProgressBridge&) = delete;
  ProgressBridge& operator=(const ProgressBridge&) = delete;
  /// The callback to hand to the library (valid while this object lives).
  inhap::Progress callback();
  /// Called first on the thread that runs the call (progress throws Interrupted there only).
  void set_working_thread(std::thread::id id) { thread_ = id; }
  const CancelFlag& flag() const { return flag_; }
  /// Takes the GIL, checks for Ctrl-C (main thread) and cancels the call when it was pressed.
  void poll();
  /// Closes the bar; rethrows the Python error that stopped the call, if any.
  void finish();

 private:
  void call(const std::string& what, double fraction, double eta);
  void stop(pyb::error_already_set&& e);
  pyb::object fn_, bar_;
  bool tqdm_ = false;
  double last_ = 0;
  std::string what_;
  std::shared_ptr<pyb::error_already_set> error_;  ///< what stopped the call (GIL held)
  CancelFlag flag_;
  std::thread::id thread_;  ///< the working thread
};

/// Runs `f(progress)` on a working thread with the GIL released and the call's CancelFlag
/// installed, while the calling thread waits and checks for Ctrl-C every 20 ms: Ctrl-C or an
/// exception of the progress callable stops the call at the library's next cancellation point
/// and comes back as that Python exception; the library's errors come back as themselves.
template <class F>
auto with_progress(pyb::object progress, F&& f) {
  ProgressBridge bridge(std::move(progress));
  inhap::Progress cb = bridge.callback();
  using R = decltype(f(cb));
  [[maybe_unused]] std::conditional_t<std::is_void_v<R>, bool, std::optional<R>> result{};
  std::exception_ptr error;
  {
    std::mutex m;
    std::condition_variable cv;
    bool done = false;
    pyb::gil_scoped_release release;
    std::thread worker([&] {
      bridge.set_working_thread(std::this_thread::get_id());
      CancelScope scope(&bridge.flag());
      try {
        if constexpr (std::is_void_v<R>)
          f(cb);
        else
          result.emplace(f(cb));
      } catch (...) {
        error = std::current_exception();
      }
      std::lock_guard lock(m);
      done = true;
      cv.notify_all();
    });
    for (;;) {
      {
        std::unique_lock lock(m);
        if (cv.wait_for(lock, std::chrono::milliseconds(20), [&] { return done; })) break;
      }
      bridge.poll();
    }
    worker.join();
  }
  bridge.finish();  // the Python error that stopped the call, if any
  if (error) std::rethrow_exception(error);
  if constexpr (!std::is_void_v<R>) return std::move(*result);
}

/// Checks for Ctrl-C from code running without the GIL (takes it briefly); throws Interrupted.
void check_signals();

/// JSON text -> Python dict / list (json.loads).
pyb::object json_to_python(const std::string& text);

}  // namespace inhap::py
