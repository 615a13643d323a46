// Decodes 1206-byte VLP-16 data packets into firing columns. Zero heap allocation per
// packet: the caller owns the DecodedPacket and reuses it.
//
// Thread-safety: one PacketDecoder per thread (it keeps the warn-once state, counters and
// the hour resolver).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "vlpground/driver/position_packet.hpp"
#include "vlpground/driver/sensor_model.hpp"
#include "vlpground/error.hpp"
#include "vlpground/types.hpp"

namespace vlpground {
namespace driver_detail {
class TimeBase;
}

inline constexpr std::size_t kDataPacketBytes = 1206;
inline constexpr std::size_t kPositionPacketBytes = 512;
inline constexpr int kBlocksPerPacket = 12;
inline constexpr int kMaxColumnsPerPacket = 24;

/// One return of one laser (a convenience view; DecodedPacket stores structure of arrays).
struct LaserReturn {
  float distance_m = 0.f;  // 0 = no return
  float x_m = 0.f, y_m = 0.f, z_m = 0.f;
  std::uint8_t intensity = 0;
};

/// Per-laser rows over the columns of one packet: `rows[laser][column]`, laser id in firing
/// order. Row-major by laser so that a ring's cells of consecutive columns are contiguous,
/// as in the range image they are copied into.
template <class T>
using LaserRows = std::array<std::array<T, kMaxColumnsPerPacket>, kLasers>;

/// One return layer of a packet.
struct PacketLayer {
  LaserRows<float> distance_m{};  // 0 = no return
  LaserRows<float> x_m{}, y_m{}, z_m{};
  LaserRows<std::uint8_t> intensity{};
};

/// The firing columns of one packet (a column = one firing sequence of 16 lasers, 2.304 us
/// apart), structure of arrays.
struct DecodedPacket {
  int column_count = 0;                                             // 24 single-return, 12 dual
  std::array<std::int64_t, kMaxColumnsPerPacket> column_time_ns{};  // laser 0's firing
  LaserRows<float> azimuth_deg{};  // [laser][column], interpolated, [0, 360)
  // [kStrongestLayer]: strongest (or the only) return; [kLastLayer]: last return (dual).
  std::array<PacketLayer, 2> layer{};
  LaserRows<std::uint8_t> same_echo{};  // dual: both layers hold the same echo

  ReturnMode mode = ReturnMode::strongest;
  Model model = Model::vlp16;  // model used to decode
  std::uint8_t product_byte = 0;
  std::uint32_t stamp_us_past_hour = 0;  // raw packet timestamp
  std::int64_t time_ns = 0;              // absolute time of the first firing
  // Nonzero when a new hour reference (the first GPS fix, a GPS hour unlike the host
  // clock's) moved this packet's time against the previous packets': the whole hours added.
  // The packet stamps themselves stay continuous; consumers re-base earlier times by it.
  std::int64_t time_rebase_ns = 0;
  std::int64_t receive_ns = 0;  // receive time given by the caller
  TimeSource time_source = TimeSource::host_clock;  // where time_ns came from
  std::uint16_t first_azimuth_centideg = 0;
  // 0-based index of this packet among all packets given to PacketDecoder::decode()
  // (the k-th data packet of a capture); ground-truth files are indexed by it.
  std::uint64_t packet_index = 0;

  /// Return of `laser` in `column` of `layer_index` (kStrongestLayer / kLastLayer).
  [[nodiscard]] LaserReturn at(int layer_index, int column, int laser) const {
    const auto& l = layer[static_cast<std::size_t>(layer_index)];
    const auto k = static_cast<std::size_t>(laser);
    const auto c = static_cast<std::size_t>(column);
    return {l.distance_m[k][c], l.x_m[k][c], l.y_m[k][c], l.z_m[k][c], l.intensity[k][c]};
  }
  /// Azimuth of `laser`'s firing in `column`, degrees.
  [[nodiscard]] float azimuth(int column, int laser) const {
    return azimuth_deg[static_cast<std::size_t>(laser)][static_cast<std::size_t>(column)];
  }
};

enum class DecodeStatus : std::uint8_t {
  ok,
  wrong_size,    // not 1206 bytes
  bad_flag,      // a block without FF EE
  bad_azimuth,   // azimuth >= 36000
  unknown_mode,  // return-mode byte not 0x37/0x38/0x39
  not_vlp16,     // packet spacing says another sensor family (e.g. HDL-32E, 553 us)
};

struct DecoderCounters {
  std::uint64_t decoded = 0;
  std::uint64_t wrong_size = 0;
  std::uint64_t bad_flag = 0;
  std::uint64_t bad_azimuth = 0;
  std::uint64_t unknown_mode = 0;
  std::uint64_t product_mismatch = 0;  // product byte unknown or contradicting the timing
  std::uint64_t not_vlp16 = 0;         // packets refused: timing of another sensor family
};

struct DecoderConfig {
  std::optional<Model> force_model;  // decode as this model whatever the product byte says
  std::string calibration_file;      // empty: built-in geometry
  bool use_gps_hour = true;          // take the hour from GPRMC when PPS is locked

