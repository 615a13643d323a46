// Firing pattern, timing, sensor motion, noise and return selection of the simulator.
#include "vlpground/sim/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>

#include "random.hpp"

namespace vlpground::sim {
namespace {

using detail::Rng;
using Mat3 = std::array<double, 9>;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr std::int64_t kHourNs = 3'600'000'000'000;
constexpr std::int64_t kWireDelayNs = 30'000;  // packet leaves ~30 us after its last firing
constexpr double kPartialEchoChance = 0.6;
constexpr double kMetersPerSecondToKnots = 1.943844;

Mat3 multiply(const Mat3& a, const Mat3& b) {
  Mat3 r{};
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      double s = 0.0;
      for (std::size_t k = 0; k < 3; ++k) s += a[3 * i + k] * b[3 * k + j];
      r[3 * i + j] = s;
    }
  }
  return r;
}

Vec3 apply(const Mat3& m, const Vec3& v) {
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
          m[6] * v.x + m[7] * v.y + m[8] * v.z};
}

// R = Ry(pitch) Rx(roll), right-handed about x (forward) and y (left), as the detector's
// Extrinsics: roll > 0 lifts the left side, pitch > 0 lowers the nose.
Mat3 roll_pitch(double roll_rad, double pitch_rad) {
  const double cr = std::cos(roll_rad), sr = std::sin(roll_rad);
  const double cp = std::cos(pitch_rad), sp = std::sin(pitch_rad);
  const Mat3 rx{1, 0, 0, 0, cr, -sr, 0, sr, cr};
  const Mat3 ry{cp, 0, sp, 0, 1, 0, -sp, 0, cp};
  return multiply(ry, rx);
}

double default_speed(SceneKind kind, Rng& rng) {
  switch (kind) {
    case SceneKind::jam:
      return rng.uniform(0.0, 0.8);
    case SceneKind::hills:
      return rng.uniform(1.0, 5.0);
    case SceneKind::slope:
    case SceneKind::fences:
      return rng.uniform(2.0, 8.0);
    default:
      return rng.uniform(2.0, 10.0);
  }
}

std::uint16_t quantise_azimuth(double deg) {
  auto c = static_cast<long>(std::lround(deg * 100.0)) % 36000;
  if (c < 0) c += 36000;
  return static_cast<std::uint16_t>(c);
}

}  // namespace

struct Simulator::Echo {
  double range_m = 0.0;
  double intensity = 0.0;
  Vec3 world;
  Label label = Label::none;
  double above_terrain_m = 0.0;  // obstacles only; ground echoes are on the terrain
};

std::int16_t height_above_terrain_cm(double above_m) {
  const double cm = std::floor(above_m * 100.0);
  if (std::isnan(cm)) return 0;
  constexpr double lowest = std::numeric_limits<std::int16_t>::min();
  constexpr double highest = std::numeric_limits<std::int16_t>::max();
  return static_cast<std::int16_t>(std::clamp(cm, lowest, highest));
}

void SimConfig::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("sim config: " + what); };
  if (frames < 1 || frames > 10000) fail("frames must be in 1..10000");
  if (!(rpm >= 300.0 && rpm <= 1200.0)) fail("rpm must be in 300..1200");
  if (sensor_height_m && !(*sensor_height_m > 0.2 && *sensor_height_m < 10.0))
    fail("sensor_height_m must be in (0.2, 10)");
  if (speed_mps && !(*speed_mps >= 0.0 && *speed_mps <= 40.0)) fail("speed_mps must be in 0..40");
  if (!(std::fabs(mount_roll_deg) <= 30.0 && std::fabs(mount_pitch_deg) <= 30.0))
    fail("mount roll/pitch must be within +-30 deg");
  if (!(range_noise_m >= 0.0 && range_noise_m <= 1.0)) fail("range_noise_m must be in 0..1");
  if (!(dropout_probability >= 0.0 && dropout_probability <= 1.0))
    fail("dropout_probability must be in 0..1");
  if (!(max_range_m > min_range_m && max_range_m <= 130.0 && min_range_m >= 0.0))
    fail("need 0 <= min_range_m < max_range_m <= 130");
  if (start_utc_ns < 0) fail("start_utc_ns must be >= 0");
}

