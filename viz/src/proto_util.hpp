// Small helpers shared by the protobuf encoders (private to vlpground::viz).
#pragma once

#include <google/protobuf/message.h>
#include <google/protobuf/timestamp.pb.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "foxglove/Color.pb.h"
#include "foxglove/Pose.pb.h"
#include "vlpground/detector/ground_detector.hpp"

namespace vlpground::viz::detail {

/// Serialises `message` into `buffer` (capacity reused) and returns the bytes.
std::span<const std::byte> serialize(const google::protobuf::Message& message,
                                     std::vector<std::byte>& buffer);

/// Sets a google.protobuf.Timestamp from ns since the epoch (nanos always in [0, 1e9)).
void set_time(google::protobuf::Timestamp& stamp, std::int64_t time_ns);

/// The pose of the sensor in the vehicle frame: translation and the rotation
/// Rz(yaw) * Ry(pitch) * Rx(roll), as the detector applies it.
void set_pose(foxglove::Pose& pose, const Extrinsics& extrinsics);
void set_identity(foxglove::Pose& pose);

void set_color(foxglove::Color& color, double r, double g, double b, double a);

/// A FileDescriptorSet holding the file of `descriptor` and every file it imports
/// (dependencies first): the schema data of a protobuf channel in Foxglove and MCAP.
std::string file_descriptor_set(const google::protobuf::Descriptor* descriptor);

}  // namespace vlpground::viz::detail
