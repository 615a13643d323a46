// vlpground._core: the compiled part of the Python package (see python/vlpground/__init__.py).
#include "bindings.hpp"
#include "py_frame.hpp"

PYBIND11_MODULE(_core, m) {
  m.doc() = "Compiled core of vlpground (VLP-16 decoding and ground detection).";
  m.attr("__version__") = VLPGROUND_VERSION;  // the CMake project's version
  vlpground::python::bind_detector(m);
  vlpground::python::bind_frame(m);
  vlpground::python::bind_reader(m);
  vlpground::python::bind_eval_sim(m);
}
