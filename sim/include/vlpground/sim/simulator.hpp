// Ray-casting VLP-16 / Puck Hi-Res simulator: fires the sensor's true pattern and timing at a
// procedural scene while the sensor spins and drives along +x, and encodes genuine data and
// position packets with per-return ground truth.
//
// Thread-safety: a Simulator is immutable after construction; simulate_packet() is const and
// deterministic per packet index (its random stream depends only on seed and index), so
// packets may be simulated concurrently or out of order.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "vlpground/driver/sensor_model.hpp"
#include "vlpground/sim/packet_encoder.hpp"
#include "vlpground/sim/scene.hpp"
#include "vlpground/types.hpp"

namespace vlpground::sim {

/// 2023-11-14 22:00:01 UTC: the default capture start (one second past the hour).
inline constexpr std::int64_t kDefaultStartUtcNs = 1'699'999'201'000'000'000;
inline constexpr int kSlotsPerPacket = 384;  // 12 blocks x 32 channels
inline constexpr int kPositionEvery = 14;    // a position packet after every 14th data packet

/// Ground-truth label per return slot (the .labels format).
enum class Label : std::uint8_t { none = 0, ground = 1, obstacle = 2, low_obstacle = 3 };
/// Obstacle points closer than this to the terrain are labelled low_obstacle.
inline constexpr double kLowObstacleHeight_m = 0.15;

/// An echo's height above the terrain under it in whole centimetres (the .heights format):
/// rounded down, so an obstacle (>= 0.15 m) holds >= 15 and a low obstacle < 15; saturated
/// to the int16 range.
std::int16_t height_above_terrain_cm(double above_m);

struct SimConfig {
  SceneKind scene = SceneKind::urban;
  std::uint64_t seed = 1;
  int frames = 10;     // complete rotations after the first 0-degree crossing
  double rpm = 600.0;  // 300..1200
  ReturnMode mode = ReturnMode::strongest;
  Model model = Model::vlp16;
  std::int64_t start_utc_ns = kDefaultStartUtcNs;  // first firing of the first packet
  // Unset: drawn from the seed (height 1.7..2.0 m, speed depends on the scene, no tilt).
  std::optional<double> sensor_height_m;
  std::optional<double> speed_mps;
  // Mounting tilt, right-handed about x (forward) and y (left) as Extrinsics: roll > 0 lifts
  // the left side, pitch > 0 lowers the nose. STEM.json writes them as mount_roll_pitch_deg.
  double mount_roll_deg = 0.0;
  double mount_pitch_deg = 0.0;
  double range_noise_m = 0.015;  // 1-sigma Gaussian range noise
  double dropout_probability = 0.004;
  double max_range_m = 100.0;
  double min_range_m = 0.4;

  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

/// What the simulator knows about one return slot (block, channel).
struct SlotTruth {
  double range_m = 0.0;      // encoded range before 2 mm quantisation (noise included); 0: none
  double azimuth_deg = 0.0;  // true azimuth of the firing, [0, 360)
  std::int64_t time_ns = 0;  // true firing time (UTC ns)
  Vec3 sensor_point;         // the return in the sensor frame (x fwd, y left, z up, offset in z)
  Vec3 world_point;          // the hit point in the world frame
  Label label = Label::none;
  double above_terrain_m = 0.0;  // height of the hit above the terrain under it; 0: ground
};

struct SimulatedPacket {
  std::uint64_t index = 0;      // k-th data packet of the capture
  std::int64_t time_ns = 0;     // UTC time of the first firing of the first block
  std::int64_t capture_ns = 0;  // when it leaves the sensor (pcap record time)
  DataPacketFields fields;
  std::array<std::uint8_t, 1206> bytes{};
  std::array<std::uint8_t, kSlotsPerPacket> labels{};  // slot = block * 32 + channel
  // Height of each slot's echo above the terrain (cm, height_above_terrain_cm): 0 for
  // ground returns and empty slots. Written beside the labels as STEM.heights.
  std::array<std::int16_t, kSlotsPerPacket> heights_cm{};
  std::array<SlotTruth, kSlotsPerPacket> truth{};
};

struct SimulatedPositionPacket {
  std::int64_t capture_ns = 0;
  std::int64_t time_ns = 0;  // UTC time the stamp encodes
  std::array<std::uint8_t, 512> bytes{};
};

class Simulator {
 public:
  /// Validates `config` (throws std::invalid_argument) and builds the scene.
  explicit Simulator(const SimConfig& config);

  [[nodiscard]] const SimConfig& config() const { return config_; }
  [[nodiscard]] const Scene& scene() const { return scene_; }
  [[nodiscard]] const SensorModel& sensor() const { return sensor_; }
  [[nodiscard]] double sensor_height_m() const { return height_m_; }
  [[nodiscard]] double speed_mps() const { return speed_mps_; }
  [[nodiscard]] double start_azimuth_deg() const { return start_azimuth_deg_; }
  /// Data packets in the capture: enough for `frames` complete rotations after the first
  /// 0-degree crossing, plus one packet past the last crossing.
  [[nodiscard]] std::uint64_t packet_count() const { return packet_count_; }
  [[nodiscard]] std::int64_t packet_period_ns() const;

  /// Simulates data packet `index` (any order, deterministic).
  void simulate_packet(std::uint64_t index, SimulatedPacket& out) const;
  /// True if a position packet follows data packet `index`; fills `out`.
  bool position_after(std::uint64_t index, SimulatedPositionPacket& out) const;

  /// Azimuth (degrees, [0, 360)) of the spinning head at UTC time `t_ns`.
  [[nodiscard]] double azimuth_at(std::int64_t t_ns) const;
  /// Sensor origin in the world at `t_ns` (constant speed along x, following the terrain).
  [[nodiscard]] Vec3 sensor_position_at(std::int64_t t_ns) const;

 private:
  struct Echo;
  int cast_echoes(const Vec3& origin, const Vec3& dir, std::uint64_t ray_key,
                  Echo (&echoes)[2]) const;

  SimConfig config_;
  Scene scene_;
  SensorModel sensor_;
  double height_m_ = 1.8;
  double speed_mps_ = 0.0;
  double start_azimuth_deg_ = 0.0;
  std::uint64_t packet_count_ = 0;
  std::array<double, 9> mount_rotation_{};  // row-major sensor -> vehicle
};

/// Default position for position packets (somewhere in Munich), used in $GPRMC.
inline constexpr double kGpsLatitudeDeg = 48.1173;
inline constexpr double kGpsLongitudeDeg = 11.5167;

}  // namespace vlpground::sim
