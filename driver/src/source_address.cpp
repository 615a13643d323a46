#include <arpa/inet.h>

#include <array>
#include <string>

#include "vlpground/driver/packet_source.hpp"

namespace vlpground {

std::string SourceAddress::to_string() const {
  if (version != 4 && version != 6) return "unknown";
  std::array<char, INET6_ADDRSTRLEN> text{};
  const int family = version == 4 ? AF_INET : AF_INET6;
  if (::inet_ntop(family, bytes.data(), text.data(), text.size()) == nullptr) return "unknown";
  std::string out;
  if (version == 6) out += '[';
  out += text.data();
  if (version == 6) out += ']';
  if (port != 0) {
    out += ':';
    out += std::to_string(port);
  }
  return out;
}

}  // namespace vlpground