  /// Throws std::invalid_argument with a clear message.
  void validate() const;
};

class PacketDecoder {
 public:
  explicit PacketDecoder(const DecoderConfig& config = {});
  ~PacketDecoder();
  PacketDecoder(PacketDecoder&&) noexcept;
  PacketDecoder& operator=(PacketDecoder&&) noexcept;

  /// Decodes `bytes` received at `receive_ns` (pcap record time or host clock, ns since the
  /// epoch) into `out`. Never throws, never allocates; a malformed packet is a status and a
  /// counter. `stamp_offset_ns` is added to the packet's stamp before it is placed in time
  /// (PacketView::stamp_offset_ns: a looped replay's later passes).
  DecodeStatus decode(std::span<const std::uint8_t> bytes, std::int64_t receive_ns,
                      DecodedPacket& out, std::int64_t stamp_offset_ns = 0);

  /// Hour of the packet stamps from GPS: `top_of_hour_ns` is the UTC top of the hour the
  /// next data packet's stamp counts from; later hour wraps follow by continuity. Prefer
  /// set_gps_time_reference(), which also survives a wrap between the two packets.
  void set_gps_hour_reference(std::int64_t top_of_hour_ns);

  /// Takes the hour from a position packet when its $GPRMC is valid and PPS is locked (and
  /// `use_gps_hour`); returns whether it was used. Until then (or without GPS) each packet
  /// gets the hour of its receive time that puts it NEAREST to that receive time.
  bool set_gps_time_reference(const PositionPacket& position);

  /// What a position packet says about GPS (fix valid, PPS locked): decides
  /// DecodedPacket::time_source together with the references above. CaptureReader calls it
  /// for every position packet.
  void note_gps_status(const PositionPacket& position);

  [[nodiscard]] const DecoderCounters& counters() const { return counters_; }
  [[nodiscard]] const SensorModel& sensor_model(Model m) const;
  /// The same model, shared (frames keep it in FrameMeta::calibration).
  [[nodiscard]] const std::shared_ptr<const SensorModel>& calibration(Model m) const;
  /// The most recent of the human-readable warnings, each raised once (product byte
  /// mismatch, not a VLP-16); empty if none.
  [[nodiscard]] const std::string& last_warning() const { return last_warning_; }
  /// The code of last_warning() (product_mismatch, wrong_sensor); empty if none.
  [[nodiscard]] std::error_code last_warning_code() const {
    return warning_count_ == 0 ? std::error_code{} : make_error_code(last_warning_code_);
  }
  /// Number of distinct warnings raised so far: a caller sees a new warning when it grows.
  [[nodiscard]] int warning_count() const { return warning_count_; }

 private:
  struct Constants;  // per-model decode constants (column_decoding.hpp)
  enum class Family : std::uint8_t { unknown, vlp16, other };
  void judge_timing(std::uint32_t stamp_us);
  Model choose_model(std::uint8_t product_byte);
  std::int64_t gps_time_ns(std::int64_t stamp_ns);
  void warn_once(bool& raised, ErrorCode code, std::string message);

  DecoderConfig config_;
  std::shared_ptr<const SensorModel> vlp16_, hires_;
  std::unique_ptr<Constants> constants_;
  std::unique_ptr<driver_detail::TimeBase> time_base_;  // time_base.hpp
  DecoderCounters counters_;
  std::string last_warning_;
  ErrorCode last_warning_code_ = ErrorCode::product_mismatch;
  int warning_count_ = 0;
  bool warned_product_ = false;
  bool warned_not_vlp16_ = false;
  std::uint64_t packets_seen_ = 0;
  // Sensor family by packet spacing: a run of 3 consistent gaps decides.
  bool have_previous_stamp_ = false;
  std::uint32_t previous_stamp_us_ = 0;
  Family family_ = Family::unknown;
  Family run_family_ = Family::unknown;
  int run_length_ = 0;
  // Hour resolution from GPS (absent until a reference is given).
  bool gps_reference_ = false;
  bool gps_anchor_pending_ = false;  // only the hour is known: next packet anchors
  std::int64_t gps_top_of_hour_ns_ = 0;
  std::int64_t gps_anchor_ns_ = 0;  // a GPS-clock time near the current packets
  bool reference_changed_ = false;  // a GPS reference arrived since the last packet
  bool gps_fix_ = false;            // latest position packet: valid $GPRMC
  bool pps_locked_ = true;          // latest position packet: PPS locked (assumed until one)
};

}  // namespace vlpground
