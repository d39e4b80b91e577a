#pragma once
// Internal to the MCAP reader (mcap_reader.cpp: iteration; mcap_reader_open.cpp: opening, the
// summary and accessors). Not part of the public API.
#include <zstd.h>

#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "io/mcap/crc32.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/mcap/record_parse.hpp"

namespace vigs::io::mcap {
namespace detail {

inline constexpr std::uint64_t kRecordHeader = 9;  // opcode + uint64 length
inline constexpr std::uint64_t kFooterRecord = kRecordHeader + 20;
inline constexpr std::uint64_t kMaxUnknownSizeChunk = 1ull << 30;
inline constexpr std::uint64_t kMaxChunkBytes = 4ull << 30;

inline std::string hex(unsigned v) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "0x%02x", v);
  return buf;
}

}  // namespace detail

struct McapReader::Impl {
  std::string path;
  McapReaderOptions options;
  const std::uint8_t* base = nullptr;
  std::uint64_t size = 0;
  std::span<const std::uint8_t> file;

  std::string profile, library;
  std::map<std::uint16_t, std::unique_ptr<Schema>> schemas;
  std::map<std::uint16_t, std::unique_ptr<Channel>> channels;
  std::optional<Statistics> statistics;
  bool summary_ok = false;
  std::vector<detail::ChunkIndexRecord> chunk_indexes;  // sorted by chunk offset
  std::vector<ReadIssue> issues;
  std::size_t open_issue_count = 0;

  // Iteration state.
  std::uint64_t pos = 8;
  bool done = false;
  std::uint32_t data_crc = 0;
  std::uint64_t crc_pos = 0;  // bytes [0, crc_pos) are in data_crc
  bool crc_valid = true;
  std::vector<std::uint8_t> chunk_buf;
  std::span<const std::uint8_t> chunk_records;
  std::uint64_t chunk_pos = 0, chunk_offset = 0;
  bool in_chunk = false;
  ZSTD_DCtx* zstd = nullptr;
  std::uint64_t released_to = 0;  // pages below this were given back (release_pages_before)

  /// The mapping's pages below `at` (read, CRC'd and parsed: a new record starts there) leave
  /// the resident set, in steps of 64 MiB: reading a long recording front to back then costs a
  /// window of memory, not the file's size (a 3-minute 720x480 recording is 4 GB). Pages read
  /// again (rewind, resync) fault back in from the file.
  void release_pages_before(std::uint64_t at);

  void issue(ReadIssue::Kind kind, std::uint64_t offset, const std::string& what) {
    issues.push_back({kind, offset, path + ": byte " + std::to_string(offset) + ": " + what});
  }

  void open_summary();
  void add_schema(const Schema& s) {
    if (s.id != 0 && !schemas.contains(s.id)) schemas[s.id] = std::make_unique<Schema>(s);
  }
  void add_channel(const Channel& c) {
    if (!channels.contains(c.id)) channels[c.id] = std::make_unique<Channel>(c);
  }
  bool wanted(std::uint16_t channel_id) const {
    if (options.topics.empty()) return true;
    auto it = channels.find(channel_id);
    return it != channels.end() && options.topics.contains(it->second->topic);
  }
  void crc_to(std::uint64_t end) {
    if (crc_valid && options.verify_crcs && end > crc_pos) {
      data_crc = crc32_update(data_crc, file.subspan(crc_pos, end - crc_pos));
    }
    crc_pos = std::max(crc_pos, end);
  }
  bool resync(std::uint64_t damaged_at);
  bool is_indexed_chunk(std::uint64_t offset) const {
    auto it = std::lower_bound(chunk_indexes.begin(), chunk_indexes.end(), offset,
                               [](const auto& ci, std::uint64_t o) { return ci.chunk_offset < o; });
    return it != chunk_indexes.end() && it->chunk_offset == offset;
  }
  bool fill(const detail::MessageRecord& m, std::uint64_t offset, MessageView& out);
  bool next_in_chunk(MessageView& out);
  bool open_chunk(std::uint64_t offset, std::span<const std::uint8_t> body);
  // Returns true when `out` holds a message.
  bool step(MessageView& out);
};

}  // namespace vigs::io::mcap
