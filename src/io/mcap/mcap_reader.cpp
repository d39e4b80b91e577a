#include "io/mcap/mcap_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <new>

#include <sys/mman.h>
#include <unistd.h>

#include "io/mcap/reader_impl.hpp"

namespace vigs::io::mcap {

using detail::hex;
using detail::kMaxChunkBytes;
using detail::kMaxUnknownSizeChunk;
using detail::kRecordHeader;

bool McapReader::Impl::resync(std::uint64_t damaged_at) {
  crc_valid = false;
  if (summary_ok) {
    for (const auto& ci : chunk_indexes) {
      if (ci.chunk_offset > damaged_at) {
        issue(ReadIssue::Kind::kCorrupt, damaged_at,
              "resuming at the next indexed chunk, byte " + std::to_string(ci.chunk_offset));
        pos = ci.chunk_offset;
        return true;
      }
    }
  }
  done = true;
  return false;
}

bool McapReader::Impl::fill(const detail::MessageRecord& m, std::uint64_t offset,
                            MessageView& out) {
  auto it = channels.find(m.channel_id);
  if (it == channels.end()) {
    issue(ReadIssue::Kind::kCorrupt, offset,
          "message on unknown channel " + std::to_string(m.channel_id));
    return false;
  }
  if (!wanted(m.channel_id)) return false;
  out.channel = it->second.get();
  auto s = schemas.find(it->second->schema_id);
  out.schema = s == schemas.end() ? nullptr : s->second.get();
  out.sequence = m.sequence;
  out.log_time_ns = m.log_time;
  out.publish_time_ns = m.publish_time;
  out.data = m.data;
  out.record_offset = offset;
  return true;
}

bool McapReader::Impl::next_in_chunk(MessageView& out) {
  while (chunk_pos < chunk_records.size()) {
    const std::uint64_t left = chunk_records.size() - chunk_pos;
    std::uint64_t n = 0;
    if (left < kRecordHeader) break;
    std::memcpy(&n, chunk_records.data() + chunk_pos + 1, 8);
    if (n > left - kRecordHeader) break;
    const std::uint8_t op = chunk_records[chunk_pos];
    const auto body = chunk_records.subspan(chunk_pos + kRecordHeader, n);
    chunk_pos += kRecordHeader + n;
    bool ok = true;
    if (op == static_cast<std::uint8_t>(Opcode::kSchema)) {
      Schema s;
      ok = detail::parse_schema(body, s);
      if (ok) add_schema(s);
    } else if (op == static_cast<std::uint8_t>(Opcode::kChannel)) {
      Channel c;
      ok = detail::parse_channel(body, c);
      if (ok) add_channel(c);
    } else if (op == static_cast<std::uint8_t>(Opcode::kMessage)) {
      detail::MessageRecord m;
      ok = detail::parse_message(body, m);
      if (ok && fill(m, chunk_offset, out)) return true;
    }
    if (!ok) break;
  }
  if (chunk_pos < chunk_records.size()) {
    issue(ReadIssue::Kind::kCorrupt, chunk_offset,
          "malformed record inside chunk at chunk byte " + std::to_string(chunk_pos));
  }
  in_chunk = false;
  return false;
}

bool McapReader::Impl::open_chunk(std::uint64_t offset, std::span<const std::uint8_t> body) {
  detail::ChunkRecord c;
  if (!detail::parse_chunk(body, c)) {
    issue(ReadIssue::Kind::kCorrupt, offset, "malformed chunk record; chunk skipped");
    return false;
  }
  if (!options.topics.empty() && summary_ok) {
    auto it = std::lower_bound(chunk_indexes.begin(), chunk_indexes.end(), offset,
                               [](const auto& ci, std::uint64_t o) { return ci.chunk_offset < o; });
    if (it != chunk_indexes.end() && it->chunk_offset == offset &&
        std::none_of(it->message_index_offsets.begin(), it->message_index_offsets.end(),
                     [&](const auto& kv) { return wanted(kv.first); })) {
      return false;  // no wanted topic in this chunk
    }
  }
  if (c.compression.empty()) {
    chunk_records = c.records;
  } else if (c.compression == "zstd") {
    const unsigned long long frame = ZSTD_getFrameContentSize(c.records.data(), c.records.size());
    const bool known = frame != ZSTD_CONTENTSIZE_UNKNOWN && frame != ZSTD_CONTENTSIZE_ERROR;
    // zstd cannot expand more than ~32768x (RLE blocks), so a larger claim is damage; the cap
    // also keeps a forged size from exhausting memory.
    const bool plausible = c.uncompressed_size <= kMaxChunkBytes &&
                           c.uncompressed_size <= c.records.size() * 40000ull + (1u << 16);
    if ((known && frame != c.uncompressed_size) || !plausible ||
        (!known && c.uncompressed_size > kMaxUnknownSizeChunk)) {
      issue(ReadIssue::Kind::kCorrupt, offset, "chunk size fields disagree; chunk skipped");
      return false;
    }
    if (zstd == nullptr) zstd = ZSTD_createDCtx();
    try {
      chunk_buf.resize(static_cast<std::size_t>(c.uncompressed_size));
    } catch (const std::bad_alloc&) {
      issue(ReadIssue::Kind::kCorrupt, offset,
            "chunk of " + std::to_string(c.uncompressed_size) + " bytes does not fit in memory");
      return false;
    }
    const std::size_t n = ZSTD_decompressDCtx(zstd, chunk_buf.data(), chunk_buf.size(),
                                              c.records.data(), c.records.size());
    if (ZSTD_isError(n) || n != c.uncompressed_size) {
      issue(ReadIssue::Kind::kCorrupt, offset,
            std::string("zstd chunk does not decompress (") +
                (ZSTD_isError(n) ? ZSTD_getErrorName(n) : "size differs") + "); chunk skipped");
      return false;
    }
    chunk_records = chunk_buf;
  } else {
    issue(ReadIssue::Kind::kUnsupported, offset,
          "chunk compression '" + c.compression + "' not supported; chunk skipped");
    return false;
  }
  if (chunk_records.size() != c.uncompressed_size) {
    issue(ReadIssue::Kind::kCorrupt, offset, "chunk uncompressed_size mismatch; chunk skipped");
    return false;
  }
  if (options.verify_crcs && c.uncompressed_crc != 0 &&
      crc32(chunk_records) != c.uncompressed_crc) {
    issue(ReadIssue::Kind::kCrcMismatch, offset, "chunk CRC mismatch; chunk skipped");
    return false;
  }
  chunk_pos = 0;
  chunk_offset = offset;
  in_chunk = true;
  return true;
}

void McapReader::Impl::release_pages_before(std::uint64_t at) {
  constexpr std::uint64_t kStepBytes = 64ull << 20;
  static const auto page = static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
  const std::uint64_t end = std::min(at, size) / page * page;
  if (end < released_to) released_to = end;  // moved back: rewind or resync
  if (base == nullptr || end - released_to < kStepBytes) return;
  // A read-only private file mapping never written: the pages are dropped, not lost.
  ::madvise(const_cast<std::uint8_t*>(base) + released_to, end - released_to, MADV_DONTNEED);
  released_to = end;
}

bool McapReader::Impl::step(MessageView& out) {
  // Everything before pos is done with: the previous record is parsed (its chunk finished, its
  // message handed out by an earlier next()) and CRC'd.
  release_pages_before(pos);
  if (pos >= size || size - pos < kRecordHeader) {
    issue(ReadIssue::Kind::kTruncated, pos, "file ends before the Data End record");
    done = true;
    return false;
  }
  const std::uint8_t op = base[pos];
  std::uint64_t n = 0;
  std::memcpy(&n, base + pos + 1, 8);
  if (n > size - pos - kRecordHeader) {
    issue(ReadIssue::Kind::kTruncated, pos,
          "record (opcode " + hex(op) + ") of " + std::to_string(n) + " bytes runs past the end (" +
              std::to_string(size) + " bytes); everything before it was read");
    resync(pos);
    return false;
  }
  if (op == 0 || (op > static_cast<std::uint8_t>(Opcode::kDataEnd) && op < 0x80)) {
    issue(ReadIssue::Kind::kCorrupt, pos, "invalid record opcode " + hex(op));
    resync(pos);
    return false;
  }
  const std::uint64_t at = pos;
  const auto body = file.subspan(pos + kRecordHeader, n);
  if (summary_ok && op != static_cast<std::uint8_t>(Opcode::kChunk) && is_indexed_chunk(at)) {
    issue(ReadIssue::Kind::kCorrupt, at, "the index has a chunk here but the record is " + hex(op));
    crc_valid = false;
    pos = at + kRecordHeader + n;
    return false;
  }
  if (op == static_cast<std::uint8_t>(Opcode::kDataEnd)) {
    crc_to(at);
    std::uint32_t expected = 0;
    if (n >= 4) std::memcpy(&expected, body.data(), 4);
    if (options.verify_crcs && crc_valid && expected != 0 && expected != data_crc) {
      issue(ReadIssue::Kind::kCrcMismatch, at, "data section CRC mismatch");
    }
    done = true;
    return false;
  }
  crc_to(at + kRecordHeader + n);
  pos = at + kRecordHeader + n;
  bool ok = true;
  switch (static_cast<Opcode>(op)) {
    case Opcode::kHeader:
      ok = at == 8 && detail::parse_header(body, profile, library);
      break;
    case Opcode::kFooter:
      issue(ReadIssue::Kind::kCorrupt, at, "footer before Data End");
      done = true;
      return false;
    case Opcode::kSchema: {
      Schema s;
      ok = detail::parse_schema(body, s);
      if (ok) add_schema(s);
      break;
    }
    case Opcode::kChannel: {
      Channel c;
      ok = detail::parse_channel(body, c);
      if (ok) add_channel(c);
      break;
    }
    case Opcode::kMessage: {
      detail::MessageRecord m;
      ok = detail::parse_message(body, m);
      if (ok) return fill(m, at, out);
      break;
    }
    case Opcode::kChunk:
      open_chunk(at, body);
      return false;
    default:
      break;  // indexes, attachments, metadata: not needed for reading messages
  }
  if (!ok) issue(ReadIssue::Kind::kCorrupt, at, "malformed record (opcode " + hex(op) + ")");
  return false;
}

bool McapReader::next(MessageView& out) {
  Impl& m = *impl_;
  for (;;) {
    if (m.in_chunk) {
      if (m.next_in_chunk(out)) return true;
      continue;
    }
    if (m.done) return false;
    if (m.step(out)) return true;
  }
}

}  // namespace vigs::io::mcap
