#pragma once
#include <cstdint>
#include <map>
#include <span>
#include <string>

#include "io/mcap/mcap_types.hpp"

namespace vigs::io::mcap::detail {

/// Parsers of single record bodies (the bytes after opcode and length). Each returns false on
/// malformed input and never reads outside `body`.
bool parse_schema(std::span<const std::uint8_t> body, Schema& out);
bool parse_channel(std::span<const std::uint8_t> body, Channel& out);
bool parse_statistics(std::span<const std::uint8_t> body, Statistics& out);

struct MessageRecord {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0, publish_time = 0;
  std::span<const std::uint8_t> data;
};
bool parse_message(std::span<const std::uint8_t> body, MessageRecord& out);

struct ChunkRecord {
  std::uint64_t start_time = 0, end_time = 0, uncompressed_size = 0;
  std::uint32_t uncompressed_crc = 0;
  std::string compression;
  std::span<const std::uint8_t> records;  // compressed bytes
};
bool parse_chunk(std::span<const std::uint8_t> body, ChunkRecord& out);

struct ChunkIndexRecord {
  std::uint64_t start_time = 0, end_time = 0, chunk_offset = 0, chunk_length = 0;
  std::map<std::uint16_t, std::uint64_t> message_index_offsets;
  std::uint64_t message_index_length = 0;
  std::string compression;
  std::uint64_t compressed_size = 0, uncompressed_size = 0;
};
bool parse_chunk_index(std::span<const std::uint8_t> body, ChunkIndexRecord& out);

struct FooterRecord {
  std::uint64_t summary_start = 0, summary_offset_start = 0;
  std::uint32_t summary_crc = 0;
};
bool parse_footer(std::span<const std::uint8_t> body, FooterRecord& out);

bool parse_header(std::span<const std::uint8_t> body, std::string& profile, std::string& library);

}  // namespace vigs::io::mcap::detail
