#include "time_base.hpp"

#include <algorithm>
#include <cstdlib>

namespace vlpground::driver_detail {
namespace {

constexpr std::int64_t kHourNs = 3'600'000'000'000;

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

std::int64_t toward(std::int64_t value, std::int64_t target, std::int64_t step) {
  return value + std::clamp(target - value, -step, step);
}

}  // namespace

std::int64_t nearest_hour_time(std::int64_t stamp_ns, std::int64_t reference_ns) {
  return stamp_ns + floor_div(reference_ns - stamp_ns + kHourNs / 2, kHourNs) * kHourNs;
}

TimeBase::Placed TimeBase::anchor(std::int64_t stamp_ns, std::int64_t receive_ns) {
  const std::int64_t base = nearest_hour_time(stamp_ns, receive_ns);
  const std::int64_t offset = receive_ns - base;  // within half an hour
  blend_ = std::llabs(offset) > kSyncedToleranceNs;
  correction_ns_ = blend_ ? offset : 0;
  have_ = true;
  last_base_ns_ = base;
  return {base + correction_ns_, 0};
}

TimeBase::Placed TimeBase::on_host(std::int64_t stamp_ns, std::int64_t receive_ns) {
  if (!have_) return anchor(stamp_ns, receive_ns);
  const std::int64_t base = nearest_hour_time(stamp_ns, last_base_ns_);  // the sensor's hour
  const std::int64_t error = receive_ns - (base + correction_ns_);
  if (std::llabs(error) > kHourNs / 2) return anchor(stamp_ns, receive_ns);
  if (blend_) correction_ns_ = toward(correction_ns_, correction_ns_ + error, kHostSlewNs);
  last_base_ns_ = base;
  return {base + correction_ns_, 0};
}

TimeBase::Placed TimeBase::on_gps(std::int64_t stamp_ns, std::int64_t gps_time_ns,
                                  bool reference_changed) {
  Placed placed;
  if (have_ && reference_changed) {
    const std::int64_t continued = nearest_hour_time(stamp_ns, last_base_ns_) + correction_ns_;
    const std::int64_t difference = gps_time_ns - continued;
    if (std::llabs(difference) < kGpsSlewableNs) {
      correction_ns_ = -difference;  // continue where the stamps were; slewed out below
    } else {
      correction_ns_ = 0;
      placed.rebase_ns = difference;
    }
  } else if (!have_) {
    correction_ns_ = 0;
  } else {
    correction_ns_ = toward(correction_ns_, 0, kGpsSlewNs);
  }
  have_ = true;
  blend_ = false;
  last_base_ns_ = gps_time_ns;
  placed.time_ns = gps_time_ns + correction_ns_;
  return placed;
}

}  // namespace vlpground::driver_detail
