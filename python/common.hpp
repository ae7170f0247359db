// Shared helpers of the `inhap` Python module (pybind11): numpy checks that raise TypeError
// instead of copying, zero-copy views of library storage, progress callbacks that release and
// re-take the GIL and stop a call on Ctrl-C, and JSON text -> Python objects.
// Units follow the library: mm, N, s, N/mm.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

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

/// N x 3 float64 C-order array as Vec3 (the library's point layout): used in place.
inline const Vec3* as_vec3(const pyb::array& a) {
  return reinterpret_cast<const Vec3*>(a.data());
}
inline const double* as_doubles(const pyb::array& a) {
  return static_cast<const double*>(a.data());
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
/// progress(what, fraction, eta_s). Every call re-takes the GIL, checks for Ctrl-C and throws
/// Interrupted (on the calling thread only) when it is pressed or the callable raised.
class ProgressBridge {
 public:
  explicit ProgressBridge(pyb::object progress);
  ~ProgressBridge();
  ProgressBridge(const ProgressBridge&) = delete;
  ProgressBridge& operator=(const ProgressBridge&) = delete;
  /// The callback to hand to the library (valid while this object lives).
  inhap::Progress callback();
  /// Closes the bar; rethrows the Python error that stopped the call, if any.
  void finish();

 private:
  void call(const std::string& what, double fraction, double eta);
  pyb::object fn_, bar_;
  bool tqdm_ = false;
  double last_ = 0;
  std::string what_;
  std::shared_ptr<pyb::error_already_set> error_;  ///< what stopped the call
  std::thread::id thread_;                         ///< the calling thread
};

/// Runs `f` with the GIL released and progress reported through `progress`; errors of the
/// callable or Ctrl-C come back as the Python exception.
template <class F>
auto with_progress(pyb::object progress, F&& f) {
  ProgressBridge bridge(std::move(progress));
  inhap::Progress cb = bridge.callback();
  try {
    if constexpr (std::is_void_v<decltype(f(cb))>) {
      {
        pyb::gil_scoped_release release;
        f(cb);
      }
      bridge.finish();
    } else {
      auto r = [&] {
        pyb::gil_scoped_release release;
        return f(cb);
      }();
      bridge.finish();
      return r;
    }
  } catch (const Interrupted&) {
    bridge.finish();
    throw;
  }
}

/// Checks for Ctrl-C from code running without the GIL (takes it briefly); throws Interrupted.
void check_signals();

/// JSON text -> Python dict / list (json.loads).
pyb::object json_to_python(const std::string& text);

}  // namespace inhap::py
