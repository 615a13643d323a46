// Registration functions of the _core extension module, one per binding file.
#pragma once

#include <pybind11/pybind11.h>

namespace vlpground::python {

void bind_frame(pybind11::module_& m);     // py_frame.cpp
void bind_reader(pybind11::module_& m);    // frame_reader.cpp
void bind_detector(pybind11::module_& m);  // detector_binding.cpp
void bind_eval_sim(pybind11::module_& m);  // eval_sim_binding.cpp

}  // namespace vlpground::python
