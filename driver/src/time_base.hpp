// Places packet stamps (microseconds past the sensor's hour) on an absolute time line, so
// that frame stamps are continuous from the first packet (private to the driver).
//
// Host regime (no GPS reference): the first packet takes the hour nearest to its receive
// time. When the sensor clock then agrees with the host clock within 1 s it is trusted as
// is (a PPS-disciplined clock: stamps keep their microseconds). Otherwise it free-runs (no
// GPS: it counts from power-on) and is BLENDED onto the host clock: time = sensor time +
// a correction that starts at the receive-time offset and follows the host clock at most
// 1 us per packet (0.075 %, enough for crystal drift), so steps between packets stay the
// sensor's. Later packets continue the previous packet's hour (never re-decided from a
// jittery receive time); only a disagreement of half an hour (host clock stepped, sensor
// restarted) re-anchors.
//
// GPS regime (a GPS reference from the decoder): the GPS time of the stamp. When it takes
// over, a difference under 1 s from the continued time is slewed out at most 10 us per
// packet (stamps stay continuous); a larger one (host clock wrong by hours, or years) is one
// step, reported as `rebase_ns` so the assembler moves the frame in progress instead of
// splitting it.
//
// Thread-safety: one per decoder.
#pragma once

#include <cstdint>

namespace vlpground::driver_detail {

class TimeBase {
 public:
  struct Placed {
    std::int64_t time_ns = 0;
    std::int64_t rebase_ns = 0;  // nonzero once, when a new GPS reference steps the time
  };

  static constexpr std::int64_t kSyncedToleranceNs = 1'000'000'000;  // host vs sensor clock
  static constexpr std::int64_t kHostSlewNs = 1'000;                 // per packet
  static constexpr std::int64_t kGpsSlewableNs = 1'000'000'000;      // smaller: slewed
  static constexpr std::int64_t kGpsSlewNs = 10'000;                 // per packet

  /// A packet without GPS reference, stamped `stamp_ns` past the hour, received at
  /// `receive_ns` (host clock, ns since the epoch).
  Placed on_host(std::int64_t stamp_ns, std::int64_t receive_ns);
  /// A packet whose GPS time is `gps_time_ns`; `reference_changed` when a new GPS
  /// reference arrived since the previous packet.
  Placed on_gps(std::int64_t stamp_ns, std::int64_t gps_time_ns, bool reference_changed);

  /// The correction added to the sensor's time now (blend or GPS slew), for tests.
  [[nodiscard]] std::int64_t correction_ns() const { return correction_ns_; }
  [[nodiscard]] bool blending() const { return blend_; }

 private:
  Placed anchor(std::int64_t stamp_ns, std::int64_t receive_ns);

  bool have_ = false;
  bool blend_ = false;              // host regime: the sensor clock is not on the host clock
  std::int64_t last_base_ns_ = 0;   // the previous packet's hour + stamp
  std::int64_t correction_ns_ = 0;  // added to the base
};

/// The time `stamp_ns` past some top of the hour that lies nearest to `reference_ns`.
std::int64_t nearest_hour_time(std::int64_t stamp_ns, std::int64_t reference_ns);

}  // namespace vlpground::driver_detail
