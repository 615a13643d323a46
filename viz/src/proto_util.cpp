#include "proto_util.hpp"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>

#include <Eigen/Geometry>
#include <cmath>
#include <set>

namespace vlpground::viz::detail {

std::span<const std::byte> serialize(const google::protobuf::Message& message,
                                     std::vector<std::byte>& buffer) {
  const std::size_t size = message.ByteSizeLong();
  buffer.resize(size);
  auto* begin = reinterpret_cast<std::uint8_t*>(buffer.data());
  message.SerializeWithCachedSizesToArray(begin);
  return {buffer.data(), size};
}

void set_time(google::protobuf::Timestamp& stamp, std::int64_t time_ns) {
  constexpr std::int64_t kNsPerS = 1'000'000'000;
  std::int64_t seconds = time_ns / kNsPerS;
  std::int64_t nanos = time_ns % kNsPerS;
  if (nanos < 0) {
    nanos += kNsPerS;
    --seconds;
  }
  stamp.set_seconds(seconds);
  stamp.set_nanos(static_cast<std::int32_t>(nanos));
}

void set_pose(foxglove::Pose& pose, const Extrinsics& e) {
  constexpr double kDegToRad = M_PI / 180.0;
  const Eigen::Quaterniond q = Eigen::AngleAxisd(e.yaw_deg * kDegToRad, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(e.pitch_deg * kDegToRad, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(e.roll_deg * kDegToRad, Eigen::Vector3d::UnitX());
  auto* p = pose.mutable_position();
  p->set_x(e.x_m);
  p->set_y(e.y_m);
  p->set_z(e.z_m);
  auto* o = pose.mutable_orientation();
  o->set_x(q.x());
  o->set_y(q.y());
  o->set_z(q.z());
  o->set_w(q.w());
}

void set_identity(foxglove::Pose& pose) { set_pose(pose, Extrinsics{}); }

void set_color(foxglove::Color& color, double r, double g, double b, double a) {
  color.set_r(r);
  color.set_g(g);
  color.set_b(b);
  color.set_a(a);
}

namespace {

void add_file(const google::protobuf::FileDescriptor* file, std::set<std::string>& added,
              google::protobuf::FileDescriptorSet& set) {
  if (!added.insert(file->name()).second) return;
  for (int i = 0; i < file->dependency_count(); ++i) add_file(file->dependency(i), added, set);
  file->CopyTo(set.add_file());
}

}  // namespace

std::string file_descriptor_set(const google::protobuf::Descriptor* descriptor) {
  google::protobuf::FileDescriptorSet set;
  std::set<std::string> added;
  add_file(descriptor->file(), added, set);
  return set.SerializeAsString();
}

}  // namespace vlpground::viz::detail
