// Helpers of the `inhap` Python module: numpy checks, views, progress, JSON (common.hpp).
#include "common.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace inhap::py {

namespace {

std::string shape_text(const pyb::array& a) {
  std::string s = "(";
  for (pyb::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

}  // namespace

pyb::array checked(const pyb::handle& obj, const char* name, std::size_t cols, std::size_t rows) {
  if (!pyb::isinstance<pyb::array>(obj))
    throw pyb::type_error(std::string(name) + ": expected a numpy array of float64, got " +
                          std::string(pyb::str(obj.get_type().attr("__name__"))));
  pyb::array a = pyb::reinterpret_borrow<pyb::array>(obj);
  if (!a.dtype().is(pyb::dtype::of<double>()))
    throw pyb::type_error(std::string(name) + ": expected dtype float64, got " +
                          std::string(pyb::str(a.dtype())) + " (convert with .astype(np.float64))");
  const std::string want = cols == 0 ? "(N,)" : "(N, " + std::to_string(cols) + ")";
  const bool shape_ok =
      cols == 0 ? a.ndim() == 1 : a.ndim() == 2 && a.shape(1) == static_cast<pyb::ssize_t>(cols);
  if (!shape_ok || (rows != 0 && a.shape(0) != static_cast<pyb::ssize_t>(rows)))
    throw pyb::type_error(
        std::string(name) + ": expected shape " +
        (rows ? "(" + std::to_string(rows) + (cols ? ", " + std::to_string(cols) + ")" : ",)")
              : want) +
        ", got " + shape_text(a));
  if (!(a.flags() & pyb::array::c_style))
    throw pyb::type_error(std::string(name) +
                          ": expected a C-contiguous array (Fortran order or a strided view would "
                          "need a copy; use np.ascontiguousarray)");
  return a;
}

pyb::array view(std::vector<Vec3>& v, pyb::handle owner) {
  const auto n = static_cast<pyb::ssize_t>(v.size());
  return pyb::array(pyb::dtype::of<double>(), {n, pyb::ssize_t{3}},
                    {pyb::ssize_t{sizeof(Vec3)}, pyb::ssize_t{sizeof(double)}},
                    v.empty() ? nullptr : v.front().data(), owner);
}

pyb::array view(std::vector<double>& v, pyb::handle owner) {
  const auto n = static_cast<pyb::ssize_t>(v.size());
  return pyb::array(pyb::dtype::of<double>(), {n}, {pyb::ssize_t{sizeof(double)}}, v.data(), owner);
}

pyb::array column_view(std::vector<Vec3>& v, int c, pyb::handle owner) {
  const auto n = static_cast<pyb::ssize_t>(v.size());
  return pyb::array(pyb::dtype::of<double>(), {n}, {pyb::ssize_t{sizeof(Vec3)}},
                    v.empty() ? nullptr : v.front().data() + c, owner);
}

pyb::array to_numpy(const std::vector<Vec3>& v) {
  pyb::array_t<double> a({static_cast<pyb::ssize_t>(v.size()), pyb::ssize_t{3}});
  auto* out = a.mutable_data();
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int c = 0; c < 3; ++c) out[3 * i + c] = v[i][c];
  return a;
}

pyb::array to_numpy(const std::vector<double>& v) {
  pyb::array_t<double> a(static_cast<pyb::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

std::vector<Vec3> to_vec3(const pyb::handle& obj, const char* name) {
  const pyb::array a = checked(obj, name, 3);
  const Vec3* p = as_vec3(a);
  return std::vector<Vec3>(p, p + a.shape(0));
}

std::vector<double> to_doubles(const pyb::handle& obj, const char* name) {
  const pyb::array a = checked(obj, name, 0);
  const double* p = as_doubles(a);
  return std::vector<double>(p, p + a.shape(0));
}

ProgressBridge::ProgressBridge(pyb::object progress) {
  if (progress.is_none() || (pyb::isinstance<pyb::bool_>(progress) && !progress.cast<bool>()))
    return;
  if (pyb::isinstance<pyb::bool_>(progress)) {  // True: tqdm when installed
    try {
      fn_ = pyb::module_::import("tqdm").attr("tqdm");
      tqdm_ = true;
    } catch (const pyb::error_already_set&) {
      fn_ = pyb::object();  // no tqdm: silent
    }
    return;
  }
  if (!PyCallable_Check(progress.ptr()))
    throw pyb::type_error(
        "progress: expected True, False, None or a callable(what, fraction, eta_s)");
  fn_ = std::move(progress);
}

ProgressBridge::~ProgressBridge() {
  if (!bar_) return;
  try {
    bar_.attr("close")();
  } catch (const pyb::error_already_set&) {  // closing a bar must not hide the real error
  }
}

inhap::Progress ProgressBridge::callback() {
  return
      [this](const std::string& what, double fraction, double eta) { call(what, fraction, eta); };
}

void ProgressBridge::stop(pyb::error_already_set&& e) {
  error_ = std::make_shared<pyb::error_already_set>(std::move(e));
  flag_.request();
}

void ProgressBridge::poll() {
  pyb::gil_scoped_acquire gil;
  if (!error_ && PyErr_CheckSignals() != 0) stop(pyb::error_already_set());
}

void ProgressBridge::call(const std::string& what, double fraction, double eta) {
  pyb::gil_scoped_acquire gil;
  if (!error_) {
    try {
      if (fn_ && tqdm_) {
        if (!bar_ || what != what_) {
          if (bar_) bar_.attr("close")();
          bar_ = fn_(
              pyb::arg("total") = 1000, pyb::arg("desc") = what, pyb::arg("leave") = false,
              pyb::arg("bar_format") = "{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]");
          what_ = what;
          last_ = 0;
        }
        const double now = std::clamp(fraction, 0.0, 1.0) * 1000;
        if (now > last_) bar_.attr("update")(static_cast<int>(now) - static_cast<int>(last_));
        last_ = std::floor(now);
      } else if (fn_) {
        fn_(what, fraction, eta);
      }
    } catch (pyb::error_already_set& e) {
      stop(std::move(e));
    }
  }
  if (error_ && std::this_thread::get_id() == thread_) throw Interrupted();
}

void ProgressBridge::finish() {
  if (bar_) {
    bar_.attr("close")();
    bar_ = pyb::object();
  }
  if (error_) throw *error_;
}

void check_signals() {
  pyb::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) throw pyb::error_already_set();
}

pyb::object json_to_python(const std::string& text) {
  return pyb::module_::import("json").attr("loads")(text);
}

}  // namespace inhap::py
