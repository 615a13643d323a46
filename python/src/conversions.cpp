#include "conversions.hpp"

namespace vlpground::python {

using py::literals::operator""_a;

std::string method_name(const DetectorConfig& config) { return config.method; }

void set_method(DetectorConfig& config, const std::string& name) {
  if (name != "tangent" && name != "ransac" && name != "lpr") {
    throw py::value_error("method must be 'tangent', 'ransac' or 'lpr', got '" + name + "'");
  }
  config.method = name;
}

Model parse_model(const std::string& name) {
  if (name == "vlp16") return Model::vlp16;
  if (name == "hires") return Model::hires;
  throw py::value_error("model must be 'vlp16' or 'hires', got '" + name + "'");
}

ReturnMode parse_mode(const std::string& name) {
  if (name == "strongest") return ReturnMode::strongest;
  if (name == "last") return ReturnMode::last;
  if (name == "dual") return ReturnMode::dual;
  throw py::value_error("mode must be 'strongest', 'last' or 'dual', got '" + name + "'");
}

py::dict counters_dict(const CaptureCounters& c) {
  const SourceCounters& s = c.source;
  const DecoderCounters& d = c.decoder;
  const AssemblerCounters& a = c.assembler;
  return py::dict(
      "source"_a = py::dict("records"_a = s.records, "data_packets"_a = s.data_packets,
                            "position_packets"_a = s.position_packets,
                            "skipped_other"_a = s.skipped_other,
                            "skipped_wrong_size"_a = s.skipped_wrong_size,
                            "skipped_fragment"_a = s.skipped_fragment,
                            "skipped_address"_a = s.skipped_address, "truncated"_a = s.truncated,
                            "kernel_drops"_a = s.kernel_drops),
      "decoder"_a = py::dict("decoded"_a = d.decoded, "wrong_size"_a = d.wrong_size,
                             "bad_flag"_a = d.bad_flag, "bad_azimuth"_a = d.bad_azimuth,
                             "unknown_mode"_a = d.unknown_mode,
                             "product_mismatch"_a = d.product_mismatch,
                             "not_vlp16"_a = d.not_vlp16),
      "assembler"_a = py::dict(
          "frames"_a = a.frames, "incomplete_frames"_a = a.incomplete_frames,
          "packets_used"_a = a.packets_used, "packets_lost"_a = a.packets_lost,
          "duplicate_packets"_a = a.duplicate_packets, "reordered_packets"_a = a.reordered_packets,
          "columns_lost"_a = a.columns_lost, "off_grid_packets"_a = a.off_grid_packets,
          "skipped_upstream"_a = a.skipped_upstream, "columns_outside_fov"_a = a.columns_outside_fov,
          "silences"_a = a.silences, "large_gaps"_a = a.large_gaps,
          "capacity_overflows"_a = a.capacity_overflows, "stream_changes"_a = a.stream_changes,
          "azimuth_jumps"_a = a.azimuth_jumps, "clock_rebases"_a = a.clock_rebases,
          "discarded_packets"_a = a.discarded_packets),
      "position_packets_parsed"_a = c.position_packets_parsed);
}

}  // namespace vlpground::python
