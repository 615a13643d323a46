#include "capture_builder.hpp"

#include <fstream>
#include <stdexcept>

namespace vlpground::test {
namespace {

void put_be16(Bytes& b, std::size_t at, std::uint32_t v) {
  b[at] = static_cast<std::uint8_t>(v >> 8);
  b[at + 1] = static_cast<std::uint8_t>(v);
}

void append_be16(Bytes& b, std::uint32_t v) {
  b.push_back(static_cast<std::uint8_t>(v >> 8));
  b.push_back(static_cast<std::uint8_t>(v));
}

void append_le16(Bytes& b, std::uint32_t v) {
  b.push_back(static_cast<std::uint8_t>(v));
  b.push_back(static_cast<std::uint8_t>(v >> 8));
}

void append_le32(Bytes& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

// push_back, not insert: GCC 12 reports a false -Warray-bounds on vector::insert here.
void append(Bytes& b, const Bytes& more) {
  b.reserve(b.size() + more.size());
  for (const std::uint8_t v : more) b.push_back(v);
}

Bytes udp_header_and_payload(const Bytes& payload, std::uint16_t destination_port) {
  Bytes udp;
  append_be16(udp, 51000);  // source port
  append_be16(udp, destination_port);
  append_be16(udp, static_cast<std::uint32_t>(payload.size() + 8));
  append_be16(udp, 0);  // checksum (not verified by anyone)
  append(udp, payload);
  return udp;
}

std::uint16_t ethertype_of(const Bytes& ip) { return (ip.at(0) >> 4) == 6 ? 0x86DD : 0x0800; }

void write_file(const std::filesystem::path& path, const Bytes& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  if (!file) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace

Bytes pattern_payload(std::size_t size, std::uint8_t seed) {
  Bytes bytes(size);
  for (std::size_t i = 0; i < size; ++i) bytes[i] = static_cast<std::uint8_t>(seed * 31u + i * 7u);
  return bytes;
}

Bytes udp_ipv4(const Bytes& payload, std::uint16_t destination_port, const Ipv4Spec& spec) {
  const std::size_t header = 20 + spec.option_bytes;
  Bytes ip(header, 0);
  ip[0] = static_cast<std::uint8_t>(0x40 | (header / 4));
  const Bytes udp = udp_header_and_payload(payload, destination_port);
  put_be16(ip, 2, static_cast<std::uint32_t>(header + udp.size()));
  put_be16(ip, 6, (spec.more_fragments ? 0x2000u : 0u) | spec.fragment_offset);
  ip[8] = 64;  // TTL
  ip[9] = spec.protocol;
  for (std::size_t i = 0; i < 4; ++i) ip[12 + i] = spec.source[i];
  const std::uint8_t destination[4] = {255, 255, 255, 255};
  for (std::size_t i = 0; i < 4; ++i) ip[16 + i] = destination[i];
  for (std::size_t i = 20; i < header; ++i) ip[i] = 1;  // NOP options
  append(ip, udp);
  return ip;
}

Bytes udp_ipv6(const Bytes& payload, std::uint16_t destination_port, const Ipv6Spec& spec) {
  Bytes chain;  // extension headers, each naming the next one
  for (std::size_t i = 0; i < spec.extensions.size(); ++i) {
    const std::uint8_t next = i + 1 < spec.extensions.size() ? spec.extensions[i + 1] : 17;
    const std::uint8_t code = spec.extensions[i];
    if (code == 51) {  // AH: 12 bytes fixed + 4 ICV = 16 bytes, length field (16/4)-2 = 2
      Bytes ah(16, 0);
      ah[0] = next;
      ah[1] = 2;
      append(chain, ah);
    } else {  // 16 bytes: length field (16/8)-1 = 1; the fragment header is always 8
      Bytes ext(code == 44 ? 8 : 16, 0);
      ext[0] = next;
      ext[1] = code == 44 ? 0 : 1;
      if (code == 44) ext[3] = 1;  // more fragments
      append(chain, ext);
    }
  }
  const Bytes udp = udp_header_and_payload(payload, destination_port);
  Bytes ip(40, 0);
  ip[0] = 0x60;
  put_be16(ip, 4, static_cast<std::uint32_t>(chain.size() + udp.size()));
  ip[6] = spec.extensions.empty() ? 17 : spec.extensions.front();
  ip[7] = 64;
  for (std::size_t i = 0; i < 16; ++i) ip[8 + i] = spec.source[i];
  ip[24] = 0xff;  // ff02::1
  ip[25] = 0x02;
  ip[39] = 0x01;
  append(ip, chain);
  append(ip, udp);
  return ip;
}

Bytes ethernet(const Bytes& ip, const std::vector<std::uint16_t>& vlan_tpids) {
  Bytes frame = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x60, 0x76, 0x88, 0x00, 0x00, 0x01};
  std::uint16_t vlan_id = 100;
  for (const std::uint16_t tpid : vlan_tpids) {
    append_be16(frame, tpid);
    append_be16(frame, vlan_id++);
  }
  append_be16(frame, ethertype_of(ip));
  append(frame, ip);
  return frame;
}

Bytes ethernet_arp() {
  Bytes frame = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x60,
                 0x76, 0x88, 0x00, 0x00, 0x01, 0x08, 0x06};
  const Bytes arp = {0,   1,   8, 0,   6, 4, 0, 1, 0x60, 0x76, 0x88, 0,   0, 1,
                     192, 168, 1, 201, 0, 0, 0, 0, 0,    0,    192,  168, 1, 1};
  append(frame, arp);
  frame.resize(60, 0);  // Ethernet minimum, padded
  return frame;
}

Bytes linux_sll(const Bytes& ip) {
  Bytes frame;
  append_be16(frame, 0);  // packet type: to us
  append_be16(frame, 1);  // ARPHRD_ETHER
  append_be16(frame, 6);  // address length
  for (int i = 0; i < 8; ++i) frame.push_back(static_cast<std::uint8_t>(i == 0 ? 0x60 : 0));
  append_be16(frame, ethertype_of(ip));
  append(frame, ip);
  return frame;
}

Bytes linux_sll2(const Bytes& ip) {
  Bytes frame;
  append_be16(frame, ethertype_of(ip));
  append_be16(frame, 0);                           // reserved
  for (int i = 0; i < 3; ++i) frame.push_back(0);  // interface index 2 (big-endian)
  frame.push_back(2);
  append_be16(frame, 1);  // ARPHRD_ETHER
  frame.push_back(0);     // packet type
  frame.push_back(6);     // address length
  for (int i = 0; i < 8; ++i) frame.push_back(static_cast<std::uint8_t>(i == 0 ? 0x60 : 0));
  append(frame, ip);
  return frame;
}

Bytes loopback(const Bytes& ip, std::uint32_t family, bool network_order) {
  Bytes frame;
  if (network_order) {
    append_be16(frame, family >> 16);
    append_be16(frame, family & 0xFFFFu);
  } else {
    append_le32(frame, family);
  }
  append(frame, ip);
  return frame;
}

void write_pcap(const std::filesystem::path& path, std::uint32_t link_type,
                const std::vector<Record>& records, bool nanosecond, std::size_t cut_last_bytes) {
  Bytes file;
  append_le32(file, nanosecond ? 0xa1b23c4du : 0xa1b2c3d4u);
  append_le16(file, 2);
  append_le16(file, 4);
  append_le32(file, 0);  // thiszone
  append_le32(file, 0);  // sigfigs
  append_le32(file, 65535);
  append_le32(file, link_type);
  const std::int64_t per_second = nanosecond ? 1'000'000'000 : 1'000'000;
  for (const Record& r : records) {
    const std::int64_t sub =
        nanosecond ? r.stamp_ns % per_second : (r.stamp_ns / 1000) % per_second;
    append_le32(file, static_cast<std::uint32_t>(r.stamp_ns / 1'000'000'000));
    append_le32(file, static_cast<std::uint32_t>(sub));
    append_le32(file, static_cast<std::uint32_t>(r.bytes.size()));
    append_le32(file,
                r.original_length ? r.original_length : static_cast<std::uint32_t>(r.bytes.size()));
    append(file, r.bytes);
  }
  file.resize(file.size() - cut_last_bytes);
  write_file(path, file);
}

void write_pcapng(const std::filesystem::path& path, std::uint16_t link_type,
                  const std::vector<Record>& records) {
  Bytes file;
  // Section header block.
  append_le32(file, 0x0A0D0D0A);
  append_le32(file, 28);
  append_le32(file, 0x1A2B3C4D);
  append_le16(file, 1);
  append_le16(file, 0);
  append_le32(file, 0xFFFFFFFF);  // section length -1 (unknown), 64 bits
  append_le32(file, 0xFFFFFFFF);
  append_le32(file, 28);
  // Interface description block with if_tsresol = 9 (nanoseconds).
  append_le32(file, 1);
  append_le32(file, 32);
  append_le16(file, link_type);
  append_le16(file, 0);
  append_le32(file, 65535);
  append_le16(file, 9);  // if_tsresol
  append_le16(file, 1);
  append(file, Bytes{9, 0, 0, 0});
  append_le32(file, 0);  // opt_endofopt
  append_le32(file, 32);
  // Enhanced packet blocks.
  for (const Record& r : records) {
    const std::size_t padded = (r.bytes.size() + 3) / 4 * 4;
    const auto total = static_cast<std::uint32_t>(32 + padded);
    const auto stamp = static_cast<std::uint64_t>(r.stamp_ns);
    append_le32(file, 6);
    append_le32(file, total);
    append_le32(file, 0);  // interface id
    append_le32(file, static_cast<std::uint32_t>(stamp >> 32));
    append_le32(file, static_cast<std::uint32_t>(stamp));
    append_le32(file, static_cast<std::uint32_t>(r.bytes.size()));
    append_le32(file,
                r.original_length ? r.original_length : static_cast<std::uint32_t>(r.bytes.size()));
    append(file, r.bytes);
    file.resize(file.size() + padded - r.bytes.size(), 0);
    append_le32(file, total);
  }
  write_file(path, file);
}

}  // namespace vlpground::test
