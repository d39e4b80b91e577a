#include "io/mcap/record_parse.hpp"

#include "io/byte_buffer.hpp"

namespace vigs::io::mcap::detail {

bool parse_schema(std::span<const std::uint8_t> body, Schema& out) {
  ByteReader r(body);
  std::uint32_t n = 0;
  std::span<const std::uint8_t> data;
  if (!r.get(out.id) || !r.get_string(out.name) || !r.get_string(out.encoding) || !r.get(n) ||
      !r.get_span(n, data)) {
    return false;
  }
  out.data.assign(data.begin(), data.end());
  return true;
}

bool parse_channel(std::span<const std::uint8_t> body, Channel& out) {
  ByteReader r(body);
  std::uint32_t map_len = 0;
  std::span<const std::uint8_t> map_bytes;
  if (!r.get(out.id) || !r.get(out.schema_id) || !r.get_string(out.topic) ||
      !r.get_string(out.message_encoding) || !r.get(map_len) || !r.get_span(map_len, map_bytes)) {
    return false;
  }
  out.metadata.clear();
  ByteReader m(map_bytes);
  while (m.remaining() > 0) {
    std::string k, v;
    if (!m.get_string(k) || !m.get_string(v)) return false;
    out.metadata[k] = v;
  }
  return true;
}

bool parse_statistics(std::span<const std::uint8_t> body, Statistics& out) {
  ByteReader r(body);
  std::uint32_t map_len = 0;
  std::span<const std::uint8_t> map_bytes;
  if (!r.get(out.message_count) || !r.get(out.schema_count) || !r.get(out.channel_count) ||
      !r.get(out.attachment_count) || !r.get(out.metadata_count) || !r.get(out.chunk_count) ||
      !r.get(out.message_start_time_ns) || !r.get(out.message_end_time_ns) || !r.get(map_len) ||
      !r.get_span(map_len, map_bytes) || map_len % 10 != 0) {
    return false;
  }
  out.channel_message_counts.clear();
  ByteReader m(map_bytes);
  while (m.remaining() > 0) {
    std::uint16_t id = 0;
    std::uint64_t count = 0;
    if (!m.get(id) || !m.get(count)) return false;
    out.channel_message_counts[id] = count;
  }
  return true;
}

bool parse_message(std::span<const std::uint8_t> body, MessageRecord& out) {
  ByteReader r(body);
  if (!r.get(out.channel_id) || !r.get(out.sequence) || !r.get(out.log_time) ||
      !r.get(out.publish_time)) {
    return false;
  }
  out.data = r.rest();
  return true;
}

bool parse_chunk(std::span<const std::uint8_t> body, ChunkRecord& out) {
  ByteReader r(body);
  std::uint64_t n = 0;
  if (!r.get(out.start_time) || !r.get(out.end_time) || !r.get(out.uncompressed_size) ||
      !r.get(out.uncompressed_crc) || !r.get_string(out.compression) || !r.get(n) ||
      n > r.remaining() || !r.get_span(static_cast<std::size_t>(n), out.records)) {
    return false;
  }
  return true;
}

bool parse_chunk_index(std::span<const std::uint8_t> body, ChunkIndexRecord& out) {
  ByteReader r(body);
  std::uint32_t map_len = 0;
  std::span<const std::uint8_t> map_bytes;
  if (!r.get(out.start_time) || !r.get(out.end_time) || !r.get(out.chunk_offset) ||
      !r.get(out.chunk_length) || !r.get(map_len) || !r.get_span(map_len, map_bytes) ||
      map_len % 10 != 0 || !r.get(out.message_index_length) || !r.get_string(out.compression) ||
      !r.get(out.compressed_size) || !r.get(out.uncompressed_size)) {
    return false;
  }
  out.message_index_offsets.clear();
  ByteReader m(map_bytes);
  while (m.remaining() > 0) {
    std::uint16_t id = 0;
    std::uint64_t off = 0;
    if (!m.get(id) || !m.get(off)) return false;
    out.message_index_offsets[id] = off;
  }
  return true;
}

bool parse_footer(std::span<const std::uint8_t> body, FooterRecord& out) {
  ByteReader r(body);
  return r.get(out.summary_start) && r.get(out.summary_offset_start) && r.get(out.summary_crc);
}

bool parse_header(std::span<const std::uint8_t> body, std::string& profile, std::string& library) {
  ByteReader r(body);
  return r.get_string(profile) && r.get_string(library);
}

}  // namespace vigs::io::mcap::detail
