// Decodes protobuf messages with nothing but a channel's schema (its FileDescriptorSet),
// as Foxglove and MCAP readers do; reads fields by name through reflection.
#pragma once

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/dynamic_message.h>

#include <cstddef>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>

#include "vlpground/viz/channels.hpp"

namespace vlpground::test {

class SchemaDecoder {
 public:
  explicit SchemaDecoder(const viz::ChannelSpec& channel) {
    google::protobuf::FileDescriptorSet set;
    if (!set.ParseFromString(channel.schema)) throw std::runtime_error("bad FileDescriptorSet");
    for (const auto& file : set.file()) {
      if (pool_.BuildFile(file) == nullptr) throw std::runtime_error("cannot build " + file.name());
    }
    type_ = pool_.FindMessageTypeByName(channel.schema_name);
    if (type_ == nullptr) throw std::runtime_error("no type " + channel.schema_name);
  }

  [[nodiscard]] std::unique_ptr<google::protobuf::Message> decode(
      std::span<const std::byte> bytes) {
    std::unique_ptr<google::protobuf::Message> m(factory_.GetPrototype(type_)->New());
    if (!m->ParseFromArray(bytes.data(), static_cast<int>(bytes.size()))) {
      throw std::runtime_error("cannot parse " + type_->full_name());
    }
    return m;
  }

 private:
  google::protobuf::DescriptorPool pool_;
  google::protobuf::DynamicMessageFactory factory_;
  const google::protobuf::Descriptor* type_ = nullptr;
};

// Reflection helpers: fields by name.
inline const google::protobuf::FieldDescriptor* field(const google::protobuf::Message& m,
                                                      const std::string& name) {
  const auto* f = m.GetDescriptor()->FindFieldByName(name);
  if (f == nullptr) throw std::runtime_error("no field " + name);
  return f;
}
inline const google::protobuf::Message& sub(const google::protobuf::Message& m,
                                            const std::string& name) {
  return m.GetReflection()->GetMessage(m, field(m, name));
}
inline const google::protobuf::Message& at(const google::protobuf::Message& m,
                                           const std::string& name, int i) {
  return m.GetReflection()->GetRepeatedMessage(m, field(m, name), i);
}
inline int count(const google::protobuf::Message& m, const std::string& name) {
  return m.GetReflection()->FieldSize(m, field(m, name));
}
inline std::string text(const google::protobuf::Message& m, const std::string& name) {
  return m.GetReflection()->GetString(m, field(m, name));
}
inline double real(const google::protobuf::Message& m, const std::string& name) {
  return m.GetReflection()->GetDouble(m, field(m, name));
}
inline std::uint32_t u32(const google::protobuf::Message& m, const std::string& name) {
  return m.GetReflection()->GetUInt32(m, field(m, name));
}

}  // namespace vlpground::test
