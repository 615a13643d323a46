// MCAP writer: records per the MCAP specification, https://mcap.dev/spec (major version 0).
#include "vlpground/mcap/writer.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "chunk_compressor.hpp"
#include "file_output.hpp"
#include "record_buffer.hpp"

namespace vlpground::mcap {

using detail::Opcode;
using detail::RecordBuffer;

namespace {

struct IndexEntry {
  std::uint64_t log_time_ns;
  std::uint64_t offset;  // of the Message record inside the chunk's uncompressed records
  bool operator<(const IndexEntry& o) const {
    return log_time_ns != o.log_time_ns ? log_time_ns < o.log_time_ns : offset < o.offset;
  }
};

struct SchemaEntry {
  std::string name, encoding;
  std::vector<std::byte> data;
};

struct ChannelEntry {
  std::uint16_t schema_id = 0;
  std::string topic, message_encoding;
  Metadata metadata;
  std::uint32_t next_sequence = 0;
  std::uint64_t message_count = 0;
  std::vector<IndexEntry> chunk_index;  // messages of this channel in the open chunk
};

// One ChunkIndex record; its message_index_offsets live in Impl::index_offsets.
struct ChunkIndexEntry {
  std::uint64_t start_ns, end_ns;
  std::uint64_t chunk_offset, chunk_length;
  std::uint64_t message_index_length;
  std::uint64_t compressed_size, uncompressed_size;
  std::size_t first_offset, offset_count;  // range in Impl::index_offsets
};

struct ChannelOffset {
  std::uint16_t channel_id;
  std::uint64_t offset;  // file offset of the channel's MessageIndex record
};

struct TimeRange {
  std::uint64_t start = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t end = 0;
  void add(std::uint64_t t) {
    start = std::min(start, t);
    end = std::max(end, t);
  }
};

std::string_view mcap_name(Compression c) { return c == Compression::none ? "" : to_string(c); }

}  // namespace

struct Writer::Impl {
  WriterConfig config;
  detail::FileOutput file;
  std::unique_ptr<detail::ChunkCompressor> compressor;
  std::vector<std::byte> chunk;    // uncompressed records of the open chunk
  std::vector<std::byte> records;  // records written outside chunks (reused)
  std::vector<SchemaEntry> schemas;    // id = index + 1
  std::vector<ChannelEntry> channels;  // id = index
  std::vector<ChunkIndexEntry> chunk_indexes;
  std::vector<ChannelOffset> index_offsets;
  TimeRange chunk_time, file_time;
  std::uint64_t chunk_messages = 0;
  WriterStats stats;
  bool closed = false;

  void require_open(const char* what) const {
    if (!file.is_open()) throw std::logic_error(std::string("mcap: ") + what + " on a closed writer");
    if (file.failed()) {
      throw std::runtime_error("mcap: '" + file.path() +
                               "' is no longer written after an earlier write error");
    }
  }

  void write_records() {
    file.write(records);
    records.clear();
  }

  void append_schema(RecordBuffer& r, std::size_t index) const {
    const SchemaEntry& s = schemas[index];
    const auto at = r.begin_record(Opcode::schema);
    r.u16(static_cast<std::uint16_t>(index + 1));
    r.string(s.name);
    r.string(s.encoding);
    r.bytes32(s.data);
    r.end_record(at);
  }

  void append_channel(RecordBuffer& r, std::size_t index) const {
    const ChannelEntry& c = channels[index];
    const auto at = r.begin_record(Opcode::channel);
    r.u16(static_cast<std::uint16_t>(index));
    r.u16(c.schema_id);
    r.string(c.topic);
    r.string(c.message_encoding);
    const auto map_at = r.begin_prefix32();
    for (const auto& [key, value] : c.metadata) {
      r.string(key);
      r.string(value);
    }
    r.end_prefix32(map_at);
    r.end_record(at);
  }

  void append_message(std::uint16_t channel_id, std::uint64_t log_time_ns,
                      std::uint64_t publish_time_ns, std::span<const std::byte> data) {
    ChannelEntry& c = channels[channel_id];
    c.chunk_index.push_back({log_time_ns, chunk.size()});
    RecordBuffer r(chunk);
    const auto at = r.begin_record(Opcode::message);
    r.u16(channel_id);
    r.u32(c.next_sequence++);
    r.u64(log_time_ns);
    r.u64(publish_time_ns);
    r.raw(data);
    r.end_record(at);
    ++c.message_count;
    ++chunk_messages;
    chunk_time.add(log_time_ns);
    file_time.add(log_time_ns);
    ++stats.messages;
  }

  // Chunk record, then one MessageIndex record per channel present in it (spec: "Chunk",
  // "Message Index"); everything reaches the file before this returns.
  void close_chunk() {
    if (chunk_messages == 0) return;
    ChunkIndexEntry entry{};
    write_chunk_record(entry);
    write_message_indexes(entry);
    if (config.sync_each_chunk) file.sync();
    chunk_indexes.push_back(entry);
    ++stats.chunks;
    stats.uncompressed_bytes += chunk.size();
    chunk.clear();
    chunk_messages = 0;
    chunk_time = {};
  }

