// DetectorConfig, Extrinsics and GroundDetector for Python.
#include <pybind11/stl.h>

#include <mutex>
#include <string>

#include "bindings.hpp"
#include "conversions.hpp"
#include "py_frame.hpp"

namespace vlpground::python {
namespace {

using py::literals::operator""_a;

// Sets each keyword as an attribute of the freshly made `value` (unknown names: TypeError).
template <class T>
T from_kwargs(const char* type_name, const py::kwargs& kwargs) {
  T value{};
  py::object view = py::cast(&value, py::return_value_policy::reference);
  for (const auto& [key, item] : kwargs) {
    const auto name = py::cast<std::string>(key);
    if (!py::hasattr(view, name.c_str()) || name.rfind('_', 0) == 0) {
      throw py::type_error(std::string(type_name) + "() got an unexpected keyword '" + name + "'");
    }
    view.attr(name.c_str()) = item;
  }
  return value;
}

class PyGroundDetector {
 public:
  explicit PyGroundDetector(const DetectorConfig& config) : detector_(config), method_(method_name(config)) {}

  PyFrame detect(const PyFrame& frame) {
    auto ground = std::make_shared<GroundResult>();
    {
      py::gil_scoped_release release;
      const std::lock_guard lock(mutex_);
      ground->reserve(frame.frame->capacity());
      detector_.detect(*frame.frame, *ground);
    }
    return PyFrame{frame.frame, std::move(ground), frame.meta, method_};
  }

  [[nodiscard]] DetectorConfig config() const { return detector_.config(); }

 private:
  std::mutex mutex_;
  GroundDetector detector_;
  std::string method_;
};

std::string repr_extrinsics(const Extrinsics& e) {
  return "Extrinsics(x_m=" + std::to_string(e.x_m) + ", y_m=" + std::to_string(e.y_m) +
         ", z_m=" + std::to_string(e.z_m) + ", roll_deg=" + std::to_string(e.roll_deg) +
         ", pitch_deg=" + std::to_string(e.pitch_deg) + ", yaw_deg=" + std::to_string(e.yaw_deg) + ")";
}

}  // namespace

void bind_detector(py::module_& m) {
  py::class_<Extrinsics>(m, "Extrinsics",
                         "Sensor pose in the vehicle frame: translation (m) and roll, pitch, yaw "
                         "(degrees). Keywords: x_m, y_m, z_m, roll_deg, pitch_deg, yaw_deg.")
      .def(py::init([](const py::kwargs& kw) { return from_kwargs<Extrinsics>("Extrinsics", kw); }))
      .def_readwrite("x_m", &Extrinsics::x_m)
      .def_readwrite("y_m", &Extrinsics::y_m)
      .def_readwrite("z_m", &Extrinsics::z_m)
      .def_readwrite("roll_deg", &Extrinsics::roll_deg)
      .def_readwrite("pitch_deg", &Extrinsics::pitch_deg)
      .def_readwrite("yaw_deg", &Extrinsics::yaw_deg)
      .def("__repr__", &repr_extrinsics);

  using C = DetectorConfig;
  py::class_<C>(m, "DetectorConfig",
                "Ground detector settings (defaults and meaning: docs/detector.md). Any field "
                "may be given as a keyword, e.g. DetectorConfig(method='ransac', "
                "min_sensor_height_m=0).")
      .def(py::init([](const py::kwargs& kw) { return from_kwargs<C>("DetectorConfig", kw); }))
      .def_property("method", &method_name, &set_method, "'tangent' (default), 'ransac' or 'lpr'.")
      .def_readwrite("extrinsics", &C::extrinsics)
      .def_readwrite("fit_radius_m", &C::fit_radius_m)
      .def_readwrite("grid_bins", &C::grid_bins)
      .def_readwrite("bin_size_m", &C::bin_size_m)
      .def_readwrite("hypotheses", &C::hypotheses)
      .def_readwrite("inlier_distance_m", &C::inlier_distance_m)
      .def_readwrite("tangent_angle_deg", &C::tangent_angle_deg)
      .def_readwrite("min_segment_inliers", &C::min_segment_inliers)
      .def_readwrite("subsample_cell_m", &C::subsample_cell_m)
      .def_readwrite("seed", &C::seed)
      .def_readwrite("max_tilt_deg", &C::max_tilt_deg)
      .def_readwrite("below_distance_m", &C::below_distance_m)
      .def_readwrite("below_penalty", &C::below_penalty)
      .def_readwrite("max_step_m", &C::max_step_m)
      .def_readwrite("min_sensor_height_m", &C::min_sensor_height_m)
      .def_readwrite("max_sensor_height_m", &C::max_sensor_height_m)
      .def_readwrite("label_height_m", &C::label_height_m)
      .def_readwrite("steep_label_height_m", &C::steep_label_height_m)
      .def_readwrite("label_below_m", &C::label_below_m)
      .def_readwrite("label_growth_per_m", &C::label_growth_per_m)
      .def_readwrite("terrain_refinement", &C::terrain_refinement)
      .def_readwrite("refinement_cell_m", &C::refinement_cell_m)
      .def_readwrite("column_profiles", &C::column_profiles)
      .def("validate", &C::validate, "Raises ValueError naming a bad field and its valid range.")
      .def("__repr__", [](const C& c) {
        return "DetectorConfig(method='" + method_name(c) + "', extrinsics=" +
               repr_extrinsics(c.extrinsics) + ", min_sensor_height_m=" +
               std::to_string(c.min_sensor_height_m) + ", ...)";
      });

  py::class_<PyGroundDetector>(m, "GroundDetector",
                               "Ground detector with its own workspace: re-runs detection on a "
                               "decoded frame with other settings. One detect() at a time per "
                               "object (calls from several threads are serialised).")
      .def(py::init<const DetectorConfig&>(), "config"_a = DetectorConfig{})
      .def("detect", &PyGroundDetector::detect, "frame"_a,
           "Labels `frame` again; returns a new Frame sharing the decoded arrays (no copy) with "
           "this detector's labels and planes. The GIL is released while detecting.")
      .def_property_readonly("config", &PyGroundDetector::config);
}

}  // namespace vlpground::python
