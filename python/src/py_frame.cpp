// Python classes Frame, FrameLayer, FrameMeta, GpsState, Plane, GroundSegment.
#include "py_frame.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"
#include "conversions.hpp"
#include "vlpground/driver/sensor_model.hpp"

namespace vlpground::python {
namespace {

using py::literals::operator""_a;

/// One return layer of a frame (0 = strongest or only, 1 = last in dual mode).
struct PyLayer {
  PyFrame f;
  int layer = 0;
  [[nodiscard]] const ReturnLayer& data() const { return f.frame->layer[layer]; }
  [[nodiscard]] int cols() const { return f.frame->columns(); }
  [[nodiscard]] int stride() const { return f.frame->stride(); }
};

PyLayer layer_of(const PyFrame& f, int layer) {
  if (layer < 0 || layer >= f.frame->layers()) {
    throw py::index_error("return layer " + std::to_string(layer) + " out of range: this frame has " +
                          std::to_string(f.frame->layers()) + " (2 only in dual-return mode)");
  }
  return PyLayer{f, layer};
}

template <class T>
py::array cell_view(const PyLayer& l, const std::vector<T>& v,
                    const py::dtype& dtype = py::dtype::of<T>()) {
  return row_view(l.f.frame, v.data(), kLasers, l.cols(), l.stride(), dtype);
}

py::array label_view(const PyLayer& l) {
  const GroundResult& g = *l.f.ground;
  return row_view(l.f.ground, g.label[l.layer].data(), kLasers, g.columns, g.stride);
}

py::array height_view(const PyLayer& l) {
  const GroundResult& g = *l.f.ground;
  return row_view(l.f.ground, g.height_m[l.layer].data(), kLasers, g.columns, g.stride);
}

// rows x cols x 3 float32, NaN where there is no return (one copy: x, y, z are separate
// arrays in the frame).
py::array_t<float> xyz_copy(const PyLayer& l) {
  const Frame& fr = *l.f.frame;
  const ReturnLayer& d = l.data();
  const int cols = fr.columns();
  py::array_t<float> out({kLasers, cols, 3});
  float* o = out.mutable_data();
  {
    py::gil_scoped_release release;
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    for (int r = 0; r < kLasers; ++r) {
      for (int c = 0; c < cols; ++c, o += 3) {
        const std::size_t i = fr.index(r, c);
        const bool ok = d.valid[i] != 0;
        o[0] = ok ? d.x_m[i] : kNaN;
        o[1] = ok ? d.y_m[i] : kNaN;
        o[2] = ok ? d.z_m[i] : kNaN;
      }
    }
  }
  return out;
}

std::int64_t firing_time_ns(const Frame& fr, int ring, int col) {
  return fr.column_time_ns[static_cast<std::size_t>(col)] +
         std::int64_t{fr.laser_of_ring[ring]} * kFiringIntervalNs;
}

// rows x cols firing times (exact ns since the epoch, or seconds as float64): one copy.
template <class T>
py::array_t<T> time_copy(const PyFrame& f, double scale) {
  const Frame& fr = *f.frame;
  py::array_t<T> out({kLasers, fr.columns()});
  T* o = out.mutable_data();
  for (int r = 0; r < kLasers; ++r) {
    for (int c = 0; c < fr.columns(); ++c) {
      const std::int64_t t = firing_time_ns(fr, r, c);
      *o++ = scale == 1.0 ? static_cast<T>(t) : static_cast<T>(static_cast<double>(t) * scale);
    }
  }
  return out;
}

// rows x cols of a per-row value (ring index or laser id): one copy.
py::array_t<std::uint8_t> per_row_copy(const PyFrame& f, bool laser) {
  const Frame& fr = *f.frame;
  py::array_t<std::uint8_t> out({kLasers, fr.columns()});
  std::uint8_t* o = out.mutable_data();
  for (int r = 0; r < kLasers; ++r) {
    const auto v = laser ? fr.laser_of_ring[r] : static_cast<std::uint8_t>(r);
    for (int c = 0; c < fr.columns(); ++c) *o++ = v;
  }
  return out;
}

// ----------------------------------------------------------------- to_numpy_points

std::uint64_t count_returns(const Frame& fr) {
  std::uint64_t n = 0;
  for (int l = 0; l < fr.layers(); ++l) {
    for (int r = 0; r < kLasers; ++r) {
      for (int c = 0; c < fr.columns(); ++c) n += fr.layer[l].valid[fr.index(r, c)];
    }
  }
  return n;
}

enum class Field : std::uint8_t {
  x, y, z, intensity, ring, laser, return_layer, azimuth_deg, range_m, time_s, label, height_m,
  column
};

constexpr std::array<std::pair<std::string_view, Field>, 13> kFields{{
    {"x", Field::x},
    {"y", Field::y},
    {"z", Field::z},
    {"intensity", Field::intensity},
    {"ring", Field::ring},
    {"laser", Field::laser},
    {"return", Field::return_layer},
    {"azimuth_deg", Field::azimuth_deg},
    {"range_m", Field::range_m},
    {"time_s", Field::time_s},
    {"label", Field::label},
    {"height_m", Field::height_m},
    {"column", Field::column},
}};

std::vector<Field> parse_fields(const std::vector<std::string>& names) {
  std::vector<Field> out;
  for (const auto& n : names) {
    bool found = false;
    for (const auto& [name, field] : kFields) {
      if (n == name) {
        out.push_back(field);
        found = true;
      }
    }
    if (!found) {
      std::string known;
      for (const auto& [name, field] : kFields) known += (known.empty() ? "" : ", ") + std::string(name);
      throw py::value_error("unknown point field '" + n + "' (known: " + known + ")");
    }
  }
  if (out.empty()) throw py::value_error("fields must name at least one field");
  return out;
}

double field_value(const Frame& fr, const GroundResult& g, Field field, int layer, int ring,
                   int col) {
  const std::size_t i = fr.index(ring, col);
  const ReturnLayer& d = fr.layer[layer];
  const std::size_t gi = static_cast<std::size_t>(ring) * static_cast<std::size_t>(g.stride) +
                         static_cast<std::size_t>(col);
  switch (field) {
    case Field::x: return d.x_m[i];
    case Field::y: return d.y_m[i];
    case Field::z: return d.z_m[i];
    case Field::intensity: return d.intensity[i];
    case Field::ring: return ring;
    case Field::laser: return fr.laser_of_ring[ring];
    case Field::return_layer: return layer;
    case Field::azimuth_deg: return d.azimuth_deg[i];
    case Field::range_m: return d.range_m[i];
    case Field::time_s: return static_cast<double>(firing_time_ns(fr, ring, col)) * 1e-9;
    case Field::label: return gi < g.label[layer].size() ? g.label[layer][gi] : 0;
    case Field::column: return col;
    case Field::height_m:
      return gi < g.height_m[layer].size() ? g.height_m[layer][gi]
                                           : std::numeric_limits<double>::quiet_NaN();
  }
  return 0;
}

// N x k float64 of the valid returns, in the order of the CLI's CSV: column by column, then
// laser id (firing order), then return layer.
py::array_t<double> points(const PyFrame& f, const std::vector<std::string>& names) {
  const std::vector<Field> fields = parse_fields(names);
  const Frame& fr = *f.frame;
  const GroundResult& g = *f.ground;
  std::array<int, kLasers> ring_of_laser{};
  for (int r = 0; r < kLasers; ++r) ring_of_laser[fr.laser_of_ring[r]] = r;
  const std::size_t n = count_returns(fr);
  const auto k = fields.size();
  py::array_t<double> out({n, k});
  double* o = out.mutable_data();
  py::gil_scoped_release release;
  for (int c = 0; c < fr.columns(); ++c) {
    for (int laser = 0; laser < kLasers; ++laser) {
      const int ring = ring_of_laser[static_cast<std::size_t>(laser)];
      for (int l = 0; l < fr.layers(); ++l) {
        if (fr.layer[l].valid[fr.index(ring, c)] == 0) continue;
        for (Field field : fields) *o++ = field_value(fr, g, field, l, ring, c);
      }
    }
  }
  return out;
}

std::vector<std::string> default_fields() {
  return {"x", "y", "z", "intensity", "ring", "laser", "return", "azimuth_deg", "range_m",
          "time_s", "label"};
}

// ----------------------------------------------------------------- metadata


const char* end_name(FrameEnd e) {
  switch (e) {
    case FrameEnd::cut: return "cut";
    case FrameEnd::end_of_input: return "end_of_input";
    case FrameEnd::silence: return "silence";
    case FrameEnd::gap: return "gap";
    case FrameEnd::capacity: return "capacity";
    case FrameEnd::stream_change: return "stream_change";
  }
  return "?";
}

py::dict timings_dict(const StageTimings& t) {
  return py::dict("cloud_ms"_a = t.cloud_ms, "tangents_ms"_a = t.tangents_ms,
                  "hypotheses_ms"_a = t.hypotheses_ms, "inliers_ms"_a = t.inliers_ms,
                  "integral_ms"_a = t.integral_ms, "search_ms"_a = t.search_ms,
                  "labelling_ms"_a = t.labelling_ms, "total_ms"_a = t.total_ms);
}

void bind_meta(py::module_& m) {
  py::class_<GpsState>(m, "GpsState",
                       "GPS state when the frame completed: the latest position packet.")
      .def_property_readonly(
          "has_position", [](const GpsState& g) { return g.has_position; },
          "True once a position packet (UDP 8308) was seen.")
      .def_property_readonly(
          "pps", [](const GpsState& g) { return pps_name(g.last.pps); },
          "PPS status: 'absent', 'synchronizing', 'locked' or 'error'.")
      .def_property_readonly(
          "gprmc",
          [](const GpsState& g) {
            return g.last.gprmc.parsed ? (g.last.gprmc.valid ? "valid" : "void") : "absent";
          },
          "$GPRMC state: 'valid' (status A), 'void' (status V) or 'absent'.")
      .def_property_readonly(
          "utc_ns",
          [](const GpsState& g) -> py::object {
            if (!g.last.gprmc.parsed) return py::none();
            return py::int_(g.last.gprmc.utc_ns());
          },
          "UTC time of the fix in ns since the epoch, or None.")
      .def_property_readonly(
          "latitude_deg", [](const GpsState& g) { return g.last.gprmc.latitude_deg; })
      .def_property_readonly(
          "longitude_deg", [](const GpsState& g) { return g.last.gprmc.longitude_deg; })
      .def_property_readonly("sentence",
                             [](const GpsState& g) { return std::string(g.last.sentence); })
      .def("__repr__", [](const GpsState& g) {
        return std::string("GpsState(pps=") + pps_name(g.last.pps) +
               ", gprmc=" +
               (g.last.gprmc.parsed ? (g.last.gprmc.valid ? "valid" : "void") : "absent") + ")";
      });

  using M = PyMeta;
  py::class_<PyMeta, std::shared_ptr<PyMeta>>(m, "FrameMeta", "Metadata of one frame.")
      .def_property_readonly("sequence", [](const M& x) { return x.frame.sequence; },
                             "Frame counter of the reader: 0, 1, 2, ...")
      .def_property_readonly("start_time_ns", [](const M& x) { return x.frame.first_time_ns; },
                             "Absolute time of the first firing, ns since the Unix epoch.")
      .def_property_readonly("end_time_ns", [](const M& x) { return x.frame.last_time_ns; },
                             "Absolute time of the last firing, ns since the Unix epoch.")
      .def_property_readonly("start_time_s",
                             [](const M& x) { return static_cast<double>(x.frame.first_time_ns) * 1e-9; })
      .def_property_readonly("rpm", [](const M& x) { return x.frame.rpm; })
      .def_property_readonly("mode", [](const M& x) { return std::string(to_string(x.frame.mode)); },
                             "'strongest', 'last' or 'dual'.")
      .def_property_readonly("model", [](const M& x) { return std::string(to_string(x.frame.model)); },
                             "'vlp16' or 'hires'.")
      .def_property_readonly("packets_used", [](const M& x) { return x.frame.packets_used; })
      .def_property_readonly("packets_lost", [](const M& x) { return x.frame.packets_lost; })
      .def_property_readonly("packets_skipped", [](const M& x) { return x.frame.packets_skipped; })
      .def_property_readonly("columns_lost", [](const M& x) { return x.frame.columns_lost; })
      .def_property_readonly("columns_outside_fov",
                             [](const M& x) { return x.frame.columns_outside_fov; })
      .def_property_readonly("complete", [](const M& x) { return x.frame.complete; },
                             "True for a full rotation from cut to cut.")
      .def_property_readonly("end", [](const M& x) { return end_name(x.frame.end); },
                             "Why the frame ended: 'cut', 'end_of_input', 'silence', 'gap', "
                             "'capacity' or 'stream_change'.")
      .def_property_readonly("completed_receive_ns",
                             [](const M& x) { return x.frame.completed_receive_ns; })
      .def_property_readonly("time_source",
                             [](const M& x) { return std::string(to_string(x.frame.time_source)); },
                             "How the frame's times were placed: 'host_clock', 'gps_no_pps' or "
                             "'gps_pps' (UTC from GPS with PPS locked).")
      .def_property_readonly("calibration",
                             [](const M& x) {
                               return x.frame.calibration ? x.frame.calibration->source
                                                          : std::string("built-in");
                             },
                             "Geometry the frame was decoded with: 'built-in' or the "
                             "calibration file's path.")
      .def_property_readonly("gps", [](const M& x) { return x.gps; })
      .def_property_readonly("counters", [](const M& x) { return counters_dict(x.counters); },
                             "Reader counters (source, decoder, assembler) when the frame was "
                             "handed out: cumulative since the reader opened.")
      .def("__repr__", [](const M& x) {
        return "FrameMeta(sequence=" + std::to_string(x.frame.sequence) +
               ", complete=" + (x.frame.complete ? "True" : "False") +
               ", packets_used=" + std::to_string(x.frame.packets_used) +
               ", packets_lost=" + std::to_string(x.frame.packets_lost) + ")";
      });

  py::class_<Plane>(m, "Plane", "Plane nx*x + ny*y + nz*z + d = 0 (vehicle frame, unit normal).")
      .def_readonly("nx", &Plane::nx)
      .def_readonly("ny", &Plane::ny)
      .def_readonly("nz", &Plane::nz)
      .def_readonly("d", &Plane::d)
      .def("height_at",
           [](const Plane& p, double x, double y) { return -(p.d + p.nx * x + p.ny * y) / p.nz; },
           "x"_a, "y"_a, "Ground height z of the plane at (x, y).")
      .def("__repr__", [](const Plane& p) {
        return "Plane(nx=" + std::to_string(p.nx) + ", ny=" + std::to_string(p.ny) +
               ", nz=" + std::to_string(p.nz) + ", d=" + std::to_string(p.d) + ")";
      });
  py::class_<GroundSegment>(m, "GroundSegment",
                            "One of the four cross-partition segments and its fitted plane.")
      .def_readonly("plane", &GroundSegment::plane)
      .def_readonly("has_ground", &GroundSegment::has_ground)
      .def_readonly("inherited", &GroundSegment::inherited)
      .def_readonly("inliers", &GroundSegment::inliers)
      .def_property_readonly("bounds_m",
                             [](const GroundSegment& s) {
                               return py::make_tuple(s.x_min_m, s.x_max_m, s.y_min_m, s.y_max_m);
                             },
                             "(x_min, x_max, y_min, y_max) in the vehicle frame.")
      .def("__repr__", [](const GroundSegment& s) {
        return std::string("GroundSegment(has_ground=") + (s.has_ground ? "True" : "False") +
               ", inliers=" + std::to_string(s.inliers) + ")";
      });
}

// Per-layer attributes, shared by Frame (layer 0) and FrameLayer.
template <class Class, class Get>
void def_layer_arrays(Class& cls, Get get) {
  cls.def_property_readonly(
         "range_m", [get](const typename Class::type& o) { const PyLayer l = get(o); return cell_view(l, l.data().range_m); },
         "rows x cols float32 range in metres, 0 where there is no return (view, no copy).")
      .def_property_readonly(
          "x", [get](const typename Class::type& o) { const PyLayer l = get(o); return cell_view(l, l.data().x_m); },
          "rows x cols float32 x (sensor frame, forward), 0 where invalid (view).")
      .def_property_readonly(
          "y", [get](const typename Class::type& o) { const PyLayer l = get(o); return cell_view(l, l.data().y_m); },
          "rows x cols float32 y (sensor frame, left), 0 where invalid (view).")
      .def_property_readonly(
          "z", [get](const typename Class::type& o) { const PyLayer l = get(o); return cell_view(l, l.data().z_m); },
          "rows x cols float32 z (sensor frame, up), 0 where invalid (view).")
      .def_property_readonly(
          "xyz", [get](const typename Class::type& o) { return xyz_copy(get(o)); },
          "rows x cols x 3 float32 points (sensor frame), NaN where invalid (one copy).")
      .def_property_readonly(
          "intensity", [get](const typename Class::type& o) { const PyLayer l = get(o); return cell_view(l, l.data().intensity); },
          "rows x cols uint8 calibrated reflectivity (view).")
      .def_property_readonly(
          "azimuth_deg", [get](const typename Class::type& o) { const PyLayer l = get(o); return cell_view(l, l.data().azimuth_deg); },
          "rows x cols float32 precise azimuth of each firing, [0, 360) (view).")
      .def_property_readonly(
          "time_offset_us", [get](const typename Class::type& o) { const PyLayer l = get(o); return cell_view(l, l.data().time_offset_us); },
          "rows x cols float32 firing time relative to meta.start_time_ns, us (view).")
      .def_property_readonly(
          "valid", [get](const typename Class::type& o) { const PyLayer l = get(o); return cell_view(l, l.data().valid, py::dtype("bool")); },
          "rows x cols bool, True where the cell holds a return (view).")
      .def_property_readonly(
          "label", [get](const typename Class::type& o) { return label_view(get(o)); },
          "rows x cols uint8: 0 no return, 1 ground, 2 obstacle (view).")
      .def_property_readonly(
          "height_m", [get](const typename Class::type& o) { return height_view(get(o)); },
          "rows x cols float32 height above the fitted ground, NaN where none (view).");
}

}  // namespace

void bind_frame(py::module_& m) {
  bind_meta(m);

  py::class_<PyLayer> layer(m, "FrameLayer",
                            "One return layer of a frame (frame.layer(1) is the last return in "
                            "dual mode). Same per-cell arrays as Frame.");
  layer.def_property_readonly("index", [](const PyLayer& l) { return l.layer; });
  def_layer_arrays(layer, [](const PyLayer& l) { return l; });

  py::class_<PyFrame, std::shared_ptr<PyFrame>> frame(
      m, "Frame",
      "One rotation as a 16 x N range image (rows = rings, 0 lowest; columns = firing sequences "
      "in time order) with ground labels. Per-cell attributes are those of return layer 0 "
      "(strongest or only); frame.layer(1) is the last return in dual mode. Arrays are "
      "read-only numpy views over the frame's memory (row stride = frame.stride) unless their "
      "docstring says 'one copy'.");
  def_layer_arrays(frame, [](const PyFrame& f) { return PyLayer{f, 0}; });
  frame
      .def_property_readonly("rows", [](const PyFrame&) { return kLasers; })
      .def_property_readonly("columns", [](const PyFrame& f) { return f.frame->columns(); })
      .def_property_readonly("stride", [](const PyFrame& f) { return f.frame->stride(); },
                             "Row stride of the per-cell arrays in elements (>= columns).")
      .def_property_readonly("return_layers", [](const PyFrame& f) { return f.frame->layers(); },
                             "2 in dual-return mode, else 1.")
      .def("layer", &layer_of, "index"_a, "Return layer 0 (strongest or only) or 1 (last, dual).")
      .def_property_readonly(
          "same_echo",
          [](const PyFrame& f) -> py::object {
            if (f.frame->layers() < 2) return py::none();
            return row_view(f.frame, f.frame->same_echo.data(), kLasers, f.frame->columns(),
                            f.frame->stride(), py::dtype("bool"));
          },
          "Dual mode: rows x cols bool, True where both layers hold the same echo (view); "
          "None otherwise.")
      .def_property_readonly("ring", [](const PyFrame& f) { return per_row_copy(f, false); },
                             "rows x cols uint8 ring index (= row; one copy).")
      .def_property_readonly("laser", [](const PyFrame& f) { return per_row_copy(f, true); },
                             "rows x cols uint8 laser id in firing order (one copy).")
      .def_property_readonly("time_ns",
                             [](const PyFrame& f) { return time_copy<std::int64_t>(f, 1.0); },
                             "rows x cols int64 firing time, exact ns since the epoch (one copy).")
      .def_property_readonly("time_s", [](const PyFrame& f) { return time_copy<double>(f, 1e-9); },
                             "rows x cols float64 firing time, s since the epoch (one copy; "
                             "resolution about 0.2 us at today's epoch, use time_ns for exact).")
      .def_property_readonly("column_azimuth_deg",
                             [](const PyFrame& f) {
                               return flat_view(f.frame, f.frame->column_azimuth_deg.data(),
                                                f.frame->columns());
                             },
                             "Per column: azimuth of the sequence's first firing (view).")
      .def_property_readonly("column_time_ns",
                             [](const PyFrame& f) {
                               return flat_view(f.frame, f.frame->column_time_ns.data(),
                                                f.frame->columns());
                             },
                             "Per column: absolute time of the first firing, ns (view).")
      .def_property_readonly("column_valid",
                             [](const PyFrame& f) {
                               return flat_view(f.frame, f.frame->column_valid.data(),
                                                f.frame->columns());
                             },
                             "Per column: 0 for columns lost with their packet (view).")
      .def_property_readonly("column_packet_index",
                             [](const PyFrame& f) {
                               return flat_view(f.frame, f.frame->column_packet_index.data(),
                                                f.frame->columns());
                             },
                             "Per column: index of the data packet that carried it (view).")
      .def_property_readonly("meta", [](const PyFrame& f) { return std::const_pointer_cast<PyMeta>(f.meta); })
      .def_property_readonly("method", [](const PyFrame& f) { return f.method; },
                             "Ground detection method that produced the labels.")
      .def_property_readonly("planes",
                             [](const PyFrame& f) {
                               return std::vector<GroundSegment>(f.ground->segments.begin(),
                                                                 f.ground->segments.end());
                             },
                             "The four cross-partition segments with their fitted planes.")
      .def_property_readonly("partition_centre",
                             [](const PyFrame& f) {
                               return py::make_tuple(f.ground->centre_x_m, f.ground->centre_y_m);
                             },
                             "(x, y) of the partition centre, vehicle frame.")
      .def_property_readonly("ground_returns", [](const PyFrame& f) { return f.ground->ground_returns; })
      .def_property_readonly("obstacle_returns",
                             [](const PyFrame& f) { return f.ground->obstacle_returns; })
      .def_property_readonly("returns",
                             [](const PyFrame& f) { return count_returns(*f.frame); },
                             "Valid returns over all layers.")
      .def_property_readonly("timings", [](const PyFrame& f) { return timings_dict(f.ground->timings); },
                             "Detector stage timings of this frame, ms.")
      .def("to_numpy_points", &points, "fields"_a = default_fields(),
           "Flat N x k float64 array of the valid returns (every layer), one row per return in "
           "the order of the CLI's CSV (column, then laser id, then return layer); columns are "
           "`fields` (default x, y, z, intensity, ring, laser, return, azimuth_deg, range_m, "
           "time_s, label; also height_m and column, the column index). One copy.")
      .def("__repr__", [](const PyFrame& f) {
        return "Frame(sequence=" + std::to_string(f.frame->meta.sequence) +
               ", columns=" + std::to_string(f.frame->columns()) +
               ", layers=" + std::to_string(f.frame->layers()) + ", method='" + f.method +
               "', complete=" + (f.frame->meta.complete ? "True" : "False") + ")";
      });
  m.attr("POINT_FIELDS") = py::make_tuple("x", "y", "z", "intensity", "ring", "laser", "return",
                                          "azimuth_deg", "range_m", "time_s", "label", "height_m",
                                          "column");
}

}  // namespace vlpground::python
