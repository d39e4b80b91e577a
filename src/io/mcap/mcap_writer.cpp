#include "io/mcap/mcap_writer.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include "io/byte_buffer.hpp"
#include "io/io_error.hpp"
#include "io/mcap/crc32.hpp"

namespace vigs::io::mcap {
namespace {

struct ChunkIndexEntry {
  std::uint64_t start_time = 0, end_time = 0, offset = 0, length = 0;
  std::map<std::uint16_t, std::uint64_t> message_index_offsets;
  std::uint64_t message_index_length = 0;
  std::string compression;
  std::uint64_t compressed_size = 0, uncompressed_size = 0;
};

// Starts a record: opcode and a uint64 length placeholder; returns the placeholder position.
std::size_t begin_record(ByteWriter& w, Opcode op) {
  w.put(static_cast<std::uint8_t>(op));
  return w.reserve<std::uint64_t>();
}
void end_record(ByteWriter& w, std::size_t length_at) {
  w.patch<std::uint64_t>(length_at, w.size() - length_at - 8);
}

void put_schema(ByteWriter& w, const Schema& s) {
  const std::size_t at = begin_record(w, Opcode::kSchema);
  w.put(s.id);
  w.put_string(s.name);
  w.put_string(s.encoding);
  w.put(static_cast<std::uint32_t>(s.data.size()));
  w.put_bytes(s.data);
  end_record(w, at);
}

void put_channel(ByteWriter& w, const Channel& c) {
  const std::size_t at = begin_record(w, Opcode::kChannel);
  w.put(c.id);
  w.put(c.schema_id);
  w.put_string(c.topic);
  w.put_string(c.message_encoding);
  const std::size_t map_at = w.reserve<std::uint32_t>();
  for (const auto& [k, v] : c.metadata) {
    w.put_string(k);
    w.put_string(v);
  }
  w.patch<std::uint32_t>(map_at, static_cast<std::uint32_t>(w.size() - map_at - 4));
  end_record(w, at);
}

}  // namespace

struct McapWriter::Impl {
  std::string path;
  McapWriterOptions options;
  McapWriterStats stats;
  int fd = -1;
  std::uint64_t offset = 0;    // bytes written to the file so far
  std::uint32_t data_crc = 0;  // CRC of every byte written before Data End
  bool in_data_section = true;

  std::vector<Schema> schemas;
  std::vector<Channel> channels;
  std::vector<std::uint32_t> sequences;  // per channel (index id - 1)
  std::vector<std::uint64_t> channel_counts;

  // Current chunk.
  std::vector<std::uint8_t> chunk;
  std::uint64_t chunk_start_time = 0, chunk_end_time = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index;
  std::vector<std::uint8_t> compressed, scratch;
  ZSTD_CCtx* zstd = nullptr;

  std::vector<ChunkIndexEntry> chunk_indexes;
  std::uint64_t start_time = 0, end_time = 0;

  [[noreturn]] void fail(const std::string& what) const {
    throw IoError("MCAP writer: " + path + ": " + what);
  }

  void write_out(std::span<const std::uint8_t> bytes) {
    if (fd < 0) fail("file is closed");
    if (in_data_section) data_crc = crc32_update(data_crc, bytes);
    const std::uint8_t* p = bytes.data();
    std::size_t n = bytes.size();
    while (n > 0) {
      const ssize_t k = ::write(fd, p, n);
      if (k < 0) {
        if (errno == EINTR) continue;
        fail(std::string("write failed at byte ") + std::to_string(offset) + ": " +
             std::strerror(errno));
      }
      p += k;
      n -= static_cast<std::size_t>(k);
      offset += static_cast<std::uint64_t>(k);
    }
    stats.bytes_written = offset;
  }