  void write_chunk_record(ChunkIndexEntry& entry) {
    const std::span<const std::byte> compressed = compressor->compress(chunk);
    entry.start_ns = chunk_time.start;
    entry.end_ns = chunk_time.end;
    entry.chunk_offset = file.offset();
    entry.compressed_size = compressed.size();
    entry.uncompressed_size = chunk.size();
    RecordBuffer r(records);
    const auto at = r.begin_record(Opcode::chunk);
    r.u64(chunk_time.start);
    r.u64(chunk_time.end);
    r.u64(chunk.size());
    r.u32(detail::crc32(0, chunk));
    r.string(mcap_name(config.compression));
    r.u64(compressed.size());
    // The record's length covers the compressed bytes, written right after this header.
    r.end_record(at, compressed.size());
    entry.chunk_length = records.size() + compressed.size();
    write_records();
    file.write(compressed);
  }

  void write_message_indexes(ChunkIndexEntry& entry) {
    RecordBuffer r(records);
    entry.first_offset = index_offsets.size();
    const std::uint64_t indexes_start = file.offset();
    for (std::size_t id = 0; id < channels.size(); ++id) {
      std::vector<IndexEntry>& index = channels[id].chunk_index;
      if (index.empty()) continue;
      if (!std::is_sorted(index.begin(), index.end())) std::sort(index.begin(), index.end());
      index_offsets.push_back({static_cast<std::uint16_t>(id), indexes_start + records.size()});
      const auto at = r.begin_record(Opcode::message_index);
      r.u16(static_cast<std::uint16_t>(id));
      const auto array_at = r.begin_prefix32();
      for (const IndexEntry& e : index) {
        r.u64(e.log_time_ns);
        r.u64(e.offset);
      }
      r.end_prefix32(array_at);
      r.end_record(at);
      index.clear();
    }
    entry.offset_count = index_offsets.size() - entry.first_offset;
    entry.message_index_length = records.size();
    write_records();
  }

  void append_chunk_index(RecordBuffer& r, const ChunkIndexEntry& e) const {
    const auto at = r.begin_record(Opcode::chunk_index);
    r.u64(e.start_ns);
    r.u64(e.end_ns);
    r.u64(e.chunk_offset);
    r.u64(e.chunk_length);
    const auto map_at = r.begin_prefix32();
    for (std::size_t i = e.first_offset; i < e.first_offset + e.offset_count; ++i) {
      r.u16(index_offsets[i].channel_id);
      r.u64(index_offsets[i].offset);
    }
    r.end_prefix32(map_at);
    r.u64(e.message_index_length);
    r.string(mcap_name(config.compression));
    r.u64(e.compressed_size);
    r.u64(e.uncompressed_size);
    r.end_record(at);
  }

  void append_statistics(RecordBuffer& r) const {
    const auto at = r.begin_record(Opcode::statistics);
    r.u64(stats.messages);
    r.u16(static_cast<std::uint16_t>(schemas.size()));
    r.u32(static_cast<std::uint32_t>(channels.size()));
    r.u32(0);  // attachments
    r.u32(0);  // metadata
    r.u32(static_cast<std::uint32_t>(chunk_indexes.size()));
    r.u64(stats.messages == 0 ? 0 : file_time.start);
    r.u64(file_time.end);
    const auto map_at = r.begin_prefix32();
    for (std::size_t id = 0; id < channels.size(); ++id) {
      r.u16(static_cast<std::uint16_t>(id));
      r.u64(channels[id].message_count);
    }
    r.end_prefix32(map_at);
    r.end_record(at);
  }

  // Summary section grouped by opcode, SummaryOffset records, Footer, magic (spec: "Summary
  // Section", "Summary Offset Section", "Footer"). The footer CRC covers the summary start
  // through the footer's summary_offset_start field.
  void write_summary_and_footer() {
    {
      RecordBuffer r(records);
      const auto at = r.begin_record(Opcode::data_end);
      // data_section_crc: every byte from the file's start to here, as the reference writer
      // (@mcap/core) computes it.
      r.u32(file.crc());
      r.end_record(at);
      write_records();
    }
    const std::uint64_t summary_start = file.offset();
    file.restart_crc();
    struct Group {
      Opcode op;
      std::uint64_t start, length;
    };
    std::vector<Group> groups;
    RecordBuffer r(records);
    auto group = [&](Opcode op, auto&& append_all) {
      const std::size_t begin = records.size();
      append_all();
      if (records.size() > begin) groups.push_back({op, summary_start + begin, records.size() - begin});
    };
    group(Opcode::schema, [&] {
      for (std::size_t i = 0; i < schemas.size(); ++i) append_schema(r, i);
    });
    group(Opcode::channel, [&] {
      for (std::size_t i = 0; i < channels.size(); ++i) append_channel(r, i);
    });
    group(Opcode::chunk_index, [&] {
      for (const ChunkIndexEntry& e : chunk_indexes) append_chunk_index(r, e);
    });
    group(Opcode::statistics, [&] { append_statistics(r); });
    const std::uint64_t summary_offset_start = summary_start + records.size();
    for (const Group& g : groups) {
      const auto at = r.begin_record(Opcode::summary_offset);
      r.u8(static_cast<std::uint8_t>(g.op));
      r.u64(g.start);
      r.u64(g.length);
      r.end_record(at);
    }
    r.u8(static_cast<std::uint8_t>(Opcode::footer));
    r.u64(8 + 8 + 4);  // the footer's length is fixed; the CRC below covers it
    r.u64(summary_start);
    r.u64(summary_offset_start);
    r.u32(detail::crc32(file.crc(), records));
    r.raw(detail::kMagic);
    write_records();
  }
};

Writer::Writer() : impl_(std::make_unique<Impl>()) {}

Writer::~Writer() {
  try {
    close();
  } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor must not throw
  }
}

