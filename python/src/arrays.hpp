// numpy views over memory owned by a shared_ptr: no copy, read-only, kept alive by a capsule.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <memory>

namespace vlpground::python {

namespace py = pybind11;

inline void make_read_only(py::array& a) {
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
}

/// A capsule that keeps `owner` alive for as long as an array refers to it.
inline py::capsule keep_alive(std::shared_ptr<const void> owner) {
  auto* held = new std::shared_ptr<const void>(std::move(owner));
  return py::capsule(held, [](void* p) { delete static_cast<std::shared_ptr<const void>*>(p); });
}

/// rows x cols view of `data` (row stride `stride` elements) as `dtype`.
template <class T>
py::array row_view(std::shared_ptr<const void> owner, const T* data, int rows, int cols,
                   int stride, const py::dtype& dtype = py::dtype::of<T>()) {
  const auto item = static_cast<py::ssize_t>(sizeof(T));
  py::array a(dtype, {static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)},
              {static_cast<py::ssize_t>(stride) * item, item}, data, keep_alive(std::move(owner)));
  make_read_only(a);
  return a;
}

/// 1-D view of `count` elements.
template <class T>
py::array flat_view(std::shared_ptr<const void> owner, const T* data, int count) {
  py::array a(py::dtype::of<T>(), {static_cast<py::ssize_t>(count)},
              {static_cast<py::ssize_t>(sizeof(T))}, data, keep_alive(std::move(owner)));
  make_read_only(a);
  return a;
}

}  // namespace vlpground::python