  void write_chunk() {
    if (chunk.empty()) return;
    std::span<const std::uint8_t> payload = chunk;
    std::string compression;
    if (options.compression == Compression::kZstd) {
      compressed.resize(ZSTD_compressBound(chunk.size()));
      const std::size_t n = ZSTD_compressCCtx(zstd, compressed.data(), compressed.size(),
                                              chunk.data(), chunk.size(), options.zstd_level);
      if (ZSTD_isError(n)) fail(std::string("zstd compression failed: ") + ZSTD_getErrorName(n));
      payload = std::span<const std::uint8_t>(compressed.data(), n);
      compression = "zstd";
    }
    ChunkIndexEntry index;
    index.start_time = chunk_start_time;
    index.end_time = chunk_end_time;
    index.offset = offset;
    index.compression = compression;
    index.compressed_size = payload.size();
    index.uncompressed_size = chunk.size();

    scratch.clear();
    ByteWriter w(scratch);
    w.put(static_cast<std::uint8_t>(Opcode::kChunk));
    w.put<std::uint64_t>(8 + 8 + 8 + 4 + 4 + compression.size() + 8 + payload.size());
    w.put(chunk_start_time);
    w.put(chunk_end_time);
    w.put<std::uint64_t>(chunk.size());
    w.put(crc32(chunk));
    w.put_string(compression);
    w.put<std::uint64_t>(payload.size());
    write_out(scratch);
    write_out(payload);
    index.length = offset - index.offset;

    scratch.clear();
    for (const auto& [channel_id, entries] : chunk_index) {
      index.message_index_offsets[channel_id] = offset + scratch.size();
      const std::size_t at = begin_record(w, Opcode::kMessageIndex);
      w.put(channel_id);
      w.put(static_cast<std::uint32_t>(entries.size() * 16));
      for (const auto& [t, off] : entries) {
        w.put(t);
        w.put(off);
      }
      end_record(w, at);
    }
    index.message_index_length = scratch.size();
    write_out(scratch);
    if (options.fsync_each_chunk && ::fsync(fd) != 0) fail("fsync failed");

    chunk_indexes.push_back(std::move(index));
    stats.chunk_count++;
    chunk.clear();
    chunk_index.clear();
  }
};

McapWriter::McapWriter(const std::string& path, McapWriterOptions options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = path;
  m.options = std::move(options);
  if (m.options.chunk_size_bytes == 0) m.fail("chunk_size_bytes must be > 0");
  if (m.options.zstd_level < 1 || m.options.zstd_level > 19) m.fail("zstd_level not in 1..19");
  m.fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (m.fd < 0) m.fail(std::string("cannot create: ") + std::strerror(errno));
  if (m.options.compression == Compression::kZstd) {
    m.zstd = ZSTD_createCCtx();
    if (m.zstd == nullptr) m.fail("cannot create a zstd context");
  }
  m.chunk.reserve(m.options.chunk_size_bytes + (64u << 10));
  std::vector<std::uint8_t> bytes(std::begin(kMagic), std::end(kMagic));
  ByteWriter w(bytes);
  const std::size_t at = begin_record(w, Opcode::kHeader);
  w.put_string(m.options.profile);
  w.put_string(m.options.library);
  end_record(w, at);
  m.write_out(bytes);
}

McapWriter::~McapWriter() {
  try {
    close();
  } catch (...) {
    // Destructors must not throw; callers who care call close() themselves.
  }
  if (impl_->zstd != nullptr) ZSTD_freeCCtx(impl_->zstd);
}

std::uint16_t McapWriter::add_schema(std::string_view name, std::string_view encoding,
                                     std::span<const std::uint8_t> data) {
  Impl& m = *impl_;
  for (const Schema& s : m.schemas) {
    if (s.name == name && s.encoding == encoding &&
        std::equal(s.data.begin(), s.data.end(), data.begin(), data.end())) {
      return s.id;
    }
  }
  if (m.schemas.size() >= 0xFFFF) m.fail("too many schemas");
  Schema s;
  s.id = static_cast<std::uint16_t>(m.schemas.size() + 1);
  s.name = name;
  s.encoding = encoding;
  s.data.assign(data.begin(), data.end());
  std::vector<std::uint8_t> bytes;
  ByteWriter w(bytes);
  put_schema(w, s);
  m.write_out(bytes);
  m.schemas.push_back(std::move(s));
  return m.schemas.back().id;
}

std::uint16_t McapWriter::add_schema(std::string_view name, std::string_view encoding,
                                     std::string_view text) {
  return add_schema(name, encoding,
                    std::span<const std::uint8_t>(
                        reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

std::uint16_t McapWriter::add_channel(std::string_view topic, std::uint16_t schema_id,
                                      std::string_view message_encoding,
                                      const std::map<std::string, std::string>& metadata) {
  Impl& m = *impl_;
  if (schema_id > m.schemas.size())
    m.fail("add_channel: unknown schema id " + std::to_string(schema_id));
  if (m.channels.size() >= 0xFFFE) m.fail("too many channels");
  Channel c;
  c.id = static_cast<std::uint16_t>(m.channels.size() + 1);
  c.schema_id = schema_id;
  c.topic = topic;
  c.message_encoding = message_encoding;
  c.metadata = metadata;
  std::vector<std::uint8_t> bytes;
  ByteWriter w(bytes);
  put_channel(w, c);
  m.write_out(bytes);
  m.channels.push_back(std::move(c));
  m.sequences.push_back(0);
  m.channel_counts.push_back(0);
  return m.channels.back().id;
}

void McapWriter::write(std::uint16_t channel_id, std::uint64_t log_time_ns,
                       std::uint64_t publish_time_ns, std::span<const std::uint8_t> data) {
  Impl& m = *impl_;
  if (channel_id == 0 || channel_id > m.channels.size()) {
    m.fail("write: unknown channel id " + std::to_string(channel_id));
  }
  if (m.fd < 0) m.fail("write after close");
  const std::size_t i = channel_id - 1u;
  if (m.chunk.empty()) {
    m.chunk_start_time = log_time_ns;
    m.chunk_end_time = log_time_ns;
  }
  m.chunk_start_time = std::min(m.chunk_start_time, log_time_ns);
  m.chunk_end_time = std::max(m.chunk_end_time, log_time_ns);
  if (m.stats.message_count == 0) {
    m.start_time = m.end_time = log_time_ns;
  }
  m.start_time = std::min(m.start_time, log_time_ns);
  m.end_time = std::max(m.end_time, log_time_ns);

  m.chunk_index[channel_id].emplace_back(log_time_ns, m.chunk.size());
  ByteWriter w(m.chunk);
  w.put(static_cast<std::uint8_t>(Opcode::kMessage));
  w.put<std::uint64_t>(2 + 4 + 8 + 8 + data.size());
  w.put(channel_id);
  w.put(m.sequences[i]++);
  w.put(log_time_ns);
  w.put(publish_time_ns);
  w.put_bytes(data);
  m.channel_counts[i]++;
  m.stats.message_count++;
  m.stats.bytes_uncompressed += 1 + 8 + 22 + data.size();
  if (m.chunk.size() >= m.options.chunk_size_bytes ||
      (m.options.chunk_max_span_ns != 0 &&
       m.chunk_end_time - m.chunk_start_time >= m.options.chunk_max_span_ns)) {
    m.write_chunk();
  }
}

void McapWriter::flush() {
  impl_->write_chunk();
}

void McapWriter::close() {
  Impl& m = *impl_;
  if (m.fd < 0) return;
  m.write_chunk();

  std::vector<std::uint8_t> bytes;
  ByteWriter w(bytes);
  std::size_t at = begin_record(w, Opcode::kDataEnd);
  w.put(m.data_crc);
  end_record(w, at);
  m.write_out(bytes);
  m.in_data_section = false;

  // Summary: groups by opcode, each remembered for its Summary Offset record.
  const std::uint64_t summary_start = m.offset;
  bytes.clear();
  std::vector<std::tuple<Opcode, std::uint64_t, std::uint64_t>> groups;
  auto group = [&](Opcode op, auto&& body) {
    const std::size_t begin = bytes.size();
    body();
    if (bytes.size() > begin) groups.emplace_back(op, summary_start + begin, bytes.size() - begin);
  };
  group(Opcode::kSchema, [&] {
    for (const Schema& s : m.schemas) put_schema(w, s);
  });
  group(Opcode::kChannel, [&] {
    for (const Channel& c : m.channels) put_channel(w, c);
  });
  group(Opcode::kChunkIndex, [&] {
    for (const ChunkIndexEntry& e : m.chunk_indexes) {
      at = begin_record(w, Opcode::kChunkIndex);
      w.put(e.start_time);
      w.put(e.end_time);
      w.put(e.offset);
      w.put(e.length);
      w.put(static_cast<std::uint32_t>(e.message_index_offsets.size() * 10));
      for (const auto& [id, off] : e.message_index_offsets) {
        w.put(id);
        w.put(off);
      }
      w.put(e.message_index_length);
      w.put_string(e.compression);
      w.put(e.compressed_size);
      w.put(e.uncompressed_size);
      end_record(w, at);
    }
  });
  group(Opcode::kStatistics, [&] {
    at = begin_record(w, Opcode::kStatistics);
    w.put(m.stats.message_count);
    w.put(static_cast<std::uint16_t>(m.schemas.size()));
    w.put(static_cast<std::uint32_t>(m.channels.size()));
    w.put<std::uint32_t>(0);  // attachments
    w.put<std::uint32_t>(0);  // metadata
    w.put(static_cast<std::uint32_t>(m.chunk_indexes.size()));
    w.put(m.start_time);
    w.put(m.end_time);
    w.put(static_cast<std::uint32_t>(m.channels.size() * 10));
    for (std::size_t i = 0; i < m.channels.size(); ++i) {
      w.put(m.channels[i].id);
      w.put(m.channel_counts[i]);
    }
    end_record(w, at);
  });
  const std::uint64_t summary_offset_start = summary_start + bytes.size();
  for (const auto& [op, start, length] : groups) {
    at = begin_record(w, Opcode::kSummaryOffset);
    w.put(static_cast<std::uint8_t>(op));
    w.put(start);
    w.put(length);
    end_record(w, at);
  }
  w.put(static_cast<std::uint8_t>(Opcode::kFooter));
  w.put<std::uint64_t>(8 + 8 + 4);
  w.put(summary_start);
  w.put(summary_offset_start);
  w.put(crc32(bytes));
  w.put_bytes(std::span<const std::uint8_t>(kMagic));
  m.write_out(bytes);
  if (::fsync(m.fd) != 0 && errno != EINVAL) m.fail("fsync failed");
  const int fd = m.fd;
  m.fd = -1;
  if (::close(fd) != 0) m.fail(std::string("close failed: ") + std::strerror(errno));
}

bool McapWriter::is_open() const {
  return impl_->fd >= 0;
}
const std::string& McapWriter::path() const {
  return impl_->path;
}
const McapWriterStats& McapWriter::stats() const {
  return impl_->stats;
}

}  // namespace vigs::io::mcap