void Writer::open(const std::string& path, WriterConfig config) {
  if (impl_->file.is_open()) throw std::logic_error("mcap: open() on an open writer");
  config.validate();
  impl_ = std::make_unique<Impl>();
  Impl& m = *impl_;
  m.config = std::move(config);
  m.compressor = std::make_unique<detail::ChunkCompressor>(m.config.compression,
                                                           m.config.compression_level);
  m.chunk.reserve(m.config.chunk_size_bytes + (64u << 10));
  m.chunk_indexes.reserve(m.config.expected_chunks);
  m.index_offsets.reserve(m.config.expected_chunks * 4);
  m.file.open(path);
  RecordBuffer r(m.records);
  r.raw(detail::kMagic);
  const auto at = r.begin_record(Opcode::header);
  r.string(m.config.profile);
  r.string(m.config.library);
  r.end_record(at);
  m.write_records();
}

std::uint16_t Writer::add_schema(std::string_view name, std::string_view encoding,
                                 std::span<const std::byte> data) {
  Impl& m = *impl_;
  m.require_open("add_schema()");
  if (m.schemas.size() >= std::numeric_limits<std::uint16_t>::max()) {
    throw std::length_error("mcap: too many schemas (65535)");
  }
  m.schemas.push_back({std::string(name), std::string(encoding), {data.begin(), data.end()}});
  RecordBuffer r(m.records);
  m.append_schema(r, m.schemas.size() - 1);
  m.write_records();
  return static_cast<std::uint16_t>(m.schemas.size());
}

std::uint16_t Writer::add_channel(std::uint16_t schema_id, std::string_view topic,
                                  std::string_view message_encoding, const Metadata& metadata) {
  Impl& m = *impl_;
  m.require_open("add_channel()");
  if (schema_id > m.schemas.size()) {
    throw std::invalid_argument("mcap: channel '" + std::string(topic) + "' names unknown schema " +
                                std::to_string(schema_id));
  }
  if (m.channels.size() > std::numeric_limits<std::uint16_t>::max()) {
    throw std::length_error("mcap: too many channels (65536)");
  }
  ChannelEntry& c = m.channels.emplace_back();
  c.schema_id = schema_id;
  c.topic = topic;
  c.message_encoding = message_encoding;
  c.metadata = metadata;
  c.chunk_index.reserve(64);
  RecordBuffer r(m.records);
  m.append_channel(r, m.channels.size() - 1);
  m.write_records();
  return static_cast<std::uint16_t>(m.channels.size() - 1);
}

void Writer::write(std::uint16_t channel_id, std::uint64_t log_time_ns,
                   std::uint64_t publish_time_ns, std::span<const std::byte> data) {
  Impl& m = *impl_;
  m.require_open("write()");
  if (channel_id >= m.channels.size()) {
    throw std::invalid_argument("mcap: write() to unknown channel " + std::to_string(channel_id));
  }
  m.append_message(channel_id, log_time_ns, publish_time_ns, data);
  if (m.chunk.size() >= m.config.chunk_size_bytes) m.close_chunk();
}

void Writer::flush() {
  Impl& m = *impl_;
  m.require_open("flush()");
  m.close_chunk();
}

void Writer::close() {
  Impl& m = *impl_;
  if (!m.file.is_open()) return;
  if (m.file.failed()) {  // a summary after a torn record would be unreadable: keep the
    m.file.close();       // file as it is (it streams up to its last complete chunk)
    return;
  }
  m.close_chunk();
  m.write_summary_and_footer();
  m.stats.file_bytes = m.file.offset();
  m.file.sync();
  m.file.close();
}

bool Writer::is_open() const { return impl_->file.is_open(); }

WriterStats Writer::stats() const {
  WriterStats s = impl_->stats;
  s.file_bytes = impl_->file.is_open() ? impl_->file.offset() : s.file_bytes;
  return s;
}

const std::string& Writer::path() const { return impl_->file.path(); }

}  // namespace vlpground::mcap
