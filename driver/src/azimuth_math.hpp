// Small azimuth helpers for the assembler (degrees, clockwise as the sensor reports them).
#pragma once

#include <cmath>

namespace vlpground::driver_detail {

/// `deg` wrapped into [0, 360).
inline double wrap_deg(double deg) {
  double w = std::fmod(deg, 360.0);
  if (w < 0.0) w += 360.0;
  return w >= 360.0 ? 0.0 : w;
}

/// Forward (clockwise) advance from `from` to `to`, in [0, 360). Called per firing: the
/// usual inputs (both in [0, 360)) avoid fmod.
inline double forward_deg(double from, double to) {
  const double d = to - from;
  if (d >= 0.0 && d < 360.0) return d;
  if (d < 0.0 && d >= -360.0) return d + 360.0 >= 360.0 ? 0.0 : d + 360.0;
  return wrap_deg(d);
}

/// Smallest angle between two azimuths, in [0, 180].
inline double distance_deg(double a, double b) {
  const double d = forward_deg(a, b);
  return d > 180.0 ? 360.0 - d : d;
}

}  // namespace vlpground::driver_detail