Simulator::Simulator(const SimConfig& config)
    : config_((config.validate(), config)),
      scene_(Scene::generate(config.scene, config.seed)),
      sensor_(SensorModel::builtin(config.model)) {
  Rng rng(config.seed, 0x9053u);
  const double drawn_height = rng.uniform(1.7, 2.0);
  const double drawn_speed = default_speed(config.scene, rng);
  start_azimuth_deg_ = rng.uniform(0.0, 360.0);
  height_m_ = config.sensor_height_m.value_or(drawn_height);
  speed_mps_ = config.speed_mps.value_or(drawn_speed);
  mount_rotation_ = roll_pitch(config.mount_roll_deg * kDeg, config.mount_pitch_deg * kDeg);

  const double sequences_per_rev = 60e9 / config.rpm / static_cast<double>(kSequencePeriodNs);
  const double sequences =
      (360.0 - start_azimuth_deg_) / 360.0 * sequences_per_rev + config.frames * sequences_per_rev;
  const double per_packet = config.mode == ReturnMode::dual ? 12.0 : 24.0;
  packet_count_ = static_cast<std::uint64_t>(std::ceil(sequences / per_packet)) + 1;
}

std::int64_t Simulator::packet_period_ns() const {
  return config_.mode == ReturnMode::dual ? kDualPacketPeriodNs : kSinglePacketPeriodNs;
}

double Simulator::azimuth_at(std::int64_t t_ns) const {
  const double deg_per_ns = config_.rpm * 6.0 / 1e9;
  const double a = std::fmod(
      start_azimuth_deg_ + deg_per_ns * static_cast<double>(t_ns - config_.start_utc_ns), 360.0);
  return a < 0.0 ? a + 360.0 : a;
}

Vec3 Simulator::sensor_position_at(std::int64_t t_ns) const {
  const double x = speed_mps_ * static_cast<double>(t_ns - config_.start_utc_ns) * 1e-9;
  return {x, 0.0, scene_.terrain().height(x, 0.0) + height_m_};
}

int Simulator::cast_echoes(const Vec3& origin, const Vec3& dir, std::uint64_t ray_key,
                           Echo (&echoes)[2]) const {
  Rng rng(config_.seed, ray_key);
  if (rng.chance(config_.dropout_probability)) return 0;
  const Terrain& terrain = scene_.terrain();
  int count = 0;
  Vec3 from = origin;
  double travelled = 0.0;
  int skip = -1;
  for (int hop = 0; hop < 4; ++hop) {
    const auto hit = scene_.cast(from, dir, config_.max_range_m - travelled, skip);
    if (!hit) break;
    const double t = travelled + hit->t_m;
    Echo e;
    e.world = {origin.x + t * dir.x, origin.y + t * dir.y, origin.z + t * dir.z};
    e.range_m = t;
    bool partial = false;
    if (hit->object < 0) {
      e.label = Label::ground;
      e.intensity = terrain.reflectivity(e.world.x, e.world.y);
    } else {
      const Obstacle& o = scene_.obstacles()[static_cast<std::size_t>(hit->object)];
      const double above = e.world.z - terrain.height(e.world.x, e.world.y);
      e.label = above < kLowObstacleHeight_m ? Label::low_obstacle : Label::obstacle;
      e.above_terrain_m = above;
      e.intensity = o.reflectivity;
      if (o.transparency > 0.f && rng.chance(o.transparency)) {
        // The beam partly passes: maybe a weak first echo, then the surface behind.
        partial = true;
        e.intensity *= 0.35;
        if (count == 0 && rng.chance(kPartialEchoChance)) echoes[count++] = e;
        from = e.world;
        travelled = t;
        skip = hit->object;
      }
    }
    if (!partial) {
      if (count == 1) e.intensity *= 0.7;  // attenuated by what it passed through
      echoes[count++] = e;
      break;
    }
  }
  // Out of range echoes vanish.
  int kept = 0;
  for (int i = 0; i < count; ++i) {
    if (echoes[i].range_m >= config_.min_range_m) echoes[kept++] = echoes[i];
  }
  for (int i = 0; i < kept; ++i) {
    echoes[i].range_m += config_.range_noise_m * rng.normal();
    echoes[i].intensity = std::clamp(echoes[i].intensity + 3.0 * rng.normal(), 1.0, 255.0);
  }
  return kept;
}

