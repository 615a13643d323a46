#include "ws_protocol.hpp"

#include <boost/beast/core/detail/base64.hpp>
#include <bit>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>

namespace vlpground::viz::detail {
namespace {

using nlohmann::json;

std::string base64(const std::string& bytes) {
  namespace b64 = boost::beast::detail::base64;
  std::string out(b64::encoded_size(bytes.size()), '\0');
  out.resize(b64::encode(out.data(), bytes.data(), bytes.size()));
  return out;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

template <typename T>
bool get_unsigned(const json& j, const char* key, T& out) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_number_unsigned()) return false;
  const auto v = it->get<std::uint64_t>();
  if (v > std::numeric_limits<T>::max()) return false;
  out = static_cast<T>(v);
  return true;
}

ClientRequest parse_subscribe(const json& j) {
  const auto it = j.find("subscriptions");
  if (it == j.end() || !it->is_array()) return Garbage{"subscribe without a subscriptions array"};
  Subscribe s;
  for (const json& sub : *it) {
    std::uint32_t id = 0;
    std::uint64_t channel = 0;
    if (!sub.is_object() || !get_unsigned(sub, "id", id) || !get_unsigned(sub, "channelId", channel)) {
      return Garbage{"subscribe entry without unsigned id and channelId"};
    }
    s.subscriptions.emplace_back(id, channel);
  }
  return s;
}

ClientRequest parse_unsubscribe(const json& j) {
  const auto it = j.find("subscriptionIds");
  if (it == j.end() || !it->is_array()) return Garbage{"unsubscribe without subscriptionIds"};
  Unsubscribe u;
  for (const json& id : *it) {
    if (!id.is_number_unsigned() || id.get<std::uint64_t>() > 0xFFFFFFFFu) {
      return Garbage{"unsubscribe with a bad subscription id"};
    }
    u.subscription_ids.push_back(id.get<std::uint32_t>());
  }
  return u;
}

}  // namespace

std::string choose_subprotocol(std::string_view requested) {
  while (!requested.empty()) {
    const auto comma = requested.find(',');
    const std::string_view token = trim(requested.substr(0, comma));
    for (const std::string_view known : kSubprotocols) {
      if (token == known) return std::string(known);
    }
    if (comma == std::string_view::npos) break;
    requested.remove_prefix(comma + 1);
  }
  return {};
}

std::string server_info_json(const std::string& name, const std::string& session_id) {
  return json{{"op", "serverInfo"},
              {"name", name},
              {"capabilities", json::array()},
              {"supportedEncodings", json::array()},
              {"metadata", json::object()},
              {"sessionId", session_id}}
      .dump();
}

std::string advertise_json(const std::vector<ChannelSpec>& channels, std::size_t first_id) {
  json list = json::array();
  for (std::size_t i = 0; i < channels.size(); ++i) {
    const ChannelSpec& c = channels[i];
    // Binary schemas (protobuf FileDescriptorSet) travel base64-encoded, text schemas as is.
    const bool binary_schema = c.schema_encoding == "protobuf" || c.schema_encoding == "flatbuffer";
    list.push_back({{"id", first_id + i},
                    {"topic", c.topic},
                    {"encoding", c.message_encoding},
                    {"schemaName", c.schema_name},
                    {"schema", binary_schema ? base64(c.schema) : c.schema},
                    {"schemaEncoding", c.schema_encoding}});
  }
  return json{{"op", "advertise"}, {"channels", std::move(list)}}.dump();
}

std::string status_json(StatusLevel level, const std::string& message) {
  return json{{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}}.dump();
}

std::array<std::uint8_t, kDataHeaderBytes> data_header(std::uint32_t subscription_id,
                                                       std::int64_t log_time_ns) {
  std::array<std::uint8_t, kDataHeaderBytes> h{};
  h[0] = 0x01;
  static_assert(std::endian::native == std::endian::little, "the header is little-endian");
  const auto t = static_cast<std::uint64_t>(log_time_ns);
  std::memcpy(h.data() + 1, &subscription_id, sizeof subscription_id);
  std::memcpy(h.data() + 5, &t, sizeof t);
  return h;
}

ClientRequest parse_client_text(std::string_view text) {
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded()) return Garbage{"not JSON"};
  if (!j.is_object()) return Garbage{"not a JSON object"};
  const auto op = j.find("op");
  if (op == j.end() || !op->is_string()) return Garbage{"no \"op\""};
  const auto& name = op->get_ref<const std::string&>();
  if (name == "subscribe") return parse_subscribe(j);
  if (name == "unsubscribe") return parse_unsubscribe(j);
  return Unsupported{name};
}

}  // namespace vlpground::viz::detail
