// The `inhap` Python module: thin pybind11 bindings over the library (no logic of its own).
// Units everywhere: millimetres, newtons, seconds, N/mm. See docs/python.md.
#include <new>

#include "common.hpp"
#include "inhap/core/error.hpp"

#ifndef INHAP_VERSION
#define INHAP_VERSION "unknown"
#endif

namespace inhap::py {
void register_io(pyb::module_& m);
void register_model(pyb::module_& m);
void register_render(pyb::module_& m);
void register_lab(pyb::module_& m);
void register_sys(pyb::module_& m);
void register_files(pyb::module_& m);
}  // namespace inhap::py

PYBIND11_MODULE(inhap, m) {
  namespace pyb = pybind11;
  m.doc() =
      "inhap: data-driven haptics (shape by tapping, sliding yield surfaces and the data-driven "
      "force model, TCA-MESH / CBA rendering, the virtual lab). Units: mm, N, s, N/mm. Arrays "
      "are float64 numpy arrays, C order; points and forces are (N, 3).";
  m.attr("__version__") = INHAP_VERSION;
  // The library's errors with the one-line message the program prints after "inhap: error: ".
  static pyb::exception<inhap::Error> error(m, "Error", PyExc_RuntimeError);
  static pyb::exception<inhap::ParseError> parse_error(m, "ParseError", error.ptr());
  static pyb::exception<inhap::IoError> io_error(m, "IoError", error.ptr());
  pyb::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const inhap::ParseError& e) {
      parse_error(e.what());
    } catch (const inhap::IoError& e) {
      io_error(e.what());
    } catch (const inhap::Error& e) {
      error(e.what());
    } catch (const inhap::py::Interrupted&) {
      PyErr_SetNone(PyExc_KeyboardInterrupt);
    }
  });
  inhap::py::register_io(m);
  inhap::py::register_model(m);
  inhap::py::register_render(m);
  inhap::py::register_lab(m);
  inhap::py::register_sys(m);
  inhap::py::register_files(m);
}