void Simulator::simulate_packet(std::uint64_t index, SimulatedPacket& out) const {
  const bool dual = config_.mode == ReturnMode::dual;
  const std::int64_t period = packet_period_ns();
  const std::int64_t t0 = config_.start_utc_ns + static_cast<std::int64_t>(index) * period;
  out.index = index;
  out.time_ns = t0;
  out.capture_ns = t0 + period + kWireDelayNs;
  DataPacketFields& f = out.fields;
  f.stamp_us_past_hour = static_cast<std::uint32_t>((t0 % kHourNs) / 1000);
  f.return_mode =
      dual ? kModeDual : (config_.mode == ReturnMode::last ? kModeLast : kModeStrongest);
  f.product = config_.model == Model::hires ? kProductHiRes : kProductVlp16;
  const Terrain& terrain = scene_.terrain();
  const int sequences = dual ? 12 : 24;
  for (int s = 0; s < sequences; ++s) {
    const std::int64_t t_seq = t0 + s * kSequencePeriodNs;
    // Vehicle attitude from the terrain under it (wheelbase ~3 m, track ~1.6 m).
    const Vec3 base = sensor_position_at(t_seq);
    // Terrain rising ahead lifts the nose: a negative pitch (right-handed about y).
    const double pitch =
        -std::atan2(terrain.height(base.x + 1.5, 0.0) - terrain.height(base.x - 1.5, 0.0), 3.0);
    const double roll = std::atan2(terrain.height(base.x, 0.8) - terrain.height(base.x, -0.8), 1.6);
    const Mat3 rotation = multiply(roll_pitch(roll, pitch), mount_rotation_);
    const Vec3 ground{base.x, 0.0, base.z - height_m_};
    const Vec3 mast = apply(roll_pitch(roll, pitch), Vec3{0.0, 0.0, height_m_});
    // Block(s) and channel half of this sequence.
    const int block = dual ? 2 * (s / 2) : s / 2;
    const int half = s % 2;
    if (half == 0) {
      f.azimuth_centideg[static_cast<std::size_t>(block)] = quantise_azimuth(azimuth_at(t_seq));
      if (dual)
        f.azimuth_centideg[static_cast<std::size_t>(block + 1)] =
            f.azimuth_centideg[static_cast<std::size_t>(block)];
    }
    for (int k = 0; k < kLasers; ++k) {
      const std::int64_t t_fire = t_seq + k * kFiringIntervalNs;
      const LaserGeometry& laser = sensor_.lasers[static_cast<std::size_t>(k)];
      const double az_deg = azimuth_at(t_fire);
      const double alpha = (az_deg + laser.azimuth_offset_deg) * kDeg;
      const Vec3 dir_sensor{laser.cos_elevation * std::cos(alpha),
                            -laser.cos_elevation * std::sin(alpha), laser.sin_elevation};
      const double moved = speed_mps_ * static_cast<double>(t_fire - t_seq) * 1e-9;
      const Vec3 offset = apply(rotation, Vec3{0.0, 0.0, laser.vertical_offset_m});
      const Vec3 origin{ground.x + mast.x + offset.x + moved, ground.y + mast.y + offset.y,
                        ground.z + mast.z + offset.z};
      const Vec3 dir = apply(rotation, dir_sensor);
      Echo echoes[2];
      // Keyed by the global firing, so every mode sees the same noise for the same ray.
      const auto ray_key =
          (index * static_cast<std::uint64_t>(sequences) + static_cast<std::uint64_t>(s)) * 16 +
          static_cast<std::uint64_t>(k);
      const int n = cast_echoes(origin, dir, ray_key, echoes);
      // Which echo each block of this firing reports.
      const int strongest = n == 2 && echoes[1].intensity > echoes[0].intensity ? 1 : 0;
      const int channel = half * 16 + k;
      const int blocks_here = dual ? 2 : 1;
      for (int j = 0; j < blocks_here; ++j) {
        // Dual: the even block holds the last echo, the odd one the strongest, or the
        // second strongest when the strongest is the last: with two echoes, the first.
        int pick = strongest;
        if (config_.mode == ReturnMode::last || (dual && j == 0)) pick = n - 1;
        if (dual && j == 1) pick = 0;
        const auto slot = static_cast<std::size_t>((block + j) * 32 + channel);
        const auto b = static_cast<std::size_t>(block + j);
        const auto c = static_cast<std::size_t>(channel);
        SlotTruth& truth = out.truth[slot];
        truth = SlotTruth{};
        truth.azimuth_deg = az_deg;
        truth.time_ns = t_fire;
        const long d2mm = n > 0 ? std::lround(echoes[pick].range_m / 0.002) : 0;
        if (n == 0 || d2mm <= 0 || d2mm > 65535 || echoes[pick].range_m > config_.max_range_m) {
          f.distance_2mm[b][c] = 0;
          f.reflectivity[b][c] = 0;
          out.labels[slot] = 0;
          out.heights_cm[slot] = 0;
          continue;
        }
        const Echo& e = echoes[pick];
        f.distance_2mm[b][c] = static_cast<std::uint16_t>(d2mm);
        f.reflectivity[b][c] = static_cast<std::uint8_t>(std::lround(e.intensity));
        truth.range_m = e.range_m;
        truth.world_point = e.world;
        truth.sensor_point = {e.range_m * dir_sensor.x, e.range_m * dir_sensor.y,
                              e.range_m * dir_sensor.z + laser.vertical_offset_m};
        truth.label = e.label;
        truth.above_terrain_m = e.above_terrain_m;
        out.labels[slot] = static_cast<std::uint8_t>(e.label);
        out.heights_cm[slot] = height_above_terrain_cm(e.above_terrain_m);
      }
    }
  }
  encode_data_packet(f, std::span<std::uint8_t, 1206>(out.bytes));
}

bool Simulator::position_after(std::uint64_t index, SimulatedPositionPacket& out) const {
  if ((index + 1) % kPositionEvery != 0) return false;
  const std::int64_t t0 =
      config_.start_utc_ns + static_cast<std::int64_t>(index) * packet_period_ns();
  out.time_ns = t0 + packet_period_ns() + kWireDelayNs + 10'000;
  out.capture_ns = out.time_ns + 10'000;
  const auto stamp = static_cast<std::uint32_t>((out.time_ns % kHourNs) / 1000);
  // $GPRMC reports the second of the last PPS edge.
  const std::int64_t pps_ns = out.time_ns - out.time_ns % 1'000'000'000;
  const std::string nmea = make_gprmc(pps_ns, true, kGpsLatitudeDeg, kGpsLongitudeDeg,
                                      speed_mps_ * kMetersPerSecondToKnots, 90.0);
  encode_position_packet(stamp, PpsStatus::locked, nmea, std::span<std::uint8_t, 512>(out.bytes));
  return true;
}

}  // namespace vlpground::sim
